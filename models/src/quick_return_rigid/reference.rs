//! The rigid-body reference of the quick return mechanism (`shared/quick-return-spec.md`):
//! closed-form kinematics of the ideal, rigid-jointed mechanism, and its inverse dynamics
//! (Newton–Euler for every link), for a given crank angle, speed and acceleration.
//!
//! The compliant model of the paper (spring-damper joints) tends to this one as its
//! joints stiffen; the tests compare the two.
//!
//! # Geometry (frame 0: origin at the crank pivot O1, X0 right, Y0 up)
//!
//! The crank pin A is at `r (cos θ, sin θ)` (r = the crank's length `l1[0]`); the slider
//! (link 2) has its centre at A and slides along the rocker (link 3), which turns about
//! O3 = (0, −d). With `u = A − O3`: the slider's distance from O3 along the rocker is
//! `s = |u|`, the rocker's angle from X0 is `φ = atan2(u_y, u_x)`, its unit vector
//! `ê = u / s` and the tip `T = O3 + L3 ê` (L3 = `l3[0]`). The connecting rod (link 4,
//! length L4 = `l4[0]`) joins T to the output slider's centre O5 = (x5, 0) on y = 0 to
//! the right of T: `x5 = T_x + sqrt(L4² − T_y²)`, rod angle `ψ = atan2(−T_y, x5 − T_x)`.
//! Centres of mass: crank `A/2`, slider A, rocker `O3 + (L3/2) ê`, rod `(T + O5)/2`,
//! output slider O5. Link angles: θ, φ, φ, ψ, 0.
//!
//! Time derivatives are exact: every quantity is evaluated on truncated Taylor series
//! in time ([`Jet`]) seeded with `θ(t) = θ + θ̇ t + θ̈ t²/2`.
//!
//! # Inverse dynamics
//!
//! Each link obeys `m a = ΣF + m g` (g = (0, −g)) and `J_z α = ΣM` about its centre of
//! mass (`J_z = m (lx² + ly²)/12`, the box's). The joints are ideal (pins at O1, A, O3,
//! T, O5; prismatic joints slider–rocker and output slider–guide), with viscous slide
//! friction: the rocker pushes the slider with `n ê⊥ − R3C ṡ ê` (`ê⊥ = (−sin φ, cos φ)`)
//! and holds its rotation with a couple M23; the guide pushes the output slider with
//! `(−R5C ẋ5, G)`. The unknowns Tc, F_O1, F_A2, n, M23, F_O3, F_34, F_O5, G (14) follow
//! from the 14 equations (3 per link, 2 for the non-rotating output slider), solved as
//! one linear system. Every force is the one the named joint exerts on the named link,
//! as in the spec's results file.

use core::f64::consts::TAU;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Parameters of the rigid mechanism (the spec's values by default).
#[allow(non_snake_case)]
#[derive(Clone, Debug, PartialEq)]
pub struct RigidParams {
    /// Crank mass, kg.
    pub m1: f64,
    /// Slider (on the rocker) mass, kg.
    pub m2: f64,
    /// Rocker arm mass, kg.
    pub m3: f64,
    /// Connecting rod mass, kg.
    pub m4: f64,
    /// Output slider mass, kg.
    pub m5: f64,
    /// Crank box edges (lx, ly, lz), m; lx is the crank radius O1–A.
    pub l1: [f64; 3],
    /// Slider box edges, m.
    pub l2: [f64; 3],
    /// Rocker box edges, m; lx is its length O3–T.
    pub l3: [f64; 3],
    /// Connecting rod box edges, m; lx is its length T–O5.
    pub l4: [f64; 3],
    /// Output slider box edges, m.
    pub l5: [f64; 3],
    /// O3 = (0, −d), m.
    pub d: f64,
    /// Gravity along −Y0, m/s².
    pub g: f64,
    /// Viscous friction of the slider sliding along the rocker, N·s/m.
    pub R3C: f64,
    /// Viscous friction of the output slider along its guide, N·s/m.
    pub R5C: f64,
}

impl Default for RigidParams {
    fn default() -> Self {
        let edge = 0.01;
        RigidParams {
            m1: 0.5,
            m2: 0.1,
            m3: 0.7,
            m4: 0.3,
            m5: 0.1,
            l1: [0.2, edge, edge],
            l2: [edge, edge, edge],
            l3: [0.7, edge, edge],
            l4: [0.4, edge, edge],
            l5: [edge, edge, edge],
            d: 0.4,
            g: 9.81,
            R3C: 20.0,
            R5C: 20.0,
        }
    }
}

/// The rigid mechanism's data (a [`RigidParams`]) from the parameters `$p` of a quick
/// return model: any struct with the compliant model's fields of those names, so the
/// speed- and the torque-driven model's alike.
macro_rules! rigid_params_of {
    ($p:expr) => {{
        let p = $p;
        $crate::quick_return_rigid::RigidParams {
            m1: p.m1,
            m2: p.m2,
            m3: p.m3,
            m4: p.m4,
            m5: p.m5,
            l1: p.l1,
            l2: p.l2,
            l3: p.l3,
            l4: p.l4,
            l5: p.l5,
            d: p.d,
            g: p.g,
            R3C: p.R3C[0],
            R5C: p.R5C[0],
        }
    }};
}
pub(crate) use rigid_params_of;

impl RigidParams {
    /// The rigid mechanism with the links, pivot distance, gravity and slide frictions
    /// of a run of the compliant model.
    pub fn of_model(p: &crate::quick_return::QuickReturnParams) -> Self {
        rigid_params_of!(p)
    }

    /// The masses, link by link.
    pub fn masses(&self) -> [f64; 5] {
        [self.m1, self.m2, self.m3, self.m4, self.m5]
    }

    /// The moments of inertia about Z through the centres of mass, link by link, kg·m².
    pub fn inertias_z(&self) -> [f64; 5] {
        let edges = [self.l1, self.l2, self.l3, self.l4, self.l5];
        let mut j = [0.0; 5];
        for (i, (m, [lx, ly, _])) in self.masses().into_iter().zip(edges).enumerate() {
            j[i] = m * (lx * lx + ly * ly) / 12.0;
        }
        j
    }
}

/// A scalar coordinate and its first two time derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// The value.
    pub value: f64,
    /// Its first time derivative.
    pub rate: f64,
    /// Its second time derivative.
    pub accel: f64,
}

