// Poor message and follow-on errors: the error is "expected `->` or `-`" at `output` (it
// should say `;` is expected after `push -> spring`), and the bond is dropped, so both
// elements are "not connected to anything". (The next statement, `output x`, is lost too.)
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
