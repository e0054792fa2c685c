//! Algebraic loops (issue 12), opted in with `#[allow(algebraic_loops)]` and solved at
//! each evaluation, against closed forms and an independent high-precision reference:
//! two dampers in series, MTT's `aRC` example, a loaded resistive divider (Thévenin), a
//! diode with a series resistor charging a capacitor (non-linear). And what happens
//! when a loop has no solution.
//!
//! Tolerances: DP5 at rtol 1e-12 keeps the global error near 1e-10 of each signal's
//! scale over these short runs, so closed forms are asserted to 1e-8 of their
//! amplitude; the diode's reference is exact to 1e-14 (see below), and is asserted to
//! 1e-8 for the same reason.

mod common;
#[path = "common/textbook.rs"]
mod textbook;

use bgdsl_runtime::{Model, ModelError, Simulation, SolverError, Trajectory};
use common::implicit::{
    assert_energy_closes, assert_jacobian_exact, assert_matches, assert_power_balances,
};
use common::{dopri5, initial_state, run, seeded_states, underdamped};
use textbook::{
    Arc, ArcParams, DiodeRc, DiodeRcParams, Divider, ImpossibleLoop, LoadedDivider,
    LoadedDividerParams, SeriesDampers, SeriesDampersParams, UnluckyLoop,
};

/// Whether `loops` has one loop, on which every name of `on` lies and none of `off`.
fn assert_one_loop(model: &str, loops: &[&[&str]], on: &[&str], off: &[&str]) {
    assert_eq!(loops.len(), 1, "{model}: one loop, found {loops:?}");
    for name in on {
        assert!(
            loops[0].contains(name),
            "{model}: {name} is on the loop {loops:?}"
        );
    }
    for name in off {
        assert!(
            !loops[0].contains(name),
            "{model}: {name} is not on the loop {loops:?}"
        );
    }
}

mod series_dampers {
    use super::*;

    /// Two dampers in series act as one of r1 r2/(r1 + r2) = 1.2 N·s/m: the mass on
    /// its spring, released from 0.1 m, follows the damped oscillator with that damper
    /// (ω0 = √10 rad/s, α = 0.6 1/s), over 3 s; the force through both is
    /// r_eq v. The states are only the mass's and the spring's.
    #[test]
    fn act_as_the_equivalent_damper() {
        let params = SeriesDampersParams::default();
        let model = SeriesDampers::new(params.clone());
        assert_eq!(SeriesDampers::N_STATES, 2);
        assert!(SeriesDampers::DEPENDENT_STORAGE.is_empty());
        assert_one_loop(
            "SeriesDampers",
            SeriesDampers::ALGEBRAIC_LOOPS,
            &["d1", "d2"],
            &["mass", "spring"],
        );
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-15),
            &initial_state(&model),
            3.0,
            301,
        );
        let r_eq = params.r1 * params.r2 / (params.r1 + params.r2);
        let omega0 = (params.k / params.m).sqrt();
        let alpha = r_eq / (2.0 * params.m);
        let exact = |t: f64| underdamped(0.0, 0.1, 0.0, omega0, alpha, t);
        let t = traj.times();
        assert_matches(
            "series dampers: x",
            t,
            traj.column("x").unwrap(),
            |t| exact(t).0,
            1e-8,
        );
        assert_matches(
            "series dampers: v",
            t,
            traj.column("speed").unwrap(),
            |t| exact(t).1,
            1e-8,
        );
        assert_matches(
            "series dampers: force r_eq v",
            t,
            traj.column("damper_force").unwrap(),
            |t| r_eq * exact(t).1,
            1e-8,
        );
        assert_energy_closes(&model, dopri5(1e-12, 1e-15), 3.0, 151, 1e-8);
        for [p, q] in seeded_states::<2>(11, 10) {
            assert_power_balances(&model, 0.0, &[p, q], 1e-12);
        }
    }

    /// The loop is linear: the Jacobian through it is the equivalent damper's,
    /// ∂ṗ/∂p = −r_eq/m, and agrees with central differences.
    #[test]
    fn differentiate_through_the_loop() {
        let model = SeriesDampers::default();
        let samples: Vec<(f64, Vec<f64>)> = seeded_states::<2>(5, 12)
            .into_iter()
            .map(|x| (0.0, x.to_vec()))
            .collect();
        assert_jacobian_exact(&model, &samples, &[1.0, 1.0]);
        let mut jac = [0.0; 4];
        bgdsl_runtime::JacobianEvaluator::new(&model).evaluate(&model, 0.0, &[0.2, 0.05], &mut jac);
        let p = &model.params;
        let r_eq = p.r1 * p.r2 / (p.r1 + p.r2);
        let dp = SeriesDampers::STATE_NAMES
            .iter()
            .position(|s| *s == "mass.p")
            .unwrap();
        assert!((jac[dp * 2 + dp] + r_eq / p.m).abs() <= 1e-14, "{jac:?}");
    }
}

