// Should compile: a model need not declare outputs.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Charger {
        Sf push = 1.0;
        C spring = 100.0;
        push -> spring;
    }
}

fn main() {}
