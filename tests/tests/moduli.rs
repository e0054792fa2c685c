//! Two-ports between bonds of different dimensions: an n₂×n₁ modulus between a
//! port-1 bond of dimension n₁ and a port-2 bond of dimension n₂, checked against
//! hand-written equations, the energy account and closed forms; and a TF or GY whose
//! modulus is a plain number on a 3-D bond, run backwards by dividing by it.

mod common;

use bgdsl_runtime::multibond::{vec3, Matrix3, Vector3};
use bgdsl_runtime::{bond_graph, JacobianEvaluator, Model};
use common::{assert_close, dopri5, initial_state, run, seeded_states};

bond_graph! {
    /// A 3-D mass pushed by a constant force, with a scalar damper acting only along
    /// the direction `n`: the damper's velocity is nᵀ v, its force n c nᵀ v.
    pub model ProjectedDamper {
        /// mass, kg
        param m = 2.0;
        /// damping along n, N·s/m
        param c = 3.0;
        /// the damper's direction (a unit vector)
        param n: Vector3 = [0.6, 0.0, 0.8];
        /// the force, N
        param F: Vector3 = [1.0, -2.0, 0.5];

        Se push = F;
        I[3] mass = m;
        1 v;
        MTF proj = n.transpose();
        R damper = c;

        push -> v -> { mass, proj };
        proj -> damper;

        output speed_along_n = damper.f;
        output P_diss = damper.e * damper.f;
    }
}

bond_graph! {
    /// A slider of mass m moving along the direction `n` of 3-D space, held by a 3-D
    /// spring K and pushed by a scalar force along its track: the slider's speed u
    /// gives the 3-D velocity n u, the spring's 3-D force K q the scalar nᵀ K q.
    pub model SliderOnATrack {
        /// slider mass, kg
        param m = 0.5;
        /// the track's direction (a unit vector)
        param n: Vector3 = [0.0, 0.6, 0.8];
        /// the spring's stiffness, N/m
        param K: Matrix3 = [[100.0, 0.0, 0.0], [0.0, 200.0, 0.0], [0.0, 0.0, 300.0]];
        /// the push along the track, N
        param f0 = 4.0;

        Se push = f0;
        I slider = m;
        1 s;
        MTF along = n;
        1 w;
        C spring = K;

        push -> s -> { slider, along };
        along -> w -> spring;

        output u = slider.f;
    }
}

bond_graph! {
    /// A 3-D mass coupled by a gyrator with a 1×3 modulus to a scalar inertia:
    /// e₂ = nᵀ v drives the inertia, e₁ = n ω pushes back on the mass.
    pub model ProjectedGyrator {
        param m = 1.5;
        param J = 0.25;
        param n: Vector3 = [0.0, 0.8, -0.6];
        param F: Vector3 = [0.5, 1.0, -1.5];

        Se push = F;
        I[3] mass = m;
        1 v;
        MGY couple = n.transpose();
        I spin = J;

        push -> v -> { mass, couple };
        couple -> spin;
    }
}

fn n_of(n: [f64; 3]) -> Vector3<f64> {
    vec3(n[0], n[1], n[2])
}

/// ṗ = F − n c nᵀ p / m, checked at several states, with the damper's power
/// c (nᵀ v)² as the model's dissipation and d(stored)/dt = input − dissipated.
#[test]
fn project_a_3d_velocity_on_a_scalar_damper() {
    let model = ProjectedDamper::default();
    let params = model.params().clone();
    let (n, force) = (n_of(params.n), n_of(params.F));
    assert_eq!(
        ProjectedDamper::STATE_NAMES,
        ["mass.p_x", "mass.p_y", "mass.p_z"]
    );
    for p in [
        vec3(0.3, -0.7, 1.1),
        vec3(-2.0, 0.5, 0.25),
        vec3(0.0, 0.0, 0.0),
    ] {
        let x = [p.x, p.y, p.z];
        let mut dx = [0.0; 3];
        model.derivatives(0.0, &x, &mut dx);
        let v = p / params.m;
        let expected = force - n * (params.c * n.dot(&v));
        assert!(
            (vec3(dx[0], dx[1], dx[2]) - expected).norm() < 1e-13,
            "{dx:?}"
        );
        let mut y = [0.0; 2];
        model.outputs(0.0, &x, &mut y);
        assert!((y[0] - n.dot(&v)).abs() < 1e-14);
        let dissipated = params.c * n.dot(&v).powi(2);
        assert!((y[1] - dissipated).abs() < 1e-13);
        let balance = model.power_balance(0.0, &x).unwrap();
        assert!((balance.dissipated - dissipated).abs() < 1e-13);
        let stored_rate = p.dot(&expected) / params.m;
        assert!((stored_rate - (balance.input - balance.dissipated)).abs() < 1e-13);
    }
}

