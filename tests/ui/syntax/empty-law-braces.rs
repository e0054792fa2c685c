// Follow-on error: `R damper {}` is not declared, so the bond reports "unknown element `damper`".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        I mass = 1.0;
        R damper {};
        1 v;
        push -> v -> { mass, damper };
    }
}

fn main() {}
