// Follow-on errors: besides the (good) "unknown element `sprnig` (did you mean `spring`?)",
// Sf `push` and C `spring` are reported as "not connected to anything".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        push -> sprnig;
    }
}

fn main() {}
