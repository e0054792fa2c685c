// A component joined twice: the second is reported (and the gap it leaves).
use bgdsl_runtime::bond_graph;

bond_graph! {
    model M {
        I[3] mass = 1.0;
        1 v;
        Sf a = 1.0;
        Sf b = 0.0;
        Sf c = 0.0;
        Split[3] s;
        a -> s.0;
        b -> s.0;
        c -> s.2;
        s -> v -> mass;
    }
}

fn main() {}
