//! The DC motor: its power balance, as an identity of the generated equations and
//! integrated over a run, and its steady state under a constant voltage.

mod common;

use bgdsl_runtime::{Model, Scalar, Simulation};
use common::{dopri5, Rng};
use models::{DcMotor, DcMotorParams};

/// The state of `DcMotor`, in physical variables.
struct Physical {
    current: f64,
    motor_speed: f64,
    twist: f64,
    load_speed: f64,
}

impl Physical {
    fn of(p: &DcMotorParams, x: &[f64]) -> Self {
        Physical {
            current: x[0] / p.inductance,
            motor_speed: x[1] / p.rotor_inertia,
            twist: x[2],
            load_speed: x[3] / p.load_inertia,
        }
    }

    /// Power into the system from the supply and the load torque, W.
    fn power_in(&self, p: &DcMotorParams) -> f64 {
        p.voltage * self.current - p.load_torque * self.load_speed
    }

    /// Power dissipated, W: winding, bearing, shaft damping, load friction.
    fn power_dissipated(&self, p: &DcMotorParams) -> f64 {
        let twist_rate = self.motor_speed / p.gear_ratio - self.load_speed;
        p.resistance * self.current.powi(2)
            + p.rotor_friction * self.motor_speed.powi(2)
            + p.shaft_damping * twist_rate.powi(2)
            + p.load_friction * self.load_speed.powi(2)
    }

    /// Stored energy, J: magnetic, kinetic, elastic.
    fn energy(&self, p: &DcMotorParams) -> f64 {
        0.5 * p.inductance * self.current.powi(2)
            + 0.5 * p.rotor_inertia * self.motor_speed.powi(2)
            + 0.5 * p.shaft_stiffness * self.twist.powi(2)
            + 0.5 * p.load_inertia * self.load_speed.powi(2)
    }
}

/// Parameters spread over two decades around the defaults.
fn random_params(rng: &mut Rng) -> DcMotorParams {
    let d = DcMotorParams::default();
    let mut spread = |v: f64| v * rng.log_uniform(0.1, 10.0);
    DcMotorParams {
        voltage: spread(d.voltage),
        resistance: spread(d.resistance),
        inductance: spread(d.inductance),
        torque_constant: spread(d.torque_constant),
        rotor_inertia: spread(d.rotor_inertia),
        rotor_friction: spread(d.rotor_friction),
        gear_ratio: spread(d.gear_ratio),
        shaft_stiffness: spread(d.shaft_stiffness),
        shaft_damping: spread(d.shaft_damping),
        load_inertia: spread(d.load_inertia),
        load_friction: spread(d.load_friction),
        load_torque: spread(d.load_torque),
    }
}

/// A random state: currents up to 10 A, motor speeds up to 500 rad/s, load speeds up
/// to 50 rad/s, twists up to 0.01 rad, in either direction.
fn random_state(rng: &mut Rng, p: &DcMotorParams) -> [f64; 4] {
    [
        p.inductance * rng.symmetric(10.0),
        p.rotor_inertia * rng.symmetric(500.0),
        rng.symmetric(0.01),
        p.load_inertia * rng.symmetric(50.0),
    ]
}

/// The analytic steady state under constant voltage: with `b = b_m + b_l / N²`,
/// `ω_m = (k V − R τ_L / N) / (R b + k²)`, `i = (b ω_m + τ_L / N) / k`,
/// `ω_l = ω_m / N`, and the shaft twisted by `(b_l ω_l + τ_L) / k_s`.
fn steady_state(p: &DcMotorParams) -> [f64; 4] {
    let n = p.gear_ratio;
    let k = p.torque_constant;
    let b = p.rotor_friction + p.load_friction / (n * n);
    let motor_speed =
        (k * p.voltage - p.resistance * p.load_torque / n) / (p.resistance * b + k * k);
    let current = (b * motor_speed + p.load_torque / n) / k;
    let load_speed = motor_speed / n;
    let twist = (p.load_friction * load_speed + p.load_torque) / p.shaft_stiffness;
    [
        p.inductance * current,
        p.rotor_inertia * motor_speed,
        twist,
        p.load_inertia * load_speed,
    ]
}

/// `DcMotor` with three more states integrating the electrical energy drawn, the
/// work done against the load torque and the energy dissipated, each computed here
/// from the state, independently of the generated code.
struct Audited(DcMotor);

