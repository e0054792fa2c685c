//! Proof that derivative evaluation and the whole stepping loop are free of heap
//! allocation once a [`Simulation`] and its recorder are set up.
//!
//! A global allocator is per binary, so this test has a binary of its own; it counts
//! the allocations (and reallocations) made on the current thread (`support/counting.rs`),
//! so neither the harness nor the tests running alongside on other threads are counted.

use std::hint::black_box;

use bgdsl_runtime::{
    DormandPrinceOptions, FixedStep, Model, Scalar, Simulation, Solver, Trajectory,
};

#[path = "support/counting.rs"]
mod counting;

use counting::{allocations_in, Counting};

#[global_allocator]
static GLOBAL: Counting = Counting;

/// A damped, driven nonlinear pendulum with two outputs: the kind of straight-line
/// code `bond_graph!` generates.
struct Pendulum {
    params: PendulumParams,
}

#[derive(Clone, Debug, Default)]
struct PendulumParams {
    g_over_l: f64,
    damping: f64,
    drive: f64,
}

impl Model for Pendulum {
    type Params = PendulumParams;
    const NAME: &'static str = "pendulum";
    const STATE_NAMES: &'static [&'static str] = &["angle", "rate"];
    const OUTPUT_NAMES: &'static [&'static str] = &["energy", "height"];
    fn params(&self) -> &PendulumParams {
        &self.params
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let p = &self.params;
        dx[0] = x[1];
        dx[1] = -T::from_f64(p.g_over_l) * x[0].sin() - T::from_f64(p.damping) * x[1]
            + T::from_f64(p.drive * t.cos());
    }
    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        let p = &self.params;
        let one = T::from_f64(1.0);
        y[0] = T::from_f64(0.5) * x[1] * x[1] + T::from_f64(p.g_over_l) * (one - x[0].cos());
        y[1] = one - x[0].cos();
    }
}

/// One test, so that nothing else runs on this thread while counting.
#[test]
fn stepping_allocates_nothing_after_set_up() {
    let model = Pendulum {
        params: PendulumParams {
            g_over_l: 9.81,
            damping: 0.1,
            drive: 0.5,
        },
    };

    // (a) 10,000 derivative evaluations.
    let mut x = [0.3, -0.2];
    let mut dx = [0.0; 2];
    let (n, ()) = allocations_in(|| {
        for i in 0..10_000 {
            model.derivatives::<f64>(i as f64 * 1e-3, black_box(&x), &mut dx);
            x[0] += 1e-6 * dx[0];
        }
    });
    assert_eq!(n, 0, "allocations in 10,000 calls of derivatives::<f64>");
    black_box(x);

    // (b) Whole runs, for every solver: set up first, then count.
    let dp_dense = DormandPrinceOptions {
        rtol: 1e-9,
        atol: 1e-12,
        ..Default::default()
    };
    let solvers = [
        Solver::rk4(1e-3),
        Solver::DormandPrinceFixed(FixedStep::new(1e-3)),
        Solver::DormandPrince(dp_dense),
    ];
    let samples = 5_001;
    let sample_times = bgdsl_runtime::sample_times_uniform(0.0, 50.0, samples);
    for solver in solvers {
        let mut sim = Simulation::new(&model, solver).unwrap();
        let mut traj = Trajectory::for_model::<Pendulum>(2 * samples);
        let x0 = [1.0, 0.0];
        let (n, result) = allocations_in(|| {
            let listed = sim.run(0.0, &x0, &sample_times, &mut traj);
            let uniform = sim.run_uniform(0.0, &x0, 50.0, samples, &mut traj);
            (listed, uniform)
        });
        let (listed, uniform) = result;
        let (listed, uniform) = (listed.unwrap(), uniform.unwrap());
        assert_eq!(n, 0, "{}: allocations in run ({listed:?})", solver.name());
        assert_eq!(listed, uniform);
        // Many steps were taken, and (for the adaptive method) most samples were
        // interpolated.
        assert!(listed.accepted >= 1_000, "{}: {listed:?}", solver.name());
        assert_eq!(traj.len(), 2 * samples);
    }

    // (c) A failing run allocates nothing either: the error is plain data.
    let budget = Solver::DormandPrince(DormandPrinceOptions {
        max_steps: 10,
        ..Default::default()
    });
    let mut sim = Simulation::new(&model, budget).unwrap();
    let (n, result) = allocations_in(|| sim.run(0.0, &[1.0, 0.0], &[1e3], &mut ()));
    assert!(result.is_err());
    assert_eq!(n, 0, "allocations in a failing run");

    // The counter does count: a recorder without room must grow.
    let mut sim = Simulation::new(&model, Solver::rk4(1e-2)).unwrap();
    let mut small = Trajectory::for_model::<Pendulum>(1);
    let (n, result) = allocations_in(|| sim.run_uniform(0.0, &[1.0, 0.0], 1.0, 100, &mut small));
    result.unwrap();
    assert!(n > 0, "the counting allocator saw nothing");
}

/// The allocation-free Dormand–Prince of `rk` with per-state tolerances
/// (`set_atol`) allocates nothing, neither setting them nor stepping with them.
#[test]
fn no_std_dormand_prince_with_per_state_atol_allocates_nothing() {
    use bgdsl_runtime::rk::DormandPrince;
    let model = Pendulum {
        params: PendulumParams {
            g_over_l: 9.81,
            damping: 0.1,
            drive: 0.5,
        },
    };
    let mut dopri = DormandPrince::<2>::new(DormandPrinceOptions::default()).unwrap();
    let (mut t, mut x) = (0.0, [1.0, 0.0]);
    let (n, result) = allocations_in(|| {
        dopri.set_atol::<Pendulum>(Some([1e-12, 1e-6]))?;
        dopri.advance_to(&model, &mut t, &mut x, 50.0)
    });
    result.unwrap();
    assert_eq!(n, 0, "allocations with per-state atol");
    assert_eq!(t, 50.0);
    assert!(dopri.stats().accepted >= 100, "{:?}", dopri.stats());
}
