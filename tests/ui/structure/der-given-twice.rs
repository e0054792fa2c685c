// A kinematic state's derivative written twice: the second is reported, with the mend.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Drift {
        Sf push = 1.0;
        C spring = 1.0;
        push -> spring;
        state x: f64 = 0.0;
        der x = spring.f;
        der x = 2.0 * spring.f;
    }
}

fn main() {}
