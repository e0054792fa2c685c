// A mode is a `bool`, an `i64` or an `f64`; a value of the wrong type is rustc's
// error at the value.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Types {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode level: u8 = 0;
    }
}

bond_graph! {
    model Values {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode on: bool = false;
        when mass.p > 1.0 {
            on = 1.0;
        }
    }
}

fn main() {}
