//! The flagship: the quick return mechanism of Vaz & Thommen (IPRoMM 2010), as
//! `shared/quick-return-spec.md` fixes it, written as the paper's multibond graph
//! (Fig. 2): five rigid links, the points where they meet, nine spring-damper joints
//! (seven translational, two rotational) and the 5 rad/s drive.

use bgdsl_runtime::multibond::{box_inertia, diag3, rot_z, vec3, Matrix3, Vector3};
use bgdsl_runtime::{bond_graph, Scalar};

/// The angle `wrapped` (in (−π, π], from `atan2`) plus the whole turns that bring it
/// nearest to `near`: `wrapped + 2π·round((near − wrapped) / 2π)`. So the result is
/// always `atan2`'s angle plus whole turns, continued without jumps as long as `near`
/// stays within π of the true angle. The turns are a constant (no derivative flows
/// through them).
pub fn unwrapped_angle<T: Scalar>(wrapped: T, near: T) -> T {
    let turns = ((near.to_f64() - wrapped.to_f64()) / core::f64::consts::TAU).round();
    if turns == 0.0 {
        wrapped
    } else {
        wrapped + T::from_f64(turns * core::f64::consts::TAU)
    }
}

/// Where every link starts: the mechanism assembled at crank angle `theta0` with every
/// joint unstretched (spec, "Geometry").
#[derive(Clone, Copy, Debug)]
pub struct Assembly {
    /// Crank, slider, rocker, rod and output-slider orientations.
    pub orientation: [Matrix3<f64>; 5],
    /// Their centres of mass.
    pub position: [Vector3<f64>; 5],
}

/// Assembles the mechanism: crank pivot at the origin, rocker pivot at (0, -d, 0), the
/// slider centred on the crank pin and aligned with the rocker, the output slider on
/// the line y = 0 to the right of the rocker's tip.
pub fn assembly(theta0: f64, d: f64, crank: f64, rocker: f64, rod: f64) -> Assembly {
    let crank_r = rot_z(theta0);
    let pin = crank_r * vec3(crank, 0.0, 0.0);
    let pivot = vec3(0.0, -d, 0.0);
    let rocker_r = rot_z((pin.y - pivot.y).atan2(pin.x - pivot.x));
    let tip = pivot + rocker_r * vec3(rocker, 0.0, 0.0);
    let slider_5 = vec3(tip.x + (rod * rod - tip.y * tip.y).sqrt(), 0.0, 0.0);
    let rod_r = rot_z((slider_5.y - tip.y).atan2(slider_5.x - tip.x));
    Assembly {
        orientation: [crank_r, rocker_r, rocker_r, rod_r, Matrix3::identity()],
        position: [
            0.5 * pin,
            pin,
            pivot + rocker_r * vec3(0.5 * rocker, 0.0, 0.0),
            0.5 * (tip + slider_5),
            slider_5,
        ],
    }
}

