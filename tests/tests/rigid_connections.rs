//! Rigid connections (issue 12): storage elements in derivative causality, opted in
//! with `#[allow(derivative_causality)]`, against closed forms. Two inertias through a
//! rigid gear, two masses glued on one 1-junction, two capacitors in parallel on one
//! 0-junction, a mass shaken by a velocity source. Each dependent element keeps its
//! place in the outputs and in the energy account.
//!
//! Tolerances: DP5 at rtol 1e-12 over at most a few hundred steps keeps the global
//! error near 1e-10 of each signal's scale, so the closed forms are asserted to 1e-8
//! of their amplitude (two orders of margin); an energy account integrated by the same
//! solver closes to the same order (1e-8 of the energies' scale). Quantities computed
//! from the state by the generated code alone (the dependent inertia's flow, its
//! stored energy) are compared to rounding (1e-12).

mod common;
#[path = "common/textbook.rs"]
mod textbook;

use bgdsl_runtime::{Model, Solver};
use common::implicit::{
    assert_energy_closes, assert_jacobian_exact, assert_matches, assert_power_balances,
};
use common::{dopri5, initial_state, run, seeded_states, underdamped};
use textbook::{
    Gear, GearParams, GluedMasses, GluedMassesParams, ParallelCapacitors, ParallelCapacitorsParams,
    ShakenMass, ShakenMassAlone, ShakenMassParams,
};

/// DP5 at rtol 1e-12 with an absolute tolerance `atol` below 1e-12 of the states' scale.
fn tight(atol: f64) -> Solver {
    dopri5(1e-12, atol)
}

mod gear {
    use super::*;

    /// `(ω₁(t), ω̇₁(t))` of (j1 + n² j2) ω̇₁ = τ₀ + A sin Ωt − n² c ω₁ from rest: the
    /// first-order response to the constant and to the sinusoid, superposed.
    fn closed_form(p: &GearParams, t: f64) -> (f64, f64) {
        let jeq = p.j1 + p.n * p.n * p.j2;
        let ceq = p.n * p.n * p.c;
        let decay = (-ceq * t / jeq).exp();
        let step = p.torque / ceq * (1.0 - decay);
        // Particular a sin Ωt + b cos Ωt, plus the transient −b e^{−ceq t/jeq}.
        let (w, amp) = (p.omega, p.amplitude);
        let den = ceq * ceq + jeq * jeq * w * w;
        let (a, b) = (amp * ceq / den, -amp * jeq * w / den);
        let (s, c) = (w * t).sin_cos();
        let sine = a * s + b * c - b * decay;
        let speed = step + sine;
        let torque = p.torque + amp * s;
        (speed, (torque - ceq * speed) / jeq)
    }

    fn check(params: GearParams, case: &str) {
        let model = Gear::new(params.clone());
        let (traj, _) = run(&model, tight(1e-15), &initial_state(&model), 2.0, 401);
        let t = traj.times();
        let p = &params;
        let label = |what: &str| format!("gear, {case}: {what}");
        assert_matches(
            &label("ω₁"),
            t,
            traj.column("w1_speed").unwrap(),
            |t| closed_form(p, t).0,
            1e-8,
        );
        assert_matches(
            &label("ω₂ = n ω₁"),
            t,
            traj.column("w2_speed").unwrap(),
            |t| p.n * closed_form(p, t).0,
            1e-8,
        );
        // The dependent shaft's torque j2 ω̇₂ and the torque the gear passes on,
        // j2 ω̇₂ + c ω₂.
        assert_matches(
            &label("shaft 2 torque j2 n ω̇₁"),
            t,
            traj.column("shaft2_torque").unwrap(),
            |t| p.j2 * p.n * closed_form(p, t).1,
            1e-8,
        );
        assert_matches(
            &label("gear torque n (j2 ω̇₁ + c ω₁)"),
            t,
            traj.column("gear_torque").unwrap(),
            |t| {
                let (w, dw) = closed_form(p, t);
                p.n * (p.j2 * dw + p.c * w)
            },
            1e-8,
        );
    }

    /// One state (the input shaft's momentum): the output shaft's inertia is
    /// dependent, listed as such.
    #[test]
    fn keep_one_state_and_list_the_dependent_shaft() {
        assert_eq!(Gear::STATE_NAMES, ["shaft1.p"]);
        assert_eq!(Gear::DEPENDENT_STORAGE, ["shaft2"]);
        assert!(Gear::ALGEBRAIC_LOOPS.is_empty());
    }

    /// Constant torque from rest: ω₁ = τ/(n² c) (1 − e^{−n² c t/(j1 + n² j2)}), the
    /// equivalent inertia j1 + n² j2 = 0.65 kg·m² against j1 = 0.2 alone.
    #[test]
    fn follow_the_equivalent_inertia_under_a_constant_torque() {
        check(GearParams::default(), "constant torque");
    }

