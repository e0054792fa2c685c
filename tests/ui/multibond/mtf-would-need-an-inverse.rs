use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{skew, vec3};

bond_graph! {
    model Lever {
        Se torque = vec3(0.0, 0.0, 1.0);
        MTF arm = skew(vec3(0.1, 0.0, 0.0));
        I[3] mass = 1.0;
        torque -> arm -> mass;
    }
}

fn main() {}
