// `.z` on a scalar state and `[0]` on a scalar parameter: a number has no components.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param k = 100.0;
        Se push = 1.0;
        I mass = 1.0;
        C spring = k[0];
        1 v;
        push -> v -> { mass, spring };
        output x = spring.q.z;
    }
}

fn main() {}
