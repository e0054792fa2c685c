// A keyword used as a name only inside an expression (declared raw, used plain): one
// error there, with the fix.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Loop {
        Se push = 1.0;
        I mass = 1.0;
        1 r#loop;
        push -> r#loop -> mass;
        output v = loop.f;
    }
}

fn main() {}