/// The rigid mechanism at one instant. Vectors are 3-D in frame 0 with z = 0; torques
/// are about Z0 (only z non-zero). Link order in arrays: crank, slider, rocker, rod,
/// output slider.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RigidSolution {
    /// Crank angle from X0 (rad), speed and acceleration: the inputs.
    pub theta: Motion,
    /// Rocker (and slider) angle φ from X0, rad.
    pub rocker_angle: Motion,
    /// Distance s of the slider's centre from O3 along the rocker, m.
    pub slider_offset: Motion,
    /// Connecting-rod angle ψ from X0, rad (negative: the rod points down to the right).
    pub rod_angle: Motion,
    /// The output slider's x (its centre O5), m.
    pub output_x: Motion,
    /// Centre-of-mass positions, m.
    pub com_position: [[f64; 3]; 5],
    /// Centre-of-mass velocities, m/s.
    pub com_velocity: [[f64; 3]; 5],
    /// Centre-of-mass accelerations, m/s².
    pub com_acceleration: [[f64; 3]; 5],
    /// Angular velocities about Z0, rad/s.
    pub angular_velocity: [f64; 5],
    /// Angular accelerations about Z0, rad/s².
    pub angular_acceleration: [f64; 5],
    /// Drive torque on the crank, N·m.
    pub tc: [f64; 3],
    /// Ground on the crank at O1, N.
    pub f_o1: [f64; 3],
    /// Crank on the slider at A2 (the crank pin), N.
    pub f_a2: [f64; 3],
    /// Rocker on the slider (normal force and slide friction), N.
    pub f_3c: [f64; 3],
    /// Rocker on the slider: the couple that turns the slider with the rocker, N·m.
    pub t_23: [f64; 3],
    /// Ground on the rocker at O3, N.
    pub f_o3: [f64; 3],
    /// Rocker on the connecting rod at the tip A33, N.
    pub f_34: [f64; 3],
    /// Connecting rod on the output slider at O5, N.
    pub f_o5: [f64; 3],
    /// Guide on the output slider (normal force and slide friction), N.
    pub f_5c: [f64; 3],
    /// Kinetic energy of all links, J.
    pub kinetic_energy: f64,
    /// Gravitational potential energy `Σ m g y` (zero at y = 0), J.
    pub potential_energy: f64,
    /// Power dissipated by the two slide frictions, W.
    pub friction_power: f64,
}

/// The rigid mechanism at crank angle `theta`, speed `theta_dot` and acceleration
/// `theta_ddot`: kinematics of every link and the forces the ideal joints transmit.
pub fn rigid_state(theta: f64, theta_dot: f64, theta_ddot: f64, p: &RigidParams) -> RigidSolution {
    let k = Kinematics::new(Jet::time_series(theta, theta_dot, theta_ddot), p);
    let masses = p.masses();
    let inertias = p.inertias_z();
    let motion = |j: Jet| Motion {
        value: j.value(),
        rate: j.rate(),
        accel: j.accel(),
    };
    let vec3 = |x: f64, y: f64| [x, y, 0.0];
    let mut sol = RigidSolution {
        theta: motion(k.angle[CRANK]),
        rocker_angle: motion(k.angle[ROCKER]),
        slider_offset: motion(k.s),
        rod_angle: motion(k.angle[ROD]),
        output_x: motion(k.o5[0]),
        ..Default::default()
    };
    let mut acc = [[0.0; 2]; 5];
    let mut alpha = [0.0; 5];
    for i in 0..5 {
        let [x, y] = k.com[i];
        sol.com_position[i] = vec3(x.value(), y.value());
        sol.com_velocity[i] = vec3(x.rate(), y.rate());
        acc[i] = [x.accel(), y.accel()];
        sol.com_acceleration[i] = vec3(acc[i][0], acc[i][1]);
        sol.angular_velocity[i] = k.angle[i].rate();
        alpha[i] = k.angle[i].accel();
        sol.angular_acceleration[i] = alpha[i];
        let v = sol.com_velocity[i];
        let w = sol.angular_velocity[i];
        sol.kinetic_energy +=
            0.5 * masses[i] * (v[0] * v[0] + v[1] * v[1]) + 0.5 * inertias[i] * w * w;
        sol.potential_energy += masses[i] * p.g * y.value();
    }
    let s_dot = k.s.rate();
    let x5_dot = k.o5[0].rate();
    sol.friction_power = p.R3C * s_dot * s_dot + p.R5C * x5_dot * x5_dot;

    // Points (values) and directions.
    let val = |v: [Jet; 2]| [v[0].value(), v[1].value()];
    let (o1, a, o3, tip, o5) = ([0.0, 0.0], val(k.pin), [0.0, -p.d], val(k.tip), val(k.o5));
    let com: Vec<[f64; 2]> = k.com.iter().map(|&c| val(c)).collect();
    let e = val(k.e);
    let e_perp = [-e[1], e[0]];
    let off = |point: [f64; 2], link: usize| [point[0] - com[link][0], point[1] - com[link][1]];
    // Slide frictions (known forces): on the slider along the rocker, on the output slider
    // along X0.
    let friction_3c = [-p.R3C * s_dot * e[0], -p.R3C * s_dot * e[1]];
    let friction_5c = [-p.R5C * x5_dot, 0.0];

    let mut sys = NewtonEuler::default();
    for i in 0..5 {
        sys.inertial(
            i,
            masses[i] * acc[i][0],
            masses[i] * (acc[i][1] + p.g),
            inertias[i] * alpha[i],
        );
    }
    // Crank: ground at O1, slider's reaction at A, drive torque.
    sys.unknown_force(CRANK, off(o1, CRANK), O1, 1.0);
    sys.unknown_force(CRANK, off(a, CRANK), A2, -1.0);
    sys.unknown_torque(CRANK, TC, 1.0);
    // Slider: crank pin, rocker's normal force, friction and couple, all at its centre.
    sys.unknown_force(SLIDER, [0.0, 0.0], A2, 1.0);
    sys.unknown_along(SLIDER, [0.0, 0.0], e_perp, N3C, 1.0);
    sys.known_force(SLIDER, [0.0, 0.0], friction_3c);
    sys.unknown_torque(SLIDER, M23, 1.0);
    // Rocker: ground at O3, the slider's reactions at A, the rod's reaction at the tip.
    sys.unknown_force(ROCKER, off(o3, ROCKER), O3, 1.0);
    sys.unknown_along(ROCKER, off(a, ROCKER), e_perp, N3C, -1.0);
    sys.known_force(ROCKER, off(a, ROCKER), [-friction_3c[0], -friction_3c[1]]);
    sys.unknown_torque(ROCKER, M23, -1.0);
    sys.unknown_force(ROCKER, off(tip, ROCKER), F34, -1.0);
    // Rod: rocker at the tip, the output slider's reaction at O5.
    sys.unknown_force(ROD, off(tip, ROD), F34, 1.0);
    sys.unknown_force(ROD, off(o5, ROD), O5, -1.0);
    // Output slider: rod, guide normal force and friction, all at its centre.
    sys.unknown_force(OUTPUT, [0.0, 0.0], O5, 1.0);
    sys.unknown_along(OUTPUT, [0.0, 0.0], [0.0, 1.0], G5Y, 1.0);
    sys.known_force(OUTPUT, [0.0, 0.0], friction_5c);
    let u = sys.solve();

    sol.tc = [0.0, 0.0, u[TC]];
    sol.f_o1 = vec3(u[O1], u[O1 + 1]);
    sol.f_a2 = vec3(u[A2], u[A2 + 1]);
    sol.f_3c = vec3(
        u[N3C] * e_perp[0] + friction_3c[0],
        u[N3C] * e_perp[1] + friction_3c[1],
    );
    sol.t_23 = [0.0, 0.0, u[M23]];
    sol.f_o3 = vec3(u[O3], u[O3 + 1]);
    sol.f_34 = vec3(u[F34], u[F34 + 1]);
    sol.f_o5 = vec3(u[O5], u[O5 + 1]);
    sol.f_5c = vec3(friction_5c[0], u[G5Y]);
    sol
}

