// Follow-on errors: "not connected to anything" for both elements of the dropped bond statement.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        push -[b1]- spring;
    }
}

fn main() {}
