use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        C spring = 100.0;
        I mass = 1.0;
        1 v;
        push -[b1]-> v -> { spring, mass };
        b1 -> v;
    }
}

fn main() {}
