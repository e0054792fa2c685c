use bgdsl_runtime::bond_graph;

bond_graph! {
    model Train {
        Se push = 1.0;
        I engine = 1000.0;
        I wagon = 500.0;
        1 v;
        push -> v -> { engine, wagon };
    }
}

fn main() {}
