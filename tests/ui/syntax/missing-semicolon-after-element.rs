// A missing `;` after an element: one error at the end of that element, and the
// element after it (`spring`) is still declared, so the bond naming it is fine.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0
        C spring = 100.0;
        push -> spring;
        output x = spring.q;
    }
}

fn main() {}
