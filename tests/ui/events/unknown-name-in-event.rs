// Unknown names in a condition and in an action's value: the did-you-mean of laws.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Ball {
        param restitution = 0.8;
        Se weight = -9.81;
        I ball = 1.0;
        weight -> ball;
        state x: f64 = 1.0;
        der x = ball.f;
        when hieght < 0.0 {
            reinit ball.p = -restitutoin * ball.p;
        }
        when x < 0.0 {
            reinit bal.p = 0.0;
        }
    }
}

fn main() {}
