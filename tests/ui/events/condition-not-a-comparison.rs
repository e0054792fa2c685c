// A condition must be a comparison or `crossing(..)`: a bare value, an equality and a
// conjunction are not.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Switcher {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode on: bool = false;
        when mass.p {
            on = true;
        }
        when mass.p == 1.0 {
            on = true;
        }
        when mass.p > 1.0 && mass.p < 2.0 {
            on = false;
        }
    }
}

fn main() {}
