// Two rigid gears between the same shafts: even with derivative causality allowed, the
// second shaft's speed is fixed twice, a redundant constraint.
use bgdsl_runtime::bond_graph;

bond_graph! {
    #[allow(derivative_causality)]
    model TwoGears {
        Se motor = 1.0;
        I shaft1 = 0.2;
        I shaft2 = 0.05;
        1 w1; 1 w2;
        TF a = 3.0;
        TF b = 3.0;
        motor -> w1 -> shaft1;
        w1 -> a -> w2 -> shaft2;
        w1 -> b -> w2;
    }
}

fn main() {}
