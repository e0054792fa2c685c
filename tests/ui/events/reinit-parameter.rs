// `reinit` of a parameter: parameters are fixed for a run; the help offers a mode.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Ball {
        param m = 1.0;
        param drop = 1.0;
        Se weight = -9.81 * m;
        I ball = m;
        weight -> ball;
        when ball.p < -5.0 {
            reinit drop = 0.0;
        }
    }
}

fn main() {}
