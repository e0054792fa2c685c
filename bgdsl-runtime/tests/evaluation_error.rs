//! A model whose evaluation fails and says why (`Model::evaluation_error`): every
//! solver ends the run with that error (`SolverError::InvalidModel`), not with a
//! non-finite derivative or a step-size underflow, and so do the stepper and the
//! allocation-free integrators of `rk`.

#[path = "support/loop_model.rs"]
mod loop_model;

use bgdsl_runtime::rk;
use bgdsl_runtime::{
    DormandPrinceOptions, FixedStep, Model, ModelError, Simulation, Solver, SolverError, Stepper,
    Trajectory,
};
use loop_model::{DiodeLoop, Fails, MEMBERS};

const T_FAIL: f64 = 0.005;
const T_END: f64 = 0.01;

fn solvers() -> [Solver; 5] {
    [
        Solver::rk4(1e-4),
        Solver::dopri5(),
        Solver::DormandPrinceFixed(FixedStep::new(1e-4)),
        Solver::from_name("radau5").unwrap(),
        Solver::from_name("rodas4").unwrap(),
    ]
}

fn run(model: &DiodeLoop, solver: Solver) -> Result<Trajectory, SolverError> {
    let mut sim = Simulation::new(model, solver)?;
    let mut trajectory = Trajectory::for_model::<DiodeLoop>(11);
    sim.run_uniform(0.0, &[0.0], T_END, 11, &mut trajectory)?;
    Ok(trajectory)
}

/// The loop's error, at a time at most `slack` after it started failing.
fn assert_unsolved_loop(error: &SolverError, slack: f64, context: &str) {
    match error {
        SolverError::InvalidModel(ModelError::UnsolvedLoop {
            members,
            t,
            residual,
        }) => {
            assert_eq!(*members, MEMBERS, "{context}");
            assert!(*t > T_FAIL && *t <= T_FAIL + slack, "{context}: t = {t}");
            assert!(residual.is_nan(), "{context}: residual {residual}");
            let text = error.to_string();
            assert!(
                text.contains("the algebraic loop through source, r, d, c")
                    && text.contains(&format!("t = {t} s")),
                "{context}: {text}"
            );
        }
        other => panic!("{context}: expected the model's error, got {other:?}: {other}"),
    }
}

#[test]
fn the_model_runs_where_it_can_evaluate() {
    // The control: without a failure the loop is solved at every evaluation.
    let model = DiodeLoop::new(f64::INFINITY, Fails::After);
    for solver in solvers() {
        let trajectory = run(&model, solver).unwrap_or_else(|e| panic!("{}: {e}", solver.name()));
        // The capacitor charges towards the source less the diode's drop.
        let q_end = trajectory.column("c.q").unwrap()[10];
        assert!(
            q_end > 4.0e-6 && q_end < 5.0e-6,
            "{}: {q_end}",
            solver.name()
        );
    }
}

#[test]
fn every_solver_ends_with_the_models_error() {
    let model = DiodeLoop::new(T_FAIL, Fails::After);
    for solver in solvers() {
        let error = run(&model, solver).unwrap_err();
        // A fixed step meets the failure within one step; an adaptive one shrinks
        // its step on the edge.
        assert_unsolved_loop(&error, 1e-4, solver.name());
    }
}

/// Without `evaluation_error` (the default, as before it existed) the same runs end
/// in a generic non-finite or step-size error: what the tests above would get without
/// the solvers asking the model.
#[test]
fn a_model_that_does_not_explain_gets_the_generic_errors() {
    let mut model = DiodeLoop::new(T_FAIL, Fails::After);
    model.explains = false;
    for solver in solvers() {
        let error = run(&model, solver).unwrap_err();
        assert!(
            matches!(
                error,
                SolverError::NonFiniteState { .. }
                    | SolverError::StepSizeTooSmall { .. }
                    | SolverError::ProbablyStiff { .. }
            ),
            "{}: {error:?}",
            solver.name()
        );
    }
}

#[test]
fn the_stepper_and_the_allocation_free_integrators_end_with_it_too() {
    let mut stepper = Stepper::new(DiodeLoop::new(T_FAIL, Fails::After), Solver::dopri5()).unwrap();
    stepper.advance_to(0.004).unwrap();
    let error = stepper.advance_to(T_END).unwrap_err();
    assert_unsolved_loop(&error, 1e-4, "stepper");
    assert_eq!(stepper.time(), 0.004, "the stepper stays where it was");

    let model = DiodeLoop::new(T_FAIL, Fails::After);
    let (mut t, mut x) = (0.0, [0.0]);
    let mut fixed = rk::Rk4::<1>::new(FixedStep::new(1e-4)).unwrap();
    let error = fixed.advance_to(&model, &mut t, &mut x, T_END).unwrap_err();
    assert_unsolved_loop(&error, 1e-4, "rk::Rk4");

    let (mut t, mut x) = (0.0, [0.0]);
    let mut adaptive = rk::DormandPrince::<1>::new(DormandPrinceOptions::default()).unwrap();
    let error = adaptive
        .advance_to(&model, &mut t, &mut x, T_END)
        .unwrap_err();
    assert_unsolved_loop(&error, 1e-4, "rk::DormandPrince");
}

/// A failure only in the dual evaluations (the stiff solvers' Jacobian) is the model's
/// error too, not a non-finite Jacobian entry.
#[test]
fn a_failed_jacobian_evaluation_is_the_models_error() {
    let model = DiodeLoop::new(T_FAIL, Fails::OnDuals);
    for name in ["radau5", "rodas4"] {
        let error = run(&model, Solver::from_name(name).unwrap()).unwrap_err();
        assert_eq!(
            error,
            SolverError::InvalidModel(ModelError::SingularConstraint {
                members: MEMBERS,
                t: 0.0
            }),
            "{name}"
        );
    }
    let mut silent = DiodeLoop::new(T_FAIL, Fails::OnDuals);
    silent.explains = false;
    let error = run(&silent, Solver::stiff()).unwrap_err();
    assert!(
        matches!(error, SolverError::NonFiniteJacobian { .. }),
        "{error:?}"
    );
}

/// Outputs that cannot be evaluated end the run at that sample (and are not recorded),
/// and the stepper refuses a state where they cannot be.
#[test]
fn failed_outputs_end_the_run_at_their_sample() {
    let model = DiodeLoop::new(T_FAIL, Fails::OutputsAfter);
    let mut sim = Simulation::new(&model, Solver::dopri5()).unwrap();
    let mut trajectory = Trajectory::for_model::<DiodeLoop>(11);
    let error = sim
        .run_uniform(0.0, &[0.0], T_END, 11, &mut trajectory)
        .unwrap_err();
    // Samples every 1 ms: the first past 5 ms is at 6 ms.
    assert_unsolved_loop(&error, 0.0011, "outputs");
    assert_eq!(trajectory.len(), 6, "samples 0..=5 ms recorded, no NaN row");

    let mut stepper = Stepper::new(
        DiodeLoop::new(T_FAIL, Fails::OutputsAfter),
        Solver::dopri5(),
    )
    .unwrap();
    let error = stepper.set_state(0.007, &[1e-6]).unwrap_err();
    assert_unsolved_loop(&error, 0.0021, "set_state");
    assert_eq!((stepper.time(), stepper.state()), (0.0, &[0.0][..]));
    assert!(stepper.outputs()[0].is_finite(), "{:?}", stepper.outputs());
    stepper.set_state(0.001, &[1e-6]).unwrap();
    assert!(
        stepper.model().evaluation_error().is_none(),
        "cleared by a success"
    );
}
