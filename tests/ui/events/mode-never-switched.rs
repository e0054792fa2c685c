// A mode that a law reads and no `when` switches is a parameter.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Clutch {
        param c = 2.0;
        Se push = 1.0;
        I mass = 1.0;
        R friction { e = if engaged { c * f } else { 0.0 * f } };
        1 v;
        push -> v -> { mass, friction };
        mode engaged: bool = true;
    }
}

fn main() {}
