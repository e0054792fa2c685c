//! Runs of the stiff solvers shared by the tests that compare two ways of solving one
//! model (`stiff_sparse`, `stiff_hand_written`).

use bgdsl_runtime::{Model, Radau5Options, Rodas4Options, Simulation, Solver, Stats};

/// Radau5 and Rodas4 at the given tolerances.
pub fn solvers(rtol: f64, atol: f64) -> [Solver; 2] {
    [
        Solver::Radau5(Radau5Options {
            rtol,
            atol,
            ..Default::default()
        }),
        Solver::Rodas4(Rodas4Options {
            rtol,
            atol,
            ..Default::default()
        }),
    ]
}

/// The state at `t_end` and the work.
pub fn run<M: Model>(model: &M, solver: Solver, t_end: f64) -> (Vec<f64>, Stats) {
    let mut sim = Simulation::new(model, solver).unwrap();
    let x0 = vec![0.0; M::N_STATES];
    let stats = sim.run(0.0, &x0, &[t_end], &mut ()).unwrap();
    (sim.state().to_vec(), stats)
}

/// The largest difference relative to `atol + rtol |b|`.
pub fn scaled_difference(a: &[f64], b: &[f64], rtol: f64, atol: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / (atol + rtol * y.abs()))
        .fold(0.0, f64::max)
}
