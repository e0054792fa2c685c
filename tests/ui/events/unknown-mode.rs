// Assigning a mode that does not exist: the nearest mode is offered.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Friction {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode stuck: bool = true;
        output held = if stuck { 1.0 } else { 0.0 };
        when mass.p > 1.0 {
            stuk = false;
        }
    }
}

fn main() {}
