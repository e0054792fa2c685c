use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        2 j;
        push -> spring;
    }
}

fn main() {}
