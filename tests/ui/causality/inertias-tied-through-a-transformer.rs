use bgdsl_runtime::bond_graph;

bond_graph! {
    model Gearbox {
        Se torque = 1.0;
        I motor = 0.01;
        TF gear = 10.0;
        I wheel = 2.0;
        1 shaft;
        1 axle;
        torque -> shaft -> { motor, gear };
        gear -> axle -> wheel;
    }
}

fn main() {}
