//! The `no_std` motor and integrators against the motor's closed-form solution.
//!
//! These tests are an ordinary (std) program, but the crate under test and the runtime
//! are built as they would be for a microcontroller: `cargo test -p bgdsl-embedded`
//! compiles `bgdsl-runtime` without its `std` feature (this crate has no
//! dev-dependency that would turn it on), so `f64`'s elementary functions come from
//! `libm` and the integrators are the allocation-free ones of `bgdsl_runtime::rk`.

use bgdsl_embedded::{Motor, MotorDrive, MotorInputs, MotorParams, MotorState, SUBSTEP};
use bgdsl_runtime::rk::{DormandPrince, Rk4};
use bgdsl_runtime::{
    DormandPrinceOptions, Dual, FixedStep, Model, SampleTimeProblem, Scalar, SolverError,
    WithInputs,
};

/// The motor's state equation with the inputs held, `dx/dt = A x + b` for
/// `x = (L i, J ω)`, the flux linkage and the angular momentum.
struct Linear {
    a: [[f64; 2]; 2],
    b: [f64; 2],
}

impl Linear {
    fn new(p: &MotorParams, u: MotorInputs) -> Self {
        let (r, l, k, j, f) = (
            p.resistance,
            p.inductance,
            p.torque_constant,
            p.inertia,
            p.friction,
        );
        Linear {
            // L di/dt = V − R i − k ω;  J dω/dt = k i − f ω − τ_L.
            a: [[-r / l, -k / j], [k / l, -f / j]],
            b: [u.voltage, -u.load_torque],
        }
    }

    /// The equilibrium `x` with `A x + b = 0`.
    fn steady_state(&self) -> [f64; 2] {
        let [[a11, a12], [a21, a22]] = self.a;
        let det = a11 * a22 - a12 * a21;
        let [b1, b2] = self.b;
        [(a12 * b2 - a22 * b1) / det, (a21 * b1 - a11 * b2) / det]
    }

    /// `x(t) = x_ss + exp(A t) (x0 − x_ss)`, with `exp(A t)` by Sylvester's formula
    /// for the two distinct real eigenvalues the motor has (it is overdamped).
    fn solution(&self, x0: [f64; 2], t: f64) -> [f64; 2] {
        let [[a11, a12], [a21, a22]] = self.a;
        let (trace, det) = (a11 + a22, a11 * a22 - a12 * a21);
        let disc = trace * trace - 4.0 * det;
        assert!(disc > 0.0, "the closed form assumes real eigenvalues");
        let (l1, l2) = ((trace + disc.sqrt()) / 2.0, (trace - disc.sqrt()) / 2.0);
        let (e1, e2) = ((l1 * t).exp(), (l2 * t).exp());
        // exp(A t) = (e1 (A − l2 I) − e2 (A − l1 I)) / (l1 − l2).
        let m = |i: usize, j: usize| {
            let a = self.a[i][j];
            let id = if i == j { 1.0 } else { 0.0 };
            (e1 * (a - l2 * id) - e2 * (a - l1 * id)) / (l1 - l2)
        };
        let ss = self.steady_state();
        let d = [x0[0] - ss[0], x0[1] - ss[1]];
        [
            ss[0] + m(0, 0) * d[0] + m(0, 1) * d[1],
            ss[1] + m(1, 0) * d[0] + m(1, 1) * d[1],
        ]
    }
}

/// The state as `(coil.p, rotor.p)`, whatever the order of the state vector.
fn pair(state: MotorState<f64>) -> [f64; 2] {
    [state.coil_p, state.rotor_p]
}

/// The sizes the state reaches on 12 V: the flux linkage at the stall current `V / R`,
/// the angular momentum at the no-load speed `k V / (R b + k²)`. (The steady state is
/// no scale: with no load the current settles to a few milliamperes.)
fn natural_scale(p: &MotorParams) -> [f64; 2] {
    let (r, k) = (p.resistance, p.torque_constant);
    [
        p.inductance * 12.0 / r,
        p.inertia * k * 12.0 / (r * p.friction + k * k),
    ]
}

/// The largest error of `x` against `exact`, relative to `scale` component by
/// component.
fn relative_error(x: [f64; 2], exact: [f64; 2], scale: [f64; 2]) -> f64 {
    ((x[0] - exact[0]) / scale[0])
        .abs()
        .max(((x[1] - exact[1]) / scale[1]).abs())
}

const SUPPLY: MotorInputs = MotorInputs {
    voltage: 12.0,
    load_torque: 0.0,
};

