// Two inertias on a 0-junction with nothing that sets its effort: the second is in
// derivative causality because nothing else sets the effort; the help says to add a C
// or an R on the junction.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Masses {
        I mass_a = 1.0;
        I mass_b = 2.0;
        0 node;
        node -> { mass_a, mass_b };
    }
}

fn main() {}
