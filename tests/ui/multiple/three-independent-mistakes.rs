// Three independent mistakes: duplicate `mass`, unknown `sprung`, and `q` in R `damper`'s
// law. Only the first two are reported (law expressions are checked only after resolve and
// causality succeed). The "q" mistake depends on nothing else and could be found in resolve.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        I mass = 1.0;
        I mass = 2.0;
        R damper { e = 0.4 * q };
        1 v;
        push -> v -> { mass, damper, sprung };
    }
}

fn main() {}
