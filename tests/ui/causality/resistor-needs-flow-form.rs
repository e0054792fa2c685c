use bgdsl_runtime::bond_graph;

bond_graph! {
    model Heater {
        Se supply = 10.0;
        R element { e = 2.0 * f + 0.1 * f * f };
        supply -> element;
    }
}

fn main() {}
