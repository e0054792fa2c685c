// Dependent storage has no state of its own to reinit.
use bgdsl_runtime::bond_graph;

bond_graph! {
    #[allow(derivative_causality)]
    model Gear {
        Se torque = 1.0;
        I motor = 0.01;
        TF gear = 5.0;
        I load = 0.5;
        1 w1;
        1 w2;
        torque -> w1 -> motor;
        w1 -> gear -> w2 -> load;
        when motor.p > 1.0 {
            reinit load.p = 0.0;
        }
    }
}

fn main() {}
