//! Sample times: hit exactly, recorded with outputs, validated.

use std::cell::RefCell;

use bgdsl_runtime::{
    sample_times_uniform, simulate, FixedStep, Model, SampleTimeProblem, Scalar, Simulation,
    Solver, SolverError, Trajectory,
};

/// `y' = -y + sin t`, `y(0) = 1`; output `2 y`.
/// `y(t) = (sin t - cos t) / 2 + 3/2 e^-t`.
struct Forced;

impl Model for Forced {
    type Params = ();
    const NAME: &'static str = "forced";
    const STATE_NAMES: &'static [&'static str] = &["y"];
    const OUTPUT_NAMES: &'static [&'static str] = &["twice_y"];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = -x[0] + T::from_f64(t.sin());
    }
    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        y[0] = T::from_f64(2.0) * x[0];
    }
}

fn exact(t: f64) -> f64 {
    0.5 * (t.sin() - t.cos()) + 1.5 * (-t).exp()
}

/// Irregular sample times: on the grid, off it, repeated, at the start.
const SAMPLES: [f64; 9] = [0.0, 0.0, 0.05, 0.1, 0.25, 0.3, 0.3, 1.0 / 3.0, 1.0];

fn all_solvers() -> [Solver; 3] {
    [
        Solver::rk4(0.1),
        Solver::DormandPrinceFixed(FixedStep::new(0.1)),
        Solver::dopri5(),
    ]
}

#[test]
fn every_solver_records_exactly_the_requested_times() {
    for solver in all_solvers() {
        let mut sim = Simulation::new(&Forced, solver).unwrap();
        let mut traj = Trajectory::for_model::<Forced>(SAMPLES.len());
        sim.run(0.0, &[1.0], &SAMPLES, &mut traj).unwrap();
        // Bitwise equal, not merely close.
        assert_eq!(traj.times(), &SAMPLES[..], "{}", solver.name());
        assert_eq!(sim.time(), 1.0);
        for (row, t) in SAMPLES.iter().enumerate() {
            let y = traj.value(row, "y").unwrap();
            assert!((y - exact(*t)).abs() < 1e-6, "{} at t = {t}", solver.name());
            assert_eq!(traj.value(row, "twice_y"), Some(2.0 * y));
        }
        // Samples at t0 record the initial state itself.
        assert_eq!(traj.value(0, "y"), Some(1.0));
        assert_eq!(traj.value(1, "y"), Some(1.0));
    }
}

/// Fixed steps lie on the grid `t0 + k h`; a sample time between grid points splits the
/// step it falls in (no interpolation), a sample on the grid costs nothing. Grid 0.1 to
/// 1.0 is 10 steps; 0.05, 0.25 and 1/3 split one each, and 0.3 (which `3 * 0.1` misses
/// by one ulp) counts as a grid point: 13 steps.
#[test]
fn fixed_steps_are_shortened_to_land_on_sample_times() {
    let mut sim = Simulation::new(&Forced, Solver::rk4(0.1)).unwrap();
    let stats = sim.run(0.0, &[1.0], &SAMPLES, &mut ()).unwrap();
    assert_eq!((stats.accepted, stats.rejected, stats.n_rhs), (13, 0, 52));
}

/// `y' = 1`, logging the time of every derivative evaluation.
struct Logged(RefCell<Vec<f64>>);

