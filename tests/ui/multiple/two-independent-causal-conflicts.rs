use bgdsl_runtime::bond_graph;

bond_graph! {
    model Twin {
        Se battery = 12.0;
        Se charger = 13.0;
        Sf pump_a = 1.0;
        Sf pump_b = 2.0;
        R load = 4.0;
        R pipe = 2.0;
        0 bus;
        1 line;
        battery -> bus -> load;
        charger -> bus;
        pump_a -> line -> pipe;
        pump_b -> line;
    }
}

fn main() {}
