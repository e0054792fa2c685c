#![deny(warnings)]
use bgdsl_runtime::bond_graph;

bond_graph! {
    pub model Oscillator {
        param m = 1.0 in "kg";
        param k = 100.0 in "N/furlong";
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        1 v;
        v -> { mass, spring };
        output x = spring.q in "metres";
    }
}

fn main() {}
