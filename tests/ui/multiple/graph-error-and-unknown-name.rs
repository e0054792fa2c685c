// A graph mistake (a bond to an element that does not exist) and an unknown name in a
// law: both reported by one compile.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param force = 1.0;
        Se push = forse;
        I mass = 1.0;
        1 v;
        push -> v -> { mass, sprung };
    }
}

fn main() {}
