// A resistor whose law cannot take the causality a source imposes through a gyrator:
// the message shows the path through the gyrator.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Motor {
        Se supply = 12.0;
        GY motor = 0.1;
        R friction { f = e / 0.01 };
        supply -> motor -> friction;
    }
}

fn main() {}
