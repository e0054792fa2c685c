// A splitter has one multibond; the scalar bonds name their component.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model M {
        I[3] mass = 1.0;
        I[3] other = 2.0;
        Sf a = 1.0;
        Sf b = 0.0;
        Sf c = 0.0;
        Split[3] s;
        a -> s.0;
        b -> s.1;
        c -> s.2;
        s -> mass;
        s -> other;
    }
}

fn main() {}
