// Without `#![deny(warnings)]` an unknown unit or a disagreeing output is a warning:
// the model compiles and keeps the unit as written.
use bgdsl_runtime::{bond_graph, Model};

bond_graph! {
    pub model Oscillator {
        I mass = 1.0, p in "kg·m/s";
        C spring = 100.0, q in "m";
        1 v;
        v -> { mass, spring };
        output x = spring.q in "furlong";
        output wrong = mass.p in "m";
    }
}

fn main() {
    assert_eq!(Oscillator::OUTPUTS[0].unit, "furlong");
    assert_eq!(Oscillator::OUTPUTS[1].unit, "m");
}
