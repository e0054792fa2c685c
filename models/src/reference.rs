//! Hand-written equations of motion, written from the physics (not from the macro's
//! expansion), for tests that compare them with the generated code and for the
//! benchmarks that time both. Not part of the crate's API.

use crate::QuarterCarParams;

/// 2π.
const TAU: f64 = core::f64::consts::TAU;

/// The vertical road velocity under the tyre of the quarter car at time `t`, m/s: the
/// derivative of the cosine bump `h/2 (1 − cos(2π (V t − d) / L))` on
/// `d/V < t < (d + L)/V`, plus that of the undulation `a sin(2π V t / λ)`.
#[inline]
pub fn quarter_car_road_velocity(p: &QuarterCarParams, t: f64) -> f64 {
    let start = p.bump_distance / p.speed;
    let end = (p.bump_distance + p.bump_length) / p.speed;
    let bump = if t > start && t < end {
        let w = TAU * p.speed / p.bump_length;
        0.5 * p.bump_height * w * (TAU * (p.speed * t - p.bump_distance) / p.bump_length).sin()
    } else {
        0.0
    };
    let w = TAU * p.speed / p.wavelength;
    bump + p.wave_amplitude * w * (w * t).cos()
}

/// The quarter car's state derivative, with the state in the order of
/// `QuarterCar::STATE_NAMES`: `[tyre compression q_t, wheel momentum p_u,
/// suspension compression q_s, body momentum p_s]`.
///
/// Newton for each mass, with the tyre force `k_t q_t` pushing the wheel up, the
/// suspension force `k_s q_s + c_s (v_u − v_s)` pushing the body up and the wheel down,
/// and the weights; the compressions grow with the relative velocities.
#[inline]
pub fn quarter_car_derivatives(p: &QuarterCarParams, t: f64, x: &[f64], dx: &mut [f64]) {
    let (q_t, p_u, q_s, p_s) = (x[0], x[1], x[2], x[3]);
    let v_road = quarter_car_road_velocity(p, t);
    let v_wheel = p_u / p.unsprung_mass;
    let v_body = p_s / p.sprung_mass;
    let tyre_force = p.tyre_stiffness * q_t;
    let suspension_force = p.suspension_stiffness * q_s + p.suspension_damping * (v_wheel - v_body);
    dx[0] = v_road - v_wheel;
    dx[1] = tyre_force - suspension_force - p.unsprung_mass * p.g;
    dx[2] = v_wheel - v_body;
    dx[3] = suspension_force - p.sprung_mass * p.g;
}