/// The time derivative of the mechanical energy (kinetic + gravitational) of the rigid
/// mechanism at crank angle `theta`, speed `theta_dot` and acceleration `theta_ddot`,
/// obtained by differentiating the energy itself along the motion (a Taylor series of
/// the energy in time), independently of the Newton–Euler equations of
/// [`rigid_state`]. For the ideal joints, `Tc θ̇ = dE/dt + friction power`.
pub fn energy_rate(theta: f64, theta_dot: f64, theta_ddot: f64, p: &RigidParams) -> f64 {
    let k = Kinematics::new(Jet::time_series(theta, theta_dot, theta_ddot), p);
    let masses = p.masses();
    let inertias = p.inertias_z();
    let mut energy = Jet::constant(0.0);
    for i in 0..5 {
        let [x, y] = k.com[i];
        let (vx, vy, w) = (x.derivative(), y.derivative(), k.angle[i].derivative());
        energy = energy
            + (vx * vx + vy * vy).scale(0.5 * masses[i])
            + (w * w).scale(0.5 * inertias[i])
            + y.scale(masses[i] * p.g);
    }
    energy.rate()
}

/// The quick-return cycle of the rigid mechanism, from its kinematics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuickReturnCycle {
    /// Crank angle (in (−π, π]) at which the rocker is at its right extreme (smallest
    /// φ; the output slider furthest right), rad.
    pub theta_right: f64,
    /// Crank angle (in (−π, π]) at the rocker's left extreme, rad.
    pub theta_left: f64,
    /// Crank rotation (counter-clockwise) during the slow forward stroke, from the
    /// right extreme to the left one (the output slider moving −X0), rad.
    pub forward_angle: f64,
    /// Crank rotation during the quick return, rad.
    pub return_angle: f64,
    /// Forward stroke time over return stroke time at constant crank speed.
    pub time_ratio: f64,
    /// Travel of the output slider between its extremes, m.
    pub stroke: f64,
    /// Smallest and largest rocker angle φ, rad.
    pub rocker_range: [f64; 2],
}

/// Finds the rocker's extremes (the crank angles where `dφ/dθ = 0`) by bisection on
/// the exact derivative, and derives the quick-return cycle from them.
///
/// # Panics
///
/// If the geometry has no quick-return cycle ([`try_quick_return_cycle`] says why).
pub fn quick_return_cycle(p: &RigidParams) -> QuickReturnCycle {
    try_quick_return_cycle(p).unwrap_or_else(|why| panic!("no quick-return cycle: {why}"))
}

/// Why a geometry has no quick-return cycle of the rigid mechanism.
#[derive(Clone, Debug, PartialEq)]
pub enum NoCycle {
    /// The crank (`l1[0]`) is not shorter than the pivot distance `d` (or one of them is
    /// not positive): the rocker turns full circle or the pin passes through O3, so it
    /// has no two extremes.
    CrankTooLong {
        /// The crank radius `l1[0]`, m.
        crank: f64,
        /// The pivot distance `d`, m.
        d: f64,
    },
    /// The connecting rod (`l4[0]`) cannot reach the guide (y = 0) from the rocker's tip
    /// somewhere in the turn.
    RodTooShort {
        /// The rod's length `l4[0]`, m.
        rod: f64,
        /// The largest height of the rocker's tip above (or below) the guide, m.
        tip_height: f64,
    },
}

impl core::fmt::Display for NoCycle {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            NoCycle::CrankTooLong { crank, d } => write!(
                f,
                "the crank (l1 = {crank} m) is not shorter than the pivot distance d = {d} m, \
                 so the rocker does not swing between two extremes"
            ),
            NoCycle::RodTooShort { rod, tip_height } => write!(
                f,
                "the connecting rod (l4 = {rod} m) cannot reach the guide from the rocker's \
                 tip, {tip_height} m away from it"
            ),
        }
    }
}

