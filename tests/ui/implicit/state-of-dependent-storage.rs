// Dependent storage has no state to read: `shaft2.p` says so and how to write the
// momentum instead.
use bgdsl_runtime::bond_graph;

bond_graph! {
    #[allow(derivative_causality)]
    model Gear {
        Se motor = 1.0;
        I shaft1 = 0.2;
        I shaft2 = 0.05;
        1 w1; 1 w2;
        TF gear = 3.0;
        motor -> w1 -> shaft1;
        w1 -> gear -> w2 -> shaft2;
        output momentum2 = shaft2.p;
    }
}

fn main() {}
