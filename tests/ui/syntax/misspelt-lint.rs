// A bond-graph lint spelt wrong: named with the one meant, on the model and on an element.
use bgdsl_runtime::bond_graph;

bond_graph! {
    #[allow(algebraic_loop)]
    model Divider {
        Se supply = 1.0;
        #[allow(derivative_casuality)]
        R load = 2.0;
        supply -> load;
    }
}

fn main() {}
