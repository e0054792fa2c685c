//! The quick return mechanism with Coulomb friction and stiction in its two slides (the
//! slider on the rocker, the output slider on its guide), beside the paper's viscous
//! 20 N·s/m (set `R3C[0]`, `R5C[0]` to 0 for Coulomb friction instead of it).
//!
//! Each slide is a [`FrictionSlide`](self): the flagship's slide joint (a spring-damper
//! that is free along the slide and stiff across it) with a friction element on its
//! slide direction. Its normal force is the joint's spring force across the guide,
//! `N = |(spring.e_y, spring.e_z)|` (in the guide's frame), and:
//!
//! - **slipping**, the friction force is `mu N` against the slip velocity, whose
//!   direction is the mode `dir` (+1: the first port moves along the guide's x
//!   relative to the second);
//! - when the slip velocity falls to zero (it crosses zero against `dir`) the slide
//!   **sticks** (mode `stuck`): it then holds along the slide as the compliant joints
//!   of the paper hold every constraint, with a spring of stiffness `K_stick` from the
//!   point where it stuck (the spring's travel is reset to 0 there);
//! - it **breaks away** when that spring's force exceeds the static limit `mu_s N`
//!   (the indicator `F² − (mu_s N)²` rises through 0), and slips on the way the spring
//!   was pushing. The energy the stick spring held is dropped at breakaway: an event
//!   energy (`bgdsl_runtime::event_energy`), part of the friction loss.
//!
//! With `mu = mu_s = 0` no indicator ever crosses (they are held at 1 in the slip
//! mode) and the slides are the flagship's: the model is the flagship plus four
//! constant modes.

use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::{box_inertia, diag3, vec3};

use crate::quick_return::assembly;
use crate::quick_return::model::unwrapped_angle;

