// Components a parameter does not have, in an initial condition and a kinematic
// state's initial value.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param K: [f64; 3] = [1.0, 2.0, 3.0];
        param k = 100.0;
        Se push = 1.0;
        I mass = 1.0;
        C spring = k;
        1 v;
        push -> v -> { mass, spring };
        init spring.q = K[(1, 1)];
        state r: Vector3 = [K.x, K.w, 0.0];
        der r = K;
    }
}

fn main() {}
