//! Rigid mechanisms (issue 12): a slider-crank and a four-bar linkage written as bond
//! graphs with configuration-dependent transformers and dependent inertias, one degree
//! of freedom each, against closed-form kinematics and Lagrange's equations written by
//! hand (`common/lagrange.rs`) and integrated by the runtime's DOPRI at rtol 1e-12.
//!
//! Tolerances: both sides are integrated by DP5 at rtol 1e-12 over 1 s (a few hundred
//! steps), each with a global error near 1e-10 of its scale: they are compared to 1e-8
//! of the amplitude. Kinematic states integrated by the bond graph (the slider's
//! position, the rocker's angle) against the closed form of the crank angle the same
//! run reached: 1e-8 of the link length. Energy, undriven: 1e-8 of the energies' scale.

mod common;
#[path = "common/lagrange.rs"]
mod lagrange;
#[path = "common/textbook.rs"]
mod textbook;

use bgdsl_runtime::{Model, ModelError, Simulation, SolverError, Trajectory};
use common::implicit::{
    assert_energy_closes, assert_jacobian_exact, assert_matches, assert_power_balances,
};
use common::{dopri5, initial_state, run, Rng};
use lagrange::{
    four_bar_angles, four_bar_energy, four_bar_ratios, slider_crank_energy, slider_crank_positions,
    slider_crank_ratios, FourBarLagrange, SliderCrankLagrange,
};
use textbook::{FourBar, FourBarParams, SliderCrank, SliderCrankParams};

/// The index of state `name` in `M`'s state vector.
fn state<M: Model>(name: &str) -> usize {
    M::STATE_NAMES
        .iter()
        .position(|s| *s == name)
        .unwrap_or_else(|| panic!("{}: no state {name} in {:?}", M::NAME, M::STATE_NAMES))
}

/// The column of state `name` of `M` in a trajectory of `M`.
fn state_column<M: Model>(traj: &Trajectory, name: &str) -> Vec<f64> {
    let j = state::<M>(name);
    (0..traj.len())
        .map(|row| traj.state(row, j).unwrap())
        .collect()
}

/// Central difference of `f` at `x` with step `h`.
fn central(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (f(x + h) - f(x - h)) / (2.0 * h)
}

mod references {
    use super::*;

    /// The hand-differentiated velocity ratios of the slider-crank (n = dq/dθ) and their
    /// derivatives n' equal central differences of the closed-form positions (and of n)
    /// at 50 crank angles over a turn: step 1e-5, truncation ~1e-11, tolerance 1e-8.
    #[test]
    fn slider_crank_ratios_are_the_derivatives_of_the_positions() {
        let p = SliderCrankParams::default();
        let h = 1e-5;
        for i in 0..50 {
            let theta = i as f64 * core::f64::consts::TAU / 50.0;
            let ratios = slider_crank_ratios(&p, theta);
            for (k, ratio) in ratios.iter().enumerate() {
                let n = central(|th| slider_crank_positions(&p, th)[k], theta, h);
                let dn = central(|th| slider_crank_ratios(&p, th)[k].n, theta, h);
                assert!(
                    (ratio.n - n).abs() <= 1e-8,
                    "coordinate {k} at {theta}: n {} vs {n}",
                    ratio.n
                );
                assert!(
                    (ratio.dn - dn).abs() <= 1e-8,
                    "coordinate {k} at {theta}: n' {} vs {dn}",
                    ratio.dn
                );
            }
        }
    }

