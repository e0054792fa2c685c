// A submodel that contains an instance of itself never ends: stopped at the nesting
// limit, with the mend.
use bgdsl_runtime::bond_graph;

bond_graph! {
    submodel Chain(m) {
        I mass = m;
        Chain next(m = m);
    }

    model Endless {
        Chain first(m = 1.0);
    }
}

fn main() {}
