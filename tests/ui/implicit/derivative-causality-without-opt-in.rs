// Two inertias through a rigid gear, without the opt-in: the second is forced into
// derivative causality, and the error says how to allow it.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Gear {
        Se motor = 1.0;
        I shaft1 = 0.2;
        I shaft2 = 0.05;
        1 w1; 1 w2;
        TF gear = 3.0;
        motor -> w1 -> shaft1;
        w1 -> gear -> w2 -> shaft2;
    }
}

fn main() {}
