// A `when` with no action does nothing.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Idle {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        when mass.p > 1.0 {}
    }
}

fn main() {}
