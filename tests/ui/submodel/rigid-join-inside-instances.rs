// Two rigid bodies joined velocity to velocity, without a compliant joint: the second
// body's momentum is forced into derivative causality. The error points at the second
// instance and names the part: `b.translation`.
use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{vec3, Matrix3};

bond_graph! {
    model Welded {
        RigidBody a(m = 1.0, J = vec3(0.1, 0.1, 0.1), R0 = Matrix3::identity(), r0 = vec3(0.0, 0.0, 0.0), g = 9.81);
        RigidBody b(m = 1.0, J = vec3(0.1, 0.1, 0.1), R0 = Matrix3::identity(), r0 = vec3(1.0, 0.0, 0.0), g = 9.81);
        a.v -> b.v;
    }
}

fn main() {}