impl Model for Audited {
    type Params = DcMotorParams;
    const NAME: &'static str = "DcMotorAudited";
    const STATE_NAMES: &'static [&'static str] = &[
        "coil.p",
        "rotor.p",
        "shaft_spring.q",
        "load.p",
        "electrical_energy",
        "load_work",
        "dissipated_energy",
    ];
    const OUTPUT_NAMES: &'static [&'static str] = &[];

    fn params(&self) -> &DcMotorParams {
        &self.0.params
    }

    fn initial_state(&self, x0: &mut [f64]) {
        self.0.initial_state(&mut x0[..4]);
        x0[4..].fill(0.0);
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.0.derivatives(t, &x[..4], &mut dx[..4]);
        let p = &self.0.params;
        let c = T::from_f64;
        let current = x[0] / c(p.inductance);
        let motor_speed = x[1] / c(p.rotor_inertia);
        let load_speed = x[3] / c(p.load_inertia);
        let twist_rate = motor_speed / c(p.gear_ratio) - load_speed;
        dx[4] = c(p.voltage) * current;
        dx[5] = c(p.load_torque) * load_speed;
        dx[6] = c(p.resistance) * current * current
            + c(p.rotor_friction) * motor_speed * motor_speed
            + c(p.shaft_damping) * twist_rate * twist_rate
            + c(p.load_friction) * load_speed * load_speed;
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

mod should {
    use super::*;

    /// `dH/dt = P_in − P_diss` holds at every state, for every parameter set: it is an
    /// identity of port-Hamiltonian equations, so the generated derivative must satisfy
    /// it up to rounding. `dH/dt` is `Σ ∂H/∂x_i · dx_i/dt` with the generated dx and the
    /// gradients `(i, ω_m, k_s q, ω_l)`; P_in and P_diss are computed here from the
    /// state. The residual is compared with the sum of the magnitudes of all power terms
    /// (the size of the numbers that cancel): 1e-9 leaves six orders of margin over
    /// rounding (about 1e-15) and is far below any wrong sign or factor.
    #[test]
    fn power_balance_is_an_identity_of_the_generated_equations() {
        let mut rng = Rng::new(0x0D_C0_40_70);
        let mut worst = 0.0f64;
        for _ in 0..2000 {
            let p = random_params(&mut rng);
            let model = DcMotor::new(p.clone());
            let x = random_state(&mut rng, &p);
            let mut dx = [0.0; 4];
            model.derivatives(rng.uniform(0.0, 10.0), &x, &mut dx);
            let s = Physical::of(&p, &x);
            let flows = [
                s.current,
                s.motor_speed,
                p.shaft_stiffness * s.twist,
                s.load_speed,
            ];
            let rates: Vec<f64> = flows.iter().zip(&dx).map(|(g, d)| g * d).collect();
            let dh_dt: f64 = rates.iter().sum();
            let (p_in, p_diss) = (s.power_in(&p), s.power_dissipated(&p));
            let scale = rates.iter().map(|r| r.abs()).sum::<f64>()
                + (p.voltage * s.current).abs()
                + (p.load_torque * s.load_speed).abs()
                + p_diss;
            let residual = (dh_dt - (p_in - p_diss)).abs() / scale;
            worst = worst.max(residual);
            assert!(
                residual < 1e-9,
                "dH/dt = {dh_dt}, P_in - P_diss = {}, at {x:?}, {p:?}",
                p_in - p_diss
            );

            // The model's own power and energy outputs say the same.
            let mut y = [0.0; DcMotor::N_OUTPUTS];
            model.outputs(0.0, &x, &mut y);
            let out = |name: &str| {
                y[DcMotor::OUTPUT_NAMES
                    .iter()
                    .position(|n| *n == name)
                    .unwrap()]
            };
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
            assert!(close(out("electrical_power"), p.voltage * s.current));
            assert!(close(out("load_power"), p.load_torque * s.load_speed));
            assert!(close(out("dissipated_power"), p_diss));
            assert!(close(out("energy"), s.energy(&p)));
        }
        eprintln!("largest relative power-balance residual: {worst:e}");
    }

    /// Integrated over a run from rest to steady state (0.5 s), `ΔH = E_el − W_load −
    /// E_diss`, with the three energies integrated alongside the state. Every integrated
    /// quantity carries a global error of at most about N·rtol of its size after N
    /// steps, and H at most twice that (it is quadratic in the state), so the balance
    /// holds to `N · rtol · (2 H + E_el + W_load + E_diss)`.
    #[test]
    fn integrated_energy_balance_holds_to_the_solvers_tolerance() {
        let rtol = 1e-10;
        let model = Audited(DcMotor::default());
        let p = model.params().clone();
        let mut x0 = [0.0; 7];
        model.initial_state(&mut x0);
        let mut sim = Simulation::new(&model, dopri5(rtol, 1e-16)).unwrap();
        let mut last = [0.0; 7];
        let stats = sim
            .run(0.0, &x0, &[0.5], &mut |_t: f64, x: &[f64], _y: &[f64]| {
                last.copy_from_slice(x)
            })
            .unwrap();
        let h0 = Physical::of(&p, &x0).energy(&p);
        let h1 = Physical::of(&p, &last).energy(&p);
        let (e_el, w_load, e_diss) = (last[4], last[5], last[6]);
        let imbalance = ((h1 - h0) - (e_el - w_load - e_diss)).abs();
        let bound = stats.steps() as f64 * rtol * (2.0 * h1 + e_el + w_load + e_diss);
        eprintln!(
            "ΔH = {:.6} J, E_el = {e_el:.6} J, W_load = {w_load:.6} J, E_diss = {e_diss:.6} J, \
             imbalance {imbalance:e} J (bound {bound:e} J, {} steps)",
            h1 - h0,
            stats.steps()
        );
        assert!(e_el > 0.1 && e_diss > 0.01, "the run did some work");
        assert!(
            imbalance <= bound,
            "energy imbalance {imbalance:e} J exceeds {bound:e} J"
        );
    }

    /// At the analytic steady state every derivative vanishes, for random parameter
    /// sets. Each derivative is a sum of terms that cancel exactly; compared with the
    /// largest term of its equation (V, the motor torque, ω_l, the shaft torque) the
    /// residual is rounding, so 1e-12 relative.
    #[test]
    fn derivatives_vanish_at_the_analytic_steady_state() {
        let mut rng = Rng::new(5);
        for _ in 0..500 {
            let p = random_params(&mut rng);
            let x = steady_state(&p);
            let mut dx = [0.0; 4];
            DcMotor::new(p.clone()).derivatives(0.0, &x, &mut dx);
            let s = Physical::of(&p, &x);
            let shaft_torque = p.shaft_stiffness * s.twist;
            let scales = [
                p.voltage,
                (p.torque_constant * s.current)
                    .abs()
                    .max(shaft_torque.abs() / p.gear_ratio),
                s.load_speed.abs(),
                shaft_torque.abs().max(p.load_torque),
            ];
            for i in 0..4 {
                assert!(
                    dx[i].abs() <= 1e-12 * scales[i],
                    "d{}/dt = {} at the steady state of {p:?}",
                    DcMotor::STATE_NAMES[i],
                    dx[i]
                );
            }
        }
    }

    /// Started from rest with the default parameters, the motor settles at the analytic
    /// steady state. The model is linear and its slowest eigenvalue (of the default
    /// parameters) is −81.4 1/s (the others: −168, −1709, −81 ± 283i), so after 0.5 s
    /// the transient is e^−40 ≈ 4e-18 of the step: what remains is the solver's error,
    /// well below 1e-8 relative at rtol 1e-10.
    #[test]
    fn settles_at_the_analytic_steady_speed_and_current() {
        let p = DcMotorParams::default();
        let model = DcMotor::new(p.clone());
        let (traj, _) = common::run(
            &model,
            dopri5(1e-10, 1e-16),
            &common::initial_state(&model),
            0.5,
            2,
        );
        let expected = steady_state(&p);
        for (i, name) in DcMotor::STATE_NAMES.iter().enumerate() {
            let x = traj.state(1, i).unwrap();
            assert!(
                (x - expected[i]).abs() <= 1e-8 * expected[i].abs(),
                "{name}: {x} after 0.5 s, steady state {}",
                expected[i]
            );
        }
        let s = Physical::of(&p, &expected);
        let current = traj.value(1, "current").unwrap();
        let speed = traj.value(1, "motor_speed").unwrap();
        assert!((current - s.current).abs() <= 1e-8 * s.current);
        assert!((speed - s.motor_speed).abs() <= 1e-8 * s.motor_speed);
        eprintln!(
            "steady state: {speed:.6} rad/s ({:.1} rpm), {current:.6} A; analytic {:.6} rad/s, {:.6} A",
            speed * 60.0 / std::f64::consts::TAU,
            s.motor_speed,
            s.current
        );
    }
}
