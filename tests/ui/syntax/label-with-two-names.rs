// The macro's own message ("expected `]`: a bond label is one name, `-[b1]->`") never
// shows: syn's "unexpected token, expected `]`" replaces it, for the whole input (see
// error-inside-braces-hides-other-errors.rs).
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        push -[b1 b2]-> spring;
    }
}

fn main() {}
