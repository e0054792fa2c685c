// Should report only "the name `spring` is declared twice" (+ note). Today the element
// loses the name to the earlier parameter, and two follow-on errors appear:
// "`spring` is a parameter, not an element" at the bond and "Sf `push` is not connected".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param spring = 100.0;
        Sf push = 1.0;
        C spring = spring;
        push -> spring;
    }
}

fn main() {}
