// Two compliances in series on a 1-junction with nothing that sets its flow: the
// second is in derivative causality because nothing else sets the flow; the help says
// to add an I or an R on the junction.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Springs {
        C spring_a = 100.0;
        C spring_b = 50.0;
        1 link;
        link -> { spring_a, spring_b };
    }
}

fn main() {}