/// From rest, the momentum along n relaxes to m nᵀF / c while the rest grows
/// linearly: p(t) = (F − n nᵀF) t + n (m nᵀF / c)(1 − e^{−c t / m}).
#[test]
fn follow_the_closed_form_of_a_mass_damped_along_one_direction() {
    let model = ProjectedDamper::default();
    let params = model.params().clone();
    let (n, force) = (n_of(params.n), n_of(params.F));
    let (trajectory, _) = run(&model, dopri5(1e-11, 1e-13), &[0.0; 3], 2.0, 41);
    for (i, &t) in trajectory.times().iter().enumerate() {
        let along = n.dot(&force);
        let exact = (force - n * along) * t
            + n * (params.m * along / params.c) * (1.0 - (-params.c * t / params.m).exp());
        let state = |j: usize| trajectory.state(i, j).unwrap();
        let p = vec3(state(0), state(1), state(2));
        assert!((p - exact).norm() < 1e-8, "t = {t}: {p:?} vs {exact:?}");
    }
}

/// u = p / m; q̇ = n u; ṗ = f0 − nᵀ K q: a scalar mass seen as a 3-D velocity, and
/// the 3-D spring's force seen as a scalar one.
#[test]
fn drive_a_3d_spring_from_a_scalar_slider() {
    let model = SliderOnATrack::default();
    let params = model.params().clone();
    let n = n_of(params.n);
    let k = Matrix3::from_fn(|i, j| params.K[i][j]);
    assert_eq!(
        SliderOnATrack::STATE_NAMES,
        ["slider.p", "spring.q_x", "spring.q_y", "spring.q_z"]
    );
    for x in [[0.4, 0.01, -0.02, 0.03], [-1.0, 0.0, 0.1, 0.0]] {
        let mut dx = [0.0; 4];
        model.derivatives(0.0, &x, &mut dx);
        let q = vec3(x[1], x[2], x[3]);
        let u = x[0] / params.m;
        assert!(
            (dx[0] - (params.f0 - n.dot(&(k * q)))).abs() < 1e-13,
            "{dx:?}"
        );
        assert!((vec3(dx[1], dx[2], dx[3]) - n * u).norm() < 1e-15, "{dx:?}");
        let balance = model.power_balance(0.0, &x).unwrap();
        assert!((balance.input - params.f0 * u).abs() < 1e-13);
        assert_eq!(balance.dissipated, 0.0);
    }
}

/// From rest at q = 0 the spring stays stretched along n, q = n s, with
/// m s̈ = f0 − (nᵀ K n) s: s(t) = f0 / k (1 − cos ω t), ω² = k / m, k = nᵀ K n.
#[test]
fn oscillate_along_the_track_as_a_scalar_oscillator_would() {
    let model = SliderOnATrack::default();
    let params = model.params().clone();
    let n = n_of(params.n);
    let k_along = n.dot(&(Matrix3::from_fn(|i, j| params.K[i][j]) * n));
    let omega = (k_along / params.m).sqrt();
    let x0 = initial_state(&model);
    let (trajectory, _) = run(&model, dopri5(1e-11, 1e-14), &x0, 1.0, 51);
    for (i, &t) in trajectory.times().iter().enumerate() {
        let s = params.f0 / k_along * (1.0 - (omega * t).cos());
        let state = |j: usize| trajectory.state(i, j).unwrap();
        let q = vec3(state(1), state(2), state(3));
        assert!((q - n * s).norm() < 1e-8, "t = {t}: {q:?} vs {:?}", n * s);
    }
}

