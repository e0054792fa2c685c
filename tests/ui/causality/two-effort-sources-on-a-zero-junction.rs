use bgdsl_runtime::bond_graph;

bond_graph! {
    model Supply {
        Se battery = 12.0;
        Se charger = 13.0;
        R load = 4.0;
        0 bus;
        battery -> bus -> load;
        charger -> bus;
    }
}

fn main() {}
