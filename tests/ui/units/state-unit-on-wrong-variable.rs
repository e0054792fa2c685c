use bgdsl_runtime::bond_graph;

bond_graph! {
    pub model Oscillator {
        I mass = 1.0, q in "kg·m/s";
        C spring = 100.0, q in "m";
        R damper = 0.4, f in "m/s";
        1 v;
        v -> { mass, spring, damper };
    }
}

fn main() {}
