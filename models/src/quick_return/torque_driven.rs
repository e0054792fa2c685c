//! The quick return mechanism driven by a motor torque instead of the spec's speed
//! source: the same links, points and joints as [`QuickReturn`](super::QuickReturn), a
//! bearing that holds the crank's rotation about X0 and Y0, and the torque about Z0 an
//! input a controller sets (see `examples/quick_return_speed_control.rs`).

use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{box_inertia, diag3, vec3};

use super::assembly;
use super::model::unwrapped_angle;

bond_graph! {
    /// The quick return mechanism with a torque-driven crank.
    pub model QuickReturnTorque {
        /// crank mass (Table 1)
        param m1 = 0.5 in "kg";
        /// slider mass (Table 1)
        param m2 = 0.1 in "kg";
        /// rocker mass (Table 1)
        param m3 = 0.7 in "kg";
        /// connecting-rod mass (Table 1)
        param m4 = 0.3 in "kg";
        /// output-slider mass (Table 1)
        param m5 = 0.1 in "kg";
        /// crank edge lengths (lx, ly, lz) (Table 1)
        param l1: [f64; 3] = [0.2, 0.01, 0.01] in "m";
        /// slider edge lengths (Table 1)
        param l2: [f64; 3] = [0.01, 0.01, 0.01] in "m";
        /// rocker edge lengths (Table 1)
        param l3: [f64; 3] = [0.7, 0.01, 0.01] in "m";
        /// connecting-rod edge lengths (Table 1)
        param l4: [f64; 3] = [0.4, 0.01, 0.01] in "m";
        /// output-slider edge lengths (Table 1)
        param l5: [f64; 3] = [0.01, 0.01, 0.01] in "m";
        /// distance from the crank pivot O1 down to the rocker pivot O3
        param d = 0.4 in "m";
        /// gravity, along -Y0
        param g = 9.81 in "m/s²";
        /// initial crank angle
        param theta0 = core::f64::consts::FRAC_PI_2 in "rad";
        /// crank pivot O1 to ground: stiffness, damping (Table 2)
        param K01 = 1.0e5 in "N/m";
        param R01 = 20.0 in "N·s/m";
        /// crank pin A1 to slider: stiffness, damping (Table 2)
        param K12 = 1.0e5 in "N/m";
        param R12 = 20.0 in "N·s/m";
        /// rocker pivot O3 to ground: stiffness, damping (Table 2)
        param K03 = 1.0e5 in "N/m";
        param R03 = 20.0 in "N·s/m";
        /// slider on the rocker, in frame 3: free along X3 (Table 2)
        param K3C: [f64; 3] = [0.0, 1.0e5, 1.0e5] in "N/m";
        param R3C: [f64; 3] = [20.0, 20.0, 20.0] in "N·s/m";
        /// slider's rotation locked to the rocker's (Table 2)
        param K23r = 100.0 in "N·m/rad";
        param R23r = 0.5 in "N·m·s/rad";
        /// bearing holding the crank's rotation about X0 and Y0 (the drive coupling's
        /// values of Table 2, with nothing about Z0: that is the motor's)
        param K_C = 100.0 in "N·m/rad";
        param R_C = 100.0 in "N·m·s/rad";
        /// rocker tip A33 to connecting rod A4 (Table 2)
        param K34 = 1.0e5 in "N/m";
        param R34 = 20.0 in "N·s/m";
        /// connecting rod B4 to output slider (Table 2)
        param K45 = 1.0e5 in "N/m";
        param R45 = 20.0 in "N·s/m";
        /// output slider on its guide, in frame 0: free along X0 (Table 2)
        param K5C: [f64; 3] = [0.0, 1.0e5, 1.0e5] in "N/m";
        param R5C: [f64; 3] = [20.0, 20.0, 20.0] in "N·s/m";
        /// the rocker's point for K3C: 0 under the crank pin (the authors' choice),
        /// 1 under the slider's centre (the periodic one)
        param k3c_point_under_slider = 0.0;

        RigidBody crank(m = m1, J = box_inertia(m1, l1.x, l1.y, l1.z), g = g,
            R0 = assembly(theta0, d, l1.x, l3.x, l4.x).orientation[0],
            r0 = assembly(theta0, d, l1.x, l3.x, l4.x).position[0]);
        RigidBody slider(m = m2, J = box_inertia(m2, l2.x, l2.y, l2.z), g = g,
            R0 = assembly(theta0, d, l1.x, l3.x, l4.x).orientation[1],
            r0 = assembly(theta0, d, l1.x, l3.x, l4.x).position[1]);
        RigidBody rocker(m = m3, J = box_inertia(m3, l3.x, l3.y, l3.z), g = g,
            R0 = assembly(theta0, d, l1.x, l3.x, l4.x).orientation[2],
            r0 = assembly(theta0, d, l1.x, l3.x, l4.x).position[2]);
        RigidBody rod(m = m4, J = box_inertia(m4, l4.x, l4.y, l4.z), g = g,
            R0 = assembly(theta0, d, l1.x, l3.x, l4.x).orientation[3],
            r0 = assembly(theta0, d, l1.x, l3.x, l4.x).position[3]);
        RigidBody output_slider(m = m5, J = box_inertia(m5, l5.x, l5.y, l5.z), g = g,
            R0 = assembly(theta0, d, l1.x, l3.x, l4.x).orientation[4],
            r0 = assembly(theta0, d, l1.x, l3.x, l4.x).position[4]);

        Point O1(body = crank, at = vec3(-0.5 * l1.x, 0.0, 0.0));
        Point A1(body = crank, at = vec3(0.5 * l1.x, 0.0, 0.0));
        Point O3(body = rocker, at = vec3(-0.5 * l3.x, 0.0, 0.0));
        Point A33(body = rocker, at = vec3(0.5 * l3.x, 0.0, 0.0));
        OffsetPoint P3(body = rocker, offset = if k3c_point_under_slider > 0.5 {
            slider.r - rocker.r
        } else {
            crank.r + crank.R * vec3(0.5 * l1.x, 0.0, 0.0) - rocker.r
        });
        Point A4(body = rod, at = vec3(-0.5 * l4.x, 0.0, 0.0));
        Point B4(body = rod, at = vec3(0.5 * l4.x, 0.0, 0.0));
        Ground ground();
        /// the motor's torque about Z0, from the host's controller
        input motor_torque = 0.0 in "N·m";
        MSe[3] motor = vec3(0.0, 0.0, motor_torque);
        Sf[3] frame = vec3(0.0, 0.0, 0.0);
        1 frame_w;
        frame -> frame_w;
        motor -> crank.w;

        Coupling j01(a = O1.v, b = ground.v, k = K01, c = R01);
        Coupling j12(a = A1.v, b = slider.v, k = K12, c = R12);
        Coupling j03(a = O3.v, b = ground.v, k = K03, c = R03);
        FrameCoupling j3C(a = slider.v, b = P3.v, frame = rocker.R,
            k = diag3(K3C.x, K3C.y, K3C.z), c = diag3(R3C.x, R3C.y, R3C.z));
        Coupling j23r(a = slider.w, b = rocker.w, k = K23r, c = R23r);
        Coupling bearing(a = frame_w, b = crank.w, k = diag3(K_C, K_C, 0.0), c = diag3(R_C, R_C, 0.0));
        Coupling j34(a = A33.v, b = A4.v, k = K34, c = R34);
        Coupling j45(a = B4.v, b = output_slider.v, k = K45, c = R45);
        Coupling j5C(a = output_slider.v, b = ground.v,
            k = diag3(K5C.x, K5C.y, K5C.z), c = diag3(R5C.x, R5C.y, R5C.z));

        /// Crank speed about Z0, rad/s.
        output crank_speed: f64 = crank.w.f.z in "rad/s";
        /// Crank angle about Z0, rad, unwrapped from `theta0` as the speed-driven
        /// model's: `atan2(R1[1][0], R1[1][1])` plus the whole turns that bring it
        /// nearest to the angle the crank turned through, which the bearing's spring
        /// state about Z0 already integrates (its deflection is `−∫ w_z dt`, as
        /// nothing holds that axis).
        output crank_angle: f64 = unwrapped_angle(crank.R.m21.atan2(crank.R.m22),
            theta0 - bearing.spring.q.z) in "rad";
        /// Output slider position along X0, m.
        output slider_x: f64 = output_slider.r.x in "m";
        /// The motor's power, W.
        output motor_power: f64 = motor.e.dot(&motor.f) in "W";
        /// Power dissipated in every joint's damper, W.
        output dissipated: f64 = j01.damper.e.dot(&j01.damper.f) + j12.damper.e.dot(&j12.damper.f)
            + j03.damper.e.dot(&j03.damper.f) + j3C.damper.e.dot(&j3C.damper.f)
            + j23r.damper.e.dot(&j23r.damper.f) + bearing.damper.e.dot(&bearing.damper.f)
            + j34.damper.e.dot(&j34.damper.f) + j45.damper.e.dot(&j45.damper.f)
            + j5C.damper.e.dot(&j5C.damper.f) in "W";
    }
}

