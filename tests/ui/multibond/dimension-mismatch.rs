use bgdsl_runtime::bond_graph;

bond_graph! {
    model Mismatch {
        Se[3] push = bgdsl_runtime::multibond::vec3(1.0, 0.0, 0.0);
        I[2] mass = 1.0;
        1 v;
        push -> v -> mass;
    }
}

fn main() {}
