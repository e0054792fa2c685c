use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring { f = 100.0 * q };
        push -> spring;
    }
}

fn main() {}
