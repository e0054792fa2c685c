// A splitter must say how many components it has.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model M {
        I[3] mass = 1.0;
        Sf a = 1.0;
        Split s;
        a -> s.0;
        s -> mass;
    }
}

fn main() {}
