// Follow-on errors: `1 v = 3.0;` is not declared, so "unknown element `v`" and three
// "not connected to anything" follow. The junction could be declared anyway (law ignored).
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        C spring = 100.0;
        I mass = 1.0;
        1 v = 3.0;
        push -> v -> { spring, mass };
    }
}

fn main() {}
