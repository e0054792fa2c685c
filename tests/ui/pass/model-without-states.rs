// Should compile: a purely resistive model has no states.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Load {
        Se supply = 1.0;
        R r = 2.0;
        supply -> r;
        output i = r.f;
    }
}

fn main() {}