    /// The four-bar's closed-form angles close the loop (|B − O4| = c, |B − A| = b), the
    /// model's default initial angles are the closed form's at θ = 0, and the hand
    /// velocity and acceleration ratios equal central differences of the closed form.
    #[test]
    fn four_bar_closed_form_closes_the_loop_and_differentiates() {
        let p = FourBarParams::default();
        let (t3, t4) = four_bar_angles(&p, p.theta0);
        assert!((t3 - p.theta3_0).abs() <= 1e-15 && (t4 - p.theta4_0).abs() <= 1e-15);
        let h = 1e-5;
        for i in 0..50 {
            let theta = i as f64 * core::f64::consts::TAU / 50.0;
            let (t3, t4) = four_bar_angles(&p, theta);
            let (ax, ay) = (p.a * theta.cos(), p.a * theta.sin());
            let (bx, by) = (p.d + p.c * t4.cos(), p.c * t4.sin());
            assert!(
                ((bx - ax).hypot(by - ay) - p.b).abs() <= 1e-14,
                "coupler length at {theta}"
            );
            assert!(
                ((bx - ax) - p.b * t3.cos()).abs() <= 1e-14
                    && ((by - ay) - p.b * t3.sin()).abs() <= 1e-14
            );
            let (r3, r4) = four_bar_ratios(&p, theta, t3, t4);
            let w3 = central(|th| four_bar_angles(&p, th).0, theta, h);
            let w4 = central(|th| four_bar_angles(&p, th).1, theta, h);
            let ratio = |th: f64| {
                let (a3, a4) = four_bar_angles(&p, th);
                four_bar_ratios(&p, th, a3, a4)
            };
            let a3 = central(|th| ratio(th).0.n, theta, h);
            let a4 = central(|th| ratio(th).1.n, theta, h);
            for (what, hand, fd) in [
                ("θ3'", r3.n, w3),
                ("θ4'", r4.n, w4),
                ("θ3''", r3.dn, a3),
                ("θ4''", r4.dn, a4),
            ] {
                assert!(
                    (hand - fd).abs() <= 1e-7 * fd.abs().max(1.0),
                    "{what} at {theta}: {hand} vs {fd}"
                );
            }
        }
    }
    /// Each reference conserves its own energy ½ M θ̇² + V undriven (so its M' and V'
    /// are those of its M and V): over 1 s from 8 and 6 rad/s, within 1e-9 relative
    /// (DP5 at rtol 1e-12 gives about 1e-11).
    #[test]
    fn lagrange_references_conserve_their_energy() {
        let p = SliderCrankParams::default();
        let m = SliderCrankLagrange(p.clone());
        let (traj, _) = run(&m, dopri5(1e-12, 1e-14), &initial_state(&m), 1.0, 51);
        let e: Vec<f64> = (0..traj.len())
            .map(|r| slider_crank_energy(&p, traj.state(r, 0).unwrap(), traj.state(r, 1).unwrap()))
            .collect();
        assert!(
            e.iter().all(|v| (v - e[0]).abs() <= 1e-9 * e[0]),
            "slider-crank: {e:?}"
        );
        let p = FourBarParams::default();
        let m = FourBarLagrange(p.clone());
        let (traj, _) = run(&m, dopri5(1e-12, 1e-14), &initial_state(&m), 1.0, 51);
        let e: Vec<f64> = (0..traj.len())
            .map(|r| four_bar_energy(&p, traj.state(r, 0).unwrap(), traj.state(r, 1).unwrap()))
            .collect();
        assert!(
            e.iter().all(|v| (v - e[0]).abs() <= 1e-9 * e[0]),
            "four-bar: {e:?}"
        );
    }
}

mod slider_crank {
    use super::*;

    /// The crank's momentum, the crank angle and the slider's position are the states;
    /// the rod's three inertias and the slider's are dependent.
    #[test]
    fn keep_one_momentum_and_list_the_dependent_inertias() {
        assert_eq!(SliderCrank::N_STATES, 3, "{:?}", SliderCrank::STATE_NAMES);
        for name in ["crank.p", "theta", "x_slider"] {
            state::<SliderCrank>(name);
        }
        let mut dependent = SliderCrank::DEPENDENT_STORAGE.to_vec();
        dependent.sort_unstable();
        assert_eq!(dependent, ["rod_mx", "rod_my", "rod_spin", "slider"]);
        assert!(SliderCrank::ALGEBRAIC_LOOPS.is_empty());
    }

