// Follow-on errors: the whole chain `push -> v -> {}` is dropped, so `push` is
// "not connected" and `v` "has only one bond".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        1 v;
        push -> v -> {};
        v -> spring;
    }
}

fn main() {}
