// Two dampers in series on a mass form an algebraic loop; without the opt-in the error
// says how to allow it.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model SeriesDampers {
        I mass = 1.0;
        R d1 = 2.0;
        R d2 = 3.0;
        1 v; 0 j;
        v -> mass;
        v -> j -> { d1, d2 };
    }
}

fn main() {}