bond_graph! {
    /// The quick return mechanism: crank (1), slider (2) on the rocker arm (3),
    /// connecting rod (4) and output slider (5), joined by compliant joints.
    pub model QuickReturn {
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
        /// drive speed
        param w_drive = 5.0 in "rad/s";
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
        /// drive coupling to the crank (Table 2)
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
        Sf[3] drive = vec3(0.0, 0.0, w_drive);
        1 drive_w;
        drive -> drive_w;

        Coupling j01(a = O1.v, b = ground.v, k = K01, c = R01);
        Coupling j12(a = A1.v, b = slider.v, k = K12, c = R12);
        Coupling j03(a = O3.v, b = ground.v, k = K03, c = R03);
        FrameCoupling j3C(a = slider.v, b = P3.v, frame = rocker.R,
            k = diag3(K3C.x, K3C.y, K3C.z), c = diag3(R3C.x, R3C.y, R3C.z));
        Coupling j23r(a = slider.w, b = rocker.w, k = K23r, c = R23r);
        Coupling jC(a = drive_w, b = crank.w, k = K_C, c = R_C);
        Coupling j34(a = A33.v, b = A4.v, k = K34, c = R34);
        Coupling j45(a = B4.v, b = output_slider.v, k = K45, c = R45);
        Coupling j5C(a = output_slider.v, b = ground.v,
            k = diag3(K5C.x, K5C.y, K5C.z), c = diag3(R5C.x, R5C.y, R5C.z));

        // The results file of the spec, column for column (forces: the named joint's on
        // the named link; a joint pushes its second port with +e, its first with -e).
        // The spec's `atan2(R1[1][0], R1[1][1])` unwrapped, starting at `theta0` (π/2):
        // exactly atan2's angle plus the whole turns that bring it nearest to the angle
        // the crank has turned through, the drive's angle `theta0 + w_drive t` less the
        // drive coupling's twist `jC.spring.q_z` (a state: the integral of the drive's
        // speed less the crank's). So it runs on without jumps through every turn, the
        // same in the results file, the figures, a `Stepper` and the FMU. The drive's
        // angle counts from t = 0 at the current `w_drive`: a run that starts later, or
        // changes `w_drive` part-way (an FMU's tunable parameter), still gets atan2's
        // angle plus whole turns, offset by the turns the drive's angle counts there.
        /// Crank angle about Z0: atan2 of R1 plus the crank's whole turns (unwrapped)
        output crank_angle = unwrapped_angle(crank.R.m21.atan2(crank.R.m22),
            theta0 + w_drive * t - jC.spring.q.z) in "rad";
        /// Crank orientation (crank frame to frame 0)
        output R1: Matrix3 = crank.R in "1";
        /// Crank angular momentum in frame 0
        output h1: Vector3 = crank.rotation.p in "kg·m²/s";
        /// Force of joint O1 (ground) on the crank
        output F_O1: Vector3 = -j01.rel.e in "N";
        /// Drive torque on the crank
        output Tc: Vector3 = jC.rel.e in "N·m";
        /// Force of the crank pin A on the slider
        output F_A2: Vector3 = j12.rel.e in "N";
        /// Rocker centre-of-mass position
        output r_C3: Vector3 = rocker.r in "m";
        /// Rocker momentum
        output p3: Vector3 = rocker.translation.p in "kg·m/s";
        /// Force of joint O3 (ground) on the rocker
        output F_O3: Vector3 = -j03.rel.e in "N";
        /// Connecting-rod orientation (rod frame to frame 0)
        output R4: Matrix3 = rod.R in "1";
        /// Output-slider centre-of-mass position
        output r_C5: Vector3 = output_slider.r in "m";
        /// Output-slider momentum
        output p5: Vector3 = output_slider.translation.p in "kg·m/s";
        /// Force of the connecting rod on the output slider at O5
        output F_O5: Vector3 = j45.rel.e in "N";
        /// Force of the guide on the output slider
        output F_5C: Vector3 = -j5C.rel.e in "N";
        /// Stored energy: kinetic, elastic and potential
        output E_stored = 0.5 * (crank.translation.p.dot(&crank.translation.f)
                + crank.rotation.p.dot(&crank.rotation.f) + slider.translation.p.dot(&slider.translation.f)
                + slider.rotation.p.dot(&slider.rotation.f) + rocker.translation.p.dot(&rocker.translation.f)
                + rocker.rotation.p.dot(&rocker.rotation.f) + rod.translation.p.dot(&rod.translation.f)
                + rod.rotation.p.dot(&rod.rotation.f) + output_slider.translation.p.dot(&output_slider.translation.f)
                + output_slider.rotation.p.dot(&output_slider.rotation.f)
                + j01.spring.q.dot(&j01.spring.e) + j12.spring.q.dot(&j12.spring.e)
                + j03.spring.q.dot(&j03.spring.e) + j3C.spring.q.dot(&j3C.spring.e)
                + j23r.spring.q.dot(&j23r.spring.e) + jC.spring.q.dot(&jC.spring.e)
                + j34.spring.q.dot(&j34.spring.e) + j45.spring.q.dot(&j45.spring.e)
                + j5C.spring.q.dot(&j5C.spring.e))
            + g * (m1 * crank.r.y + m2 * slider.r.y + m3 * rocker.r.y + m4 * rod.r.y + m5 * output_slider.r.y) in "J";
        /// Power delivered by the drive
        output P_in = drive.e.dot(&drive.f) in "W";
        /// Power dissipated in the joints' dampers
        output P_diss = j01.damper.e.dot(&j01.damper.f) + j12.damper.e.dot(&j12.damper.f)
            + j03.damper.e.dot(&j03.damper.f) + j3C.damper.e.dot(&j3C.damper.f)
            + j23r.damper.e.dot(&j23r.damper.f) + jC.damper.e.dot(&jC.damper.f)
            + j34.damper.e.dot(&j34.damper.f) + j45.damper.e.dot(&j45.damper.f)
            + j5C.damper.e.dot(&j5C.damper.f) in "W";
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bgdsl_runtime::Model;

    /// The initial state of `model` with the crank turned to `angle` (its orientation
    /// only: what `crank_angle` reads) and the drive coupling twisted by `twist`.
    fn turned(model: &QuickReturn, angle: f64, twist: f64) -> Vec<f64> {
        let mut x = vec![0.0; QuickReturn::N_STATES];
        model.initial_state(&mut x);
        let r = rot_z(angle);
        for (k, name) in QuickReturn::STATE_NAMES.iter().enumerate() {
            if let Some(ij) = name.strip_prefix("crank.R_") {
                let (i, j) = (ij.as_bytes()[0] - b'1', ij.as_bytes()[1] - b'1');
                x[k] = r[(usize::from(i), usize::from(j))];
            }
            if *name == "jC.spring.q_z" {
                x[k] = twist;
            }
        }
        x
    }

    fn crank_angle(model: &QuickReturn, t: f64, x: &[f64]) -> f64 {
        let mut y = vec![0.0; QuickReturn::N_OUTPUTS];
        model.outputs::<f64>(t, x, &mut y);
        y[QuickReturn::OUTPUT_NAMES
            .iter()
            .position(|n| *n == "crank_angle")
            .unwrap()]
    }

    /// Whatever the time and the twist, the output is atan2's angle plus the whole
    /// turns the crank made: the drive's angle less the twist, to within the half turn
    /// that picks the branch.
    #[test]
    fn crank_angle_is_atan2_plus_the_turns_the_crank_made() {
        let model = QuickReturn::default();
        let (theta0, w) = (model.params.theta0, model.params.w_drive);
        for t in [0.0, 0.7, 3.9, 25.0] {
            for twist in [-1.0, 0.0, 0.5, 1.0] {
                let angle = theta0 + w * t - twist;
                // The crank's orientation a little off what the twist says (the
                // integration's drift): the branch is the same.
                for drift in [-1.0, 0.0, 1.0] {
                    let x = turned(&model, angle + drift, twist);
                    let got = crank_angle(&model, t, &x);
                    let expected = angle + drift;
                    assert!(
                        (got - expected).abs() < 1e-12 * expected.abs().max(1.0),
                        "t = {t}, twist {twist}, drift {drift}: {got} vs {expected}"
                    );
                }
            }
        }
        let mut x0 = vec![0.0; QuickReturn::N_STATES];
        model.initial_state(&mut x0);
        assert_eq!(crank_angle(&model, 0.0, &x0), theta0);
    }
}