/// The quick-return cycle of the rigid mechanism, or why its geometry has none (see
/// [`quick_return_cycle`]).
///
/// # Errors
///
/// [`NoCycle`]: the crank is not shorter than `d`, or the rod cannot reach the guide.
pub fn try_quick_return_cycle(p: &RigidParams) -> Result<QuickReturnCycle, NoCycle> {
    let (crank, d) = (p.l1[0], p.d);
    if !(crank > 0.0 && d > crank) {
        return Err(NoCycle::CrankTooLong { crank, d });
    }
    const GRID: usize = 720;
    let at = |i: usize| -core::f64::consts::PI + TAU * i as f64 / GRID as f64;
    let state = |theta: f64| Kinematics::new(Jet::time_series(theta, 1.0, 0.0), p);
    // The tip is highest with the rocker upright (θ = π/2) and lowest at an extreme, so
    // the grid and the extremes below cover its range.
    let rod = p.l4[0];
    let reaches = |k: &Kinematics| k.tip[1].value().abs() <= rod * (1.0 + 1e-12);
    let mut tip_height = 0.0f64;
    let rocker_rate = |theta: f64| state(theta).angle[ROCKER].rate();
    let mut roots = Vec::new();
    for i in 0..GRID {
        let k = state(at(i));
        tip_height = tip_height.max(k.tip[1].value().abs());
        let (mut lo, mut hi) = (at(i), at(i + 1));
        let (f_lo, f_hi) = (rocker_rate(lo), rocker_rate(hi));
        if f_lo == 0.0 {
            roots.push(lo);
            continue;
        }
        if f_lo.signum() == f_hi.signum() || f_hi == 0.0 {
            continue;
        }
        while hi - lo > 4.0 * f64::EPSILON * hi.abs().max(1.0) {
            let mid = 0.5 * (lo + hi);
            if rocker_rate(mid).signum() == f_lo.signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        roots.push(0.5 * (lo + hi));
    }
    let upright = state(core::f64::consts::FRAC_PI_2);
    tip_height = tip_height.max(upright.tip[1].value().abs());
    assert_eq!(
        roots.len(),
        2,
        "a crank shorter than d gives the rocker two extremes, found {roots:?}"
    );
    let (k0, k1) = (state(roots[0]), state(roots[1]));
    if ![&k0, &k1, &upright].into_iter().all(reaches) || tip_height > rod * (1.0 + 1e-12) {
        return Err(NoCycle::RodTooShort { rod, tip_height });
    }
    let (phi0, phi1) = (k0.angle[ROCKER].value(), k1.angle[ROCKER].value());
    let (right, left, k_right, k_left) = if phi0 < phi1 {
        (roots[0], roots[1], k0, k1)
    } else {
        (roots[1], roots[0], k1, k0)
    };
    let forward_angle = (left - right).rem_euclid(TAU);
    let return_angle = TAU - forward_angle;
    Ok(QuickReturnCycle {
        theta_right: right,
        theta_left: left,
        forward_angle,
        return_angle,
        time_ratio: forward_angle / return_angle,
        stroke: k_right.o5[0].value() - k_left.o5[0].value(),
        rocker_range: [k_right.angle[ROCKER].value(), k_left.angle[ROCKER].value()],
    })
}

// ---------------------------------------------------------------------------------------
// Kinematics on Taylor series in time.
// ---------------------------------------------------------------------------------------

const CRANK: usize = 0;
const SLIDER: usize = 1;
const ROCKER: usize = 2;
const ROD: usize = 3;
const OUTPUT: usize = 4;

/// Every position-level quantity of the mechanism, as a series in time.
#[derive(Clone, Copy, Debug)]
struct Kinematics {
    /// Crank pin A.
    pin: [Jet; 2],
    /// Distance O3–A.
    s: Jet,
    /// Rocker unit vector.
    e: [Jet; 2],
    /// Rocker tip T.
    tip: [Jet; 2],
    /// Output slider centre O5.
    o5: [Jet; 2],
    /// Centres of mass.
    com: [[Jet; 2]; 5],
    /// Link angles from X0.
    angle: [Jet; 5],
}

impl Kinematics {
    fn new(theta: Jet, p: &RigidParams) -> Self {
        let (r, l3, l4) = (p.l1[0], p.l3[0], p.l4[0]);
        let (sin, cos) = theta.sin_cos();
        let pin = [cos.scale(r), sin.scale(r)];
        let u = [pin[0], pin[1] + Jet::constant(p.d)];
        let s = (u[0] * u[0] + u[1] * u[1]).sqrt();
        let phi = u[1].atan2(u[0]);
        let e = [u[0] / s, u[1] / s];
        let o3 = [Jet::constant(0.0), Jet::constant(-p.d)];
        let tip = [o3[0] + e[0].scale(l3), o3[1] + e[1].scale(l3)];
        let reach = (Jet::constant(l4 * l4) - tip[1] * tip[1]).sqrt();
        let o5 = [tip[0] + reach, Jet::constant(0.0)];
        let psi = (-tip[1]).atan2(reach);
        let half = |a: Jet, b: Jet| (a + b).scale(0.5);
        let com = [
            [pin[0].scale(0.5), pin[1].scale(0.5)],
            pin,
            [o3[0] + e[0].scale(0.5 * l3), o3[1] + e[1].scale(0.5 * l3)],
            [half(tip[0], o5[0]), half(tip[1], o5[1])],
            o5,
        ];
        Kinematics {
            pin,
            s,
            e,
            tip,
            o5,
            com,
            angle: [theta, phi, phi, psi, Jet::constant(0.0)],
        }
    }
}

/// Number of Taylor coefficients kept: value, first and second derivative.
const ORDER: usize = 3;

/// A quantity as a truncated Taylor series in time about the current instant:
/// `f(t₀ + τ) = c₀ + c₁ τ + c₂ τ² + O(τ³)`. Arithmetic and the elementary functions act
/// on the series exactly (to rounding), so the value, rate and acceleration of any
/// expression come out exact. A coefficient that is not known (the top one of a
/// [`Jet::derivative`]) is NaN, which cannot leak into lower coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    c: [f64; ORDER],
}

impl Jet {
    /// A quantity that does not change in time.
    pub fn constant(value: f64) -> Self {
        let mut c = [0.0; ORDER];
        c[0] = value;
        Jet { c }
    }