#[test]
fn start_up_at_1_khz_follows_the_closed_form() {
    let params = MotorParams::default();
    let exact = Linear::new(&params, SUPPLY);
    let scale = natural_scale(&params);
    let mut drive = MotorDrive::new(params.clone(), SUBSTEP).unwrap();
    let mut worst: f64 = 0.0;
    for tick in 1..=30 {
        let outputs = drive.step(SUPPLY, 1e-3).unwrap();
        let t = f64::from(tick) * 1e-3;
        assert!((drive.time() - t).abs() < 1e-15, "{} vs {t}", drive.time());
        let x = pair(drive.state());
        worst = worst.max(relative_error(x, exact.solution([0.0, 0.0], t), scale));
        // The outputs are the state over the storage elements' parameters.
        assert!((outputs.current - x[0] / params.inductance).abs() < 1e-9);
        assert!((outputs.speed - x[1] / params.inertia).abs() < 1e-9);
    }
    // RK4's error on the electrical transient (0.05 ms steps against a 0.59 ms time
    // constant); 2.1e-7 when this was written.
    assert!(worst < 1e-6, "worst relative error {worst:e}");
    // Settled to the no-load speed k V / (R b + k²) within the slow mode's decay.
    let k = params.torque_constant;
    let no_load = k * 12.0 / (params.resistance * params.friction + k * k);
    assert!((drive.outputs().speed / no_load - 1.0).abs() < 1e-3);
}

#[test]
fn a_load_torque_set_between_ticks_takes_effect_from_that_tick() {
    let params = MotorParams::default();
    let loaded = MotorInputs {
        voltage: 12.0,
        load_torque: 5e-3,
    };
    let mut drive = MotorDrive::new(params.clone(), SUBSTEP).unwrap();
    for _ in 0..20 {
        drive.step(SUPPLY, 1e-3).unwrap();
    }
    // The closed form in two pieces: the start-up, then the loaded motor from there.
    let at_switch = Linear::new(&params, SUPPLY).solution([0.0, 0.0], 20e-3);
    let after = Linear::new(&params, loaded);
    let scale = natural_scale(&params);
    let mut worst: f64 = 0.0;
    for tick in 1..=20 {
        drive.step(loaded, 1e-3).unwrap();
        let exact = after.solution(at_switch, f64::from(tick) * 1e-3);
        worst = worst.max(relative_error(pair(drive.state()), exact, scale));
    }
    // A gentler transient than the start-up's: 2.6e-10 when this was written.
    assert!(worst < 1e-8, "worst relative error {worst:e}");
    assert_eq!(drive.motor().inputs(), loaded);
    // The load slows the motor by R τ_L / (R b + k²).
    let k = params.torque_constant;
    let drop = params.resistance * 5e-3 / (params.resistance * params.friction + k * k);
    let unloaded = k * 12.0 / (params.resistance * params.friction + k * k);
    assert!((drive.outputs().speed - (unloaded - drop)).abs() < 0.1);
}

#[test]
fn rk4_error_falls_sixteenfold_when_the_step_halves() {
    let mut motor = Motor::default();
    motor.set_inputs(SUPPLY);
    let exact = Linear::new(motor.params(), SUPPLY);
    let scale = natural_scale(motor.params());
    let t_end = 5e-3;
    let error = |h: f64| {
        let mut rk4 = Rk4::<{ Motor::N_STATES }>::new(FixedStep::new(h)).unwrap();
        let (mut t, mut x) = (0.0, [0.0; Motor::N_STATES]);
        rk4.advance_to(&motor, &mut t, &mut x, t_end).unwrap();
        assert_eq!(t, t_end);
        let state = MotorState::from_slice(&x);
        relative_error(pair(state), exact.solution([0.0, 0.0], t_end), scale)
    };
    let (coarse, fine) = (error(1e-4), error(5e-5));
    let order = (coarse / fine).log2();
    assert!((order - 4.0).abs() < 0.2, "observed order {order}");
}