mod arc {
    use super::*;

    /// MTT's aRC (two resistors in series with a capacitor, one algebraic loop): its
    /// reduced ODE c de2/dt = (e1 − e2)/(r_1 + r_2) from an empty capacitor gives
    /// e2 = e1 (1 − e^{−t/((r_1 + r_2) c)}), τ = 0.3 s; the loop current is
    /// (e1 − e2)/(r_1 + r_2).
    #[test]
    fn follow_mtt_reduced_ode() {
        let params = ArcParams::default();
        let model = Arc::new(params.clone());
        assert_eq!(Arc::STATE_NAMES, ["cap.q"]);
        assert_one_loop(
            "Arc",
            Arc::ALGEBRAIC_LOOPS,
            &["r1", "r2"],
            &["source", "cap"],
        );
        let tau = (params.r_1 + params.r_2) * params.c;
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-16),
            &initial_state(&model),
            1.0,
            201,
        );
        let t = traj.times();
        let e2 = |t: f64| params.e1 * (1.0 - (-t / tau).exp());
        assert_matches("aRC: e2", t, traj.column("e2").unwrap(), e2, 1e-8);
        assert_matches(
            "aRC: loop current",
            t,
            traj.column("i").unwrap(),
            |t| (params.e1 - e2(t)) / (params.r_1 + params.r_2),
            1e-8,
        );
        assert_energy_closes(&model, dopri5(1e-12, 1e-16), 1.0, 101, 1e-8);
    }
}

mod divider {
    use super::*;

    /// A 10 V source over 1 kΩ and 3 kΩ, loaded by 250 Ω and 1 µF: seen from the load,
    /// 7.5 V behind 750 Ω, so the capacitor charges to 7.5 V with τ = (750 + 250) Ω ×
    /// 1 µF = 1 ms, and the divider's output is v_c + r3 i.
    #[test]
    fn look_like_its_thevenin_equivalent() {
        let params = LoadedDividerParams::default();
        let model = LoadedDivider::new(params.clone());
        assert_eq!(LoadedDivider::N_STATES, 1);
        assert_one_loop(
            "LoadedDivider",
            LoadedDivider::ALGEBRAIC_LOOPS,
            &["upper", "lower"],
            &["source", "load_c"],
        );
        let LoadedDividerParams { e0, r1, r2, r3, c } = params;
        let (v_th, r_th) = (e0 * r2 / (r1 + r2), r1 * r2 / (r1 + r2));
        let tau = (r_th + r3) * c;
        let v_c = |t: f64| v_th * (1.0 - (-t / tau).exp());
        // q ~ 7.5e-6 C: atol 1e-19 is about 1e-14 of it.
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-19),
            &initial_state(&model),
            0.004,
            201,
        );
        let t = traj.times();
        assert_matches("divider: v_c", t, traj.column("v_c").unwrap(), v_c, 1e-8);
        assert_matches(
            "divider: v_out",
            t,
            traj.column("v_out").unwrap(),
            |t| v_c(t) + r3 * (v_th - v_c(t)) / (r_th + r3),
            1e-8,
        );
        assert_energy_closes(&model, dopri5(1e-12, 1e-19), 0.004, 101, 1e-8);
    }
}

mod divider_alone {
    use super::*;

    /// With nothing but the source and the two resistors there is no state: the loop is
    /// solved for the outputs alone, e0 r2/(r1 + r2) = 7.5 V and e0/(r1 + r2) = 2.5 mA.
    #[test]
    fn divide_without_any_state() {
        assert_eq!(Divider::N_STATES, 0);
        assert_one_loop(
            "Divider",
            Divider::ALGEBRAIC_LOOPS,
            &["upper", "lower"],
            &["source"],
        );
        let model = Divider::default();
        let p = &model.params;
        let mut y = [0.0; 2];
        model.outputs::<f64>(0.0, &[], &mut y);
        let (v, i) = (p.e0 * p.r2 / (p.r1 + p.r2), p.e0 / (p.r1 + p.r2));
        assert!(
            (y[0] - v).abs() <= 1e-14 * v && (y[1] - i).abs() <= 1e-14 * i,
            "{y:?}"
        );
        let balance = model.power_balance::<f64>(0.0, &[]).unwrap();
        assert!((balance.input - p.e0 * i).abs() <= 1e-14 * p.e0 * i);
        assert!((balance.dissipated - balance.input).abs() <= 1e-14 * balance.input);
    }

