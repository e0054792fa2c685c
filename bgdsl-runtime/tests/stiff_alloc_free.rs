//! Proof that the stiff solvers' stepping loops, Jacobian evaluations, LU
//! factorizations and dense output included, are free of heap allocation once a
//! [`Simulation`] and its recorder are set up.
//!
//! A global allocator is per binary, so this test has a binary of its own; it counts
//! the allocations (and reallocations) made on the current thread (`support/counting.rs`),
//! so neither the harness nor the tests running alongside on other threads are counted.

mod stiff_common;

#[path = "support/pairs.rs"]
mod pairs;

#[path = "support/large_chains.rs"]
mod large_chains;

use std::time::Duration;

use bgdsl_runtime::{
    Model, Radau5Options, Rodas4Options, Rodas5POptions, Scalar, Simulation, Solver, SolverError,
    Trajectory,
};
use large_chains::{BlockChain, Interleaved, MassChain};
use pairs::Pairs;
use stiff_common::{Hires, Oregonator, Robertson};

#[path = "support/counting.rs"]
mod counting;

use counting::{allocations_in, Counting};

#[global_allocator]
static GLOBAL: Counting = Counting;

/// A forced, damped Duffing oscillator made stiff by a fast first-order actuator: time
/// dependent (so Rodas4 evaluates `∂f/∂t`), nonlinear, with outputs.
struct ForcedDuffing;

impl Model for ForcedDuffing {
    type Params = ();
    const NAME: &'static str = "forced_duffing";
    const STATE_NAMES: &'static [&'static str] = &["q", "p", "actuator.f"];
    const OUTPUT_NAMES: &'static [&'static str] = &["energy"];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&[&[1], &[0, 1, 2], &[2]]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let c = T::from_f64;
        dx[0] = x[1];
        dx[1] = -x[0] - c(0.5) * x[0] * x[0] * x[0] - c(0.1) * x[1] + x[2];
        dx[2] = c(-1e5) * (x[2] - c(0.3 * (1.3 * t).cos()));
    }
    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        let h = T::from_f64(0.5);
        y[0] = h * x[1] * x[1] + h * x[0] * x[0];
    }
}

/// Runs `solver` on `model` through `samples` sample times, twice (listed and uniform),
/// counting allocations after set-up; returns the steps taken.
fn count_runs<M: Model>(model: &M, solver: Solver, t_end: f64, samples: usize) -> usize {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let times = bgdsl_runtime::sample_times_uniform(0.0, t_end, samples);
    let mut sim = Simulation::new(model, solver).unwrap();
    let mut traj = Trajectory::for_model::<M>(2 * samples);
    let (n, (listed, uniform)) = allocations_in(|| {
        let listed = sim.run(0.0, &x0, &times, &mut traj);
        let uniform = sim.run_uniform(0.0, &x0, t_end, samples, &mut traj);
        (listed, uniform)
    });
    let (listed, uniform) = (listed.unwrap(), uniform.unwrap());
    assert_eq!(
        n,
        0,
        "{} on {}: allocations in run ({listed:?})",
        solver.name(),
        M::NAME
    );
    assert_eq!(listed, uniform);
    assert_eq!(traj.len(), 2 * samples);
    listed.accepted
}