#[test]
fn dormand_prince_in_ticks_meets_its_tolerance() {
    let mut motor = Motor::default();
    motor.set_inputs(SUPPLY);
    let exact = Linear::new(motor.params(), SUPPLY);
    let scale = natural_scale(motor.params());
    let options = DormandPrinceOptions {
        rtol: 1e-9,
        atol: 1e-12,
        ..DormandPrinceOptions::default()
    };
    let mut dopri = DormandPrince::<{ Motor::N_STATES }>::new(options).unwrap();
    assert_eq!(dopri.step_size(), None);
    let (mut t, mut x) = (0.0, [0.0; Motor::N_STATES]);
    let mut worst: f64 = 0.0;
    for tick in 1..=30 {
        let t_end = f64::from(tick) * 1e-3;
        dopri.advance_to(&motor, &mut t, &mut x, t_end).unwrap();
        assert_eq!(t, t_end);
        let state = pair(MotorState::from_slice(&x));
        worst = worst.max(relative_error(state, exact.solution([0.0, 0.0], t), scale));
    }
    // 1.7e-10 when this was written.
    assert!(worst < 1e-8, "worst relative error {worst:e}");
    let stats = dopri.stats();
    assert!(dopri.step_size().is_some());
    // Every tick ends a step, and the step size carries over from tick to tick rather
    // than starting small each time.
    assert!(stats.accepted >= 30, "{stats:?}");
    assert!(stats.accepted < 300, "{stats:?}");
    // Six evaluations per attempt, the one each tick starts with, and one more to
    // choose the first step.
    assert_eq!(stats.n_rhs, 6 * stats.steps() + 30 + 1, "{stats:?}");
}

#[test]
fn one_adaptive_step_ends_on_time_or_short_of_it() {
    let mut motor = Motor::default();
    motor.set_inputs(SUPPLY);
    let mut dopri = DormandPrince::<2>::new(DormandPrinceOptions::default()).unwrap();
    let (mut t, mut x) = (0.0, [0.0; 2]);
    dopri.step(&motor, &mut t, &mut x, 1.0).unwrap();
    assert!(t > 0.0 && t < 1.0, "{t}");
    assert_eq!(dopri.stats().accepted, 1);
    let reached = t;
    dopri.step(&motor, &mut t, &mut x, reached).unwrap();
    assert_eq!(t, reached, "a step to where it already is does nothing");
    dopri.restart();
    assert_eq!(dopri.step_size(), None);
}

#[test]
fn bad_ticks_and_settings_are_errors() {
    assert!(matches!(
        MotorDrive::new(MotorParams::default(), 0.0),
        Err(SolverError::InvalidOptions { option: "step", .. })
    ));
    let mut drive = MotorDrive::new(MotorParams::default(), SUBSTEP).unwrap();
    drive.step(SUPPLY, 1e-3).unwrap();
    assert!(matches!(
        drive.step(SUPPLY, -1e-3),
        Err(SolverError::InvalidSampleTimes {
            problem: SampleTimeProblem::BeforeStart { .. },
            ..
        })
    ));
    assert!(matches!(
        drive.step(SUPPLY, f64::NAN),
        Err(SolverError::InvalidSampleTimes {
            problem: SampleTimeProblem::NotFinite,
            ..
        })
    ));
    // A failed tick leaves the drive where it was.
    assert_eq!(drive.time(), 1e-3);
    let mut nan = drive.state();
    nan.rotor_p = f64::NAN;
    drive.set_state(nan);
    let err = drive.step(SUPPLY, 1e-3).unwrap_err();
    assert!(
        matches!(
            err,
            SolverError::NonFiniteState {
                state: "rotor.p",
                ..
            }
        ),
        "{err}"
    );
    let mut rk4 = Rk4::<2>::new(FixedStep::new(1e-3)).unwrap();
    let (mut t, mut x) = (0.0, [0.0; 2]);
    assert!(matches!(
        rk4.step(&Motor::default(), &mut t, &mut x, 0.0),
        Err(SolverError::FixedStepTooSmall { step: 0.0, .. })
    ));
    assert!(matches!(
        DormandPrince::<2>::new(DormandPrinceOptions {
            rtol: -1.0,
            ..DormandPrinceOptions::default()
        }),
        Err(SolverError::InvalidOptions { option: "rtol", .. })
    ));
}