    /// The series of a quantity with the given value, rate and acceleration.
    pub fn time_series(value: f64, rate: f64, accel: f64) -> Self {
        Jet {
            c: [value, rate, 0.5 * accel],
        }
    }

    /// The value.
    pub fn value(self) -> f64 {
        self.c[0]
    }

    /// The first time derivative.
    pub fn rate(self) -> f64 {
        self.c[1]
    }

    /// The second time derivative.
    pub fn accel(self) -> f64 {
        2.0 * self.c[2]
    }

    /// The series of the time derivative (one order fewer: the top coefficient is NaN).
    pub fn derivative(self) -> Self {
        let mut c = [f64::NAN; ORDER];
        for (k, ck) in c.iter_mut().take(ORDER - 1).enumerate() {
            *ck = (k + 1) as f64 * self.c[k + 1];
        }
        Jet { c }
    }

    /// The series whose derivative is `rate` and whose value is `value`.
    fn integral(value: f64, rate: Jet) -> Self {
        let mut c = [value; ORDER];
        for (k, ck) in c.iter_mut().enumerate().skip(1) {
            *ck = rate.c[k - 1] / k as f64;
        }
        Jet { c }
    }

    /// Multiplication by a constant.
    pub fn scale(self, k: f64) -> Self {
        Jet {
            c: self.c.map(|x| k * x),
        }
    }

    /// Square root.
    pub fn sqrt(self) -> Self {
        let mut s = [0.0; ORDER];
        s[0] = self.c[0].sqrt();
        for k in 1..ORDER {
            let mut acc = self.c[k];
            for i in 1..k {
                acc -= s[i] * s[k - i];
            }
            s[k] = acc / (2.0 * s[0]);
        }
        Jet { c: s }
    }

    /// Sine and cosine.
    pub fn sin_cos(self) -> (Self, Self) {
        let (mut s, mut c) = ([0.0; ORDER], [0.0; ORDER]);
        (s[0], c[0]) = self.c[0].sin_cos();
        for k in 1..ORDER {
            let (mut ds, mut dc) = (0.0, 0.0);
            for j in 1..=k {
                ds += j as f64 * self.c[j] * c[k - j];
                dc -= j as f64 * self.c[j] * s[k - j];
            }
            s[k] = ds / k as f64;
            c[k] = dc / k as f64;
        }
        (Jet { c: s }, Jet { c })
    }

    /// Four-quadrant arctangent of `self / x`: `d/dt atan2(y, x) = (x y' − y x')/(x² + y²)`.
    pub fn atan2(self, x: Jet) -> Self {
        let y = self;
        let rate = (x * y.derivative() - y * x.derivative()) / (x * x + y * y);
        Jet::integral(y.c[0].atan2(x.c[0]), rate)
    }
}

impl Add for Jet {
    type Output = Jet;
    fn add(self, b: Jet) -> Jet {
        let mut c = self.c;
        for (ci, bi) in c.iter_mut().zip(b.c) {
            *ci += bi;
        }
        Jet { c }
    }
}

impl Sub for Jet {
    type Output = Jet;
    fn sub(self, b: Jet) -> Jet {
        self + (-b)
    }
}

impl Neg for Jet {
    type Output = Jet;
    fn neg(self) -> Jet {
        self.scale(-1.0)
    }
}

impl Mul for Jet {
    type Output = Jet;
    fn mul(self, b: Jet) -> Jet {
        let mut c = [0.0; ORDER];
        for (k, ck) in c.iter_mut().enumerate() {
            for i in 0..=k {
                *ck += self.c[i] * b.c[k - i];
            }
        }
        Jet { c }
    }
}

impl Div for Jet {
    type Output = Jet;
    fn div(self, b: Jet) -> Jet {
        let mut q = [0.0; ORDER];
        for k in 0..ORDER {
            let mut acc = self.c[k];
            for i in 1..=k {
                acc -= b.c[i] * q[k - i];
            }
            q[k] = acc / b.c[0];
        }
        Jet { c: q }
    }
}

// ---------------------------------------------------------------------------------------
// The Newton–Euler system.
// ---------------------------------------------------------------------------------------

/// Number of unknowns (and equations).
const N: usize = 14;
/// Unknown columns: drive torque; O1 (x, y); A2 (x, y); the rocker's normal force on the
/// slider along ê⊥; the rocker's couple on the slider; O3 (x, y); F34 (x, y); O5 (x, y);
/// the guide's normal force on the output slider.
const TC: usize = 0;
const O1: usize = 1;
const A2: usize = 3;
const N3C: usize = 5;
const M23: usize = 6;
const O3: usize = 7;
const F34: usize = 9;
const O5: usize = 11;
const G5Y: usize = 13;

/// `A u = b`: rows 3i, 3i+1, 3i+2 are link i's force x, force y and moment (about its
/// centre of mass) equations, for the crank, slider, rocker and rod; rows 12, 13 the
/// output slider's force equations (it does not turn and every force on it acts at its
/// centre).
#[derive(Default)]
struct NewtonEuler {
    a: [[f64; N]; N],
    b: [f64; N],
}

impl NewtonEuler {
    fn rows(link: usize) -> (usize, usize, Option<usize>) {
        if link == OUTPUT {
            (12, 13, None)
        } else {
            (3 * link, 3 * link + 1, Some(3 * link + 2))
        }
    }

    /// The right-hand sides `m a − m g` and `J α` (before known forces are moved over).
    fn inertial(&mut self, link: usize, fx: f64, fy: f64, moment: f64) {
        let (rx, ry, rm) = Self::rows(link);
        self.b[rx] = fx;
        self.b[ry] = fy;
        if let Some(rm) = rm {
            self.b[rm] = moment;
        }
    }

    /// An unknown scalar `u[col]` times the direction `dir`, times `sign`, acting on
    /// `link` at `offset` from its centre of mass.
    fn unknown_along(
        &mut self,
        link: usize,
        offset: [f64; 2],
        dir: [f64; 2],
        col: usize,
        sign: f64,
    ) {
        let (rx, ry, rm) = Self::rows(link);
        self.a[rx][col] += sign * dir[0];
        self.a[ry][col] += sign * dir[1];
        if let Some(rm) = rm {
            self.a[rm][col] += sign * (offset[0] * dir[1] - offset[1] * dir[0]);
        }
    }