impl Model for Logged {
    type Params = ();
    const NAME: &'static str = "logged";
    const STATE_NAMES: &'static [&'static str] = &["y"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 0.0;
    }
    fn derivatives<T: Scalar>(&self, t: f64, _x: &[T], dx: &mut [T]) {
        self.0.borrow_mut().push(t);
        dx[0] = T::from_f64(1.0);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// Landing on a sample time does not move the grid: after the split step
/// 0 -> 0.05 -> 0.1 the steps start again at grid points.
#[test]
fn fixed_step_grid_is_anchored_at_the_start_time() {
    let model = Logged(RefCell::new(Vec::new()));
    let mut sim = Simulation::new(&model, Solver::rk4(0.1)).unwrap();
    sim.run(0.0, &[0.0], &[0.05, 0.3], &mut ()).unwrap();
    // RK4 evaluates at t, t + h/2 (twice) and t + h: every fourth call starts a step.
    let starts: Vec<f64> = model.0.borrow().iter().step_by(4).copied().collect();
    let expected = [0.0, 0.05, 0.1, 0.2];
    assert_eq!(starts.len(), expected.len(), "{starts:?}");
    for (s, e) in starts.iter().zip(expected) {
        assert!((s - e).abs() < 1e-15, "{starts:?}");
    }
    // y' = 1 is integrated exactly.
    assert_eq!(sim.state(), &[0.3]);
}

#[test]
fn uniform_runs_match_explicit_sample_lists() {
    let times = sample_times_uniform(0.5, 3.0, 26);
    assert_eq!(times.len(), 26);
    assert_eq!((times[0], times[25]), (0.5, 3.0));
    assert!((times[1] - 0.6).abs() < 1e-15);
    assert!(sample_times_uniform(0.0, 1.0, 0).is_empty());
    assert_eq!(sample_times_uniform(2.0, 3.0, 1), vec![2.0]);
    for solver in all_solvers() {
        let mut sim = Simulation::new(&Forced, solver).unwrap();
        let mut listed = Trajectory::for_model::<Forced>(26);
        let s1 = sim.run(0.5, &[exact(0.5)], &times, &mut listed).unwrap();
        let mut uniform = Trajectory::for_model::<Forced>(26);
        let s2 = sim
            .run_uniform(0.5, &[exact(0.5)], 3.0, 26, &mut uniform)
            .unwrap();
        assert_eq!(listed, uniform);
        assert_eq!(s1, s2);
    }
    let traj = simulate(&Forced, Solver::dopri5(), 0.0, 2.0, 21).unwrap();
    assert_eq!(traj.len(), 21);
    assert!((traj.value(20, "y").unwrap() - exact(2.0)).abs() < 1e-6);
}

/// A run asked for no sample is an error (it used to be an empty success), and does
/// no work.
#[test]
fn no_sample_times_is_an_error_and_no_work() {
    for solver in all_solvers() {
        let mut sim = Simulation::new(&Forced, solver).unwrap();
        let err = sim.run(0.0, &[1.0], &[], &mut ()).unwrap_err();
        assert_eq!(err, bgdsl_runtime::SolverError::NoSampleTimes);
        assert_eq!(sim.stats().steps(), 0);
    }
}

#[test]
fn closures_are_recorders() {
    let mut seen = Vec::new();
    let mut sim = Simulation::new(&Forced, Solver::dopri5()).unwrap();
    sim.run(
        0.0,
        &[1.0],
        &[0.5, 1.0],
        &mut |t: f64, x: &[f64], y: &[f64]| seen.push((t, x[0], y[0])),
    )
    .unwrap();
    assert_eq!(seen.len(), 2);
    assert_eq!(seen[1].0, 1.0);
    assert_eq!(seen[1].2, 2.0 * seen[1].1);
}

#[test]
fn invalid_sample_times_are_reported_with_their_position() {
    let mut sim = Simulation::new(&Forced, Solver::dopri5()).unwrap();
    let cases: [(&[f64], usize, SampleTimeProblem); 3] = [
        (
            &[0.5, 0.2],
            1,
            SampleTimeProblem::Decreasing { previous: 0.5 },
        ),
        (&[0.1, -1.0], 1, SampleTimeProblem::BeforeStart { t0: 0.0 }),
        (&[0.1, 0.2, f64::NAN], 2, SampleTimeProblem::NotFinite),
    ];
    for (times, index, problem) in cases {
        match sim.run(0.0, &[1.0], times, &mut ()) {
            Err(SolverError::InvalidSampleTimes {
                index: i,
                problem: p,
                ..
            }) => assert_eq!((i, p), (index, problem)),
            other => panic!("{times:?}: {other:?}"),
        }
    }
    let err = sim.run(0.0, &[1.0], &[0.5, 0.2], &mut ()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "sample time #1 (0.2) is smaller than the sample time before it (0.5); sample \
         times must be in increasing order"
    );
    assert_eq!(
        sim.run(f64::INFINITY, &[1.0], &[], &mut ()),
        Err(SolverError::NonFiniteStartTime { t0: f64::INFINITY })
    );
}
