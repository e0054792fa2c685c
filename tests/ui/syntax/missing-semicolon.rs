// A missing `;` after a bond: one error after `spring`; the bond and the output after
// it are both kept, so nothing else is reported.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        push -> spring
        output x = spring.q;
    }
}

fn main() {}
