//! The quick return mechanism with an end stop on the output slider's guide: an
//! impact with restitution where the slider reaches `x_stop` (inside its stroke of
//! about −0.008 to 0.694 m with the default parameters; beyond it the stop is never
//! reached and the model is the flagship), with a rest mode against Zeno's cascade of
//! ever smaller impacts while the rod keeps pushing the slider against the stop.
//!
//! The stop is a [`GuideStop`](self) on the slider's momentum: when the slider's x
//! passes `x_stop` (event `stop.hit`) its momentum along X0 is turned over and scaled
//! by the restitution (Newton's law; y and z unchanged); an impact whose rebound speed
//! would be below `v_rest` while the rod pushes the slider into the stop brings it to
//! rest there instead (mode `stop.resting`: momentum along X0 zero, and the stop's
//! reaction, minus the rod's push along X0, holds it), until the rod pulls it away
//! (its push along X0 falls through 0: event `stop.lift`). The energy an impact
//! removes is that event's energy change (`bgdsl_runtime::event_energy`).

use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{box_inertia, diag3, vec3};

use crate::quick_return::assembly;
use crate::quick_return::model::unwrapped_angle;

bond_graph! {
    /// An end stop at `x_stop` along X0 for a body whose momentum element is `body`
    /// (an `I[3]`, handed by name) and whose velocity junction is `at`: `position` is
    /// the body's x, `push` the force along +X0 the rest of the model puts on the body
    /// (what the stop must hold while the body rests on it), `restitution` Newton's
    /// coefficient, `v_rest` the rebound speed below which the body comes to rest.
    submodel GuideStop(body, at, position, push, x_stop, restitution, v_rest) {
        /// resting against the stop
        mode resting: bool = false;
        Se[3] support = ::bgdsl_runtime::multibond::vec3(if resting { -push } else { 0.0 }, 0.0, 0.0);
        support -> at;
        /// hit: the body reaches the stop
        when hit: position > x_stop {
            if restitution * body.f.x.abs() < v_rest && push > 0.0 {
                resting = true;
                reinit body.p = ::bgdsl_runtime::multibond::vec3(0.0, body.p.y, body.p.z);
            } else {
                reinit body.p = ::bgdsl_runtime::multibond::vec3(-restitution * body.p.x, body.p.y, body.p.z);
            }
        }
        /// lift: the rest of the model pulls the body off the stop
        when lift: (if resting { push } else { 1.0 }) < 0.0 {
            resting = false;
        }
    }

    /// The quick return mechanism of the flagship (viscous slides, as the paper) with
    /// an end stop on the output slider's guide at `x_stop`: `GuideStop` instance
    /// `stop`.
    pub model QuickReturnEndStop {
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
        /// the end stop's position on the output slider's guide (X0): reached only inside
        /// the stroke (about −0.008 to 0.694 m with the other defaults)
        param x_stop = 0.69 in "m";
        /// coefficient of restitution of the impacts on the stop
        param restitution = 0.5 in "1";
        /// rebound speed below which the slider comes to rest on the stop
        param v_rest = 0.01 in "m/s";

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
        GuideStop stop(body = output_slider.translation, at = output_slider.v,
            position = output_slider.r.x, push = j45.rel.e.x - j5C.rel.e.x,
            x_stop = x_stop, restitution = restitution, v_rest = v_rest);

        // The spec's results file, column for column, as the flagship writes it.
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

        // The stop's own columns.
        /// Force of the end stop on the output slider along X0 (while it rests there;
        /// an impact's force is an impulse, in the events)
        output F_stop = stop.support.e.x in "N";
        /// Gap between the output slider and the stop along X0 (negative: beyond it)
        output gap = x_stop - output_slider.r.x in "m";
        /// Resting on the stop: 1, else 0
        output resting = if stop.resting { 1.0 } else { 0.0 } in "1";
    }
}
