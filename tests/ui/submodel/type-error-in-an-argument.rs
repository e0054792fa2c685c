use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{vec3, Matrix3};

bond_graph! {
    model Wrong {
        RigidBody a(m = "heavy", J = vec3(0.1, 0.1, 0.1), R0 = Matrix3::identity(), r0 = vec3(0.0, 0.0, 0.0), g = 9.81);
    }
}

fn main() {}
