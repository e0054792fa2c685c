// Before an element or a bond, `allow` takes only the bond-graph lints: nothing of
// Rust's is generated there for a Rust lint to act on.
use bgdsl_runtime::bond_graph;

bond_graph! {
    #[allow(dead_code)]
    model Divider {
        Se supply = 1.0;
        #[allow(dead_code)]
        R load = 2.0;
        #[inline]
        supply -> load;
    }
}

fn main() {}
