// Follow-on errors: the bond statement is dropped after the (correct) attribute error,
// though it parses; its elements are then "not connected to anything".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        /// the only bond
        push -> spring;
    }
}

fn main() {}