/// A gyrator with a 1×3 modulus: e₂ = nᵀ v into the inertia, e₁ = n ω out of the
/// 3-D junction: ṗ = F − n h / J, ḣ = nᵀ p / m.
#[test]
fn gyrate_between_a_3d_bond_and_a_scalar_one() {
    let model = ProjectedGyrator::default();
    let params = model.params().clone();
    let (n, force) = (n_of(params.n), n_of(params.F));
    let x = [0.2, -0.4, 0.9, 0.3];
    let mut dx = [0.0; 4];
    model.derivatives(0.0, &x, &mut dx);
    let p = vec3(x[0], x[1], x[2]);
    let expected = force - n * (x[3] / params.J);
    assert!(
        (vec3(dx[0], dx[1], dx[2]) - expected).norm() < 1e-14,
        "{dx:?}"
    );
    assert!((dx[3] - n.dot(&p) / params.m).abs() < 1e-14, "{dx:?}");
}

bond_graph! {
    /// A force given in frame 0 pushing a mass whose momentum is kept in a frame turned
    /// by θ about z: the MTF's modulus is R(θ)ᵀ, and the force at port 1 makes it run
    /// backwards through the inverse its law gives, R(θ + wrong). With `wrong = 0`
    /// that is the inverse; otherwise it is not.
    pub model TurnedFrame {
        param theta = 0.4;
        /// how far the given inverse is turned from the true one, rad
        param wrong = 0.0;
        param m = 2.0;
        param F: Vector3 = [1.0, 2.0, 3.0];

        Se push = F;
        MTF to_frame = rot_z(theta).transpose(), inverse = rot_z(theta + wrong);
        I[3] mass = m;
        1 w;

        push -> to_frame -> w -> mass;
    }
}

use bgdsl_runtime::multibond::rot_z;
use bgdsl_runtime::{ModelError, Simulation, SolverError};

fn turned_frame(wrong: f64) -> TurnedFrame {
    TurnedFrame::new(TurnedFrameParams {
        wrong,
        ..Default::default()
    })
}

/// A right inverse passes the check, and the mass feels e₂ = M⁻ᵀ e₁ = R(θ)ᵀ F.
#[test]
fn accept_an_inverse_that_is_one() {
    let model = turned_frame(0.0);
    let x0 = initial_state(&model);
    assert_eq!(model.check(0.0, &x0), Ok(()));
    let mut dx = [0.0; 3];
    model.derivatives(0.0, &x0, &mut dx);
    let expected = rot_z(0.4).transpose() * vec3(1.0, 2.0, 3.0);
    assert!(
        (vec3(dx[0], dx[1], dx[2]) - expected).norm() < 1e-14,
        "{dx:?}"
    );
    let (trajectory, _) = run(&model, dopri5(1e-9, 1e-12), &x0, 0.2, 3);
    assert_eq!(trajectory.times().len(), 3);
}

/// A wrong inverse compiles (the compiler cannot tell), but the check before a run
/// refuses it, naming the element, the time and ‖M X − I‖ = ‖R(θ)ᵀ R(θ + δ) − I‖ =
/// ‖R(δ) − I‖ = 2 √(1 − cos δ).
#[test]
fn refuse_a_wrong_inverse_before_the_run_starts() {
    let model = turned_frame(0.5);
    let x0 = initial_state(&model);
    let expected = 2.0 * (1.0 - 0.5_f64.cos()).sqrt();
    match model.check(0.0, &x0) {
        Err(ModelError::WrongInverse {
            element,
            t,
            residual,
        }) => {
            assert_eq!((element, t), ("to_frame", 0.0));
            assert!((residual - expected).abs() < 1e-14, "{residual}");
        }
        other => panic!("expected a wrong inverse, got {other:?}"),
    }
    let mut simulation = Simulation::new(&model, dopri5(1e-9, 1e-12)).unwrap();
    let error = simulation
        .run_uniform(0.0, &x0, 0.2, 3, &mut ())
        .unwrap_err();
    assert!(matches!(error, SolverError::InvalidModel(_)), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains("the inverse given for the modulus of `to_frame` is not its inverse"),
        "{message}"
    );
}

