// Follow-on errors: `spring`, `mass` "not connected" and `v` "has only one bond".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        C spring = 100.0;
        I mass = 1.0;
        1 v;
        push -> v -[b1]-> { spring, mass };
    }
}

fn main() {}
