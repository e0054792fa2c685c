use bgdsl_runtime::bond_graph;

bond_graph! {
    model Motor {
        Se volts = 1.0;
        I coil = 0.01;
        GY motor = 0.5;
        I rotor = 0.1;
        1 i;
        volts -> i -> coil;
        motor -> { i, rotor };
    }
}

fn main() {}
