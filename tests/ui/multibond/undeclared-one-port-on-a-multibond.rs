use bgdsl_runtime::bond_graph;

bond_graph! {
    model ScalarDamperOn3d {
        param c = 2.0;
        I[3] mass = 1.0;
        R damper = c;
        1 v;
        v -> { mass, damper };
    }
}

fn main() {}
