// Follow-on errors: four "not connected to anything" after the ambiguous-arrow error.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        Se pull = 2.0;
        C spring = 100.0;
        I mass = 1.0;
        { push, pull } -> { spring, mass };
    }
}

fn main() {}
