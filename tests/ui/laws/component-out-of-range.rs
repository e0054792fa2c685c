// Components past a vector's or matrix's end, and a vector's component on a matrix, on
// a signal, a state, a parameter and a kinematic state.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Body {
        param K: [f64; 3] = [1.0, 2.0, 3.0];
        param J: [[f64; 2]; 2] = [[1.0, 0.0], [0.0, 1.0]];
        Se[3] push = bgdsl_runtime::multibond::vec3(1.0, 0.0, 0.0);
        I[3] mass = 1.0;
        1 v;
        push -> v -> mass;
        state R: Matrix3 = bgdsl_runtime::multibond::identity3();
        der R = R * 0.0;
        output a = v.f.w;
        output b = mass.p[3] + K[(0, 1)];
        output c = J[2][0] + J.x;
        output d = R.m41;
    }
}

fn main() {}
