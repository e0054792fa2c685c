//! The DC motor under a 1 kHz discrete PI speed controller, checked against the exact
//! solution of the linear closed loop.
//!
//! The plant is linear, and within a sampling period its inputs are constant, so its
//! state at the samples follows `x_{k+1} = A_d x_k + B_d u_k + E_d τ_k` exactly, with
//! `[A_d B_d E_d] = [I 0 0] exp([[A, B, E], [0, 0, 0]] T)`. The continuous matrices are
//! written here from the physics (not from the generated code); with the controller in
//! the loop the two runs must agree to the solver's accuracy.

use bgdsl_runtime::multibond::{SMatrix, SVector};
use bgdsl_runtime::{Radau5Options, Solver};
use models::control::PiController;
use models::dc_servo::{run_speed_loop, DcServo, DcServoParams, SPEED_LOOP};

/// `dx/dt = A x + B v + E τ_L` with `x = [λ, p_m, θ, p_l]` (flux linkage, rotor momentum,
/// shaft twist, load momentum):
/// `λ' = v − R_a λ/L − k_t p_m/J_m`,
/// `p_m' = k_t λ/L − b_m p_m/J_m − τ_s/N`,
/// `θ' = p_m/(N J_m) − p_l/J_l`,
/// `p_l' = τ_s − b_l p_l/J_l − τ_L`, where the shaft torque is
/// `τ_s = k_s θ + c_s (p_m/(N J_m) − p_l/J_l)`.
fn plant(p: &DcServoParams) -> (SMatrix<f64, 4, 4>, SVector<f64, 4>, SVector<f64, 4>) {
    let (l, jm, jl, n) = (p.inductance, p.rotor_inertia, p.load_inertia, p.gear_ratio);
    let (kt, ks, cs) = (p.torque_constant, p.shaft_stiffness, p.shaft_damping);
    // The shaft torque as a row: τ_s = [0, c_s/(N J_m), k_s, −c_s/J_l] · x.
    let shaft = [0.0, cs / (n * jm), ks, -cs / jl];
    let a = SMatrix::<f64, 4, 4>::from_row_slice(&[
        -p.resistance / l,
        -kt / jm,
        0.0,
        0.0,
        kt / l,
        -p.rotor_friction / jm - shaft[1] / n,
        -shaft[2] / n,
        -shaft[3] / n,
        0.0,
        1.0 / (n * jm),
        0.0,
        -1.0 / jl,
        0.0,
        shaft[1],
        shaft[2],
        shaft[3] - p.load_friction / jl,
    ]);
    let b = SVector::<f64, 4>::new(1.0, 0.0, 0.0, 0.0);
    let e = SVector::<f64, 4>::new(0.0, 0.0, 0.0, -1.0);
    (a, b, e)
}

/// The closed loop sampled exactly: the same controller, the plant stepped with the
/// zero-order-hold discretisation.
fn linear_loop(
    p: &DcServoParams,
    mut controller: PiController,
    setpoint: impl Fn(f64) -> f64,
    load: impl Fn(f64) -> f64,
    periods: usize,
) -> Vec<f64> {
    let (a, b, e) = plant(p);
    let mut augmented = SMatrix::<f64, 6, 6>::zeros();
    augmented.fixed_view_mut::<4, 4>(0, 0).copy_from(&a);
    augmented.fixed_view_mut::<4, 1>(0, 4).copy_from(&b);
    augmented.fixed_view_mut::<4, 1>(0, 5).copy_from(&e);
    let discrete = (augmented * controller.period).exp();
    let ad = discrete.fixed_view::<4, 4>(0, 0).into_owned();
    let bd = discrete.fixed_view::<4, 1>(0, 4).into_owned();
    let ed = discrete.fixed_view::<4, 1>(0, 5).into_owned();
    let mut x = SVector::<f64, 4>::zeros();
    let mut speeds = Vec::with_capacity(periods + 1);
    for k in 0..=periods {
        let t = k as f64 * controller.period;
        let speed = x[3] / p.load_inertia;
        speeds.push(speed);
        let u = controller.update(setpoint(t), speed);
        x = ad * x + bd * u + ed * load(t);
    }
    speeds
}

fn setpoint(t: f64) -> f64 {
    if t >= 0.05 {
        10.0
    } else {
        0.0
    }
}

fn load(t: f64) -> f64 {
    if t >= 0.6 {
        0.1
    } else {
        0.02
    }
}

#[test]
fn the_closed_loop_matches_the_exact_linear_solution() {
    let servo = DcServo::default();
    let params = servo.params.clone();
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    });
    let periods = 1200;
    let run = run_speed_loop(servo, solver, SPEED_LOOP, setpoint, load, periods).expect("runs");
    let exact = linear_loop(&params, SPEED_LOOP, setpoint, load, periods);
    assert_eq!(run.len(), exact.len());
    let worst = run
        .iter()
        .zip(&exact)
        .map(|(s, e)| (s.speed - e).abs())
        .fold(0.0, f64::max);
    // rtol 1e-10 per period over 1,200 restarts, on speeds of order 10 rad/s: 1e-6
    // leaves room for accumulation and nothing for a wrong equation (a 1 % error in
    // any coefficient moves the speed by ~1e-2).
    assert!(worst < 1e-6, "worst speed difference {worst:e} rad/s");

    // And the loop does what a speed loop must: reach the set-point, and return to it
    // after the load step (integral action).
    let at = |t: f64| run[(t / SPEED_LOOP.period).round() as usize].speed;
    assert!(
        (at(0.55) - 10.0).abs() < 0.01,
        "before the load step: {}",
        at(0.55)
    );
    assert!(at(0.65) < 9.99, "the load step must show: {}", at(0.65));
    assert!(
        (at(1.2) - 10.0).abs() < 0.01,
        "after the load step: {}",
        at(1.2)
    );
}
