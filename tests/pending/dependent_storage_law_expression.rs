//! A dependent C whose law is a parameter expression (`1.0 / c2`, hoisted into the
//! model's cache) must compile and charge with the time constant R (C1 + C2). Run by
//! the ignored test `parallel_capacitors::charge_with_a_law_expression_on_the_dependent_capacitor`
//! in `tests/tests/rigid_connections.rs` (issue 12: fails to compile with "cannot find
//! macro `__bgdsl_hoisted`").

use bgdsl_runtime::{bond_graph, simulate, Solver};

bond_graph! {
    /// Two capacitors in parallel charged through a resistor, both laws expressions.
    #[allow(derivative_causality)]
    pub model ParallelCapacitors {
        param e0 = 2.0;
        param r = 1000.0;
        param c1 = 1.0e-6;
        param c2 = 3.0e-6;

        Se source = e0;
        R resistor = r;
        C cap1 = 1.0 / c1;
        C cap2 = 1.0 / c2;
        1 current;
        0 node;

        source -> current -> { resistor, node };
        node -> { cap1, cap2 };

        output voltage = node.e;
    }
}

fn main() {
    let run = simulate(&ParallelCapacitors::default(), Solver::dopri5(), 0.0, 4e-3, 2).unwrap();
    let v = run.value(1, "voltage").unwrap();
    let expected = 2.0 * (1.0 - (-1.0f64).exp());
    assert!((v - expected).abs() < 1e-6, "{v} vs {expected}");
}
