// A model with no elements is no bond graph: an error at its name, not an empty model.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Nothing {
        param k = 1.0;
    }
}

fn main() {}