bond_graph! {
    /// A slide with Coulomb friction and stiction between ports `a` and `b` (point
    /// velocities), its laws in the moving frame `frame` (frame → frame 0) whose x axis
    /// is the slide: the flagship's slide joint (stiffness `k`, damping `c`, both
    /// vectors of the three axes, `k.x` normally 0) with a friction element along x.
    /// `mu`, `mu_s`: kinetic and static coefficients on the normal force (the spring
    /// force across the slide); `k_stick`: the stiffness along x while stuck.
    submodel FrictionSlide(a, b, frame, k, c, mu, mu_s, k_stick) {
        /// the slide holds (static friction)
        mode stuck: bool = false;
        /// the way the slide slips: +1 when `a` moves along x relative to `b`, −1 back
        mode dir: f64 = 1.0;
        0 rel;
        MTF to_frame = frame.transpose(), inverse = frame;
        1 d;
        /// deflection: the integral of a − b in the moving frame (x: the travel since
        /// the slide last stuck, while stuck)
        C[3] spring = diag3(if stuck { k_stick } else { k.x }, k.y, k.z);
        R[3] damper = diag3(c.x, c.y, c.z);
        /// kinetic friction along the slide, `mu N` against the slip (0 while stuck);
        /// the 1e-9 N keeps N differentiable where the joint is unloaded (t = 0)
        R[3] friction {
            e = ::bgdsl_runtime::multibond::vec3(
                if stuck { 0.0 } else {
                    mu * dir * (spring.e.y * spring.e.y + spring.e.z * spring.e.z + 1e-18).sqrt()
                },
                0.0,
                0.0,
            )
        };
        a -> rel -> b;
        rel -> to_frame -> d -> { spring, damper, friction };

        /// stick: the slip velocity falls to zero
        when stick: (if stuck || mu_s <= 0.0 && mu <= 0.0 { 1.0 } else { d.f.x * dir }) < 0.0 {
            if mu_s > 0.0 {
                stuck = true;
                reinit spring.q = ::bgdsl_runtime::multibond::vec3(0.0, spring.q.y, spring.q.z);
            } else {
                dir = -dir;
            }
        }
        /// breakaway: the stick spring's force exceeds the static limit
        when breakaway: (if stuck {
            spring.e.x * spring.e.x
                - mu_s * mu_s * (spring.e.y * spring.e.y + spring.e.z * spring.e.z + 1e-18)
        } else { -1.0 }) > 0.0 {
            stuck = false;
            dir = if spring.q.x > 0.0 { 1.0 } else { -1.0 };
        }
    }

    /// The quick return mechanism of the flagship with Coulomb friction and stiction
    /// in its two slides: the slider on the rocker (`j3C`) and the output slider on its
    /// guide (`j5C`), each a `FrictionSlide`.
    pub model QuickReturnFriction {
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
        /// its damping; the x entry is the slide's viscous friction (0: Coulomb only)
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
        /// its damping; the x entry is the slide's viscous friction (0: Coulomb only)
        param R5C: [f64; 3] = [20.0, 20.0, 20.0] in "N·s/m";
        /// the rocker's point for K3C: 0 under the crank pin (the authors' choice),
        /// 1 under the slider's centre (the periodic one)
        param k3c_point_under_slider = 0.0;
        /// kinetic (Coulomb) friction coefficient of both slides, on the normal force
        param mu = 0.1 in "1";
        /// static friction coefficient of both slides (0: no stiction)
        param mu_s = 0.15 in "1";
        /// stiffness of a stuck slide along it (as stiff as the joints across it)
        param K_stick = 1.0e5 in "N/m";

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
        FrictionSlide j3C(a = slider.v, b = P3.v, frame = rocker.R,
            k = vec3(K3C.x, K3C.y, K3C.z), c = vec3(R3C.x, R3C.y, R3C.z),
            mu = mu, mu_s = mu_s, k_stick = K_stick);
        Coupling j23r(a = slider.w, b = rocker.w, k = K23r, c = R23r);
        Coupling jC(a = drive_w, b = crank.w, k = K_C, c = R_C);
        Coupling j34(a = A33.v, b = A4.v, k = K34, c = R34);
        Coupling j45(a = B4.v, b = output_slider.v, k = K45, c = R45);
        FrictionSlide j5C(a = output_slider.v, b = ground.v,
            frame = diag3(1.0, 1.0, 1.0),
            k = vec3(K5C.x, K5C.y, K5C.z), c = vec3(R5C.x, R5C.y, R5C.z),
            mu = mu, mu_s = mu_s, k_stick = K_stick);

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
        /// Force of the guide on the output slider (friction included)
        output F_5C: Vector3 = -j5C.rel.e in "N";
        /// Stored energy: kinetic, elastic (a stuck slide's spring included) and potential
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
        /// Power dissipated in the joints' dampers and the slides' kinetic friction
        output P_diss = j01.damper.e.dot(&j01.damper.f) + j12.damper.e.dot(&j12.damper.f)
            + j03.damper.e.dot(&j03.damper.f) + j3C.damper.e.dot(&j3C.damper.f)
            + j23r.damper.e.dot(&j23r.damper.f) + jC.damper.e.dot(&jC.damper.f)
            + j34.damper.e.dot(&j34.damper.f) + j45.damper.e.dot(&j45.damper.f)
            + j5C.damper.e.dot(&j5C.damper.f)
            + j3C.friction.e.dot(&j3C.friction.f) + j5C.friction.e.dot(&j5C.friction.f) in "W";

        // The friction's own columns.
        /// Friction force of the rocker on the slider along the rocker (X3): kinetic
        /// while slipping, the stick spring's while stuck
        output Ff_3C = -(j3C.friction.e.x + j3C.spring.e.x) in "N";
        /// Normal force between the slider and the rocker (the joint's spring force
        /// across the slide)
        output N_3C = (j3C.spring.e.y * j3C.spring.e.y + j3C.spring.e.z * j3C.spring.e.z).sqrt() in "N";
        /// Friction force of the guide on the output slider along X0
        output Ff_5C = -(j5C.friction.e.x + j5C.spring.e.x) in "N";
        /// Normal force between the output slider and its guide
        output N_5C = (j5C.spring.e.y * j5C.spring.e.y + j5C.spring.e.z * j5C.spring.e.z).sqrt() in "N";
        /// Slip velocity of the slider along the rocker (X3)
        output u_3C = j3C.d.f.x in "m/s";
        /// Slip velocity of the output slider along its guide (X0)
        output u_5C = j5C.d.f.x in "m/s";
        /// Mode of the rocker's slide: 0 stuck, +1 the slider slipping along X3
        /// relative to the rocker, −1 against
        output mode_3C = if j3C.stuck { 0.0 } else { j3C.dir } in "1";
        /// Mode of the output slider's guide: 0 stuck, ±1 slipping along ±X0
        output mode_5C = if j5C.stuck { 0.0 } else { j5C.dir } in "1";
        /// Power dissipated by kinetic friction in both slides
        output P_fric = j3C.friction.e.dot(&j3C.friction.f) + j5C.friction.e.dot(&j5C.friction.f) in "W";
        /// Power dissipated by the slides' viscous friction (the dampers' x entries)
        output P_visc_slides = j3C.damper.e.x * j3C.damper.f.x + j5C.damper.e.x * j5C.damper.f.x in "W";
    }
}
