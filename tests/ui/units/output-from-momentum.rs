#![deny(warnings)]
use bgdsl_runtime::bond_graph;

bond_graph! {
    pub model Oscillator {
        param m = 1.0 in "kg";
        param k = 100.0 in "N/m";
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        1 v;
        v -> { mass, spring };
        // A momentum is not a position.
        output x = mass.p in "m";
        // A position is not a force, and nothing turns metres into millimetres.
        output F = spring.q in "N";
        output x_mm = spring.q in "mm";
        // p / m is a velocity; k q is a force: in N it is right, in W it is not.
        output speed = mass.p / m in "m/s";
        output force = k * spring.q in "W";
        // Adding a position to a momentum.
        output nonsense = spring.q + mass.p;
    }
}

fn main() {}
