use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{skew, vec3};

bond_graph! {
    model Coupling {
        Se torque = vec3(0.0, 0.0, 1.0);
        MGY couple = skew(vec3(0.1, 0.0, 0.0));
        C[3] spring = 1.0;
        torque -> couple -> spring;
    }
}

fn main() {}
