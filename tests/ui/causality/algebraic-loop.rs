use bgdsl_runtime::bond_graph;

bond_graph! {
    model Divider {
        Se supply = 10.0;
        R series = 1.0;
        R shunt_a = 2.0;
        R shunt_b = 3.0;
        1 i;
        0 v;
        supply -> i -> { series, v };
        v -> { shunt_a, shunt_b };
    }
}

fn main() {}
