// Follow-on errors: after the statement fails to parse (correctly, at `<`), Sf `push`
// and C `spring` are reported as "not connected to anything".
// Also: the message "expected `->` or `-`" could say "write `push -> spring`: power flows left to right".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        spring <- push;
    }
}

fn main() {}
