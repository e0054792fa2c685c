//! Sampling through the stiff methods' continuous extensions.

use bgdsl_runtime::{
    Model, Radau5Options, Rodas4Options, Rodas5POptions, Scalar, Simulation, Solver, Trajectory,
};

/// The Prothero–Robinson problem `y' = λ (y - sin t) + cos t`, `y(0) = 0`, with
/// `λ = -1e6`: the exact solution is `y = sin t` (Prothero & Robinson, Math. Comp. 28
/// (1974) 145–162; HW II, Sect. IV.15). Non-autonomous, so Rodas4's `∂f/∂t` terms
/// matter; very stiff, so order reduction shows if the methods are mis-implemented.
struct ProtheroRobinson;

impl Model for ProtheroRobinson {
    type Params = ();
    const NAME: &'static str = "prothero_robinson";
    const STATE_NAMES: &'static [&'static str] = &["y"];
    const OUTPUT_NAMES: &'static [&'static str] = &["exact"];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 0.0;
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = T::from_f64(-1e6) * (x[0] - T::from_f64(t.sin())) + T::from_f64(t.cos());
    }
    fn outputs<T: Scalar>(&self, t: f64, _x: &[T], y: &mut [T]) {
        y[0] = T::from_f64(t.sin());
    }
}

/// The error estimates of both methods measure the error at the end of a step. On this
/// problem the solution hugs the slowly moving quasi-stationary state `sin t`, which
/// the stiffly accurate methods reproduce at any step size, so the steps grow to O(1)
/// and the end points stay accurate (Radau5 to a few tolerances: RADAU5's tolerance
/// transformation aims at, not under, the requested accuracy).
#[test]
fn long_steps_on_a_quasi_stationary_solution_are_accurate_at_their_ends() {
    let (rtol, atol) = (1e-6, 1e-8);
    for solver in [
        radau5(rtol, atol, f64::INFINITY),
        rodas4(rtol, atol, f64::INFINITY),
        rodas5p(rtol, atol, f64::INFINITY),
    ] {
        let mut sim = Simulation::new(&ProtheroRobinson, solver).unwrap();
        let stats = sim.run(0.0, &[0.0], &[10.0], &mut ()).unwrap();
        assert!(stats.accepted <= 20, "{}: {stats:?}", solver.name());
        let err = (sim.state()[0] - 10f64.sin()).abs() / (atol + rtol * 10f64.sin().abs());
        assert!(err <= 5.0, "{}: error {err} tolerances", solver.name());
    }
}

/// Between steps, samples come from the continuous extensions, whose error is not
/// controlled. With `max_step` bounding the steps, all 8001 samples on `[0, 10]` (most
/// of them inside steps) are within the tolerance of the exact solution; and sampling
/// does not change the steps taken.
///
/// Measured on this problem (`λ = -1e6`), the worst sample error on `[0, 1]` is
/// `6e-4 h^4` for Radau5's collocation polynomial (order 3, as in non-stiff problems)
/// and `1.3e-2 h^3` for Rodas4's continuous extension (order 3 on non-stiff problems,
/// order 2 here): hence the different bounds. Rodas5P's (order 4) stays at 0.12
/// tolerances with Radau5's bound `h <= 0.1` (5.2 at 0.2, 0.0053 at 0.05: about
/// `h^4.5`), where Rodas4 needs `h <= 0.005`.
#[test]
fn samples_between_bounded_steps_follow_the_exact_solution() {
    let (rtol, atol) = (1e-6, 1e-8);
    for solver in [
        radau5(rtol, atol, 0.1),
        rodas4(rtol, atol, 0.005),
        rodas5p(rtol, atol, 0.1),
    ] {
        let mut sim = Simulation::new(&ProtheroRobinson, solver).unwrap();
        let n = 8001;
        let mut traj = Trajectory::for_model::<ProtheroRobinson>(n);
        let dense = sim.run_uniform(0.0, &[0.0], 10.0, n, &mut traj).unwrap();
        assert_eq!(traj.len(), n);
        assert!(dense.accepted < n / 3, "{}: {dense:?}", solver.name());
        let (y, exact) = (traj.column("y").unwrap(), traj.column("exact").unwrap());
        let worst = y
            .iter()
            .zip(exact)
            .map(|(y, e)| (y - e).abs() / (atol + rtol * e.abs()))
            .fold(0.0, f64::max);
        assert!(worst <= 1.0, "{}: error {worst} tolerances", solver.name());
        // The steps do not depend on where the samples are.
        let sparse = sim.run(0.0, &[0.0], &[10.0], &mut ()).unwrap();
        assert_eq!(dense, sparse, "{}", solver.name());
    }
}

fn radau5(rtol: f64, atol: f64, max_step: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol,
        max_step,
        ..Default::default()
    })
}

fn rodas4(rtol: f64, atol: f64, max_step: f64) -> Solver {
    Solver::Rodas4(Rodas4Options {
        rtol,
        atol,
        max_step,
        ..Default::default()
    })
}

fn rodas5p(rtol: f64, atol: f64, max_step: f64) -> Solver {
    Solver::Rodas5P(Rodas5POptions {
        rtol,
        atol,
        max_step,
        ..Default::default()
    })
}

/// A sample at the start time records the initial state; repeated sample times are
/// all recorded; the run ends exactly on the last sample.
#[test]
fn sample_times_are_honoured_exactly() {
    for solver in [
        Solver::from_name("radau5").unwrap(),
        Solver::from_name("rodas4").unwrap(),
        Solver::from_name("rodas5p").unwrap(),
    ] {
        let mut sim = Simulation::new(&ProtheroRobinson, solver).unwrap();
        let times = [0.0, 0.0, 0.5, 0.5, 2.0];
        let mut traj = Trajectory::for_model::<ProtheroRobinson>(times.len());
        sim.run(0.0, &[0.0], &times, &mut traj).unwrap();
        assert_eq!(traj.times(), &times);
        assert_eq!(traj.value(0, "y"), Some(0.0));
        assert_eq!(sim.time(), 2.0);
        assert!((sim.state()[0] - 2f64.sin()).abs() < 1e-5);
    }
}
