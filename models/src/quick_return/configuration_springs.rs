//! The quick return's periodic variant (K3C's point under the slider's centre) with its
//! two rotational joints written as springs of the configuration: a study model for the
//! out-of-plane Floquet multiplier 1.08 of the flagship (`docs/quick-return-floquet.md`).
//!
//! In the flagship, `j23r` (slider to rocker) and `jC` (drive to crank) are `Coupling`s:
//! their spring state is the integral of the relative angular velocity in frame 0,
//! which is not a function of the two orientations (rotations do not commute), so their
//! torque is not the gradient of a potential of the configuration. Here each is a
//! [`RotationSpring`](self): the potential `V = k (3 − tr(R_aᵀ R_b)) / 2` of the
//! relative orientation (zero when aligned, `k θ²/2` for a small relative angle θ)
//! exerts the torque `−k vee(skew(R_b R_aᵀ))` on `b` and its opposite on `a`, beside the
//! flagship's damper on the relative angular velocity. The drive's orientation is
//! `rot_z(theta0 + w_drive t)`. Every other element, parameter and initial state is the
//! flagship's; the model has no twist states (the rotational joints store no state), so
//! it is driven in time rather than autonomous.

use bgdsl_runtime::multibond::{box_inertia, diag3, rot_z, vec3, Matrix3, Vector3};
use bgdsl_runtime::{bond_graph, Scalar};

use crate::quick_return::assembly;
use crate::quick_return::model::unwrapped_angle;

/// The rotation spring's moment `vee((M − Mᵀ)/2)` with `M = R_b R_aᵀ`, the relative
/// rotation from `a` to `b` in frame 0: `sin θ` times the unit axis for a rotation by θ.
/// `k` times it is the torque the spring exerts on `a` (its opposite on `b`), the
/// gradient of `k (3 − tr(R_aᵀ R_b)) / 2`.
pub fn rotation_moment<T: Scalar>(ra: Matrix3<T>, rb: Matrix3<T>) -> Vector3<T> {
    let m = rb * ra.transpose();
    let half = T::from_f64(0.5);
    vec3(
        half * (m.m32 - m.m23),
        half * (m.m13 - m.m31),
        half * (m.m21 - m.m12),
    )
}

/// The rotation spring's potential `k (3 − tr(R_aᵀ R_b)) / 2`, J.
pub fn rotation_energy<T: Scalar>(k: T, ra: Matrix3<T>, rb: Matrix3<T>) -> T {
    let trace = (ra.transpose() * rb).trace();
    T::from_f64(0.5) * k * (T::from_f64(3.0) - trace)
}

bond_graph! {
    /// A rotational spring-damper between angular-velocity ports `a` and `b` whose
    /// orientations are `Ra` and `Rb` (frame → frame 0): the spring is the potential
    /// `k (3 − tr(Raᵀ Rb)) / 2` of their relative orientation, the damper `c` acts on
    /// the relative angular velocity a − b. Its torque acts on `b`, its opposite on
    /// `a`, as a `Coupling`'s does.
    submodel RotationSpring(a, b, Ra, Rb, k, c) {
        0 rel;
        1 d;
        /// the spring's torque on `a` (the 1-junction's effort balance gives `b` its
        /// opposite): it absorbs exactly the potential's rate of change
        Se[3] spring = crate::quick_return::configuration_springs::rotation_moment(Ra, Rb) * k;
        R[3] damper = c;
        a -> rel -> b;
        rel -> d -> damper;
        spring -> d;
    }

    /// The quick return mechanism's periodic variant (K3C's point under the slider)
    /// with configuration springs in its two rotational joints.
    pub model QuickReturnRotationSprings {
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
        /// slider's rotation locked to the rocker's (Table 2), a configuration spring
        param K23r = 100.0 in "N·m/rad";
        param R23r = 0.5 in "N·m·s/rad";
        /// drive coupling to the crank (Table 2), a configuration spring
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
        OffsetPoint P3(body = rocker, offset = slider.r - rocker.r);
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
        RotationSpring j23r(a = slider.w, b = rocker.w, Ra = slider.R, Rb = rocker.R,
            k = K23r, c = R23r);
        RotationSpring jC(a = drive_w, b = crank.w, Ra = rot_z(theta0 + w_drive * t),
            Rb = crank.R, k = K_C, c = R_C);
        Coupling j34(a = A33.v, b = A4.v, k = K34, c = R34);
        Coupling j45(a = B4.v, b = output_slider.v, k = K45, c = R45);
        Coupling j5C(a = output_slider.v, b = ground.v,
            k = diag3(K5C.x, K5C.y, K5C.z), c = diag3(R5C.x, R5C.y, R5C.z));

        /// Crank angle about Z0: atan2 of R1 plus the whole turns nearest the drive's
        /// angle (the crank lags it by far less than half a turn)
        output crank_angle = unwrapped_angle(crank.R.m21.atan2(crank.R.m22),
            theta0 + w_drive * t) in "rad";
        /// Drive torque on the crank
        output Tc: Vector3 = jC.rel.e in "N·m";
        /// Stored energy: kinetic, elastic (the rotation springs' potentials) and
        /// potential
        output E_stored = 0.5 * (crank.translation.p.dot(&crank.translation.f)
                + crank.rotation.p.dot(&crank.rotation.f) + slider.translation.p.dot(&slider.translation.f)
                + slider.rotation.p.dot(&slider.rotation.f) + rocker.translation.p.dot(&rocker.translation.f)
                + rocker.rotation.p.dot(&rocker.rotation.f) + rod.translation.p.dot(&rod.translation.f)
                + rod.rotation.p.dot(&rod.rotation.f) + output_slider.translation.p.dot(&output_slider.translation.f)
                + output_slider.rotation.p.dot(&output_slider.rotation.f)
                + j01.spring.q.dot(&j01.spring.e) + j12.spring.q.dot(&j12.spring.e)
                + j03.spring.q.dot(&j03.spring.e) + j3C.spring.q.dot(&j3C.spring.e)
                + j34.spring.q.dot(&j34.spring.e) + j45.spring.q.dot(&j45.spring.e)
                + j5C.spring.q.dot(&j5C.spring.e))
            + rotation_energy(K23r, slider.R, rocker.R)
            + rotation_energy(K_C, rot_z(theta0 + w_drive * t), crank.R)
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
