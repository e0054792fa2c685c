use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        I mass = 1.0;
        R damper { e = 0.4 * f, e = 0.5 * f };
        1 v;
        push -> v -> { mass, damper };
    }
}

fn main() {}
