//! Failures end the run with an error that says when and why; none loops or panics.

use bgdsl_runtime::{
    DormandPrinceOptions, FixedStep, Model, NonFiniteKind, Scalar, Simulation, Solver, SolverError,
    Trajectory,
};

/// Two states; the second, `tank.level`, has derivative `sqrt(1 - t)`, which is NaN for
/// t > 1.
struct Expiring;

impl Model for Expiring {
    type Params = ();
    const NAME: &'static str = "expiring";
    const STATE_NAMES: &'static [&'static str] = &["clock", "tank.level"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[0.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, t: f64, _x: &[T], dx: &mut [T]) {
        dx[0] = T::from_f64(1.0);
        dx[1] = T::from_f64(1.0 - t).sqrt();
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// `y' = y^2`, `y(0) = 1`: `y = 1 / (1 - t)` blows up at t = 1.
struct BlowUp;

impl Model for BlowUp {
    type Params = ();
    const NAME: &'static str = "blow_up";
    const STATE_NAMES: &'static [&'static str] = &["y"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[0] * x[0];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// A harmonic oscillator, for long runs.
struct Oscillator;

impl Model for Oscillator {
    type Params = ();
    const NAME: &'static str = "oscillator";
    const STATE_NAMES: &'static [&'static str] = &["q", "p"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[1];
        dx[1] = -x[0];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

#[test]
fn nan_derivative_stops_rk4_at_once_naming_the_state() {
    let mut sim = Simulation::new(&Expiring, Solver::rk4(0.1)).unwrap();
    let mut traj = Trajectory::for_model::<Expiring>(21);
    let err = sim
        .run_uniform(0.0, &[0.0, 0.0], 2.0, 21, &mut traj)
        .unwrap_err();
    // The step from t = 1.0 evaluates its second stage at 1.05.
    match err {
        SolverError::NonFiniteState {
            t,
            state,
            value,
            kind,
        } => {
            assert!((t - 1.05).abs() < 1e-12, "{t}");
            assert_eq!(state, "tank.level");
            assert!(value.is_nan());
            assert_eq!(kind, NonFiniteKind::Derivative);
        }
        other => panic!("{other:?}"),
    }
    assert!(err
        .to_string()
        .starts_with("at t = 1.05, the derivative of state `tank.level` evaluated to NaN"));
    // The samples before the failure were recorded; the run stopped at t = 1.
    assert_eq!(traj.len(), 11);
    assert_eq!(sim.time(), 1.0);
}

#[test]
fn nan_derivative_is_located_by_the_adaptive_method() {
    let mut sim = Simulation::new(&Expiring, Solver::dopri5()).unwrap();
    let err = sim.run(0.0, &[0.0, 0.0], &[2.0], &mut ()).unwrap_err();
    // Shorter and shorter steps probe the edge of the domain until the step size
    // reaches the resolution of t: the failure is pinned to t = 1.
    match err {
        SolverError::NonFiniteState { t, state, kind, .. } => {
            assert!(t > 1.0 && t - 1.0 < 1e-12, "{t}");
            assert_eq!(state, "tank.level");
            assert_eq!(kind, NonFiniteKind::Derivative);
        }
        other => panic!("{other:?}"),
    }
    assert!(
        sim.time() <= 1.0 && sim.time() > 1.0 - 1e-12,
        "{}",
        sim.time()
    );
    assert!(sim.stats().steps() < 1000, "{:?}", sim.stats());
}

#[test]
fn non_finite_initial_state_is_reported() {
    let mut sim = Simulation::new(&Oscillator, Solver::dopri5()).unwrap();
    let err = sim
        .run(0.0, &[1.0, f64::INFINITY], &[1.0], &mut ())
        .unwrap_err();
    assert_eq!(
        err,
        SolverError::NonFiniteState {
            t: 0.0,
            state: "p",
            value: f64::INFINITY,
            kind: NonFiniteKind::State,
        }
    );
}

#[test]
fn blow_up_is_an_error_for_the_adaptive_method() {
    let mut sim = Simulation::new(&BlowUp, Solver::dopri5()).unwrap();
    let err = sim.run(0.0, &[1.0], &[2.0], &mut ()).unwrap_err();
    match err {
        SolverError::StepSizeTooSmall { t, h } => {
            // The numerical singularity lies within the tolerance of the true one
            // (observed: t = 1 + 2.4e-7, after 210 accepted and 205 rejected steps).
            assert!((t - 1.0).abs() < 1e-5, "{t}");
            assert!(h < 1e-10, "{h}");
        }
        other => panic!("{other:?}"),
    }
    let message = err.to_string();
    assert!(message.starts_with("at t = 1.0000002"), "{err}");
    assert!(
        message.contains(", dopri5's step size fell to 3.3"),
        "{err}"
    );
    assert!(
        message.ends_with(
            "e-15, below the resolution of the time axis (16 * eps * |t|): the solution may \
             have a singularity there (it escapes to infinity or jumps), or the model is too \
             stiff for this explicit method (use a stiff solver: Solver::stiff(), radau5)"
        ),
        "{err}"
    );
    assert!(sim.stats().steps() < 10_000, "{:?}", sim.stats());
}

#[test]
fn blow_up_is_an_error_for_rk4() {
    let mut sim = Simulation::new(&BlowUp, Solver::rk4(0.01)).unwrap();
    let err = sim.run(0.0, &[1.0], &[2.0], &mut ()).unwrap_err();
    match err {
        SolverError::NonFiniteState { t, state, .. } => {
            assert!(t > 1.0 && t < 2.0, "{t}");
            assert_eq!(state, "y");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn step_budget_is_enforced() {
    let dp = Solver::DormandPrince(DormandPrinceOptions {
        max_steps: 10,
        ..Default::default()
    });
    let rk4 = Solver::Rk4(FixedStep {
        step: 0.1,
        max_steps: 10,
    });
    for solver in [dp, rk4] {
        let mut sim = Simulation::new(&Oscillator, solver).unwrap();
        let err = sim.run(0.0, &[1.0, 0.0], &[1000.0], &mut ()).unwrap_err();
        match err {
            SolverError::StepBudgetExhausted { t, t_end, steps } => {
                assert_eq!(steps, 10);
                assert_eq!(t_end, 1000.0);
                assert_eq!(t, sim.time());
                assert!(t > 0.0 && t < 1000.0);
            }
            other => panic!("{}: {other:?}", solver.name()),
        }
        assert_eq!(sim.stats().steps(), 10);
    }
    let mut sim = Simulation::new(&Oscillator, rk4).unwrap();
    let err = sim.run(0.0, &[1.0, 0.0], &[1000.0], &mut ()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "the budget of 10 steps was used up at t = 1, before the last sample time 1000: \
         raise `max_steps`, loosen the tolerances, or use a larger step"
    );
}

#[test]
fn fixed_step_below_the_time_resolution_is_refused() {
    let mut sim = Simulation::new(&Oscillator, Solver::rk4(1e-12)).unwrap();
    let err = sim
        .run(1e4, &[1.0, 0.0], &[1e4 + 1.0], &mut ())
        .unwrap_err();
    assert_eq!(
        err,
        SolverError::FixedStepTooSmall {
            t: 1e4,
            step: 1e-12
        }
    );
    assert_eq!(
        err.to_string(),
        "the fixed step 1e-12 is below the resolution of the time axis at t = 10000 \
         (16 * eps * |t|): the steps would not advance the time; use a larger step"
    );
}

#[test]
fn set_up_errors() {
    let bad = Solver::DormandPrince(DormandPrinceOptions {
        atol: f64::NAN,
        ..Default::default()
    });
    let err = Simulation::new(&Oscillator, bad).unwrap_err();
    assert_eq!(
        err.to_string(),
        "invalid solver option `atol` = NaN: expected a finite number >= 0"
    );
    let mut sim = Simulation::new(&Oscillator, Solver::dopri5()).unwrap();
    let err = sim.run(0.0, &[1.0], &[1.0], &mut ()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "the initial state has 1 values but model `oscillator` has 2 states"
    );
}

/// `y' = 1` from `y = 0` with a purely relative tolerance: the error scale is zero at
/// the start, which must not produce a NaN or zero step size.
#[test]
fn pure_relative_tolerance_from_a_zero_state_works() {
    struct Ramp;
    impl Model for Ramp {
        type Params = ();
        const NAME: &'static str = "ramp";
        const STATE_NAMES: &'static [&'static str] = &["y"];
        const OUTPUT_NAMES: &'static [&'static str] = &[];
        fn params(&self) -> &() {
            &()
        }
        fn initial_state(&self, x0: &mut [f64]) {
            x0[0] = 0.0;
        }
        fn derivatives<T: Scalar>(&self, _t: f64, _x: &[T], dx: &mut [T]) {
            dx[0] = T::from_f64(1.0);
        }
        fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    }
    let solver = Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-6,
        atol: 0.0,
        ..Default::default()
    });
    let mut sim = Simulation::new(&Ramp, solver).unwrap();
    let stats = sim.run(0.0, &[0.0], &[3.0], &mut ()).unwrap();
    assert!((sim.state()[0] - 3.0).abs() < 1e-12);
    assert!(stats.steps() < 20, "{stats:?}");
}

/// Keeps the samples it is given and asks to stop once it holds `stop_after`.
struct StopAfter {
    times: Vec<f64>,
    stop_after: usize,
}

impl bgdsl_runtime::Recorder for StopAfter {
    fn record(&mut self, t: f64, _x: &[f64], _y: &[f64]) {
        self.times.push(t);
    }
    fn stop_requested(&self) -> bool {
        self.times.len() >= self.stop_after
    }
}

#[test]
fn a_recorder_can_stop_every_kind_of_run_keeping_what_it_recorded() {
    for solver in [
        Solver::Rk4(FixedStep {
            step: 1e-3,
            ..Default::default()
        }),
        Solver::DormandPrince(DormandPrinceOptions::default()),
        Solver::stiff(),
        Solver::from_name("rodas4").expect("a known solver"),
    ] {
        let name = solver.name();
        let mut sim = Simulation::new(&Oscillator, solver).expect("valid options");
        let mut recorder = StopAfter {
            times: Vec::new(),
            stop_after: 4,
        };
        let result = sim.run_uniform(0.0, &[1.0, 0.0], 1.0, 11, &mut recorder);
        assert_eq!(
            result.err(),
            Some(SolverError::Stopped { t: 0.3 }),
            "{name}"
        );
        assert_eq!(recorder.times, [0.0, 0.1, 0.2, 0.3], "{name}");
    }
}

/// A run asked for no sample used to return Ok with an empty trajectory.
#[test]
fn a_run_without_sample_times_is_an_error_for_every_solver() {
    for name in ["rk4", "dopri5", "dopri5-fixed", "radau5", "rodas4"] {
        let solver = Solver::from_name(name).expect("a known solver");
        assert_eq!(
            bgdsl_runtime::simulate(&Oscillator, solver, 0.0, 1.0, 0).err(),
            Some(SolverError::NoSampleTimes),
            "{name}"
        );
        let mut sim = Simulation::new(&Oscillator, solver).expect("valid options");
        let mut traj = Trajectory::for_model::<Oscillator>(2);
        assert_eq!(
            sim.run(0.0, &[1.0, 0.0], &[], &mut traj).err(),
            Some(SolverError::NoSampleTimes),
            "{name}"
        );
        assert_eq!(traj.len(), 0, "{name}");
        assert_eq!(sim.stats().steps(), 0, "{name}: no step was taken");
    }
    assert!(SolverError::NoSampleTimes
        .to_string()
        .starts_with("no sample times"));
}

#[test]
fn samples_out_of_order_are_refused_before_any_step() {
    let mut sim = Simulation::new(&Oscillator, Solver::dopri5()).expect("valid options");
    let mut traj = Trajectory::for_model::<Oscillator>(3);
    let err = sim
        .run(0.0, &[1.0, 0.0], &[0.0, 0.5, 0.2], &mut traj)
        .unwrap_err();
    assert_eq!(
        err,
        SolverError::InvalidSampleTimes {
            index: 2,
            t: 0.2,
            problem: bgdsl_runtime::SampleTimeProblem::Decreasing { previous: 0.5 },
        }
    );
    assert_eq!(traj.len(), 0);
    assert_eq!(sim.stats().steps(), 0);
}

/// `x' = −1000 (x − cos t)`: a stiff decay (eigenvalue −1000) onto a slow curve.
struct StiffDecay;

impl Model for StiffDecay {
    type Params = ();
    const NAME: &'static str = "stiff_decay";
    const STATE_NAMES: &'static [&'static str] = &["x", "y"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[0.0, 1.0]);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = T::from_f64(-1000.0) * (x[0] - T::from_f64(t.cos()));
        dx[1] = T::from_f64(-0.5) * x[1];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// An explicit method that blew up on a stiff model said only "evaluated to -inf":
/// now it says the model is probably stiff, how stiff, what step would be stable and
/// which solvers suit it.
#[test]
fn a_fixed_step_blow_up_on_a_stiff_model_says_so() {
    for (solver, bound) in [
        (Solver::rk4(0.01), 2.785),
        (
            Solver::DormandPrinceFixed(FixedStep {
                step: 0.01,
                ..Default::default()
            }),
            3.307,
        ),
    ] {
        let name = solver.name();
        let err = bgdsl_runtime::simulate(&StiffDecay, solver, 0.0, 10.0, 11).unwrap_err();
        let SolverError::ProbablyStiff {
            cause,
            method,
            spectral_radius,
            stable_step,
            ..
        } = &err
        else {
            panic!("{name}: {err}");
        };
        assert!(
            matches!(
                **cause,
                SolverError::NonFiniteState { .. } | SolverError::StepSizeTooSmall { .. }
            ),
            "{name}: {cause}"
        );
        assert_eq!(*method, name);
        assert!((spectral_radius - 1000.0).abs() < 1e-3, "{spectral_radius}");
        assert!((stable_step - bound / 1000.0).abs() < 1e-9, "{stable_step}");
        let text = err.to_string();
        assert!(
            text.contains("The model is probably stiff") && text.contains("radau5 or rodas4"),
            "{text}"
        );
    }
    // The same step on a model that is not stiff, failing for another reason, keeps
    // its own error.
    let err = bgdsl_runtime::simulate(&Expiring, Solver::rk4(0.1), 0.0, 2.0, 21).unwrap_err();
    assert!(matches!(err, SolverError::NonFiniteState { .. }), "{err}");
}

#[test]
fn the_spectral_radius_estimate_finds_the_largest_eigenvalue() {
    use bgdsl_runtime::solver::stiffness::spectral_radius;
    let rho = spectral_radius(&StiffDecay, 0.0, &[0.3, 1.0]).unwrap();
    assert!((rho - 1000.0).abs() < 1e-3, "{rho}");
    // The harmonic oscillator's eigenvalues are ±i.
    let rho = spectral_radius(&Oscillator, 0.0, &[1.0, 0.0]).unwrap();
    assert!((rho - 1.0).abs() < 1e-6, "{rho}");
    assert_eq!(spectral_radius(&Expiring, 0.0, &[0.0, 0.0]), Some(0.0));
}
