// A voltage source behind a gyrator sets the flow of the shaft's 1-junction, where a
// flow source sets it too: the conflict names the gyrator and the path through it.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Motor {
        Se supply = 12.0;
        GY motor = 0.1;
        Sf drive = 5.0;
        R friction = 0.01;
        1 shaft;
        supply -> motor -> shaft -> friction;
        drive -> shaft;
    }
}

fn main() {}
