#![deny(warnings)]
use bgdsl_runtime::{bond_graph, Model};

bond_graph! {
    /// Every unit is known and every output agrees with what it reads: no warning.
    pub model Oscillator {
        param m = 1.0 in "kg";
        param k = 100.0 in "N/m";
        param c = 0.4 in "N·s/m";
        param x0 = 0.01 in "mm";
        /// the mass's momentum
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        R damper = c;
        1 v;
        v -> { mass, spring, damper };
        init spring.q = x0 * 1e-3;
        state travelled: f64 = 0.0 in "m";
        der travelled = v.f.abs();
        output x = spring.q;
        output x_mm = spring.q * 1000.0 in "mm";
        output speed = mass.p / m in "m/s";
        output force = k * spring.q in "N";
        output energy = 0.5 * k * spring.q.powi(2) + mass.p.powi(2) / (2.0 * m) in "J";
        output power = (k * spring.q) * (mass.p / m) in "W";
    }
}

fn main() {
    assert_eq!(Oscillator::STATES[0].unit, "kg·m/s");
    assert_eq!(Oscillator::STATES[0].doc, "the mass's momentum");
    assert_eq!(Oscillator::OUTPUTS[0].unit, "m");
}