    /// A linear loop whose Jacobian vanishes (r2 = −r1: 1 + r1/r2 = 0, exactly) is a
    /// singular constraint named by the loop's members at the first evaluation.
    #[test]
    fn report_a_singular_loop() {
        let model = SeriesDampers::new(SeriesDampersParams {
            r2: -2.0,
            ..Default::default()
        });
        let mut dx = [0.0; 2];
        model.derivatives(0.0, &[0.1, 0.1], &mut dx);
        assert!(dx.iter().all(|v| v.is_nan()), "{dx:?}");
        match model.evaluation_error() {
            Some(ModelError::SingularConstraint { members, t }) => {
                assert!(
                    members.contains("d1") && members.contains("d2"),
                    "{members}"
                );
                assert_eq!(t, 0.0);
            }
            other => panic!("expected SingularConstraint, found {other:?}"),
        }
    }
}

mod diode {
    use super::*;

    /// `(t, capacitor voltage, loop current)` of the reduced ODE C dv/dt = i(v), i(v)
    /// by Lambert's W, integrated by mpmath's Taylor method at 30 digits and checked
    /// against scipy's DOP853 (they agree to 1.5e-14 V), each the `f64` nearest the
    /// 30-digit value. Made by
    /// `python3 tests/references/diode_rc.py` (its docstring says how and why) with
    /// the model's default parameters: E = 1.5 V, R = 100 Ω, Is = 1 nA, Vt = 50 mV,
    /// C = 10 µF, from an empty capacitor.
    const REFERENCE: [(f64, f64, f64); 21] = [
        (0.0, 0.0, 0.007111395408440084),
        (0.0001, 0.06789938195637639, 0.006478970047090764),
        (0.0002, 0.12977896488037458, 0.005906433866274125),
        (0.0003, 0.1862085593339359, 0.005388065799526187),
        (0.0004, 0.23770352843670742, 0.004918688382025738),
        (0.0005, 0.28472996141229007, 0.004493616120764072),
        (0.0006, 0.32770935592443173, 0.004108608800192987),
        (0.0007, 0.36702285617143116, 0.003759829253751603),
        (0.0008, 0.4030150892344735, 0.0034438051756114714),
        (0.0009, 0.43599763812070946, 0.0031573945866443204),
        (0.001, 0.4662521862641159, 0.0028977546044495835),
        (0.0011, 0.49403336491029526, 0.002662313199691387),
        (0.0012, 0.5195713317831187, 0.0024487436503684156),
        (0.0013, 0.5430741066828825, 0.002254941432325713),
        (0.0014, 0.564729687172165, 0.0020790033086322546),
        (0.0015, 0.5847079652445692, 0.001919208402673044),
        (0.0016, 0.6031624638233548, 0.001774001060181116),
        (0.0017, 0.6202319100841663, 0.001641975324163791),
        (0.0018, 0.6360416609229922, 0.0015218608639180385),
        (0.0019, 0.6507049943828997, 0.0014125102152022862),
        (0.002, 0.6643242794977596, 0.0013128872032227002),
    ];

    /// The defaults the reference was made with: a changed default must change it.
    #[test]
    fn keep_the_parameters_the_reference_was_made_with() {
        let p = DiodeRcParams::default();
        assert_eq!(
            (p.e0, p.r, p.i_s, p.vt, p.c),
            (1.5, 100.0, 1e-9, 0.05, 10e-6)
        );
    }