/// In a debug build every evaluation of the derivatives in `f64` checks it too.
#[cfg(debug_assertions)]
#[test]
#[should_panic(
    expected = "at t = 0.25, the inverse given for the modulus of `to_frame` is not its inverse"
)]
fn assert_a_wrong_inverse_at_every_use_in_debug_builds() {
    let model = turned_frame(0.5);
    let mut dx = [0.0; 3];
    model.derivatives(0.25, &[0.0; 3], &mut dx);
}

bond_graph! {
    /// A 3-D lever of ratio n run backwards: a spring on port 1 gives it its effort,
    /// a mass on port 2 its flow, so it computes `e2 = e1 / n` and `f1 = f2 / n`. A
    /// number's inverse is its reciprocal: no `inverse = ...` is needed.
    ///
    /// ```text
    /// Sf drive ⇀ 0 node ⇀ { C[3] spring, TF lever ⇀ 1 v ⇀ { I[3] mass, R[3] damper } }
    /// ```
    pub model LeverRunBackwards {
        /// mass, kg
        param m = 2.0;
        /// spring stiffness, N/m
        param k = 50.0;
        /// damping, N·s/m
        param c = 3.0;
        /// the lever's ratio, f2 = n f1
        param ratio = 2.5;
        /// the drive's velocity, m/s
        param V: Vector3 = [0.3, -0.2, 0.5];

        Sf drive = V;
        0 node;
        C[3] spring = k;
        TF lever = ratio;
        1 v;
        I[3] mass = m;
        R[3] damper = c;

        drive -> node -> { spring, lever };
        lever -> v -> { mass, damper };

        output lever_f1: Vector3 = lever.f1;
        output lever_e2: Vector3 = lever.e2;
    }
}

/// The lever by hand: v = p / m, f1 = v / n, e1 = k q, e2 = e1 / n, so
/// q̇ = V − v / n and ṗ = k q / n − c v.
fn lever_by_hand(p: &LeverRunBackwardsParams, x: &[f64; 6]) -> ([f64; 6], [f64; 6]) {
    let mut dx = [0.0; 6];
    let mut y = [0.0; 6];
    for i in 0..3 {
        let (stretch, momentum) = (x[i], x[3 + i]);
        let v = momentum / p.m;
        let (f1, e2) = (v / p.ratio, p.k * stretch / p.ratio);
        dx[i] = p.V[i] - f1;
        dx[3 + i] = e2 - p.c * v;
        y[i] = f1;
        y[3 + i] = e2;
    }
    (dx, y)
}

bond_graph! {
    /// A 3-D gyrator of modulus r run backwards: springs on both ports give it both
    /// efforts, so it computes `f2 = e1 / r` and `f1 = e2 / r`.
    ///
    /// ```text
    /// Sf drive ⇀ 0 a ⇀ { C[3] first, GY gyro ⇀ 0 b ⇀ { C[3] second, R[3] leak } }
    /// ```
    pub model GyratorRunBackwards {
        /// first spring's stiffness, N/m
        param k1 = 40.0;
        /// second spring's stiffness, N/m
        param k2 = 70.0;
        /// the leak's resistance, N·s/m
        param c = 5.0;
        /// the gyrator's modulus, e2 = r f1
        param r = 0.8;
        /// the drive's velocity, m/s
        param V: Vector3 = [0.3, -0.2, 0.5];

        Sf drive = V;
        0 a;
        C[3] first = k1;
        GY gyro = r;
        0 b;
        C[3] second = k2;
        R[3] leak = c;

        drive -> a -> { first, gyro };
        gyro -> b -> { second, leak };

        output gyro_f1: Vector3 = gyro.f1;
        output gyro_f2: Vector3 = gyro.f2;
    }
}

