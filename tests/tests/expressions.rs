//! Expressions in laws, outputs and `der`: `f64` constants and functions of parameters
//! (computed once, in `f64`, and lifted into the scalar type), time-dependent sources,
//! and component access on every kind of value, against hand-written equations.

mod common;

use bgdsl_runtime::multibond::{box_inertia, vec3};
use bgdsl_runtime::{bond_graph, DualN, Model};
use common::{dopri5, max_abs, run};

/// A constant of the user's scope, used in a law.
const GAIN: f64 = 2.0;

/// A plain `f64` function of the user's scope, used on parameters in a law.
fn stiffness_of(area: f64, modulus: f64, length: f64) -> f64 {
    area * modulus / length
}

bond_graph! {
    /// A series RL circuit driven by `v0 sin(2π f t)`: `L di/dt = v0 sin(ωt) − R i`.
    pub model SineRl {
        param v0 = 3.0 in "V";
        param freq = 2.0 in "Hz";
        param l = 0.5 in "H";
        param r = 4.0 in "Ω";
        Se src = v0 * (2.0 * core::f64::consts::PI * freq * t).sin();
        I coil = l, p in "Wb";
        R res = r;
        1 loop_current;
        src -> loop_current -> { coil, res };
        output current = loop_current.f in "A";
    }
}

bond_graph! {
    /// Parameter expressions of every kind: a user's constant and function, a
    /// standard-library helper, a square root, a vector parameter's components.
    pub model Derived {
        param m = 2.0;
        param area = 1.0e-4;
        param modulus = 2.0e9;
        param length = 0.5;
        param sides: [f64; 3] = [0.3, 0.2, 0.1];
        Se push = GAIN * (stiffness_of(area, modulus, length) / m).sqrt();
        I mass = m;
        C spring = stiffness_of(area, modulus, length);
        1 v;
        push -> v -> { mass, spring };
        output inertia_x = box_inertia(m, sides.x, sides[1], sides.z).x * v.f;
        output natural = (stiffness_of(area, modulus, length) / m).sqrt();
    }
}

bond_graph! {
    /// Component access on a 3-D signal, a storage state, a kinematic state and a
    /// parameter, in laws, outputs and `der`.
    pub model Components {
        param K: [f64; 3] = [1.0, 2.0, 3.0];
        param M: [[f64; 2]; 2] = [[1.0, 2.0], [3.0, 4.0]];
        Se[3] drive = vec3(K.x, K[1], K.z);
        I[3] mass = 1.0;
        1 vel;
        drive -> vel -> mass;
        state pos: Vector3 = [0.0, 0.0, 0.0];
        der pos = vel.f;
        Se push = M[1][0] + M[(0, 1)] + pos.y;
        C spring = 10.0;
        I coil = 1.0;
        1 s;
        push -> s -> { spring, coil };
        init coil.p = M[0][1] + K.z;
        output vx = vel.f.x;
        output pz = mass.p[2];
        output py = pos.y;
        output qz = spring.q * K.z;
    }
}

mod should {
    use super::*;

    /// The Se's `f64` time function drives the coil: the current follows the closed
    /// form of a series RL circuit switched onto a sine at t = 0,
    /// `i = v0 / (R² + ω²L²) (R sin ωt − ωL cos ωt + ωL e^{−Rt/L})`.
    #[test]
    fn drive_a_series_rl_circuit_with_a_sine_of_time() {
        let model = SineRl::default();
        let p = &model.params;
        let (v0, omega, l, r) = (p.v0, 2.0 * core::f64::consts::PI * p.freq, p.l, p.r);
        let (traj, _) = run(&model, dopri5(1e-11, 1e-14), &[0.0], 2.0, 401);
        let exact = |t: f64| {
            v0 / (r * r + omega * omega * l * l)
                * (r * (omega * t).sin() - omega * l * (omega * t).cos()
                    + omega * l * (-r * t / l).exp())
        };
        let computed = traj.column("current").unwrap();
        let error = max_abs(
            traj.times()
                .iter()
                .zip(computed)
                .map(|(&t, i)| i - exact(t)),
        );
        let scale = max_abs(traj.times().iter().map(|&t| exact(t)));
        assert!(
            error < 1e-8 * scale,
            "error {error:e} of amplitude {scale:e}"
        );
    }