#[test]
fn the_elementary_functions_agree_with_the_platforms() {
    // Without `std` these are libm's; they must agree with the platform's to an ulp or
    // two (both are faithfully rounded, not necessarily identical).
    let close = |a: f64, b: f64| a == b || (a - b).abs() <= 4.0 * f64::EPSILON * b.abs();
    for &x in &[0.3, -1.7, 2.5, 1e-3, 10.0] {
        assert!(close(Scalar::sin(x), x.sin()), "sin {x}");
        assert!(close(Scalar::cos(x), x.cos()), "cos {x}");
        assert!(close(Scalar::tan(x), x.tan()), "tan {x}");
        assert!(close(Scalar::exp(x), x.exp()), "exp {x}");
        assert!(close(Scalar::atan(x), x.atan()), "atan {x}");
        assert!(close(Scalar::sinh(x), x.sinh()), "sinh {x}");
        assert!(close(Scalar::cosh(x), x.cosh()), "cosh {x}");
        assert!(close(Scalar::tanh(x), x.tanh()), "tanh {x}");
        assert!(close(Scalar::cbrt(x), x.cbrt()), "cbrt {x}");
        assert!(close(Scalar::atan2(x, 0.7), x.atan2(0.7)), "atan2 {x}");
        assert!(close(Scalar::powi(x, 5), x.powi(5)), "powi {x}");
        assert!(close(Scalar::powi(x, -3), x.powi(-3)), "powi {x}");
        let a = x.abs();
        assert!(close(Scalar::sqrt(a), a.sqrt()), "sqrt {x}");
        assert!(close(Scalar::ln(a), a.ln()), "ln {x}");
        assert!(close(Scalar::powf(a, 0.37), a.powf(0.37)), "powf {x}");
    }
    for &x in &[0.3, -0.9, 0.0] {
        assert!(close(Scalar::asin(x), x.asin()), "asin {x}");
        assert!(close(Scalar::acos(x), x.acos()), "acos {x}");
    }
}

#[test]
fn dual_numbers_differentiate_without_std() {
    let x = Dual::variable(0.3);
    let y = Scalar::sin(x) * Scalar::exp(x);
    let exact = 0.3f64.exp() * (0.3f64.sin() + 0.3f64.cos());
    assert!((y.eps - exact).abs() < 1e-15, "{} vs {exact}", y.eps);
    // The model's Jacobian, exactly: ∂(dp_J/dt)/∂p_L = k / L.
    let motor = Motor::default();
    let index = MotorState::from_slice(&[0usize, 1]);
    let mut x = [Dual::constant(0.0); 2];
    x[index.coil_p] = Dual::variable(0.0);
    let mut dx = [Dual::constant(0.0); 2];
    motor.derivatives(0.0, &x, &mut dx);
    let p = motor.params();
    assert_eq!(dx[index.rotor_p].eps, p.torque_constant / p.inductance);
}

/// Per-state absolute tolerances in the allocation-free Dormand–Prince
/// (`DormandPrince::set_atol`): with a loose scalar `atol = 1e-3` (about the states'
/// own size) the start-up's flux linkage is resolved only to about 4e-3 of its scale;
/// an `atol` of 1e-12 for `coil.p` alone brings it, against the closed form, within
/// 1e-7 of its scale (rtol 1e-7 governs then), at the price of more steps. The same integrator on the std driver is
/// compared bit for bit in `bgdsl-runtime`'s `tolerances_per_state.rs`.
#[test]
fn per_state_atol_tightens_the_state_it_names() {
    let mut motor = Motor::default();
    motor.set_inputs(SUPPLY);
    let exact = Linear::new(motor.params(), SUPPLY);
    let scale = natural_scale(motor.params());
    let options = DormandPrinceOptions {
        rtol: 1e-7,
        atol: 1e-3,
        ..DormandPrinceOptions::default()
    };
    let coil = Motor::STATE_NAMES
        .iter()
        .position(|n| *n == "coil.p")
        .unwrap();
    let mut atol = [1e-3; Motor::N_STATES];
    atol[coil] = 1e-12;
    // The largest error of `coil.p` over 30 ticks of 1 ms, relative to its scale.
    let coil_error = |per_state: Option<[f64; Motor::N_STATES]>| {
        let mut dopri = DormandPrince::<{ Motor::N_STATES }>::new(options).unwrap();
        dopri.set_atol::<Motor>(per_state).unwrap();
        let (mut t, mut x) = (0.0, [0.0; Motor::N_STATES]);
        let mut worst: f64 = 0.0;
        for tick in 1..=30 {
            dopri
                .advance_to(&motor, &mut t, &mut x, f64::from(tick) * 1e-3)
                .unwrap();
            let state = pair(MotorState::from_slice(&x));
            let e = (state[0] - exact.solution([0.0, 0.0], t)[0]) / scale[0];
            worst = worst.max(e.abs());
        }
        (worst, dopri.stats().accepted)
    };
    let (loose, loose_steps) = coil_error(None);
    let (tight, tight_steps) = coil_error(Some(atol));
    // Measured: 3.7e-3 in 32 steps, and 1.1e-8 in 117 steps.
    assert!(loose > 1e-4, "scalar atol 1e-3: {loose:e}");
    assert!(tight < 1e-7, "per-state atol: {tight:e}");
    assert!(tight_steps > loose_steps);
}