/// The gyrator by hand: e1 = k1 q1, e2 = k2 q2, f2 = e1 / r, f1 = e2 / r, so
/// q̇1 = V − k2 q2 / r and q̇2 = k1 q1 / r − k2 q2 / c.
fn gyrator_by_hand(p: &GyratorRunBackwardsParams, x: &[f64; 6]) -> ([f64; 6], [f64; 6]) {
    let mut dx = [0.0; 6];
    let mut y = [0.0; 6];
    for i in 0..3 {
        let (e1, e2) = (p.k1 * x[i], p.k2 * x[3 + i]);
        let (f1, f2) = (e2 / p.r, e1 / p.r);
        dx[i] = p.V[i] - f1;
        dx[3 + i] = f2 - e2 / p.c;
        y[i] = f1;
        y[3 + i] = f2;
    }
    (dx, y)
}

#[test]
fn run_a_scalar_lever_on_a_multibond_backwards_by_dividing() {
    let model = LeverRunBackwards::default();
    assert_eq!(
        LeverRunBackwards::STATE_NAMES,
        [
            "spring.q_x",
            "spring.q_y",
            "spring.q_z",
            "mass.p_x",
            "mass.p_y",
            "mass.p_z"
        ]
    );
    let p = model.params().clone();
    for x in seeded_states::<6>(0x1e7e5, 50) {
        let (expected_dx, expected_y) = lever_by_hand(&p, &x);
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        assert_close(&dx, &expected_dx, "derivative");
        let mut y = [0.0; 6];
        model.outputs(0.0, &x, &mut y);
        assert_close(&y, &expected_y, "output");
        // The lever passes power on: d(stored)/dt = input − dissipated.
        let balance = model.power_balance(0.0, &x).expect("an account");
        let rate: f64 = (0..3)
            .map(|i| p.k * x[i] * dx[i] + x[3 + i] / p.m * dx[3 + i])
            .sum();
        assert!((rate - (balance.input - balance.dissipated)).abs() <= 1e-12);
    }
    // The solvers' Jacobian (dual numbers through the same division): per component,
    // ∂q̇/∂p = −1 / (m n), ∂ṗ/∂q = k / n, ∂ṗ/∂p = −c / m, and nothing across components.
    let mut evaluator = JacobianEvaluator::new(&model);
    let mut jacobian = [f64::NAN; 36];
    evaluator.evaluate(
        &model,
        0.0,
        &[0.1, -0.2, 0.3, 0.4, -0.5, 0.6],
        &mut jacobian,
    );
    let mut expected = [0.0; 36];
    for i in 0..3 {
        expected[i * 6 + 3 + i] = -1.0 / (p.m * p.ratio);
        expected[(3 + i) * 6 + i] = p.k / p.ratio;
        expected[(3 + i) * 6 + 3 + i] = -p.c / p.m;
    }
    assert_close(&jacobian, &expected, "Jacobian entry");
}

#[test]
fn run_a_scalar_gyrator_on_a_multibond_backwards_by_dividing() {
    let model = GyratorRunBackwards::default();
    assert_eq!(
        GyratorRunBackwards::STATE_NAMES,
        [
            "first.q_x",
            "first.q_y",
            "first.q_z",
            "second.q_x",
            "second.q_y",
            "second.q_z"
        ]
    );
    let p = model.params().clone();
    for x in seeded_states::<6>(0x1e7e5, 50) {
        let (expected_dx, expected_y) = gyrator_by_hand(&p, &x);
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        assert_close(&dx, &expected_dx, "derivative");
        let mut y = [0.0; 6];
        model.outputs(0.0, &x, &mut y);
        assert_close(&y, &expected_y, "output");
        let balance = model.power_balance(0.0, &x).expect("an account");
        let rate: f64 = (0..3)
            .map(|i| p.k1 * x[i] * dx[i] + p.k2 * x[3 + i] * dx[3 + i])
            .sum();
        assert!((rate - (balance.input - balance.dissipated)).abs() <= 1e-12);
    }
}
