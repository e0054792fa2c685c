// A host sets inputs one number at a time.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model M {
        input push: [f64; 3] = [0.0, 0.0, 0.0];
        I[3] mass = 1.0;
        MSe[3] force = push;
        force -> mass;
    }
}

fn main() {}