    /// The generated model's capacitor voltage and loop current at every reference
    /// point, within 1e-8 of their largest value. The first evaluation solves the loop
    /// from a zero guess with the diode 1.5 V forward (exp(30)): Newton walks down the
    /// exponential about Vt per step, so this also checks that it gets there.
    #[test]
    fn follow_the_lambert_w_reference() {
        let model = DiodeRc::default();
        assert_eq!(DiodeRc::STATE_NAMES, ["cap.q"]);
        assert_one_loop(
            "DiodeRc",
            DiodeRc::ALGEBRAIC_LOOPS,
            &["resistor", "diode"],
            &["source", "cap"],
        );
        // q ~ 7e-6 C: atol 1e-19 is about 1e-14 of it.
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-19),
            &initial_state(&model),
            2e-3,
            21,
        );
        let t = traj.times();
        for (row, (tr, _, _)) in REFERENCE.iter().enumerate() {
            assert!(
                (t[row] - tr).abs() <= 1e-15,
                "sample times: {} vs {tr}",
                t[row]
            );
        }
        let volts: Vec<f64> = REFERENCE.iter().map(|r| r.1).collect();
        let amps: Vec<f64> = REFERENCE.iter().map(|r| r.2).collect();
        let at = |values: &[f64], t: f64| values[(t / 1e-4).round() as usize];
        assert_matches(
            "diode: v_c",
            t,
            traj.column("v_c").unwrap(),
            |t| at(&volts, t),
            1e-8,
        );
        assert_matches(
            "diode: current",
            t,
            traj.column("i").unwrap(),
            |t| at(&amps, t),
            1e-8,
        );
        // KVL closes: E = R i + v_D + v_c at every sample.
        let (i, vd, vc) = (
            traj.column("i").unwrap(),
            traj.column("v_diode").unwrap(),
            traj.column("v_c").unwrap(),
        );
        for row in 0..t.len() {
            let kvl = 100.0 * i[row] + vd[row] + vc[row];
            assert!((kvl - 1.5).abs() <= 1e-9, "KVL at row {row}: {kvl}");
        }
        assert_energy_closes(&model, dopri5(1e-12, 1e-19), 2e-3, 101, 1e-8);
    }

    /// The stiff solvers, whose Jacobians go through the Newton solve (the implicit
    /// function step on dual numbers), at rtol 1e-10 follow the reference to 1e-6 of
    /// the amplitude (their global error is a few hundred times the local tolerance
    /// at most).
    #[test]
    fn follow_the_reference_with_the_stiff_solvers() {
        use bgdsl_runtime::{Radau5Options, Rodas4Options, Solver};
        let model = DiodeRc::default();
        let radau = Solver::Radau5(Radau5Options {
            rtol: 1e-10,
            atol: 1e-17,
            ..Default::default()
        });
        let rodas = Solver::Rodas4(Rodas4Options {
            rtol: 1e-10,
            atol: 1e-17,
            ..Default::default()
        });
        let volts: Vec<f64> = REFERENCE.iter().map(|r| r.1).collect();
        for solver in [radau, rodas] {
            let mut sim = Simulation::new(&model, solver).unwrap();
            let mut traj = Trajectory::for_model::<DiodeRc>(21);
            let stats = sim
                .run_uniform(0.0, &initial_state(&model), 2e-3, 21, &mut traj)
                .unwrap();
            assert!(stats.n_jac > 0, "{}: Jacobians used", solver.name());
            assert_matches(
                &format!("diode, {}: v_c", solver.name()),
                traj.times(),
                traj.column("v_c").unwrap(),
                |t| volts[(t / 1e-4).round() as usize],
                1e-6,
            );
        }
    }

    /// The Jacobian through the Newton solve (exact by the implicit function theorem)
    /// against central differences, at capacitor voltages from 0 to 1 V.
    #[test]
    fn differentiate_through_the_newton_solve() {
        let model = DiodeRc::default();
        let c = model.params.c;
        let samples: Vec<(f64, Vec<f64>)> =
            (0..11).map(|k| (0.0, vec![c * 0.1 * k as f64])).collect();
        assert_jacobian_exact(&model, &samples, &[c * 0.1]);
        for (_, x) in &samples {
            assert_power_balances(&model, 0.0, x, 1e-10);
        }
    }
}

mod unsolvable {
    use super::*;