/// What [`hold_speed`] measured over the settled part of the run (2.5 s to the end).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedHold {
    /// Lowest and highest crank speed, rad/s.
    pub speed_min: f64,
    /// See `speed_min`.
    pub speed_max: f64,
    /// Largest |motor torque|, N·m.
    pub torque_peak: f64,
    /// Mean motor torque, N·m.
    pub torque_mean: f64,
    /// RMS motor torque, N·m.
    pub torque_rms: f64,
    /// Energy the motor delivered, J (∫ torque · speed dt).
    pub motor_energy: f64,
    /// Energy the joints dissipated, J.
    pub dissipated_energy: f64,
    /// Change of the mechanism's energy, kinetic + elastic + potential, J: what the
    /// motor delivered and the joints did not dissipate.
    pub stored_change: f64,
}

/// The speed controller of the example: the torque the rigid mechanism needs at the
/// measured crank angle to turn at the set speed (feedforward, from
/// [`rigid_state`](crate::quick_return_rigid::rigid_state)), corrected by a 1 kHz PI on
/// the crank speed (N·m per rad/s, N·m per rad). Feedback alone cannot be stiff: the
/// crank's inertia (~7e-3 kg·m²) over the 1 ms period bounds a stable proportional
/// gain to a few N·m per rad/s, while the mechanism asks for ±40 N·m within a turn.
pub const SPEED_CONTROLLER: crate::control::PiController =
    crate::control::PiController::with_gains(2.0, 40.0, 1e-3);

