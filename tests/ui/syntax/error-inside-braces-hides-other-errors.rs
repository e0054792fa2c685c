// Two independent mistakes. Today only syn's generic "unexpected token, expected `}`"
// is reported (at `g`); `Q x = 1.0;` is lost and no stub is emitted, because the
// statement's nested ParseBuffer is dropped with tokens left in it, which syn turns
// into an error for the whole input at the end of `parse2`.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring { e = 100.0 * q g };
        Q x = 1.0;
        push -> spring;
        output x = spring.q;
    }
}

fn main() {}
