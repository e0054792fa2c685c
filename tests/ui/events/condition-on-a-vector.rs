// A condition compares numbers: a 3-vector momentum is not one.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Body {
        param m = 1.0;
        Se[3] weight = vec3(0.0, -9.81 * m, 0.0);
        I[3] body = m;
        weight -> body;
        when body.p < 0.0 {
            stop;
        }
    }
}

fn main() {}