    /// A sinusoidal torque 2 sin 5t from rest (no constant part).
    #[test]
    fn follow_the_equivalent_inertia_under_a_sinusoidal_torque() {
        let params = GearParams {
            torque: 0.0,
            amplitude: 2.0,
            ..Default::default()
        };
        check(params, "sinusoidal torque");
    }

    /// Stored energy ½ j1 ω₁² + ½ j2 ω₂² (the dependent shaft's included), supplied =
    /// dissipated + Δstored along a run, and d(stored)/dt = input − dissipated exactly
    /// at seeded states.
    #[test]
    fn account_for_the_dependent_shaft_energy() {
        let params = GearParams {
            torque: 0.5,
            amplitude: 1.0,
            ..Default::default()
        };
        let model = Gear::new(params.clone());
        for [p1] in seeded_states::<1>(3, 20) {
            let x = [p1];
            let w1 = p1 / params.j1;
            let expected = 0.5 * params.j1 * w1 * w1 + 0.5 * params.j2 * (params.n * w1).powi(2);
            let stored = model.power_balance(0.0, &x).unwrap().stored;
            assert!(
                (stored - expected).abs() <= 1e-12 * expected.max(1e-300),
                "stored {stored} vs ½ j1 ω₁² + ½ j2 ω₂² = {expected}"
            );
            assert_power_balances(&model, 0.37, &x, 1e-12);
        }
        assert_energy_closes(&model, tight(1e-15), 2.0, 201, 1e-8);
    }

    /// ∂ṗ₁/∂p₁ = −n² c / (j1 + n² j2) through the solve, by dual numbers and central
    /// differences; the declared pattern covers it.
    #[test]
    fn differentiate_through_the_constraint() {
        let model = Gear::default();
        let samples: Vec<(f64, Vec<f64>)> = seeded_states::<1>(7, 12)
            .into_iter()
            .enumerate()
            .map(|(i, x)| (0.1 * i as f64, x.to_vec()))
            .collect();
        assert_jacobian_exact(&model, &samples, &[1.0]);
        let mut jac = [0.0];
        bgdsl_runtime::JacobianEvaluator::new(&model).evaluate(&model, 0.0, &[0.3], &mut jac);
        let p = &model.params;
        let exact = -p.n * p.n * p.c / (p.j1 + p.n * p.n * p.j2);
        assert!((jac[0] - exact).abs() <= 1e-14, "{} vs {exact}", jac[0]);
    }
}

mod glued_masses {
    use super::*;

    /// Without a spring: uniform acceleration F/(m1 + m2) from rest; the second mass
    /// needs the force m2 a.
    #[test]
    fn accelerate_as_one_mass() {
        let params = GluedMassesParams {
            k: 0.0,
            ..Default::default()
        };
        let model = GluedMasses::new(params.clone());
        assert_eq!(GluedMasses::N_STATES, 2, "one momentum and the spring");
        assert_eq!(GluedMasses::DEPENDENT_STORAGE.len(), 1);
        let (traj, _) = run(&model, tight(1e-15), &initial_state(&model), 1.0, 101);
        let a = params.force / (params.m1 + params.m2);
        let t = traj.times();
        assert_matches(
            "glued: x = a t²/2",
            t,
            traj.column("x").unwrap(),
            |t| 0.5 * a * t * t,
            1e-8,
        );
        assert_matches(
            "glued: v = a t",
            t,
            traj.column("speed").unwrap(),
            |t| a * t,
            1e-8,
        );
        assert_matches(
            "glued: second mass's force m2 a",
            t,
            traj.column("second_force").unwrap(),
            |_| params.m2 * a,
            1e-12,
        );
    }

    /// With the spring: an undamped oscillation of angular frequency √(k/(m1 + m2))
    /// = 5 rad/s about F/k, over 2 s (1.6 periods).
    #[test]
    fn oscillate_at_the_frequency_of_the_sum_of_the_masses() {
        let params = GluedMassesParams::default();
        let model = GluedMasses::new(params.clone());
        let (traj, _) = run(&model, tight(1e-16), &initial_state(&model), 2.0, 401);
        let omega0 = (params.k / (params.m1 + params.m2)).sqrt();
        let exact = |t: f64| underdamped(params.force / params.k, 0.0, 0.0, omega0, 0.0, t);
        let t = traj.times();
        assert_matches(
            "glued spring: x",
            t,
            traj.column("x").unwrap(),
            |t| exact(t).0,
            1e-8,
        );
        assert_matches(
            "glued spring: v",
            t,
            traj.column("speed").unwrap(),
            |t| exact(t).1,
            1e-8,
        );
        assert_energy_closes(&model, tight(1e-16), 2.0, 201, 1e-8);
    }
}

mod parallel_capacitors {
    use super::*;

