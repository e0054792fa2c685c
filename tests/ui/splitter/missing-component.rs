// Every component of a splitter needs its scalar bond.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model M {
        I[3] mass = 1.0;
        1 v;
        Sf a = 1.0;
        Sf b = 0.0;
        Split[3] s;
        a -> s.0;
        b -> s.2;
        s -> v -> mass;
    }
}

fn main() {}
