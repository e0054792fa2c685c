use bgdsl_runtime::bond_graph;

bond_graph! {
    model WrongProjection {
        param n: Vector3 = [0.0, 0.0, 1.0];
        I[3] mass = 1.0;
        1 v;
        MTF proj = n;
        R damper = 2.0;
        v -> { mass, proj };
        proj -> damper;
    }
}

fn main() {}
