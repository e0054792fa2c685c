//! The quick return mechanism with rigid joints, written as the paper's bond graph
//! without the joint springs: the five links' inertias, the points where they meet, the
//! two prismatic joints' viscous friction (R3C, R5C) and the drive.
//!
//! # The joint set, and why
//!
//! The mechanism is planar, so the model is too: each link has a planar translation
//! (`I[2]`, its mass) and a rotation about Z0 (`I`, its box inertia `J_z`); the
//! out-of-plane motion the 3-D model holds stiff is simply absent. That is the
//! well-posed joint set with the fewest unknowns: the 3-D links with every
//! out-of-plane motion locked would add constraints that only carry zeros, and a 3-D
//! pin that locks two rotations twice over (the slider's and the rocker's) is a
//! redundant constraint.
//!
//! - **Pins** (O1, A, O3, the rocker's tip) are shared point velocities: a point of a
//!   link (`PlanarPoint`: `v = v_c + ω × offset`, its force turned into a torque by
//!   the same lever) joined to the ground by a zero flow source, or to the other link's
//!   point by one bond, whose effort is the pin's force.
//! - **The slider turns with the rocker**: its rotation sits on the rocker's angular
//!   velocity junction, one bond whose effort is the couple M23.
//! - **Each closed loop is closed by one configuration-dependent transformer.** The
//!   crank, slider, rocker and ground form a loop, and so do the rocker, rod, output
//!   slider and ground. Each is closed where the loop's two unknown speeds meet: the
//!   slider's velocity `v_A` gives the rocker's angular velocity and the slide speed,
//!   `(ω₃, ṡ)`, through the 2×2 `slider_joint` (with O3 fixed, `v_A = s ω₃ ê⊥ + ṡ ê`);
//!   the rocker tip's velocity gives the rod's angular velocity and the output
//!   slider's speed, `(ω₄, ẋ₅)`, through `output_joint`. A splitter hands the two
//!   components to their junctions: the angular velocity to the link, the slide speed
//!   to its viscous friction (R3C, R5C, as in the reference). So every flow follows
//!   causally from the crank's speed, and with the crank driven by a flow source no
//!   storage element is independent: all of them are dependent storage
//!   (`#[allow(derivative_causality)]`), the only state is the crank angle, and no
//!   equation is solved at run time.
//! - **Where the loop's force goes.** A closure transformer carries the joint's force
//!   to the links as generalised forces (the rocker's moment about O3, the slide's
//!   force; the rod's moment about its pin at the tip, the output slider's push), so
//!   the dynamics are exact. The closure's own bond carries the joint's force
//!   (`closure_3.e`: the slider's on the rocker; `closure_5.e`: the rod's on the output
//!   slider, `F_O5`), and so do the bonds of the links outside the loops (`pin_A`,
//!   the pivot O1, the drive). The bond that holds the link a loop closes on carries
//!   that force too, since it reaches the link through the closure instead of at the
//!   joint: the rocker's pivot bond (the output `F_O3` takes it off,
//!   `-pivot_O3.e - closure_3.e`) and the rod's pin at the tip (its force on the rod
//!   is `pin_34.e + closure_5.e`, the output `F_34`). The guide's normal force on the
//!   output slider is likewise the part of the rod's force the guide's projection does
//!   not pass on: `F_5C_y = m5 g − F_O5_y`.
//!
//! # Why the crank angle is the one state
//!
//! Every modulus (the levers, the two closures) is a closed form of the crank angle θ
//! ([`super::pose`]): the configuration of a one-degree-of-freedom mechanism. Integrating
//! each link's position and angle instead (as the compliant model must) would let them
//! drift off the constraints at the integrator's tolerance, with nothing to pull them
//! back; reading the pose from θ keeps the links assembled exactly, at any tolerance.
//!
//! # The two models
//!
//! - [`QuickReturnRigid`]: the crank driven by a flow source at `w_drive`. One state
//!   (θ), no solve: the drive torque and every joint force are what the inertias need
//!   along the prescribed motion, the inverse dynamics in bond-graph form.
//! - [`QuickReturnRigidCoupled`]: the crank driven through the paper's compliant drive
//!   coupling (a torsional spring-damper from a motor at `w_drive`), as the flagship.
//!   The crank's rotation is the one independent inertia (its angular momentum is a
//!   state); every other inertia is dependent, so each evaluation solves one linear
//!   equation for the crank's angular acceleration (the mechanism's configuration-
//!   dependent inertia, in disguise).
//!
//! Both write the spec's results columns (the compliant model's outputs, by name), so
//! the catalogue writes the same results file and draws the same figures.