/// The rigid-body data of the mechanism `model` describes.
pub fn rigid_params(model: &QuickReturnTorque) -> crate::quick_return_rigid::RigidParams {
    crate::quick_return_rigid::rigid_params_of!(&model.params)
}

/// Runs `model` for `t_end` seconds with [`SPEED_CONTROLLER`] holding the crank at
/// `speed` rad/s (the crank starts at rest at the spec's assembly), and measures the
/// settled part of the run (from 2.5 s).
///
/// # Errors
///
/// The solver fails.
pub fn hold_speed(
    model: QuickReturnTorque,
    speed: f64,
    t_end: f64,
) -> Result<SpeedHold, bgdsl_runtime::SolverError> {
    let mut controller = SPEED_CONTROLLER;
    let period = controller.period;
    let rigid = rigid_params(&model);
    let mut stepper = bgdsl_runtime::Stepper::new(model, bgdsl_runtime::Solver::stiff())?;
    let periods = (t_end / period).round() as usize;
    let settled = (2.5 / period).round() as usize;
    let (mut speed_min, mut speed_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut peak, mut sum, mut sum_sq, mut count) = (0.0f64, 0.0, 0.0, 0usize);
    let (mut motor_energy, mut dissipated_energy) = (0.0, 0.0);
    // The outputs by name (the generated record), not by position.
    let mut outputs = QuickReturnTorqueOutputs::from_slice(stepper.outputs());
    let mut energy_at_settle = 0.0;
    for k in 0..periods {
        let t = k as f64 * period;
        let feedforward =
            crate::quick_return_rigid::rigid_state(outputs.crank_angle, speed, 0.0, &rigid).tc[2];
        let torque = feedforward + controller.update(speed, outputs.crank_speed);
        let before = outputs;
        let inputs = QuickReturnTorqueInputs {
            motor_torque: torque,
        };
        outputs = QuickReturnTorqueOutputs::from_slice(stepper.advance_with(t + period, inputs)?);
        if k >= settled {
            if k == settled {
                energy_at_settle = mechanism_energy(&stepper);
            }
            speed_min = speed_min.min(outputs.crank_speed);
            speed_max = speed_max.max(outputs.crank_speed);
            peak = peak.max(torque.abs());
            sum += torque;
            sum_sq += torque * torque;
            count += 1;
            // Trapezoids over the period (the torque is held; the speed varies).
            motor_energy += 0.5 * period * (before.motor_power + outputs.motor_power);
            dissipated_energy += 0.5 * period * (before.dissipated + outputs.dissipated);
        }
    }
    let n = count.max(1) as f64;
    Ok(SpeedHold {
        speed_min,
        speed_max,
        torque_peak: peak,
        torque_mean: sum / n,
        torque_rms: (sum_sq / n).sqrt(),
        motor_energy,
        dissipated_energy,
        stored_change: mechanism_energy(&stepper) - energy_at_settle,
    })
}