    /// Every parameter expression takes the value hand-written Rust gives it, in
    /// `f64` and in dual numbers (where it is a constant: no derivative).
    #[test]
    fn evaluate_constants_and_functions_of_parameters() {
        let model = Derived::default();
        let k = stiffness_of(1.0e-4, 2.0e9, 0.5);
        let (m, q, momentum) = (2.0, 1.0e-3, 0.5);
        let mut dx = [0.0; 2];
        model.derivatives(0.0, &[momentum, q], &mut dx);
        assert_eq!(dx, [GAIN * (k / m).sqrt() - k * q, momentum / m]);
        let mut y = [0.0; 2];
        model.outputs(0.0, &[momentum, q], &mut y);
        assert_eq!(y[0], box_inertia(m, 0.3, 0.2, 0.1).x * (momentum / m));
        assert_eq!(y[1], (k / m).sqrt());
        // In dual numbers, seeded along the momentum: d(dp/dt)/dp = 0, d(dq/dt)/dp = 1/m.
        let x = [DualN::<1>::new(momentum, [1.0]), DualN::constant(q)];
        let mut dx = [DualN::<1>::constant(0.0); 2];
        model.derivatives(0.0, &x, &mut dx);
        assert_eq!(
            (dx[0].value(), *dx[0].tangents()),
            (GAIN * (k / m).sqrt() - k * q, [0.0])
        );
        assert_eq!(*dx[1].tangents(), [1.0 / m]);
    }

    /// The parameter expressions follow the parameters however they change: through
    /// `set_parameter_values` (which recomputes them) and written straight into the
    /// public `params` (read fresh, not from a stale cache).
    #[test]
    fn recompute_parameter_expressions_when_parameters_change() {
        let mut model = Derived::default();
        let rhs = |model: &Derived| {
            let mut dx = [0.0; 2];
            model.derivatives(0.0, &[0.0, 0.0], &mut dx);
            dx[0]
        };
        let before = rhs(&model);
        let mut values = vec![0.0; Derived::N_PARAMETER_VALUES];
        model.parameter_values(&mut values);
        values[0] = 8.0; // m: 2 -> 8 halves sqrt(k / m)
        model.set_parameter_values(&values);
        assert_eq!(rhs(&model), before / 2.0);
        let mut y = [0.0; 2];
        model.outputs(0.0, &[0.0, 0.0], &mut y);
        assert_eq!(y[1], (stiffness_of(1.0e-4, 2.0e9, 0.5) / 8.0).sqrt());

        model.params.m = 32.0; // halves it again
        assert_eq!(rhs(&model), before / 4.0);
        let rebuilt = Derived::new(model.params.clone());
        assert_eq!(rhs(&rebuilt), before / 4.0);
    }

    /// `.x` `.y` `.z`, `[i]`, `[r][c]` and `[(r, c)]` read the same components on
    /// signals, storage and kinematic states and parameters, in laws, outputs, `der` and
    /// initial values.
    #[test]
    fn read_components_of_every_kind_of_value() {
        let model = Components::default();
        assert_eq!(
            Components::STATE_NAMES,
            ["mass.p_x", "mass.p_y", "mass.p_z", "spring.q", "coil.p", "pos_x", "pos_y", "pos_z"]
        );
        let mut x0 = [0.0; 8];
        model.initial_state(&mut x0);
        assert_eq!(x0[4], 2.0 + 3.0, "init coil.p = M[0][1] + K.z");
        let x = [0.5, 1.5, 2.5, 0.1, 0.2, 7.0, 8.0, 9.0];
        let mut dx = [0.0; 8];
        model.derivatives(0.0, &x, &mut dx);
        // d(mass.p)/dt = K; d(coil.p)/dt = M[1][0] + M[0][1] + pos.y − 10 q = 3 + 2 + 8 − 1;
        // d(spring.q)/dt = coil.p / 1; d(pos)/dt = vel.f = mass.p / 1.
        assert_eq!(dx, [1.0, 2.0, 3.0, 0.2, 12.0, 0.5, 1.5, 2.5]);
        let mut y = [0.0; 4];
        model.outputs(0.0, &x, &mut y);
        assert_eq!(y, [0.5, 2.5, 8.0, 0.1 * 3.0]);
    }
}