    /// Driven by 0.2 + 0.5 sin 7t N·m from 8 rad/s at θ = 0.3 over 1 s (about 1.3
    /// turns): θ and θ̇ follow Lagrange's equation; the slider's position, integrated
    /// from its velocity through the transformer, stays on the closed form
    /// r cos θ + √(l² − r² sin² θ) of the crank angle reached.
    #[test]
    fn follow_lagrange_and_the_closed_form_kinematics() {
        let params = SliderCrankParams {
            tau: 0.2,
            tau1: 0.5,
            ..Default::default()
        };
        let model = SliderCrank::new(params.clone());
        let reference = SliderCrankLagrange(params.clone());
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-14),
            &initial_state(&model),
            1.0,
            201,
        );
        let (lag, _) = run(
            &reference,
            dopri5(1e-12, 1e-14),
            &initial_state(&reference),
            1.0,
            201,
        );
        let t = traj.times();
        let theta = state_column::<SliderCrank>(&traj, "theta");
        let lag_theta = lag.column_at(1).unwrap().to_vec();
        let lag_omega = lag.column_at(2).unwrap().to_vec();
        let row = |t: f64| (t / 0.005).round() as usize;
        assert_matches(
            "slider-crank: θ vs Lagrange",
            t,
            &theta,
            |t| lag_theta[row(t)],
            1e-8,
        );
        assert_matches(
            "slider-crank: θ̇ vs Lagrange",
            t,
            traj.column("omega").unwrap(),
            |t| lag_omega[row(t)],
            1e-8,
        );
        let x_slider = state_column::<SliderCrank>(&traj, "x_slider");
        let closed: Vec<f64> = theta
            .iter()
            .map(|&th| slider_crank_positions(&params, th)[0])
            .collect();
        let error = x_slider
            .iter()
            .zip(&closed)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            error <= 1e-8 * params.r,
            "slider position off the closed form by {error:e} m"
        );
        eprintln!("slider-crank: slider position within {error:e} m of the closed form");
        // The slider's force is ms ẍ_B: its momentum's rate, ms (n' θ̇² + n θ̈).
        let omega = traj.column("omega").unwrap();
        let force = traj.column("slider_force").unwrap();
        let mut dx = [0.0; 2];
        for (i, &time) in t.iter().enumerate() {
            reference.derivatives(time, &[theta[i], omega[i]], &mut dx);
            let [slider, ..] = slider_crank_ratios(&params, theta[i]);
            let expected = params.ms * (slider.dn * omega[i] * omega[i] + slider.n * dx[1]);
            assert!(
                (force[i] - expected).abs() <= 1e-9 * expected.abs().max(1.0),
                "slider force at t = {time}: {} vs ms ẍ = {expected}",
                force[i]
            );
        }
    }

    /// The stiff solvers differentiate through the mass-matrix solve (dual numbers
    /// through `Tangent`): Radau5 and Rodas4 at rtol 1e-10 follow the same Lagrange
    /// reference to 1e-6 of the amplitude (their global error is a few hundred times
    /// the local tolerance at most), using Jacobians.
    #[test]
    fn follow_lagrange_with_the_stiff_solvers() {
        use bgdsl_runtime::{Radau5Options, Rodas4Options, Simulation, Solver};
        let params = SliderCrankParams {
            tau: 0.2,
            tau1: 0.5,
            ..Default::default()
        };
        let model = SliderCrank::new(params.clone());
        let reference = SliderCrankLagrange(params);
        let (lag, _) = run(
            &reference,
            dopri5(1e-12, 1e-14),
            &initial_state(&reference),
            0.5,
            101,
        );
        let lag_theta = lag.column_at(1).unwrap().to_vec();
        let radau = Solver::Radau5(Radau5Options {
            rtol: 1e-10,
            atol: 1e-12,
            ..Default::default()
        });
        let rodas = Solver::Rodas4(Rodas4Options {
            rtol: 1e-10,
            atol: 1e-12,
            ..Default::default()
        });
        for solver in [radau, rodas] {
            let mut sim = Simulation::new(&model, solver).unwrap();
            let mut traj = Trajectory::for_model::<SliderCrank>(101);
            let stats = sim
                .run_uniform(0.0, &initial_state(&model), 0.5, 101, &mut traj)
                .unwrap();
            assert!(stats.n_jac > 0, "{}: Jacobians used", solver.name());
            let theta = state_column::<SliderCrank>(&traj, "theta");
            let row = |t: f64| (t / 0.005).round() as usize;
            assert_matches(
                &format!("slider-crank, {}: θ vs Lagrange", solver.name()),
                traj.times(),
                &theta,
                |t| lag_theta[row(t)],
                1e-6,
            );
        }
    }

    /// Undriven, from 8 rad/s: ½ M(θ) θ̇² + mr g y_G is constant (the reference's
    /// formula on the bond graph's states) and the generated account (dependent
    /// inertias' energy, the rod's weight as a source) closes.
    #[test]
    fn conserve_energy_when_undriven() {
        let params = SliderCrankParams::default();
        let model = SliderCrank::new(params.clone());
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-14),
            &initial_state(&model),
            1.0,
            101,
        );
        let theta = state_column::<SliderCrank>(&traj, "theta");
        let omega = traj.column("omega").unwrap();
        let energy: Vec<f64> = theta
            .iter()
            .zip(omega)
            .map(|(&th, &w)| slider_crank_energy(&params, th, w))
            .collect();
        let drift = energy
            .iter()
            .fold(0.0f64, |m, e| m.max((e - energy[0]).abs()));
        assert!(
            drift <= 1e-8 * energy[0].abs(),
            "energy drifts by {drift:e} of {}",
            energy[0]
        );
        eprintln!(
            "slider-crank: energy drift {:e} relative",
            drift / energy[0].abs()
        );
        assert_energy_closes(&model, dopri5(1e-12, 1e-14), 1.0, 101, 1e-8);
        let x0 = initial_state(&model);
        assert_power_balances(&model, 0.0, &x0, 1e-10);
    }

    /// The Jacobian through the mass-matrix solve, by dual numbers, against central
    /// differences at 12 states around the start; the declared pattern covers it.
    #[test]
    fn differentiate_through_the_constraint() {
        let model = SliderCrank::new(SliderCrankParams {
            tau: 0.3,
            tau1: 0.2,
            ..Default::default()
        });
        let x0 = initial_state(&model);
        let mut rng = Rng::new(13);
        let samples: Vec<(f64, Vec<f64>)> = (0..12)
            .map(|_| {
                (
                    rng.uniform(0.0, 1.0),
                    x0.iter().map(|v| v + rng.symmetric(0.5)).collect(),
                )
            })
            .collect();
        assert_jacobian_exact(&model, &samples, &[1.0; 3]);
    }

    /// A mass matrix that vanishes: M(θ) = jc + ms x_B'(θ)² = 0.25 − 1 × 0.5² at
    /// θ = π/2 (r = 0.5, l = 1, massless rod). The only way an independent inertia's
    /// mass matrix reaches zero is a negative coefficient elsewhere; the numbers are
    /// powers of two, so the constraint's Jacobian is exactly zero. The first
    /// evaluation says so, naming the constrained storage, and a run ends with it.
    #[test]
    fn report_a_singular_constraint() {
        let params = SliderCrankParams {
            r: 0.5,
            l: 1.0,
            jc: 0.25,
            mr: 0.0,
            jr: 0.0,
            ms: -1.0,
            theta0: core::f64::consts::FRAC_PI_2,
            w0: 0.0,
            ..Default::default()
        };
        assert_eq!(slider_crank_ratios(&params, params.theta0)[0].n, -0.5);
        let model = SliderCrank::new(params);
        let x0 = initial_state(&model);
        let mut dx = vec![0.0; SliderCrank::N_STATES];
        model.derivatives(0.0, &x0, &mut dx);
        assert!(
            dx.iter().any(|v| v.is_nan()),
            "a singular solve gives NaN: {dx:?}"
        );
        match model.evaluation_error() {
            Some(ModelError::SingularConstraint { members, t }) => {
                assert!(members.contains("slider"), "{members}");
                assert_eq!(t, 0.0);
            }
            other => panic!("expected SingularConstraint, found {other:?}"),
        }
        let mut sim = Simulation::new(&model, dopri5(1e-8, 1e-10)).unwrap();
        let mut traj = Trajectory::for_model::<SliderCrank>(11);
        let error = sim
            .run_uniform(0.0, &x0, 1.0, 11, &mut traj)
            .expect_err("singular");
        let text = error.to_string();
        assert!(
            matches!(
                error,
                SolverError::InvalidModel(ModelError::SingularConstraint { .. })
            ),
            "{error:?}: {text}"
        );
        assert!(
            text.contains("slider") && text.contains("singular"),
            "{text}"
        );
    }
}

