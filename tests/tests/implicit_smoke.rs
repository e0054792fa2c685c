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
    let causality = |name: &str| {
        Gear::GRAPH
            .elements
            .iter()
            .find(|e| e.name == name)
            .map(|e| e.causality)
    };
    assert_eq!(
        causality("shaft2"),
        Some(bgdsl_runtime::ElementCausality::Derivative)
    );
    assert_eq!(
        causality("shaft1"),
        Some(bgdsl_runtime::ElementCausality::Integral)
    );
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
    assert_eq!(SeriesDampers::ALGEBRAIC_LOOPS, [["d1", "d2", "j"]]);
    let looped: Vec<&str> = SeriesDampers::GRAPH.loops[0]
        .iter()
        .map(|&i| SeriesDampers::GRAPH.elements[i].name)
        .collect();
    assert_eq!(looped, ["d1", "d2", "j"]);
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

bond_graph! {
    /// A quadratic damper in series with a linear one: a non-linear loop.
    #[allow(algebraic_loops)]
    pub model QuadraticSeries {
        param c = 4.0; param r2 = 3.0; param m = 1.5; param v0 = 1.0;
        I mass = m;
        R d1 { e = c * f * f.abs() };
        R d2 = r2;
        1 v; 0 j;
        v -> mass;
        v -> j -> { d1, d2 };
        init mass.p = m * v0;
    }
}

