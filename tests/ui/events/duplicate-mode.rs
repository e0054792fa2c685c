// Two modes of one name.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Twice {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode on: bool = false;
        mode on: i64 = 0;
        when mass.p > 1.0 {
            on = true;
        }
    }
}

fn main() {}
