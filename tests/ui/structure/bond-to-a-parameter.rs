use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param k = 100.0;
        Sf push = 1.0;
        C spring = k;
        push -> spring;
        push -> k;
    }
}

fn main() {}
