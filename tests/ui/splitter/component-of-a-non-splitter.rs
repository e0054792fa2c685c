// Only a splitter has numbered components.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model M {
        I mass = 1.0;
        Se push = 1.0;
        push -> mass.0;
    }
}

fn main() {}
