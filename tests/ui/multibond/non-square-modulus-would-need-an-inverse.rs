use bgdsl_runtime::bond_graph;

bond_graph! {
    model PushAlong {
        param n: Vector3 = [0.0, 0.6, 0.8];
        Se push = 3.0;
        MTF along = n;
        I[3] mass = 1.0;
        1 v;
        push -> along -> v -> mass;
    }
}

fn main() {}
