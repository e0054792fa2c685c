// Initial values are computed from parameters, before any mode has a value.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Start {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode fast: bool = false;
        init mass.p = if fast { 2.0 } else { 1.0 };
        when mass.p > 3.0 {
            fast = true;
        }
    }
}

fn main() {}
