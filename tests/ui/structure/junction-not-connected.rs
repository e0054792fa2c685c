// A junction left dangling, with no bonds at all: the help says to bond it or remove it.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        I mass = 1.0;
        1 v;
        0 spare;
        push -> v -> mass;
    }
}

fn main() {}