    /// The loop e = r1 (v − e² − b e − 1) has no real root at rest: the first evaluation
    /// fills dx with NaN and records why; a run ends with that error, naming the
    /// loop's elements, the time and the residual, never passing a NaN on.
    #[test]
    fn end_the_run_with_an_error_naming_the_loop() {
        let model = ImpossibleLoop::default();
        assert_one_loop(
            "ImpossibleLoop",
            ImpossibleLoop::ALGEBRAIC_LOOPS,
            &["d1", "d2"],
            &["mass"],
        );
        let mut dx = [0.0];
        model.derivatives(0.0, &[0.0], &mut dx);
        assert!(dx[0].is_nan(), "a failed solve gives NaN, found {dx:?}");
        match model.evaluation_error() {
            Some(ModelError::UnsolvedLoop {
                members,
                t,
                residual,
            }) => {
                assert!(
                    members.contains("d1") && members.contains("d2"),
                    "{members}"
                );
                assert_eq!(t, 0.0);
                assert!(
                    residual.abs() > 1e-3,
                    "the residual says how far: {residual}"
                );
            }
            other => panic!("expected UnsolvedLoop, found {other:?}"),
        }

        let mut sim = Simulation::new(&model, dopri5(1e-8, 1e-10)).unwrap();
        let mut traj = Trajectory::for_model::<ImpossibleLoop>(11);
        let error = sim
            .run_uniform(0.0, &[0.0], 1.0, 11, &mut traj)
            .expect_err("no solution, no run");
        let text = error.to_string();
        match &error {
            SolverError::InvalidModel(ModelError::UnsolvedLoop { members, t, .. }) => {
                assert!(members.contains("d1") && members.contains("d2"), "{text}");
                assert_eq!(*t, 0.0, "{text}");
            }
            other => panic!("expected the loop's error, found {other:?}: {text}"),
        }
        assert!(
            text.contains("d1") && text.contains("d2") && text.contains("t = 0"),
            "{text}"
        );
        assert!(!text.to_lowercase().contains("nan"), "{text}");
        for row in 0..traj.len() {
            for j in 0..ImpossibleLoop::N_STATES {
                assert!(
                    traj.state(row, j).unwrap().is_finite(),
                    "a NaN was recorded"
                );
            }
        }
    }

    /// A non-linear loop without a solution whose Newton iterate lands where its
    /// derivative vanishes is still a loop that did not converge (with its residual),
    /// not a "redundant constraint or dead-point configuration".
    #[test]
    fn report_an_unconverged_loop_even_where_newton_meets_a_zero_derivative() {
        let model = UnluckyLoop::default();
        let mut dx = [0.0];
        model.derivatives(0.0, &[0.0], &mut dx);
        assert!(dx[0].is_nan());
        match model.evaluation_error() {
            Some(ModelError::UnsolvedLoop {
                members,
                t,
                residual,
            }) => {
                assert!(
                    members.contains("d1") && members.contains("d2"),
                    "{members}"
                );
                assert_eq!(t, 0.0);
                assert!(residual.abs() > 1e-3, "{residual}");
            }
            other => panic!("expected UnsolvedLoop, found {other:?}"),
        }
    }

    /// Where the loop has a solution (the mass moving fast enough, v ≥ 1 − (1 + b)²/4
    /// with r1 = 1), the same model evaluates, and the failure recorded before is
    /// cleared.
    #[test]
    fn recover_where_the_loop_has_a_solution() {
        let model = ImpossibleLoop::default();
        let mut dx = [0.0];
        model.derivatives(0.0, &[0.0], &mut dx);
        assert!(model.evaluation_error().is_some());
        // p = 2 kg·m/s: v = 2, e² + (1 + b) e − 1 = 0 has the root below.
        model.derivatives(0.0, &[2.0], &mut dx);
        let b1 = 1.1234567f64;
        let e = (-b1 + (b1 * b1 + 4.0).sqrt()) / 2.0;
        assert!(
            (dx[0] + e).abs() <= 1e-12,
            "ṗ = −e = {}, found {}",
            -e,
            dx[0]
        );
        assert!(
            model.evaluation_error().is_none(),
            "a later solve clears the failure"
        );
    }
}

mod drawing {
    use super::*;
    use common::implicit::{assert_drawing_marks, assert_graphviz_parses};

    /// `ALGEBRAIC_LOOPS` names each loop's members, the causal graph has the same
    /// loops, and the DOT text outlines exactly those elements in orange (with a
    /// legend); nothing is dependent storage. Graphviz reads every drawing.
    #[test]
    fn mark_the_loops() {
        let drawings = [
            assert_drawing_marks::<SeriesDampers>(&SeriesDampers::GRAPH),
            assert_drawing_marks::<Arc>(&Arc::GRAPH),
            assert_drawing_marks::<Divider>(&Divider::GRAPH),
            assert_drawing_marks::<LoadedDivider>(&LoadedDivider::GRAPH),
            assert_drawing_marks::<DiodeRc>(&DiodeRc::GRAPH),
            assert_drawing_marks::<ImpossibleLoop>(&ImpossibleLoop::GRAPH),
        ];
        for dot in &drawings {
            assert!(
                dot.contains("algebraic loop (solved at each evaluation)"),
                "{dot}"
            );
            assert!(
                !dot.contains("fontcolor=\"red\""),
                "no dependent storage: {dot}"
            );
            assert_graphviz_parses(dot);
        }
    }
}
