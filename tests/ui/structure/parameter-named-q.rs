use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param q = 0.01;
        Sf push = 1.0;
        C spring = 100.0;
        push -> spring;
    }
}

fn main() {}
