// A transformer with only its input bond: the help says which bond is missing.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Gear {
        Se motor = 1.0;
        TF gear = 3.0;
        motor -> gear;
    }
}

fn main() {}
