use bgdsl_runtime::bond_graph;

bond_graph! {
    model Pumps {
        Sf pump_a = 1.0;
        Sf pump_b = 2.0;
        R pipe = 4.0;
        1 line;
        pump_a -> line -> pipe;
        pump_b -> line;
    }
}

fn main() {}