/// One test, so that nothing else runs on this thread while counting.
#[test]
fn stiff_stepping_allocates_nothing_after_set_up() {
    let radau = Solver::Radau5(Radau5Options {
        rtol: 1e-8,
        atol: 1e-10,
        // Checked every step: reading the clock does not allocate either.
        max_wall_time: Some(Duration::from_secs(60)),
        ..Default::default()
    });
    let rodas = Solver::Rodas4(Rodas4Options {
        rtol: 1e-6,
        atol: 1e-9,
        max_wall_time: Some(Duration::from_secs(60)),
        ..Default::default()
    });
    let rodas5p = Solver::Rodas5P(Rodas5POptions {
        rtol: 1e-6,
        atol: 1e-9,
        max_wall_time: Some(Duration::from_secs(60)),
        ..Default::default()
    });
    // Refined stages: one compensated residual and one more solve per stage.
    let refined = Solver::Rodas5P(Rodas5POptions {
        refine_stages: true,
        ..Rodas5POptions::default()
    });
    for solver in [radau, rodas, rodas5p, refined] {
        // Many steps, Jacobians, LUs (including rejections); most samples inside steps.
        let steps = count_runs(&Oregonator, solver, 360.0, 3_001);
        assert!(steps >= 500, "{}: {steps} steps", solver.name());
        count_runs(&Hires, solver, 321.8122, 1_001);
        count_runs(&ForcedDuffing, solver, 20.0, 2_001);
        // The sparse linear algebra: its numerical pattern grows during the run (and is
        // analysed again), and with `ω = 1e10` some static pivots fail their stability
        // test and fall back to partial pivoting.
        count_runs(&Pairs::<true>::new(1e3), solver, 6.0, 601);
        count_runs(&Pairs::<true>::new(1e10), solver, 6.0, 601);
        // Large models: 10,000 states on the banded path and on the sparse path (whose
        // fallback band, the whole matrix, is not allocated), dense blocks.
        count_runs(&Interleaved::<10_000>::default(), solver, 0.02, 11);
        count_runs(&MassChain::<10_000, 34_996>::default(), solver, 0.02, 11);
        count_runs(&BlockChain::<2_000>, solver, 0.02, 11);
    }

    // A failing run allocates nothing either: the error is plain data.
    let budget = Solver::Radau5(Radau5Options {
        max_steps: 10,
        ..Default::default()
    });
    let mut sim = Simulation::new(&Oregonator, budget).unwrap();
    let (n, result) = allocations_in(|| sim.run(0.0, &[1.0, 2.0, 3.0], &[360.0], &mut ()));
    assert!(result.is_err());
    assert_eq!(n, 0, "allocations in a failing run");

    // Per-state tolerances and non-negative states (steps rejected for going below
    // zero, others projected, dense samples projected), and the errors of a step
    // underflow and of Dormand–Prince's stiffness test.
    for solver in [radau, rodas] {
        let mut sim = Simulation::new(&Robertson, solver).unwrap();
        sim.set_atol(&[1e-8, 1e-14, 1e-8]).unwrap();
        sim.set_non_negative(&[0, 1, 2]).unwrap();
        let mut traj = Trajectory::for_model::<Robertson>(101);
        let (n, result) =
            allocations_in(|| sim.run_uniform(0.0, &[1.0, 0.0, 0.0], 1e15, 101, &mut traj));
        assert!(result.is_ok(), "{result:?}");
        assert_eq!(n, 0, "{}: allocations with constraints", solver.name());
    }
    let tiny = Solver::Radau5(Radau5Options {
        atol: 0.0,
        ..Default::default()
    });
    let mut sim = Simulation::new(&Robertson, tiny).unwrap();
    let (n, result) = allocations_in(|| sim.run(0.0, &[1.0, 0.0, 0.0], &[1.0], &mut ()));
    assert!(matches!(result, Err(SolverError::StepUnderflow { .. })));
    assert_eq!(n, 0, "allocations in a run ending in a step underflow");
    let mut sim = Simulation::new(&Robertson, Solver::dopri5()).unwrap();
    sim.set_non_negative(&[0, 1, 2]).unwrap();
    let (n, result) = allocations_in(|| sim.run(0.0, &[1.0, 0.0, 0.0], &[1e5], &mut ()));
    assert!(matches!(result, Err(SolverError::StiffnessDetected { .. })));
    assert_eq!(n, 0, "allocations in a run ending in the stiffness test");

    // Setting up does allocate (the workspace), so the counter does count.
    let (n, sim) = allocations_in(|| Simulation::new(&Oregonator, radau));
    drop(sim);
    assert!(n > 0, "the counting allocator saw nothing");
}