/// The force F of the series pair at speed v: F = c f1 |f1| with f1 = v − F/r2, by
/// bisection (F lies between 0 and r2 v).
fn quadratic_series_force(c: f64, r2: f64, v: f64) -> f64 {
    let excess = |force: f64| {
        let f1 = v - force / r2;
        c * f1 * f1.abs() - force
    };
    let (mut lo, mut hi) = (0.0_f64.min(r2 * v), 0.0_f64.max(r2 * v));
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (excess(mid) > 0.0) == (excess(lo) > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn a_nonlinear_loop_is_solved_by_newton() {
    let model = QuadraticSeries::default();
    let p = model.params.clone();
    for v in [1.0, -0.3, 2.5] {
        let dx = derivative(&model, 0.0, &[p.m * v]);
        let force = quadratic_series_force(p.c, p.r2, v);
        assert!((dx[0] + force).abs() < 1e-9, "v = {v}: {dx:?} vs {force}");
    }
}

#[test]
fn a_singular_loop_is_reported_with_its_members_not_passed_on_as_numbers() {
    let mut model = SeriesDampers::default();
    model.params.r1 = -model.params.r2;
    let dx = derivative(&model, 0.25, &[1.0]);
    assert!(dx[0].is_nan(), "{dx:?}");
    let error = model.evaluation_error().expect("the failure is recorded");
    let text = error.to_string();
    assert!(
        matches!(error, bgdsl_runtime::ModelError::SingularConstraint { t, .. } if t == 0.25),
        "{text}"
    );
    for name in ["d1", "d2"] {
        assert!(text.contains(name), "{text}");
    }
}

bond_graph! {
    /// Storage driven by sources: the inertia's effort and the compliance's flow are
    /// derivatives of what the sources prescribe; no unknown, no solve.
    #[allow(derivative_causality)]
    pub model Prescribed {
        param m = 2.0; param k = 4.0; param a = 3.0;
        Sf push = a * t;
        I mass = m;
        Se squeeze = a * t * t;
        C spring = k;
        1 v; 0 j;
        push -> v -> mass;
        squeeze -> j -> spring;
        output force = mass.e;
        output rate = spring.f;
    }
}

#[test]
fn storage_driven_by_sources_returns_the_derivative_of_its_energy_variable() {
    assert_eq!(Prescribed::N_STATES, 0);
    assert_eq!(Prescribed::DEPENDENT_STORAGE, ["mass", "spring"]);
    let model = Prescribed::default();
    let p = model.params.clone();
    let t = 0.7;
    let mut y = [0.0; 2];
    model.outputs(t, &[], &mut y);
    // F = d/dt (m a t) = m a; q = a t² / k, so f = 2 a t / k.
    assert!((y[0] - p.m * p.a).abs() < 1e-12, "{y:?}");
    assert!((y[1] - 2.0 * p.a * t / p.k).abs() < 1e-12, "{y:?}");
    let balance = model.power_balance(t, &[]).unwrap();
    let stored = 0.5 * p.m * (p.a * t).powi(2) + 0.5 * (p.a * t * t).powi(2) / p.k;
    let stored_now: f64 = balance.stored;
    assert!((stored_now - stored).abs() < 1e-12, "{stored_now}");
}

bond_graph! {
    /// A wheel driving a slider through a rigid arm: the slider's speed is r cos θ ω, so
    /// the inertia the motor sees depends on the configuration.
    #[allow(derivative_causality)]
    pub model RigidArm {
        param j = 0.1; param m = 2.0; param r = 0.5; param tau = 1.0;
        state theta: f64 = 0.3;
        der theta = wheel.f;
        Se motor = tau;
        I wheel = j;
        MTF arm = r * theta.cos();
        I slider = m;
        1 w; 1 s;
        motor -> w -> wheel;
        w -> arm -> s -> slider;
    }
}

/// ṗ of the wheel from Lagrange: (j + m r² cos²θ) ω̇ = τ + m r² cos θ sin θ ω².
fn rigid_arm_rate(p: &RigidArmParams, x: &[f64]) -> f64 {
    let (omega, theta) = (x[0] / p.j, x[1]);
    let (c, s) = (theta.cos(), theta.sin());
    p.j * (p.tau + p.m * p.r * p.r * c * s * omega * omega) / (p.j + p.m * p.r * p.r * c * c)
}

#[test]
fn a_configuration_dependent_inertia_follows_lagrange_with_an_exact_jacobian() {
    let model = RigidArm::default();
    let p = model.params.clone();
    // ṗ reads both states through the solve; θ̇ only the momentum.
    let sparsity: &[&[usize]] = &[&[0, 1], &[0]];
    assert_eq!(RigidArm::JACOBIAN_SPARSITY, Some(sparsity));
    for x in [[0.05, 0.3], [-0.2, 1.2], [0.3, 2.9]] {
        let dx = derivative(&model, 0.0, &x);
        assert!(
            (dx[0] - rigid_arm_rate(&p, &x)).abs() < 1e-12,
            "{x:?}: {dx:?}"
        );
        assert!((dx[1] - x[0] / p.j).abs() < 1e-12, "{x:?}: {dx:?}");
        for column in 0..2 {
            let mut seeded = [Dual::constant(x[0]), Dual::constant(x[1])];
            seeded[column] = Dual::variable(x[column]);
            let mut dual = [Dual::constant(0.0); 2];
            model.derivatives(0.0, &seeded, &mut dual);
            let h = 1e-6;
            let (mut up, mut down) = (x, x);
            up[column] += h;
            down[column] -= h;
            let central = (rigid_arm_rate(&p, &up) - rigid_arm_rate(&p, &down)) / (2.0 * h);
            assert!(
                (dual[0].eps - central).abs() < 1e-6 * (1.0 + central.abs()),
                "{x:?} column {column}: {} vs {central}",
                dual[0].eps
            );
        }
    }
}

bond_graph! {
    /// A slider pushed along its track drags a 3-D body rigidly along direction n: the
    /// body's 3-D momentum is dependent storage (a vector energy variable).
    #[allow(derivative_causality)]
    pub model DraggedBody {
        param ms = 0.5; param mb = 2.0; param f0 = 4.0;
        param n: Vector3 = [0.0, 0.6, 0.8];
        Se push = f0;
        I slider = ms;
        MTF along = n;
        I[3] body = mb;
        1 s; 1 w;
        push -> s -> { slider, along };
        along -> w -> body;
        output body_force = body.e;
    }
}

#[test]
fn a_vector_dependent_storage_adds_its_projected_inertia() {
    let model = DraggedBody::default();
    let p = model.params.clone();
    let n2: f64 = p.n.iter().map(|c| c * c).sum();
    let dx = derivative(&model, 0.0, &[0.3]);
    // (ms + mb |n|²) u̇ = f0, and ṗ_slider = ms u̇.
    let accel = p.f0 / (p.ms + p.mb * n2);
    assert!((dx[0] - p.ms * accel).abs() < 1e-12, "{dx:?}");
    let mut y = [0.0; 3];
    model.outputs(0.0, &[0.3], &mut y);
    for (component, direction) in y.iter().zip(p.n) {
        assert!(
            (component - p.mb * direction * accel).abs() < 1e-12,
            "{y:?}"
        );
    }
}

#[test]
fn a_stiff_solver_runs_the_rigid_arm_to_the_same_state() {
    let model = RigidArm::default();
    let run = |solver| {
        let trajectory = bgdsl_runtime::simulate(&model, solver, 0.0, 0.5, 2).unwrap();
        [
            trajectory.state(1, 0).unwrap(),
            trajectory.state(1, 1).unwrap(),
        ]
    };
    let explicit = run(bgdsl_runtime::Solver::DormandPrince(
        bgdsl_runtime::DormandPrinceOptions {
            rtol: 1e-10,
            atol: 1e-12,
            ..Default::default()
        },
    ));
    let stiff = run(bgdsl_runtime::Solver::Rodas4(Default::default()));
    for (a, b) in explicit.iter().zip(stiff) {
        assert!((a - b).abs() < 1e-4, "{explicit:?} vs {stiff:?}");
    }
}

bond_graph! {
    /// The gear with its inverse modulus given: `Model::check` solves first too.
    #[allow(derivative_causality)]
    pub model CheckedGear {
        param n = 3.0; param wrong = 0.0;
        Se motor = 1.0;
        I shaft1 = 0.2;
        I shaft2 = 0.05;
        1 w1; 1 w2;
        TF gear = n, inverse = 1.0 / n + wrong;
        motor -> w1 -> shaft1;
        w1 -> gear -> w2 -> shaft2;
    }
}

#[test]
fn the_inverse_check_of_an_implicit_model_runs_after_the_solve() {
    let mut model = CheckedGear::default();
    assert!(model.check(0.0, &[0.1]).is_ok());
    model.params.wrong = 0.5;
    assert!(matches!(
        model.check(0.0, &[0.1]),
        Err(bgdsl_runtime::ModelError::WrongInverse {
            element: "gear",
            ..
        })
    ));
}
