// Dependent storage needs a linear law to compute its energy variable from what it
// receives: an explicit law there is refused.
use bgdsl_runtime::bond_graph;

bond_graph! {
    #[allow(derivative_causality)]
    model Gear {
        Se motor = 1.0;
        I shaft1 = 0.2;
        I shaft2 { f = p / 0.05 };
        1 w1; 1 w2;
        TF gear = 3.0;
        motor -> w1 -> shaft1;
        w1 -> gear -> w2 -> shaft2;
    }
}

fn main() {}