use bgdsl_runtime::bond_graph;
use bgdsl_runtime::multibond::box_inertia;

use super::pose::{
    about_z, centre_of, crank_lever, in_plane, in_plane_scaled, mass_moment_y, output_closure,
    rocker_lever, rod_angle, rod_lever, rotation, slider_closure, vec2, OUTPUT, ROCKER,
};

bond_graph! {
    /// A link moving in the plane: its mass (a 2-D translation) and its inertia about
    /// Z0, its weight along −Y0. Ports: `v` (the centre of mass's velocity) and `w`
    /// (the angular velocity).
    submodel PlanarBody(m, J, g) {
        /// angular momentum about Z0 (first: where one inertia of a mechanism stays
        /// independent, the crank's rotation is the natural one)
        I rotation = J, p in "kg·m²/s";
        /// momentum in frame 0
        I[2] translation = m, p in "kg·m/s";
        Se[2] weight = vec2(0.0, -m * g);
        1[2] v;
        1 w;
        weight -> v -> translation;
        w -> rotation;
    }

    /// The point of `body` whose lever (from the centre of mass) is `arm_at`: its
    /// velocity `v + lever ω` is the common flow of its port `v`; a force there is a
    /// torque `lever · F` on the body.
    submodel PlanarPoint(body, arm_at) {
        MTF arm = arm_at;
        0[2] sum;
        1[2] v;
        body.v -> sum;
        body.w -> arm -> sum;
        sum -> v;
    }

    /// The five links and their rigid joints (see the [module documentation](self)):
    /// the crank's angular velocity `crank.w` is the port a drive turns, `theta` the
    /// crank angle.
    // README.md shows this submodel from here to its end marker, word for word (a
    // test in models/tests/quick_return_rigid.rs compares them).
    // README: rigid_links
    submodel RigidLinks(m1, m2, m3, m4, m5, l1, l2, l3, l4, l5, d, g, theta0, R3C, R5C) {
        /// crank angle θ from X0: the mechanism's configuration
        state theta: f64 = theta0 in "rad";
        der theta = crank.w.f;

        PlanarBody crank(m = m1, J = box_inertia(m1, l1.x, l1.y, l1.z).z, g = g);
        PlanarBody slider(m = m2, J = box_inertia(m2, l2.x, l2.y, l2.z).z, g = g);
        PlanarBody rocker(m = m3, J = box_inertia(m3, l3.x, l3.y, l3.z).z, g = g);
        PlanarBody rod(m = m4, J = box_inertia(m4, l4.x, l4.y, l4.z).z, g = g);
        /// the output slider's momentum (it does not turn)
        I[2] output_slider = m5, p in "kg·m/s";
        Se[2] output_weight = vec2(0.0, -m5 * g);
        1[2] output_v;
        output_weight -> output_v -> output_slider;

        PlanarPoint O1(body = crank, arm_at = crank_lever(theta, -0.5 * l1.x));
        PlanarPoint A1(body = crank, arm_at = crank_lever(theta, 0.5 * l1.x));
        PlanarPoint O3(body = rocker, arm_at = rocker_lever(theta, l1.x, d, -0.5 * l3.x));
        PlanarPoint A33(body = rocker, arm_at = rocker_lever(theta, l1.x, d, 0.5 * l3.x));
        PlanarPoint A4(body = rod, arm_at = rod_lever(theta, l1.x, d, l3.x, l4.x, -0.5 * l4.x));

        // The two fixed pivots.
        Sf[2] pivot_O1 = vec2(0.0, 0.0);
        Sf[2] pivot_O3 = vec2(0.0, 0.0);
        O1.v -> pivot_O1;
        O3.v -> pivot_O3;

        // Pins: the crank pin is the slider's centre; the rod hangs on the rocker's tip.
        A1.v -[pin_A]-> slider.v;
        A33.v -[pin_34]-> A4.v;
        // The slider turns with the rocker.
        rocker.w -[couple_23]-> slider.w;

        // The slider's loop, closed at the slider: (ω₃, ṡ) from v_A.
        MTF slider_joint = slider_closure(theta, l1.x, d);
        Split[2] rocker_slide;
        1 slide;
        R friction_3C = R3C;
        slider.v -[closure_3]-> slider_joint -> rocker_slide;
        rocker_slide.0 -> rocker.w;
        rocker_slide.1 -> slide -> friction_3C;

        // The output slider's loop, closed at the tip: (ω₄, ẋ₅) from the tip's velocity.
        MTF output_joint = output_closure(theta, l1.x, d, l3.x, l4.x);
        Split[2] rod_output;
        1 output_x;
        R friction_5C = R5C;
        MTF guide = vec2(1.0, 0.0);
        A33.v -[closure_5]-> output_joint -> rod_output;
        rod_output.0 -> rod.w;
        rod_output.1 -> output_x;
        output_x -> friction_5C;
        output_x -> guide -> output_v;
    }

    // README_END: rigid_links

    /// The quick return mechanism with rigid joints, the crank driven at `w_drive`
    /// by a flow source: crank (1), slider (2) on the rocker (3), connecting rod (4),
    /// output slider (5), in the plane. Every inertia is dependent storage; the one
    /// state is the crank angle.
    #[allow(derivative_causality)]
    pub model QuickReturnRigid {
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
        /// crank edge lengths (lx, ly, lz): lx from O1 to the pin A (Table 1)
        param l1: [f64; 3] = [0.2, 0.01, 0.01] in "m";
        /// slider edge lengths (Table 1)
        param l2: [f64; 3] = [0.01, 0.01, 0.01] in "m";
        /// rocker edge lengths: lx from O3 to the tip (Table 1)
        param l3: [f64; 3] = [0.7, 0.01, 0.01] in "m";
        /// connecting-rod edge lengths: lx from the rocker's tip to O5 (Table 1)
        param l4: [f64; 3] = [0.4, 0.01, 0.01] in "m";
        /// output-slider edge lengths (Table 1; it slides without turning, so only its
        /// mass enters)
        param l5: [f64; 3] = [0.01, 0.01, 0.01] in "m";
        /// distance from the crank pivot O1 down to the rocker pivot O3
        param d = 0.4 in "m";
        /// gravity, along -Y0
        param g = 9.81 in "m/s²";
        /// drive speed
        param w_drive = 5.0 in "rad/s";
        /// initial crank angle
        param theta0 = core::f64::consts::FRAC_PI_2 in "rad";
        /// viscous friction of the slider along the rocker (Table 2, R3C along X3)
        param R3C = 20.0 in "N·s/m";
        /// viscous friction of the output slider along its guide (Table 2, R5C along X0)
        param R5C = 20.0 in "N·s/m";


        RigidLinks links(m1 = m1, m2 = m2, m3 = m3, m4 = m4, m5 = m5, l1 = l1, l2 = l2, l3 = l3, l4 = l4,
            l5 = l5, d = d, g = g, theta0 = theta0, R3C = R3C, R5C = R5C);
        Sf drive = w_drive;
        drive -> links.crank.w;

        // The spec's results columns (forces: the named joint's on the named link).
        /// Crank angle about Z0 (the state: unwrapped)
        output crank_angle = links.theta in "rad";
        /// Crank orientation (crank frame to frame 0)
        output R1: Matrix3 = rotation(links.theta) in "1";
        /// Crank angular momentum in frame 0
        output h1: Vector3 = about_z(box_inertia(m1, l1.x, l1.y, l1.z).z * links.crank.w.f) in "kg·m²/s";
        /// Force of joint O1 (ground) on the crank
        output F_O1: Vector3 = in_plane(-links.pivot_O1.e) in "N";
        /// Drive torque on the crank
        output Tc: Vector3 = about_z(drive.e) in "N·m";
        /// Force of the crank pin A on the slider
        output F_A2: Vector3 = in_plane(links.pin_A.e) in "N";
        /// Rocker centre-of-mass position
        output r_C3: Vector3 = in_plane(centre_of(ROCKER, links.theta, l1.x, d, l3.x, l4.x)) in "m";
        /// Rocker momentum
        output p3: Vector3 = in_plane_scaled(m3, links.rocker.v.f) in "kg·m/s";
        /// Force of joint O3 (ground) on the rocker: the pivot's bond less the slider's
        /// force, which reaches the rocker through the loop's closure
        output F_O3: Vector3 = in_plane(-links.pivot_O3.e - links.closure_3.e) in "N";
        /// Connecting-rod orientation (rod frame to frame 0)
        output R4: Matrix3 = rotation(rod_angle(links.theta, l1.x, d, l3.x, l4.x)) in "1";
        /// Output-slider centre-of-mass position
        output r_C5: Vector3 = in_plane(centre_of(OUTPUT, links.theta, l1.x, d, l3.x, l4.x)) in "m";
        /// Output-slider momentum
        output p5: Vector3 = in_plane_scaled(m5, links.output_v.f) in "kg·m/s";
        /// Force of the connecting rod on the output slider at O5
        output F_O5: Vector3 = in_plane(links.closure_5.e) in "N";
        /// Force of the rocker on the slider: the normal force and the slide's friction
        output F_3C: Vector3 = in_plane(-links.closure_3.e) in "N";
        /// Force of the rocker on the connecting rod at the tip (the pin's bond less the
        /// output slider's force, which reaches the rod through the loop's closure)
        output F_34: Vector3 = in_plane(links.pin_34.e + links.closure_5.e) in "N";
        /// Force of the guide on the output slider: friction along X0, normal support
        output F_5C: Vector3 = in_plane(vec2(-links.friction_5C.e, m5 * g - links.closure_5.e.y)) in "N";
        /// Stored energy: kinetic and potential
        output E_stored = 0.5 * (m1 * links.crank.v.f.dot(&links.crank.v.f)
                + m2 * links.slider.v.f.dot(&links.slider.v.f)
                + m3 * links.rocker.v.f.dot(&links.rocker.v.f)
                + m4 * links.rod.v.f.dot(&links.rod.v.f)
                + m5 * links.output_v.f.dot(&links.output_v.f)
                + box_inertia(m1, l1.x, l1.y, l1.z).z * links.crank.w.f * links.crank.w.f
                + box_inertia(m2, l2.x, l2.y, l2.z).z * links.slider.w.f * links.slider.w.f
                + box_inertia(m3, l3.x, l3.y, l3.z).z * links.rocker.w.f * links.rocker.w.f
                + box_inertia(m4, l4.x, l4.y, l4.z).z * links.rod.w.f * links.rod.w.f)
            + g * mass_moment_y(links.theta, l1.x, d, l3.x, l4.x, [m1, m2, m3, m4]) in "J";
        /// Power delivered by the drive
        output P_in = drive.e * drive.f in "W";
        /// Power dissipated by the slides' friction
        output P_diss = links.friction_3C.e * links.friction_3C.f
            + links.friction_5C.e * links.friction_5C.f in "W";
    }

    /// The rigid quick return driven as the flagship: a motor at `w_drive` turns the
    /// crank through the paper's compliant drive coupling (a torsional spring-damper).
    /// The crank's rotation is the one independent inertia.
    #[allow(derivative_causality)]
    pub model QuickReturnRigidCoupled {
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
        /// crank edge lengths (lx, ly, lz): lx from O1 to the pin A (Table 1)
        param l1: [f64; 3] = [0.2, 0.01, 0.01] in "m";
        /// slider edge lengths (Table 1)
        param l2: [f64; 3] = [0.01, 0.01, 0.01] in "m";
        /// rocker edge lengths: lx from O3 to the tip (Table 1)
        param l3: [f64; 3] = [0.7, 0.01, 0.01] in "m";
        /// connecting-rod edge lengths: lx from the rocker's tip to O5 (Table 1)
        param l4: [f64; 3] = [0.4, 0.01, 0.01] in "m";
        /// output-slider edge lengths (Table 1; it slides without turning, so only its
        /// mass enters)
        param l5: [f64; 3] = [0.01, 0.01, 0.01] in "m";
        /// distance from the crank pivot O1 down to the rocker pivot O3
        param d = 0.4 in "m";
        /// gravity, along -Y0
        param g = 9.81 in "m/s²";
        /// drive speed
        param w_drive = 5.0 in "rad/s";
        /// initial crank angle
        param theta0 = core::f64::consts::FRAC_PI_2 in "rad";
        /// viscous friction of the slider along the rocker (Table 2, R3C along X3)
        param R3C = 20.0 in "N·s/m";
        /// viscous friction of the output slider along its guide (Table 2, R5C along X0)
        param R5C = 20.0 in "N·s/m";

        /// drive coupling to the crank: stiffness (Table 2)
        param K_C = 100.0 in "N·m/rad";
        /// drive coupling to the crank: damping (Table 2)
        param R_C = 100.0 in "N·m·s/rad";

        RigidLinks links(m1 = m1, m2 = m2, m3 = m3, m4 = m4, m5 = m5, l1 = l1, l2 = l2, l3 = l3, l4 = l4,
            l5 = l5, d = d, g = g, theta0 = theta0, R3C = R3C, R5C = R5C);
        Sf drive = w_drive;
        0 coupling;
        1 twist_rate;
        /// the drive coupling's twist: the drive's angle less the crank's
        C coupling_spring = K_C, q in "rad";
        R coupling_damper = R_C;
        drive -> coupling -> links.crank.w;
        coupling -> twist_rate -> { coupling_spring, coupling_damper };

        // The spec's results columns (forces: the named joint's on the named link).
        /// Crank angle about Z0 (the state: unwrapped)
        output crank_angle = links.theta in "rad";
        /// Crank orientation (crank frame to frame 0)
        output R1: Matrix3 = rotation(links.theta) in "1";
        /// Crank angular momentum in frame 0
        output h1: Vector3 = about_z(box_inertia(m1, l1.x, l1.y, l1.z).z * links.crank.w.f) in "kg·m²/s";
        /// Force of joint O1 (ground) on the crank
        output F_O1: Vector3 = in_plane(-links.pivot_O1.e) in "N";
        /// Drive torque on the crank
        output Tc: Vector3 = about_z(coupling.e) in "N·m";
        /// Force of the crank pin A on the slider
        output F_A2: Vector3 = in_plane(links.pin_A.e) in "N";
        /// Rocker centre-of-mass position
        output r_C3: Vector3 = in_plane(centre_of(ROCKER, links.theta, l1.x, d, l3.x, l4.x)) in "m";
        /// Rocker momentum
        output p3: Vector3 = in_plane_scaled(m3, links.rocker.v.f) in "kg·m/s";
        /// Force of joint O3 (ground) on the rocker: the pivot's bond less the slider's
        /// force, which reaches the rocker through the loop's closure
        output F_O3: Vector3 = in_plane(-links.pivot_O3.e - links.closure_3.e) in "N";
        /// Connecting-rod orientation (rod frame to frame 0)
        output R4: Matrix3 = rotation(rod_angle(links.theta, l1.x, d, l3.x, l4.x)) in "1";
        /// Output-slider centre-of-mass position
        output r_C5: Vector3 = in_plane(centre_of(OUTPUT, links.theta, l1.x, d, l3.x, l4.x)) in "m";
        /// Output-slider momentum
        output p5: Vector3 = in_plane_scaled(m5, links.output_v.f) in "kg·m/s";
        /// Force of the connecting rod on the output slider at O5
        output F_O5: Vector3 = in_plane(links.closure_5.e) in "N";
        /// Force of the rocker on the slider: the normal force and the slide's friction
        output F_3C: Vector3 = in_plane(-links.closure_3.e) in "N";
        /// Force of the rocker on the connecting rod at the tip (the pin's bond less the
        /// output slider's force, which reaches the rod through the loop's closure)
        output F_34: Vector3 = in_plane(links.pin_34.e + links.closure_5.e) in "N";
        /// Force of the guide on the output slider: friction along X0, normal support
        output F_5C: Vector3 = in_plane(vec2(-links.friction_5C.e, m5 * g - links.closure_5.e.y)) in "N";
        /// Stored energy: kinetic, elastic and potential
        output E_stored = 0.5 * (m1 * links.crank.v.f.dot(&links.crank.v.f)
                + m2 * links.slider.v.f.dot(&links.slider.v.f)
                + m3 * links.rocker.v.f.dot(&links.rocker.v.f)
                + m4 * links.rod.v.f.dot(&links.rod.v.f)
                + m5 * links.output_v.f.dot(&links.output_v.f)
                + box_inertia(m1, l1.x, l1.y, l1.z).z * links.crank.w.f * links.crank.w.f
                + box_inertia(m2, l2.x, l2.y, l2.z).z * links.slider.w.f * links.slider.w.f
                + box_inertia(m3, l3.x, l3.y, l3.z).z * links.rocker.w.f * links.rocker.w.f
                + box_inertia(m4, l4.x, l4.y, l4.z).z * links.rod.w.f * links.rod.w.f
                + coupling_spring.q * coupling_spring.e)
            + g * mass_moment_y(links.theta, l1.x, d, l3.x, l4.x, [m1, m2, m3, m4]) in "J";
        /// Power delivered by the drive
        output P_in = drive.e * drive.f in "W";
        /// Power dissipated by the slides' friction and the coupling
        output P_diss = links.friction_3C.e * links.friction_3C.f
            + links.friction_5C.e * links.friction_5C.f
            + coupling_damper.e * coupling_damper.f in "W";
    }
}