    /// From empty: v = E (1 − e^{−t/τ}) with τ = R (C1 + C2) = 4 ms, and the second
    /// (dependent) capacitor takes i₂ = C2 dv/dt = C2 E/τ e^{−t/τ}.
    #[test]
    fn charge_with_the_summed_capacitance() {
        let params = ParallelCapacitorsParams::default();
        let model = ParallelCapacitors::new(params.clone());
        assert_eq!(ParallelCapacitors::N_STATES, 1);
        assert_eq!(ParallelCapacitors::DEPENDENT_STORAGE.len(), 1);
        let c2 = params.c2;
        let tau = params.r * (params.c1 + c2);
        // q ~ 2e-6 C: atol 1e-20 is 1e-14 of it.
        let (traj, _) = run(&model, tight(1e-20), &initial_state(&model), 0.012, 301);
        let t = traj.times();
        let e = params.e0;
        assert_matches(
            "parallel capacitors: voltage",
            t,
            traj.column("voltage").unwrap(),
            |t| e * (1.0 - (-t / tau).exp()),
            1e-8,
        );
        assert_matches(
            "parallel capacitors: current into C2",
            t,
            traj.column("i2").unwrap(),
            |t| c2 * e / tau * (-t / tau).exp(),
            1e-8,
        );
        assert_energy_closes(&model, tight(1e-20), 0.012, 101, 1e-8);
    }
}

mod shaken_mass {
    use super::*;

    /// v = A sin ωt imposed on the mass: the source must deliver F = m A ω cos ωt, and
    /// the kinematic position is A/ω (1 − cos ωt). Nothing to solve (the motion is
    /// prescribed), and the only state is the kinematic one.
    #[test]
    fn need_the_force_that_accelerates_the_mass() {
        let params = ShakenMassParams::default();
        let model = ShakenMass::new(params.clone());
        assert_eq!(ShakenMass::STATE_NAMES, ["x"]);
        assert_eq!(ShakenMass::DEPENDENT_STORAGE, ["mass"]);
        let (traj, _) = run(&model, tight(1e-16), &initial_state(&model), 1.0, 201);
        let (m, a, w) = (params.m, params.a, params.omega);
        let t = traj.times();
        // Read from t alone, with nothing integrated: to rounding.
        assert_matches(
            "shaken: source force",
            t,
            traj.column("force").unwrap(),
            |t| m * a * w * (w * t).cos(),
            1e-12,
        );
        assert_matches(
            "shaken: mass force",
            t,
            traj.column("mass_force").unwrap(),
            |t| m * a * w * (w * t).cos(),
            1e-12,
        );
        assert_matches(
            "shaken: position",
            t,
            traj.column("x").unwrap(),
            |t| a / w * (1.0 - (w * t).cos()),
            1e-8,
        );
        // The mass's kinetic energy ½ m v(t)² is what the source has put in.
        assert_energy_closes(&model, tight(1e-16), 1.0, 201, 1e-8);
    }

    /// Without the kinematic position the model has no state at all: its outputs
    /// still give the force, evaluated alone and along a run.
    #[test]
    fn need_no_state_to_say_the_force() {
        assert_eq!(ShakenMassAlone::N_STATES, 0);
        let model = ShakenMassAlone::default();
        let (m, a, w) = (model.params.m, model.params.a, model.params.omega);
        let mut y = [0.0];
        model.outputs::<f64>(0.3, &[], &mut y);
        assert!((y[0] - m * a * w * (w * 0.3).cos()).abs() <= 1e-15, "{y:?}");
        let (traj, _) = run(&model, tight(1e-16), &[], 1.0, 11);
        let t = traj.times();
        assert_matches(
            "shaken, no state: force",
            t,
            traj.column("force").unwrap(),
            |t| m * a * w * (w * t).cos(),
            1e-12,
        );
    }
}

mod drawing {
    use super::*;
    use common::implicit::{assert_drawing_marks, assert_graphviz_parses};

    /// `DEPENDENT_STORAGE` names the storage without a state, the causal graph has it
    /// in derivative causality and the DOT text draws it and its bonds red (with a
    /// legend); nothing is on a loop. Graphviz reads every drawing.
    #[test]
    fn mark_the_dependent_storage() {
        assert_eq!(GluedMasses::DEPENDENT_STORAGE.len(), 1);
        assert!(["first", "second"].contains(&GluedMasses::DEPENDENT_STORAGE[0]));
        assert_eq!(ParallelCapacitors::DEPENDENT_STORAGE.len(), 1);
        assert!(["cap1", "cap2"].contains(&ParallelCapacitors::DEPENDENT_STORAGE[0]));
        let drawings = [
            assert_drawing_marks::<Gear>(&Gear::GRAPH),
            assert_drawing_marks::<GluedMasses>(&GluedMasses::GRAPH),
            assert_drawing_marks::<ParallelCapacitors>(&ParallelCapacitors::GRAPH),
            assert_drawing_marks::<ShakenMass>(&ShakenMass::GRAPH),
            assert_drawing_marks::<ShakenMassAlone>(&ShakenMassAlone::GRAPH),
        ];
        for dot in &drawings {
            assert!(dot.contains("derivative causality (dependent storage)"));
            assert!(!dot.contains("color=\"orange\""), "no loop drawn: {dot}");
            assert_graphviz_parses(dot);
        }
    }
}