    /// An unknown force (columns `col`, `col + 1`), times `sign`, at `offset`.
    fn unknown_force(&mut self, link: usize, offset: [f64; 2], col: usize, sign: f64) {
        self.unknown_along(link, offset, [1.0, 0.0], col, sign);
        self.unknown_along(link, offset, [0.0, 1.0], col + 1, sign);
    }

    /// An unknown torque `sign u[col]`.
    fn unknown_torque(&mut self, link: usize, col: usize, sign: f64) {
        let (_, _, rm) = Self::rows(link);
        self.a[rm.expect("a turning link")][col] += sign;
    }

    /// A known force `f` at `offset`.
    fn known_force(&mut self, link: usize, offset: [f64; 2], f: [f64; 2]) {
        let (rx, ry, rm) = Self::rows(link);
        self.b[rx] -= f[0];
        self.b[ry] -= f[1];
        if let Some(rm) = rm {
            self.b[rm] -= offset[0] * f[1] - offset[1] * f[0];
        }
    }

    /// Gaussian elimination with partial pivoting.
    fn solve(mut self) -> [f64; N] {
        for col in 0..N {
            let pivot = (col..N)
                .max_by(|&i, &j| self.a[i][col].abs().total_cmp(&self.a[j][col].abs()))
                .unwrap();
            assert!(
                self.a[pivot][col] != 0.0,
                "singular Newton–Euler system (column {col})"
            );
            self.a.swap(col, pivot);
            self.b.swap(col, pivot);
            for row in col + 1..N {
                let f = self.a[row][col] / self.a[col][col];
                if f != 0.0 {
                    for k in col..N {
                        self.a[row][k] -= f * self.a[col][k];
                    }
                    self.b[row] -= f * self.b[col];
                }
            }
        }
        let mut u = [0.0; N];
        for row in (0..N).rev() {
            let tail: f64 = (row + 1..N).map(|k| self.a[row][k] * u[k]).sum();
            u[row] = (self.b[row] - tail) / self.a[row][row];
        }
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::{FRAC_PI_2, FRAC_PI_6, PI};

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    /// The jets against central differences of the value along `θ(t)`: a check of the
    /// series arithmetic (sqrt, division, sin/cos, atan2) itself. Step 1e-4 s: the
    /// truncation error (h² f'''/6 ~ 1e-8 × f''') and rounding (1e-16 / 1e-8) both stay
    /// near 1e-7 relative.
    #[test]
    fn jets_match_finite_differences() {
        let p = RigidParams::default();
        let (w, dw) = (5.0, 3.0);
        for i in 0..12 {
            let theta0 = -3.0 + 0.5 * i as f64;
            let at = |t: f64| {
                let theta = theta0 + w * t + 0.5 * dw * t * t;
                let k = Kinematics::new(Jet::constant(theta), &p);
                [
                    k.s.value(),
                    k.angle[ROCKER].value(),
                    k.angle[ROD].value(),
                    k.o5[0].value(),
                    k.com[ROD][1].value(),
                ]
            };
            let k = Kinematics::new(Jet::time_series(theta0, w, dw), &p);
            let jets = [k.s, k.angle[ROCKER], k.angle[ROD], k.o5[0], k.com[ROD][1]];
            let h = 1e-4;
            let (minus, mid, plus) = (at(-h), at(0.0), at(h));
            for q in 0..jets.len() {
                let rate = (plus[q] - minus[q]) / (2.0 * h);
                let accel = (plus[q] - 2.0 * mid[q] + minus[q]) / (h * h);
                assert!(close(jets[q].value(), mid[q], 1e-15));
                assert!(
                    close(jets[q].rate(), rate, 1e-6 * (1.0 + rate.abs())),
                    "{q}: {} vs {rate}",
                    jets[q].rate()
                );
                assert!(
                    close(jets[q].accel(), accel, 2e-5 * (1.0 + accel.abs())),
                    "{q}: {} vs {accel}",
                    jets[q].accel()
                );
            }
        }
    }

    /// The spec's cycle: with r/d = 1/2 the rocker swings ±30° about the vertical, the
    /// crank turns 240° forward and 120° back (ratio exactly 2), and the stroke is
    /// exactly 2 L3 sin 30° = 0.7 m. The extremes are found numerically, so the
    /// tolerances are rounding: 1e-12.
    #[test]
    fn cycle_has_ratio_two_stroke_0_7_and_swing_30_degrees() {
        let cycle = quick_return_cycle(&RigidParams::default());
        assert!(close(cycle.theta_right, -FRAC_PI_6, 1e-12), "{cycle:?}");
        assert!(
            close(cycle.theta_left, PI + FRAC_PI_6, 1e-12)
                || close(cycle.theta_left, -PI + FRAC_PI_6, 1e-12),
            "{cycle:?}"
        );
        assert!(
            close(cycle.forward_angle, 4.0 * PI / 3.0, 1e-12),
            "{cycle:?}"
        );
        assert!(
            close(cycle.return_angle, 2.0 * PI / 3.0, 1e-12),
            "{cycle:?}"
        );
        assert!(close(cycle.time_ratio, 2.0, 1e-12), "{cycle:?}");
        assert!(close(cycle.stroke, 0.7, 1e-12), "{cycle:?}");
        assert!(
            close(cycle.rocker_range[0], FRAC_PI_2 - FRAC_PI_6, 1e-12),
            "{cycle:?}"
        );
        assert!(
            close(cycle.rocker_range[1], FRAC_PI_2 + FRAC_PI_6, 1e-12),
            "{cycle:?}"
        );
        // The output slider's extremes found by a dense scan agree with the stroke.
        let x5: Vec<f64> = (0..100_000)
            .map(|i| {
                rigid_state(
                    TAU * i as f64 / 100_000.0,
                    1.0,
                    0.0,
                    &RigidParams::default(),
                )
                .output_x
                .value
            })
            .collect();
        let (lo, hi) = x5
            .iter()
            .fold((f64::MAX, f64::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        assert!(close(hi - lo, 0.7, 1e-8), "scan stroke {}", hi - lo);
    }

    /// The spec's initial configuration: crank up, rocker vertical, tip at (0, 0.3),
    /// rod at −asin(0.75), O5 at sqrt(0.07).
    #[test]
    fn initial_configuration_is_the_specs() {
        let sol = rigid_state(FRAC_PI_2, 0.0, 0.0, &RigidParams::default());
        assert!(close(sol.rocker_angle.value, FRAC_PI_2, 1e-15));
        assert!(close(sol.slider_offset.value, 0.6, 1e-15));
        assert!(close(sol.rod_angle.value, -(0.75f64).asin(), 1e-15));
        assert!(close(sol.output_x.value, 0.07f64.sqrt(), 1e-15));
        assert!(close(sol.com_position[ROCKER][1], -0.05, 1e-15));
    }

    /// Static equilibrium (θ̇ = θ̈ = 0, so no friction) at θ = 0, by hand, link by link:
    /// - the rod is a uniform two-pin link, so each pin carries half its weight
    ///   vertically (the output slider takes no horizontal force at rest):
    ///   F_O5 = (0, −m4 g/2), F_34 = (0, +m4 g/2);
    /// - rocker moments about O3: its weight at (L3/2) ê, the rod's (0, −m4 g/2) at
    ///   L3 ê, the slider's reaction −n ê⊥ at s ê:
    ///   −(L3/2) m3 g cos φ − L3 (m4 g/2) cos φ − s n = 0;
    /// - slider: F_A2 = −n ê⊥ + (0, m2 g);
    /// - crank moments about O1: Tc = A × F_A2 + (A/2) × (0, m1 g)
    ///   = r F_A2y + (r/2) m1 g at θ = 0.
    ///
    /// At θ = 0: u = (0.2, 0.4), s = √0.2, cos φ = 0.2/s = 1/√5, so
    /// n = −0.35 g (m3 + m4) = −3.4335 N, F_A2 = (−3.0710, 3.4335/√5 + 0.981) N and
    /// Tc = 0.2 (3.4335/√5 + 0.981) + 0.1 · 0.5 · 9.81 = 0.99380 N·m. The solver's
    /// answer must agree to rounding (1e-12). Virtual work gives the same torque as
    /// dV/dθ, from the energy rate at a vanishing speed ε = 1e-6 rad/s (the kinetic
    /// part of the rate is O(ε³), 1e-12 relative).
    #[test]
    fn static_equilibrium_matches_a_hand_calculation() {
        let p = RigidParams::default();
        let g = p.g;
        let sol = rigid_state(0.0, 0.0, 0.0, &p);
        let (r, l3, d): (f64, f64, f64) = (0.2, 0.7, 0.4);
        let s = (r * r + d * d).sqrt();
        let (cos_phi, sin_phi) = (r / s, d / s);
        let n = -(0.5 * l3 * p.m3 * g + 0.5 * l3 * p.m4 * g) * cos_phi / s;
        assert!(close(n, -0.35 * g * (p.m3 + p.m4), 1e-12));
        let e_perp = [-sin_phi, cos_phi];
        let f_a2 = [-n * e_perp[0], -n * e_perp[1] + p.m2 * g];
        let tc = r * f_a2[1] + 0.5 * r * p.m1 * g;
        let tc_by_hand = 0.2 * (3.4335 / 5.0f64.sqrt() + 0.981) + 0.1 * 0.5 * 9.81;
        assert!(
            close(tc, tc_by_hand, 1e-12) && close(tc, 0.99380, 1e-5),
            "tc {tc}"
        );
        assert!(close(sol.tc[2], tc, 1e-12), "Tc {} vs hand {tc}", sol.tc[2]);
        assert!(
            close(sol.f_a2[0], f_a2[0], 1e-12) && close(sol.f_a2[1], f_a2[1], 1e-12),
            "{:?} vs {f_a2:?}",
            sol.f_a2
        );
        assert!(
            close(sol.f_o5[0], 0.0, 1e-12) && close(sol.f_o5[1], -0.5 * p.m4 * g, 1e-12),
            "{:?}",
            sol.f_o5
        );
        assert!(close(sol.f_34[1], 0.5 * p.m4 * g, 1e-12), "{:?}", sol.f_34);
        assert!(
            close(sol.f_o1[0], f_a2[0], 1e-12) && close(sol.f_o1[1], f_a2[1] + p.m1 * g, 1e-12)
        );
        // The supports carry the whole weight.
        let weight: f64 = p.masses().iter().sum::<f64>() * g;
        assert!(close(
            sol.f_o1[1] + sol.f_o3[1] + sol.f_5c[1],
            weight,
            1e-12
        ));
        assert!(close(sol.f_o1[0] + sol.f_o3[0] + sol.f_5c[0], 0.0, 1e-12));
        // Virtual work: the static torque is dV/dθ.
        let eps = 1e-6;
        let dv_dtheta = energy_rate(0.0, eps, 0.0, &p) / eps;
        assert!(
            close(sol.tc[2], dv_dtheta, 1e-9),
            "Tc {} vs dV/dθ {dv_dtheta}",
            sol.tc[2]
        );
    }

    /// Power balance of the inverse dynamics: the drive's power equals the rate of
    /// change of kinetic plus potential energy (differentiated from the kinematics,
    /// independently of the Newton–Euler equations) plus the slide-friction
    /// dissipation, at 720 crank angles at θ̇ = 5 rad/s, and at random speeds and
    /// accelerations, with and without gravity. Both sides are exact, so the residual is
    /// rounding: 1e-9 of the largest power term.
    #[test]
    fn drive_power_equals_energy_rate_plus_friction() {
        let mut worst: f64 = 0.0;
        for (g, theta_dot, theta_ddot) in [
            (9.81, 5.0, 0.0),
            (0.0, 5.0, 0.0),
            (9.81, -2.0, 7.0),
            (9.81, 11.0, -40.0),
        ] {
            let p = RigidParams {
                g,
                ..RigidParams::default()
            };
            for i in 0..720 {
                let theta = -PI + TAU * (i as f64 + 0.37) / 720.0;
                let sol = rigid_state(theta, theta_dot, theta_ddot, &p);
                let p_in = sol.tc[2] * theta_dot;
                let de = energy_rate(theta, theta_dot, theta_ddot, &p);
                let scale = p_in.abs() + de.abs() + sol.friction_power;
                let residual = (p_in - de - sol.friction_power).abs() / scale;
                worst = worst.max(residual);
                assert!(
                    residual < 1e-9,
                    "θ = {theta}: P_in {p_in}, dE/dt {de}, friction {}",
                    sol.friction_power
                );
            }
        }
        eprintln!("largest relative power residual: {worst:e}");
    }

    /// The whole mechanism as one body: the external forces (supports, guide, gravity)
    /// equal the rate of change of its momentum, and their moments about O1 plus the
    /// drive torque the rate of change of its angular momentum about O1. This catches
    /// what the power balance cannot see: forces that do no work (the slide friction's
    /// reaction on the rocker, the supports). Rounding only: 1e-9 of the largest term.
    #[test]
    fn momentum_and_angular_momentum_balance_of_the_whole_mechanism() {
        let p = RigidParams::default();
        let masses = p.masses();
        let inertias = p.inertias_z();
        let cross = |r: [f64; 3], f: [f64; 3]| r[0] * f[1] - r[1] * f[0];
        for (theta_dot, theta_ddot) in [(5.0, 0.0), (-3.0, 25.0)] {
            for i in 0..360 {
                let theta = TAU * (i as f64 + 0.5) / 360.0;
                let sol = rigid_state(theta, theta_dot, theta_ddot, &p);
                let (mut momentum_rate, mut weight) = ([0.0; 2], [0.0; 2]);
                let (mut angular_rate, mut weight_moment) = (0.0, 0.0);
                for l in 0..5 {
                    let (r, a) = (sol.com_position[l], sol.com_acceleration[l]);
                    let ma = [masses[l] * a[0], masses[l] * a[1], 0.0];
                    let mg = [0.0, -masses[l] * p.g, 0.0];
                    for k in 0..2 {
                        momentum_rate[k] += ma[k];
                        weight[k] += mg[k];
                    }
                    angular_rate += cross(r, ma) + inertias[l] * sol.angular_acceleration[l];
                    weight_moment += cross(r, mg);
                }
                let o3 = [0.0, -p.d, 0.0];
                let o5 = sol.com_position[OUTPUT];
                let external = [
                    sol.f_o1[0] + sol.f_o3[0] + sol.f_5c[0] + weight[0],
                    sol.f_o1[1] + sol.f_o3[1] + sol.f_5c[1] + weight[1],
                ];
                let moment = sol.tc[2] + cross(o3, sol.f_o3) + cross(o5, sol.f_5c) + weight_moment;
                let scale = 1.0 + momentum_rate[0].abs() + momentum_rate[1].abs() + weight[1].abs();
                for k in 0..2 {
                    assert!(
                        close(external[k], momentum_rate[k], 1e-9 * scale),
                        "θ = {theta}: force {k}: {} vs {}",
                        external[k],
                        momentum_rate[k]
                    );
                }
                let scale = 1.0 + angular_rate.abs() + weight_moment.abs() + sol.tc[2].abs();
                assert!(
                    close(moment, angular_rate, 1e-9 * scale),
                    "θ = {theta}: moment {moment} vs {angular_rate}"
                );
            }
        }
    }

    /// Friction dissipates: at constant speed with g = 0 and no friction the drive's
    /// work over a revolution is zero; with friction it is the integral of the
    /// friction power (a periodic check of the sign of the friction terms).
    #[test]
    fn work_over_a_revolution_is_the_friction_loss() {
        for friction in [0.0, 20.0] {
            let p = RigidParams {
                g: 0.0,
                R3C: friction,
                R5C: friction,
                ..RigidParams::default()
            };
            let n = 20_000;
            let (mut work, mut loss) = (0.0, 0.0);
            for i in 0..n {
                let theta = TAU * i as f64 / n as f64;
                let sol = rigid_state(theta, 5.0, 0.0, &p);
                // Trapezoid on a periodic integrand: spectrally accurate.
                work += sol.tc[2] * 5.0;
                loss += sol.friction_power;
            }
            let dt = TAU / 5.0 / n as f64;
            assert!(
                close(work * dt, loss * dt, 1e-9 * (1.0 + loss * dt)),
                "work {} loss {}",
                work * dt,
                loss * dt
            );
            if friction > 0.0 {
                assert!(loss > 0.0);
            }
        }
    }

    /// Any crank shorter than `d` gives the shaper's closed form: the rocker is at an
    /// extreme when the line O3–A is tangent to the crank circle, at `α = asin(r/d)` from
    /// the vertical, so the stroke is `2 L3 r/d` and the crank turns `π + 2α` forward and
    /// `π − 2α` back.
    #[test]
    fn cycle_follows_the_geometry() {
        let p = RigidParams {
            d: 0.3,
            ..RigidParams::default()
        };
        let cycle = try_quick_return_cycle(&p).unwrap();
        let alpha = (0.2f64 / 0.3).asin();
        assert!(
            close(cycle.stroke, 2.0 * 0.7 * 0.2 / 0.3, 1e-12),
            "{cycle:?}"
        );
        assert!(
            close(
                cycle.time_ratio,
                (PI + 2.0 * alpha) / (PI - 2.0 * alpha),
                1e-12
            ),
            "{cycle:?}"
        );
    }

    #[test]
    fn says_when_there_is_no_cycle() {
        let whitworth = RigidParams {
            d: 0.15,
            ..RigidParams::default()
        };
        assert_eq!(
            try_quick_return_cycle(&whitworth),
            Err(NoCycle::CrankTooLong {
                crank: 0.2,
                d: 0.15
            })
        );
        let short_rod = RigidParams {
            l4: [0.2, 0.01, 0.01],
            ..RigidParams::default()
        };
        let Err(NoCycle::RodTooShort { rod, tip_height }) = try_quick_return_cycle(&short_rod)
        else {
            panic!("a 0.2 m rod reaches the guide");
        };
        // The tip is highest with the rocker upright: L3 − d above the guide.
        assert_eq!(rod, 0.2);
        assert!(close(tip_height, 0.7 - 0.4, 1e-12), "{tip_height}");
    }
}
