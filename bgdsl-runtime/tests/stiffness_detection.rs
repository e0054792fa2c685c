//! Dormand–Prince detects stiffness (Hairer's test, *Solving ODEs I*, Sect. II.10, as in
//! DOPRI5): on stiff problems that would use up its budget of 1,000,000 steps it stops
//! after about 1,000 and says to use a stiff solver; a stiff run that can finish within
//! its budget goes on; on non-stiff problems it never fires.

mod stiff_common;

use bgdsl_runtime::rk::DormandPrince;
use bgdsl_runtime::{DormandPrinceOptions, Model, Simulation, Solver, SolverError, Stats};
use stiff_common::{Hires, Oregonator, Robertson, VanDerPol, HIRES_T_END};

fn initial<M: Model>(model: &M) -> Vec<f64> {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    x0
}

fn dopri5(model: &impl Model, t_end: f64) -> (Result<Stats, SolverError>, Stats) {
    fn run<M: Model>(model: &M, t_end: f64) -> (Result<Stats, SolverError>, Stats) {
        let mut sim = Simulation::new(model, Solver::dopri5()).unwrap();
        let result = sim.run(0.0, &initial(model), &[t_end], &mut ());
        (result, sim.stats())
    }
    run(model, t_end)
}

/// The stiffness test may fail a run once 1,000 steps are accepted (the default
/// `stiffness_after`), after 15 stiff steps in a row, when at the stiff step size the
/// run would not finish within its budget: Robertson to 1e11 and Van der Pol (μ = 1000)
/// stop there, within 1,100 attempted steps; the Oregonator, whose stiff phase comes
/// later, within 3,000 (at t ≈ 23 of 360). HIRES (about 20,000 stability-limited steps
/// to its end) finishes, with its stiff steps counted.
#[test]
fn stiff_problems_stop_early_with_advice() {
    let runs = [
        ("ROBER", dopri5(&Robertson, 1e11), 1100),
        ("VDPOL", dopri5(&VanDerPol, 2.0), 1100),
        ("OREGO", dopri5(&Oregonator, 360.0), 3000),
    ];
    for (name, (result, stats), most) in runs {
        let err = result.expect_err(name);
        let SolverError::StiffnessDetected {
            steps,
            h_lambda,
            needed,
            left,
            ..
        } = err
        else {
            panic!("{name}: expected StiffnessDetected, got {err:?}");
        };
        assert!(steps >= 15 && h_lambda > 3.25, "{name}: {err:?}");
        assert!(needed > left as f64 && left > 990_000, "{name}: {err:?}");
        assert!(
            stats.accepted >= 1000 && stats.steps() < most,
            "{name}: {stats:?}"
        );
        assert!(stats.n_stiff_steps >= 15, "{name}: {stats:?}");
        let text = err.to_string();
        assert!(
            text.contains("use a stiff solver (Solver::stiff(), radau5)"),
            "{text}"
        );
    }
    let (result, stats) = dopri5(&Hires, HIRES_T_END);
    assert_eq!(result.unwrap_or_else(|e| panic!("HIRES: {e}")), stats);
    assert!(stats.n_stiff_steps > 1000, "HIRES: {stats:?}");
}

/// The exact message, on Van der Pol (μ = 1000).
#[test]
fn the_stiffness_message() {
    let (result, _) = dopri5(&VanDerPol, 2.0);
    let err = result.unwrap_err();
    let SolverError::StiffnessDetected {
        t,
        h,
        h_lambda,
        steps,
        needed,
        left,
    } = err
    else {
        panic!("{err:?}");
    };
    assert_eq!(
        err.to_string(),
        format!(
            "at t = {t}, dopri5 found the model stiff: for {steps} steps in a row its step \
             size ({h:e} s, h|λ| ≈ {h_lambda:.2}) was held by stability, not accuracy \
             (Hairer's stiffness test), and at that size the ~{needed:.1e} steps still \
             needed exceed the {left} left of its budget; use a stiff solver \
             (Solver::stiff(), radau5), or set `DormandPrinceOptions::detect_stiffness` \
             to false to go on"
        )
    );
}

/// With the test off, the run crawls on until its budget (here 20,000 steps) is spent,
/// as before, and counts no stiff step.
#[test]
fn the_test_can_be_turned_off() {
    let solver = Solver::DormandPrince(DormandPrinceOptions {
        detect_stiffness: false,
        max_steps: 20_000,
        ..Default::default()
    });
    let mut sim = Simulation::new(&VanDerPol, solver).unwrap();
    let err = sim.run(0.0, &[2.0, 0.0], &[2.0], &mut ()).unwrap_err();
    assert!(
        matches!(err, SolverError::StepBudgetExhausted { steps: 20_000, .. }),
        "{err:?}"
    );
    assert_eq!(sim.stats().n_stiff_steps, 0);
}

/// A stiff run that can finish (Robertson to t = 100, a few tens of thousands of
/// stability-limited steps) goes on: the stiff steps are counted, the run succeeds. A
/// smaller budget makes the same run fail early, and `stiffness_after` can make that
/// earlier still.
#[test]
fn stiff_runs_that_can_finish_go_on() {
    let mut sim = Simulation::new(&Robertson, Solver::dopri5()).unwrap();
    let stats = sim.run(0.0, &[1.0, 0.0, 0.0], &[100.0], &mut ()).unwrap();
    assert!(stats.n_stiff_steps > 1000, "{stats:?}");
    let small = |stiffness_after| {
        Solver::DormandPrince(DormandPrinceOptions {
            max_steps: stats.steps() / 2,
            stiffness_after,
            ..Default::default()
        })
    };
    let mut sim = Simulation::new(&Robertson, small(1000)).unwrap();
    let err = sim
        .run(0.0, &[1.0, 0.0, 0.0], &[100.0], &mut ())
        .unwrap_err();
    assert!(
        matches!(err, SolverError::StiffnessDetected { .. }),
        "{err:?}"
    );
    assert!(sim.stats().accepted < 1100, "{:?}", sim.stats());
    let mut sim = Simulation::new(&Robertson, small(0)).unwrap();
    let err = sim
        .run(0.0, &[1.0, 0.0, 0.0], &[100.0], &mut ())
        .unwrap_err();
    assert!(
        matches!(err, SolverError::StiffnessDetected { steps: 15, .. }),
        "{err:?}"
    );
    assert!(sim.stats().accepted < 100, "{:?}", sim.stats());
}

/// The allocation-free integrator of `rk` shares the kernel and the test.
#[test]
fn the_no_std_integrator_detects_stiffness_too() {
    let mut rk = DormandPrince::<2>::new(DormandPrinceOptions::default()).unwrap();
    let (mut t, mut x) = (0.0, [2.0, 0.0]);
    let err = rk.advance_to(&VanDerPol, &mut t, &mut x, 2.0).unwrap_err();
    assert!(
        matches!(err, SolverError::StiffnessDetected { .. }),
        "{err:?}"
    );
    assert!(rk.stats().steps() < 1100, "{:?}", rk.stats());
}
