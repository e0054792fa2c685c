// Two effort sources are the only bonds of a 1-junction: efforts add there, and nothing
// sets the junction's flow (a loop without its inertia or resistance).
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Loop {
        Se battery = 12.0;
        Se charger = 13.0;
        1 current;
        battery -> current;
        charger -> current;
    }
}

fn main() {}