mod four_bar {
    use super::*;

    /// The crank's momentum and the three angles; the coupler's three inertias and the
    /// rocker are dependent.
    #[test]
    fn keep_one_momentum_and_list_the_dependent_inertias() {
        assert_eq!(FourBar::N_STATES, 4, "{:?}", FourBar::STATE_NAMES);
        let mut dependent = FourBar::DEPENDENT_STORAGE.to_vec();
        dependent.sort_unstable();
        assert_eq!(
            dependent,
            ["coupler_mx", "coupler_my", "coupler_spin", "rocker"]
        );
    }

    /// Params starting at crank angle `theta0` from `w0`, assembled by the closed form.
    fn assembled(theta0: f64, w0: f64, tau: f64) -> FourBarParams {
        let base = FourBarParams {
            theta0,
            w0,
            tau,
            ..Default::default()
        };
        let (theta3_0, theta4_0) = four_bar_angles(&base, theta0);
        FourBarParams {
            theta3_0,
            theta4_0,
            ..base
        }
    }

    /// Driven by 0.5 N·m from 6 rad/s at θ = 0.4 over 1 s: θ and θ̇ follow Lagrange's
    /// equation, and the coupler and rocker angles, integrated from their rates through
    /// the transformers, stay on the closed form of the crank angle reached.
    #[test]
    fn follow_lagrange_and_the_closed_form_kinematics() {
        let params = assembled(0.4, 6.0, 0.5);
        let model = FourBar::new(params.clone());
        let reference = FourBarLagrange(params.clone());
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-14),
            &initial_state(&model),
            1.0,
            201,
        );
        let (lag, _) = run(
            &reference,
            dopri5(1e-12, 1e-14),
            &initial_state(&reference),
            1.0,
            201,
        );
        let t = traj.times();
        let theta = state_column::<FourBar>(&traj, "theta");
        let (lag_theta, lag_omega) = (
            lag.column_at(1).unwrap().to_vec(),
            lag.column_at(2).unwrap().to_vec(),
        );
        let row = |t: f64| (t / 0.005).round() as usize;
        assert_matches(
            "four-bar: θ vs Lagrange",
            t,
            &theta,
            |t| lag_theta[row(t)],
            1e-8,
        );
        assert_matches(
            "four-bar: θ̇ vs Lagrange",
            t,
            traj.column("omega").unwrap(),
            |t| lag_omega[row(t)],
            1e-8,
        );
        let theta3 = state_column::<FourBar>(&traj, "theta3");
        let theta4 = state_column::<FourBar>(&traj, "theta4");
        let mut worst: f64 = 0.0;
        for i in 0..t.len() {
            let (c3, c4) = four_bar_angles(&params, theta[i]);
            worst = worst
                .max((theta3[i] - c3).abs())
                .max((theta4[i] - c4).abs());
        }
        assert!(
            worst <= 1e-8,
            "coupler/rocker angles off the closed form by {worst:e} rad"
        );
        eprintln!("four-bar: integrated angles within {worst:e} rad of the closed form");
    }

    /// Undriven from 6 rad/s: ½ M θ̇² + V constant, and the generated account closes.
    #[test]
    fn conserve_energy_when_undriven() {
        let params = assembled(0.0, 6.0, 0.0);
        let model = FourBar::new(params.clone());
        let (traj, _) = run(
            &model,
            dopri5(1e-12, 1e-14),
            &initial_state(&model),
            1.0,
            101,
        );
        let theta = state_column::<FourBar>(&traj, "theta");
        let omega = traj.column("omega").unwrap();
        let energy: Vec<f64> = theta
            .iter()
            .zip(omega)
            .map(|(&th, &w)| four_bar_energy(&params, th, w))
            .collect();
        let scale = energy.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        let drift = energy
            .iter()
            .fold(0.0f64, |m, e| m.max((e - energy[0]).abs()));
        assert!(
            drift <= 1e-8 * scale,
            "energy drifts by {drift:e} of {scale}"
        );
        eprintln!("four-bar: energy drift {:e} relative", drift / scale);
        assert_energy_closes(&model, dopri5(1e-12, 1e-14), 1.0, 101, 1e-8);
        assert_power_balances(&model, 0.0, &initial_state(&model), 1e-10);
    }

    /// The Jacobian through the solve against central differences, at 12 states near
    /// assembled configurations (angles within ±0.05 rad, away from the toggles).
    #[test]
    fn differentiate_through_the_constraint() {
        let mut rng = Rng::new(17);
        let model = FourBar::new(assembled(0.0, 6.0, 0.5));
        let mut samples = Vec::new();
        for _ in 0..12 {
            let theta = rng.uniform(0.0, core::f64::consts::TAU);
            let (t3, t4) = four_bar_angles(&model.params, theta);
            let mut x = vec![0.0; 4];
            x[state::<FourBar>("crank.p")] = rng.symmetric(0.1);
            x[state::<FourBar>("theta")] = theta;
            x[state::<FourBar>("theta3")] = t3 + rng.symmetric(0.05);
            x[state::<FourBar>("theta4")] = t4 + rng.symmetric(0.05);
            samples.push((0.0, x));
        }
        assert_jacobian_exact(&model, &samples, &[1.0; 4]);
    }
}

mod drawing {
    use super::*;
    use common::implicit::{assert_drawing_marks, assert_graphviz_parses};

    /// The mechanisms' dependent inertias are drawn red, the crank is not.
    #[test]
    fn mark_the_dependent_inertias() {
        for dot in [
            assert_drawing_marks::<SliderCrank>(&SliderCrank::GRAPH),
            assert_drawing_marks::<FourBar>(&FourBar::GRAPH),
        ] {
            let crank = dot
                .lines()
                .find(|l| l.contains("\"I : crank\""))
                .expect("the crank's node");
            assert!(!crank.contains("red"), "{crank}");
            assert_graphviz_parses(&dot);
        }
    }
}
