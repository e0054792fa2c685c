// A splitter has no law.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model M {
        I[3] mass = 1.0;
        Sf a = 1.0;
        Sf b = 0.0;
        Sf c = 0.0;
        Split[3] s = 2.0;
        a -> s.0;
        b -> s.1;
        c -> s.2;
        s -> mass;
    }
}

fn main() {}
