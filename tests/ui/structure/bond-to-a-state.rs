// A kinematic state is not an element: bonds cannot reach it, but a law can read it.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Ramp {
        R load = 2.0;
        1 v;
        state x: f64 = 0.0;
        der x = 1.0;
        x -> v -> load;
    }
}

fn main() {}
