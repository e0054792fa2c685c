// `reinit` of a signal (an effort computed from the states), and of an element that
// has no state at all.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        C spring = 100.0;
        I mass = 1.0;
        R damper = 0.5;
        1 v;
        push -> v -> { spring, mass, damper };
        when spring.q > 0.1 {
            reinit spring.e = 0.0;
            reinit damper.f = 0.0;
        }
    }
}

fn main() {}
