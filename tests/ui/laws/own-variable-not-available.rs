use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        I mass = 1.0;
        R damper { e = 0.4 * f + q };
        1 v;
        push -> v -> { mass, damper };
        output speed = v.f;
    }
}

fn main() {}
