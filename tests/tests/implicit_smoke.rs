//! End to end through the compiler's implicit path (issue 12): a rigid gear (dependent
//! storage, one torn unknown) and two dampers in series (an allowed algebraic loop),
//! against closed forms; and the gear's Jacobian through the solve against a central
//! difference.

use bgdsl_runtime::{bond_graph, Dual, Model};

bond_graph! {
    /// Two inertias through a rigid gear: one degree of freedom. The drag makes the
    /// derivative depend on the state, so the Jacobian through the solve is not zero.
    #[allow(derivative_causality)]
    pub model Gear {
        param j1 = 0.2; param j2 = 0.05; param n = 3.0; param torque = 1.0;
        param drag = 0.0;
        Se motor = torque - drag * shaft1.f;
        I  shaft1 = j1;
        I  shaft2 = j2;
        1  w1; 1 w2;
        TF gear = n;
        motor -> w1 -> shaft1;
        w1 -> gear -> w2 -> shaft2;
        output w2_speed = shaft2.f;
        output gear_torque = shaft2.e;
    }
}

bond_graph! {
    /// A mass slowed by two dampers in series: one force, velocities that add.
    pub model SeriesDampers {
        param r1 = 2.0; param r2 = 3.0; param m = 1.5; param v0 = 1.0;
        I mass = m;
        #[allow(algebraic_loops)]
        R d1 = r1;
        R d2 = r2;
        1 v; 0 j;
        v -> mass;
        v -> j -> { d1, d2 };
        init mass.p = m * v0;
        output force = d1.e;
    }
}

fn derivative(model: &impl Model, t: f64, x: &[f64]) -> Vec<f64> {
    let mut dx = vec![0.0; x.len()];
    model.derivatives(t, x, &mut dx);
    dx
}

#[test]
fn the_gear_has_one_state_and_the_reflected_inertia() {
    assert_eq!(Gear::STATE_NAMES, ["shaft1.p"]);
    assert_eq!(Gear::DEPENDENT_STORAGE, ["shaft2"]);
    let gear = Gear::default();
    let p = gear.params.clone();
    let t_end = 0.5;
    let trajectory =
        bgdsl_runtime::simulate(&gear, bgdsl_runtime::Solver::default(), 0.0, t_end, 3).unwrap();
    let omega1 = p.torque * t_end / (p.j1 + p.n * p.n * p.j2);
    let p1 = trajectory.value(2, "shaft1.p").unwrap();
    assert!(
        (p1 - p.j1 * omega1).abs() < 1e-9,
        "{p1} vs {}",
        p.j1 * omega1
    );
    let speed = trajectory.value(2, "w2_speed").unwrap();
    assert!((speed - p.n * omega1).abs() < 1e-9, "{speed}");
    // The gear's torque on the second shaft accelerates it: J2 n ω̇1.
    let mut y = [0.0; 2];
    gear.outputs(t_end, &[p1], &mut y);
    let alpha1 = p.torque / (p.j1 + p.n * p.n * p.j2);
    assert!((y[1] - p.j2 * p.n * alpha1).abs() < 1e-12, "{y:?}");
}

#[test]
fn the_gear_stores_the_energy_of_both_shafts() {
    let gear = Gear::default();
    let p = gear.params.clone();
    let omega1 = 2.0;
    let balance = gear.power_balance(0.0, &[p.j1 * omega1]).unwrap();
    let expected = 0.5 * p.j1 * omega1.powi(2) + 0.5 * p.j2 * (p.n * omega1).powi(2);
    assert!(
        (balance.stored - expected).abs() < 1e-12,
        "{} vs {expected}",
        balance.stored
    );
}

#[test]
fn the_gear_jacobian_through_the_solve_is_exact() {
    let mut gear = Gear::default();
    gear.params.drag = 0.7;
    let x = 0.3;
    let mut dx = [Dual::constant(0.0)];
    gear.derivatives(0.1, &[Dual::variable(x)], &mut dx);
    let h = 1e-6;
    let central =
        (derivative(&gear, 0.1, &[x + h])[0] - derivative(&gear, 0.1, &[x - h])[0]) / (2.0 * h);
    let p = &gear.params;
    let exact = -p.drag / (p.j1 + p.n * p.n * p.j2);
    assert!(
        (dx[0].eps - exact).abs() < 1e-12,
        "{} vs {exact}",
        dx[0].eps
    );
    assert!(
        (dx[0].eps - central).abs() < 1e-7,
        "{} vs {central}",
        dx[0].eps
    );
}

#[test]
fn two_dampers_in_series_act_as_one() {
    let model = SeriesDampers::default();
    let p = model.params.clone();
    assert_eq!(SeriesDampers::ALGEBRAIC_LOOPS.len(), 1);
    let r = p.r1 * p.r2 / (p.r1 + p.r2);
    let t_end = 0.4;
    let trajectory =
        bgdsl_runtime::simulate(&model, bgdsl_runtime::Solver::default(), 0.0, t_end, 2).unwrap();
    let momentum = trajectory.value(1, "mass.p").unwrap();
    let expected = p.m * p.v0 * (-r * t_end / p.m).exp();
    assert!(
        (momentum - expected).abs() < 1e-7,
        "{momentum} vs {expected}"
    );
    let dx = derivative(&model, 0.0, &[p.m * p.v0]);
    assert!((dx[0] + r * p.v0).abs() < 1e-12, "{dx:?}");
}
