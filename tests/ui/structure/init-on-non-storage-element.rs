use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        I mass = 1.0;
        R damper = 0.4;
        1 v;
        push -> v -> { mass, damper };
        init damper.q = 0.01;
    }
}

fn main() {}
