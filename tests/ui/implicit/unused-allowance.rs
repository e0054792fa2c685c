// An allowance that nothing uses is an error, so that a stale opt-in hides nothing:
// the inertia keeps integral causality and there is no loop.
use bgdsl_runtime::bond_graph;

bond_graph! {
    #[allow(derivative_causality)]
    model Plain {
        Se push = 1.0;
        #[allow(algebraic_loops)]
        R drag = 0.5;
        I mass = 1.0;
        1 v;
        push -> v -> { drag, mass };
    }
}

fn main() {}