/// The mechanism's stored energy from its bond graph (kinetic, elastic) plus the
/// potential energy of gravity, which the graph's weight sources feed.
fn mechanism_energy(stepper: &bgdsl_runtime::Stepper<QuickReturnTorque>) -> f64 {
    use bgdsl_runtime::Model;
    let model = stepper.model();
    let x = stepper.state();
    let stored = model
        .power_balance(stepper.time(), x)
        .map_or(f64::NAN, |balance| balance.stored);
    let p = &model.params;
    let heights: f64 = [
        "crank.r_y",
        "slider.r_y",
        "rocker.r_y",
        "rod.r_y",
        "output_slider.r_y",
    ]
    .iter()
    .zip([p.m1, p.m2, p.m3, p.m4, p.m5])
    .map(|(name, m)| {
        let index = QuickReturnTorque::STATE_NAMES
            .iter()
            .position(|s| s == name)
            .map_or(f64::NAN, |i| x[i]);
        m * p.g * index
    })
    .sum();
    stored + heights
}

#[cfg(test)]
mod tests {
    use super::*;
    use bgdsl_runtime::multibond::rot_z;
    use bgdsl_runtime::Model;
    use core::f64::consts::TAU;

    /// The bearing's spring about Z0 holds minus the angle the crank turned through,
    /// so the output follows the crank through whole turns, as the speed-driven
    /// model's does.
    #[test]
    fn crank_angle_is_unwrapped_by_the_bearing_state() {
        let model = QuickReturnTorque::default();
        let theta0 = model.params.theta0;
        let angle = theta0 + 0.3 + 2.0 * TAU;
        let mut x = vec![0.0; QuickReturnTorque::N_STATES];
        model.initial_state(&mut x);
        let r = rot_z(angle);
        for (k, name) in QuickReturnTorque::STATE_NAMES.iter().enumerate() {
            if let Some(ij) = name.strip_prefix("crank.R_") {
                let (i, j) = (ij.as_bytes()[0] - b'1', ij.as_bytes()[1] - b'1');
                x[k] = r[(usize::from(i), usize::from(j))];
            }
            if *name == "bearing.spring.q_z" {
                x[k] = -(angle - theta0);
            }
        }
        let mut y = vec![0.0; QuickReturnTorque::N_OUTPUTS];
        model.outputs::<f64>(0.0, &x, &mut y);
        let outputs = QuickReturnTorqueOutputs::from_slice(&y);
        assert!(
            (outputs.crank_angle - angle).abs() < 1e-12,
            "{}",
            outputs.crank_angle
        );
    }
}
