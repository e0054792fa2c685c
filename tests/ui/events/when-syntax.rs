// Malformed `when` blocks: no condition, no braces, an action that is none. Each is
// reported and the statements after it still parse.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Broken {
        Se push = 1.0;
        I mass = 1.0;
        push -> mass;
        mode on: bool = false;
        when { on = true; }
        when mass.p > 1.0 { on == true; }
        when mass.p > 2.0 { reinit mass.p; }
        C spring = 1.0
    }
}

fn main() {}
