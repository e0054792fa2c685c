// Two parallel bonds from a 0-junction to a 1-junction: the effort source's effort
// reaches the 1-junction along both, so nothing is left to set its flow. The source
// clashes with its own consequences, met around the loop the two bonds make.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Loop {
        Se supply = 1.0;
        0 node;
        1 ring;
        supply -> node;
        node -> ring;
        node -> ring;
    }
}

fn main() {}
