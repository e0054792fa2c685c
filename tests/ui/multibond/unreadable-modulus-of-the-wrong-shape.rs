use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{Vector3, vec3};
use bgdsl_runtime::Scalar;

/// A direction the macro cannot see into: its shape is checked by rustc.
fn direction<S: Scalar>(t: S) -> Vector3<S> {
    vec3(t.cos(), t.sin(), S::from_f64(0.0))
}

bond_graph! {
    model HiddenProjection {
        I[3] mass = 1.0;
        1 v;
        MTF proj = direction(t);
        R damper = 2.0;
        v -> { mass, proj };
        proj -> damper;
    }
}

fn main() {}
