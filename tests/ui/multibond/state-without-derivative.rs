use bgdsl_runtime::bond_graph;

bond_graph! {
    model Drift {
        Sf push = 1.0;
        C spring = 1.0;
        push -> spring;
        state x: f64 = 0.0;
    }
}

fn main() {}
