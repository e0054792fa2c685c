//! The stiff solvers end every failing run with an error that says when and why; none
//! loops, hangs or panics.

mod stiff_common;

use std::time::Duration;

use bgdsl_runtime::{
    Model, NonFiniteKind, Radau5Options, Rodas4Options, Scalar, Simulation, Solver, SolverError,
};
use stiff_common::{Robertson, VanDerPol};

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

/// A block against dry friction, `v' = -1000 sign(v)`: at `v = 0` no implicit step
/// has a solution (the Newton iterates flip sign; sticking needs a force the relay
/// cannot give).
struct DryFriction;

impl Model for DryFriction {
    type Params = ();
    const NAME: &'static str = "dry_friction";
    const STATE_NAMES: &'static [&'static str] = &["block.v"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = -T::from_f64(1e3) * x[0].signum();
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// `tank.level' = sqrt(1 - t)`: NaN for t > 1.
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
        x0.fill(0.0);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = T::from_f64(1.0) - x[0] * T::from_f64(0.0);
        dx[1] = T::from_f64(1.0 - t).sqrt();
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// `drain.level' = -sqrt(drain.level)`, from 0: finite rate, infinite derivative of the
/// rate (Torricelli's law at an empty tank).
struct EmptyTank;

impl Model for EmptyTank {
    type Params = ();
    const NAME: &'static str = "empty_tank";
    const STATE_NAMES: &'static [&'static str] = &["drain.level"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 0.0;
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = -x[0].sqrt();
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// `x' = 1e300 (x + y)`, `y' = 1e300 (x + y)` at rest: the derivative is zero, but the
/// iteration matrix `σ I - J` rounds to a singular one for every step size the time
/// axis resolves (`σ` vanishes next to 1e300).
struct Degenerate;

impl Model for Degenerate {
    type Params = ();
    const NAME: &'static str = "degenerate";
    const STATE_NAMES: &'static [&'static str] = &["x", "y"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let s = T::from_f64(1e300) * (x[0] + x[1]);
        dx[0] = s;
        dx[1] = s;
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// Van der Pol in the scaled form of the Bari test set with `ε = 1e-12` (`μ = 1e6`):
/// `y1' = y2`, `y2' = ((1 - y1²) y2 - y1) / ε`.
struct VanDerPolMu1e6;

impl Model for VanDerPolMu1e6 {
    type Params = ();
    const NAME: &'static str = "vdp_mu_1e6";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[2.0, -0.66]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        dy[0] = y[1];
        dy[1] = ((T::from_f64(1.0) - y[0] * y[0]) * y[1] - y[0]) / T::from_f64(1e-12);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// `tank.level' = -k tank.level`, `valve.flow' = tank.level - valve.flow` with a
/// hand-written Jacobian whose entry ∂(valve.flow)'/∂(tank.level) is (wrongly) NaN.
struct BadHandJacobian;

impl Model for BadHandJacobian {
    type Params = ();
    const NAME: &'static str = "bad_hand_jacobian";
    const STATE_NAMES: &'static [&'static str] = &["tank.level", "valve.flow"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = -T::from_f64(2.0) * x[0];
        dx[1] = x[0] - x[1];
    }
    fn jacobian(&self, _t: f64, _x: &[f64], jac: &mut [f64]) -> bool {
        jac.copy_from_slice(&[-2.0, 0.0, f64::NAN, -1.0]);
        true
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

fn solvers() -> [Solver; 2] {
    [
        Solver::Radau5(Radau5Options::default()),
        Solver::Rodas4(Rodas4Options::default()),
    ]
}

/// Towards the singularity the Newton iteration (Radau5) or the error estimate (Rodas4)
/// fails at ever smaller steps until the step size underflows, within the tolerance of
/// t = 1 (the numerical solution's singularity lies a little off the exact one). The
/// error test's failure is blamed on a singularity, not on the tolerance (the weight of
/// `y`, about `1e-6 y`, is far above the rounding error) and never on an explicit
/// method.
#[test]
fn blow_up_ends_in_newton_divergence_or_step_underflow() {
    for solver in solvers() {
        let mut sim = Simulation::new(&BlowUp, solver).unwrap();
        let err = sim.run(0.0, &[1.0], &[2.0], &mut ()).unwrap_err();
        let t = match err {
            SolverError::NewtonDiverged { t, h, iterations } => {
                assert!(h < 1e-12 && iterations >= 1, "{err:?}");
                t
            }
            SolverError::StepUnderflow {
                t,
                state,
                too_tight,
                ..
            } => {
                assert_eq!((state, too_tight), ("y", false), "{err:?}");
                let text = err.to_string();
                assert!(
                    text.contains("The solution probably has a singularity there"),
                    "{text}"
                );
                t
            }
            other => panic!("{}: unexpected {other:?}", solver.name()),
        };
        assert!(!err.to_string().contains("explicit"), "{err}");
        assert!((t - 1.0).abs() < 1e-6, "{}: stopped at {t}", solver.name());
        assert!(sim.time() == t && sim.state()[0] > 1e4, "{}", solver.name());
    }
}

/// Radau5 on dry friction from rest at `t0 = 1e6` s, where the time axis resolves
/// steps down to 3.6e-9 s: the Newton iteration fails at every such step size (the
/// increments, about `1000 h`, stay far above the tolerance), and the run ends with the
/// Newton iteration named as the cause.
#[test]
fn newton_divergence_at_a_discontinuity_is_reported() {
    let t0 = 1e6;
    let mut sim = Simulation::new(&DryFriction, solvers()[0]).unwrap();
    let err = sim.run(t0, &[0.0], &[t0 + 1.0], &mut ()).unwrap_err();
    match err {
        SolverError::NewtonDiverged { t, h, iterations } => {
            assert_eq!(t, t0);
            assert!(h < 16.0 * f64::EPSILON * t0, "h = {h}");
            assert!(iterations >= 2);
        }
        other => panic!("expected NewtonDiverged, got {other:?}"),
    }
    assert_eq!(sim.stats().accepted, 0);
    let text = err.to_string();
    assert!(
        text.starts_with("at t = 1000000, the Newton iteration"),
        "{text}"
    );
}

/// A zero wall-time limit stops the run before its first step; a tiny one stops a long
/// run on the way.
#[test]
fn wall_time_limit_is_enforced() {
    for tiny in [Duration::ZERO, Duration::from_micros(50)] {
        let solvers = [
            Solver::Radau5(Radau5Options {
                max_wall_time: Some(tiny),
                rtol: 1e-10,
                ..Default::default()
            }),
            Solver::Rodas4(Rodas4Options {
                max_wall_time: Some(tiny),
                rtol: 1e-10,
                ..Default::default()
            }),
        ];
        for solver in solvers {
            let mut sim = Simulation::new(&VanDerPol, solver).unwrap();
            let err = sim.run(0.0, &[2.0, 0.0], &[2.0], &mut ()).unwrap_err();
            match err {
                SolverError::WallTimeExceeded { t, elapsed, limit } => {
                    assert_eq!(limit, tiny);
                    assert!(elapsed > limit);
                    assert!(t < 2.0);
                    assert_eq!(t, sim.time());
                    if tiny.is_zero() {
                        assert_eq!(t, 0.0);
                    }
                }
                other => panic!(
                    "{}: expected a wall-time error, got {other:?}",
                    solver.name()
                ),
            }
            let text = err.to_string();
            assert!(text.contains("more than its wall-time limit of"), "{text}");
        }
    }
}

/// A non-finite initial state, a derivative that becomes NaN ahead of the solution, and
/// a Jacobian that is infinite where the derivative is finite.
#[test]
fn non_finite_values_are_reported_with_the_state() {
    for solver in solvers() {
        let mut sim = Simulation::new(&Expiring, solver).unwrap();
        let err = sim.run(0.0, &[f64::NAN, 0.0], &[1.0], &mut ()).unwrap_err();
        assert!(
            matches!(
                err,
                SolverError::NonFiniteState {
                    t: 0.0,
                    state: "clock",
                    kind: NonFiniteKind::State,
                    ..
                }
            ),
            "{err:?}"
        );

        let err = sim.run(0.0, &[0.0, 0.0], &[2.0], &mut ()).unwrap_err();
        match err {
            SolverError::NonFiniteState {
                t,
                state,
                value,
                kind,
            } => {
                assert_eq!((state, kind), ("tank.level", NonFiniteKind::Derivative));
                assert!(value.is_nan());
                // The derivative is NaN only past t = 1, and the run got close to it.
                assert!(t > 1.0 && sim.time() > 0.99, "{}: {err:?}", solver.name());
            }
            other => panic!("{}: unexpected {other:?}", solver.name()),
        }

        let mut sim = Simulation::new(&EmptyTank, solver).unwrap();
        let err = sim.run(0.0, &[0.0], &[1.0], &mut ()).unwrap_err();
        assert_eq!(
            err,
            SolverError::NonFiniteJacobian {
                t: 0.0,
                state: "drain.level",
                wrt: "drain.level",
                value: f64::NEG_INFINITY,
            }
        );
        assert_eq!(
            err.to_string(),
            "at t = 0, the derivative of state `drain.level`'s rate with respect to state \
             `drain.level` evaluated to -inf: the model's equations are not differentiable \
             there (e.g. sqrt, cbrt or powf at 0)"
        );
    }
}

/// An iteration matrix singular at every step size: five tries, then an error.
#[test]
fn singular_iteration_matrix_is_reported() {
    for solver in solvers() {
        let mut sim = Simulation::new(&Degenerate, solver).unwrap();
        let err = sim.run(0.0, &[0.0, 0.0], &[1.0], &mut ()).unwrap_err();
        match err {
            SolverError::SingularMatrix { t, h } => {
                assert_eq!(t, 0.0);
                assert!(h > 0.0);
            }
            other => panic!("{}: unexpected {other:?}", solver.name()),
        }
        assert_eq!(sim.stats().rejected, 5, "{}", solver.name());
        assert_eq!(sim.stats().n_lu, 0, "{}", solver.name());
        assert!(err
            .to_string()
            .contains("was singular to working precision five times"));
    }
}

/// The step budget counts accepted and rejected steps.
#[test]
fn step_budget_is_enforced() {
    let solvers = [
        Solver::Radau5(Radau5Options {
            max_steps: 10,
            ..Default::default()
        }),
        Solver::Rodas4(Rodas4Options {
            max_steps: 10,
            ..Default::default()
        }),
    ];
    for solver in solvers {
        let mut sim = Simulation::new(&VanDerPol, solver).unwrap();
        let err = sim.run(0.0, &[2.0, 0.0], &[2.0], &mut ()).unwrap_err();
        assert!(
            matches!(
                err,
                SolverError::StepBudgetExhausted {
                    steps: 10,
                    t_end: 2.0,
                    ..
                }
            ),
            "{err:?}"
        );
        assert_eq!(sim.stats().steps(), 10);
    }
}

/// Options out of range are refused at set-up. (A zero `atol` is allowed since per-state
/// tolerances came: it is refused only with `rtol = 0`, where every weight would vanish.)
#[test]
fn invalid_options_are_refused() {
    let bad = [
        (
            Solver::Radau5(Radau5Options {
                rtol: 0.0,
                ..Default::default()
            }),
            "rtol",
        ),
        (
            Solver::Radau5(Radau5Options {
                atol: -1e-9,
                ..Default::default()
            }),
            "atol",
        ),
        (
            Solver::Rodas4(Rodas4Options {
                rtol: 0.0,
                atol: 0.0,
                ..Default::default()
            }),
            "atol",
        ),
        (
            Solver::Radau5(Radau5Options {
                max_newton_iterations: 0,
                ..Default::default()
            }),
            "max_newton_iterations",
        ),
        (
            Solver::Radau5(Radau5Options {
                hold_step_max: 0.5,
                ..Default::default()
            }),
            "hold_step_max",
        ),
        (
            Solver::Rodas4(Rodas4Options {
                safety: 1.5,
                ..Default::default()
            }),
            "safety",
        ),
        (
            Solver::Rodas4(Rodas4Options {
                max_steps: 0,
                ..Default::default()
            }),
            "max_steps",
        ),
    ];
    for (solver, name) in bad {
        match Simulation::new(&VanDerPol, solver) {
            Err(SolverError::InvalidOptions { option, .. }) => assert_eq!(option, name),
            other => panic!("{name}: expected InvalidOptions, got {other:?}"),
        }
    }
}

/// The case: with `atol = 1e-200` and states that start at zero (Robertson's
/// `y2`, `y3`), Radau5 rejected 1007 steps down to `h = 1.46e-309` and blamed a singular
/// iteration matrix. Since the Newton iteration may stop after one iteration only on a
/// contraction rate measured at the same step size, the run gets through: `atol` this
/// small asks for relative accuracy only, which the states that start at zero reach once
/// they are not zero. The end point is within the tolerance of the Bari reference
/// (`atol + rtol |ref|` with the `atol = 1e-14` that `y2 ≈ 8e-14` needs). When a
/// tolerance cannot be met, the step guard names the state instead
/// ([`a_zero_atol_on_a_state_at_zero_is_named`]).
#[test]
fn a_tolerance_of_1e_minus_200_reaches_the_reference() {
    let solver = Solver::Radau5(Radau5Options {
        atol: 1e-200,
        ..Default::default()
    });
    let mut sim = Simulation::new(&Robertson, solver).unwrap();
    sim.run(0.0, &[1.0, 0.0, 0.0], &[1e11], &mut ()).unwrap();
    let err = stiff_common::scaled_error(sim.state(), &stiff_common::ROBERTSON_REF, 1e-6, 1e-14);
    assert!(err <= 1.0, "scaled error {err:e}: {:?}", sim.state());
    assert!(sim.stats().rejected < 1007, "{:?}", sim.stats());
}

/// `atol = 0` is allowed (with `rtol > 0`): where no state is zero it asks for relative
/// accuracy only; Robertson's `y2 = 0` at the start cannot meet it in Radau5's Newton
/// iteration, which is held to the zero weight, and the error says so.
#[test]
fn a_zero_atol_on_a_state_at_zero_is_named() {
    {
        let solver = Solver::Radau5(Radau5Options {
            atol: 0.0,
            ..Default::default()
        });
        let mut sim = Simulation::new(&Robertson, solver).unwrap();
        let err = sim.run(0.0, &[1.0, 0.0, 0.0], &[1.0], &mut ()).unwrap_err();
        assert!(
            matches!(
                err,
                SolverError::StepUnderflow {
                    t: 0.0,
                    state: "y2",
                    weight: 0.0,
                    too_tight: true,
                    ..
                }
            ),
            "{}: {err:?}",
            solver.name()
        );
        assert!(err.to_string().contains("held to an absolute error of 0"));
    }
}

/// Rodas4 on Van der Pol with μ = 1e6 at rtol 1e-10 (the issue: "too stiff for an
/// explicit method", from an implicit method): its accepted steps shrink through the
/// fast jump to the resolution of the time axis; the error says the step underflowed
/// and points at the tolerance, and never mentions an explicit method.
#[test]
fn rodas4_step_underflow_never_blames_an_explicit_method() {
    let solver = Solver::Rodas4(Rodas4Options {
        rtol: 1e-10,
        atol: 1e-10,
        ..Default::default()
    });
    let mut sim = Simulation::new(&VanDerPolMu1e6, solver).unwrap();
    let err = sim.run(0.0, &[2.0, -0.66], &[2.0], &mut ()).unwrap_err();
    let SolverError::StepUnderflow { t, h, .. } = err else {
        panic!("expected StepUnderflow, got {err:?}");
    };
    // The time axis's resolution at t, where the jump (time scale ~ε) happens.
    assert!(t > 0.5 && t < 2.0 && h < 16.0 * f64::EPSILON * t, "{err:?}");
    let text = err.to_string();
    assert!(
        text.contains("the step size underflowed") && !text.contains("explicit"),
        "{text}"
    );
}

/// A NaN from the hand-written Jacobian is reported as such, naming the entry; it used
/// to say "the model's equations are not differentiable".
#[test]
fn a_nan_in_a_hand_written_jacobian_is_reported_as_such() {
    for solver in solvers() {
        let mut sim = Simulation::new(&BadHandJacobian, solver).unwrap();
        let err = sim.run(0.0, &[1.0, 0.0], &[1.0], &mut ()).unwrap_err();
        assert!(
            matches!(
                err,
                SolverError::NonFiniteHandWrittenJacobian {
                    t: 0.0,
                    state: "valve.flow",
                    wrt: "tank.level",
                    value,
                } if value.is_nan()
            ),
            "{err:?}"
        );
        assert_eq!(
            err.to_string(),
            "at t = 0, the model's hand-written Jacobian (Model::jacobian) has a non-finite \
             entry ∂ẋ_i/∂x_j = NaN for i = `valve.flow`, j = `tank.level`, while the \
             derivatives are finite there: check that entry of Model::jacobian"
        );
    }
}
