// A mode is assigned without `reinit`.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Latch {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode fast: bool = false;
        when mass.p > 2.0 {
            reinit fast = true;
        }
    }
}

fn main() {}
