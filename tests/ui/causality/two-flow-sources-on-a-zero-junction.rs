// Two flow sources are the only bonds of a 0-junction: flows add there, and nothing
// sets the junction's effort (a tank without its compliance). The message says so at
// the 0-junction, not "two flows on one 1-junction".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Tank {
        Sf pump_a = 1.0;
        Sf pump_b = 2.0;
        0 tank;
        pump_a -> tank;
        pump_b -> tank;
    }
}

fn main() {}
