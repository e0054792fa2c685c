//! The quick return mechanism of the seed paper (`shared/quick-return-spec.md`), written
//! by hand in plain Rust from the spec and the physics, as an independent reference for
//! the model written in the bond-graph language.
//!
//! Not part of any crate's API: the benchmark `models/benches/quick_return_hand.rs`
//! includes it, and so do tests:
//! `#[path = "../../models/benches/quick_return_hand/model.rs"] mod quick_return_hand;`
//! (from `tests/tests/`). It depends on `bgdsl_runtime` only.
//!
//! # The model (the paper's Fig. 2, every vector in frame 0)
//!
//! Per link i = 1..5 (crank, slider, rocker, connecting rod, output slider): the
//! translational momentum `p` with `v = p / m`; the angular momentum `h` about the
//! centre of mass with `w = (R J Rᵀ)⁻¹ h`, evaluated as `R J⁻¹ Rᵀ h` (the same matrix
//! for an orthogonal `R`; with it, `d/dt(½ h·w) = w·dh/dt` holds exactly for any `R`
//! moving by `dR/dt = skew(w) R`, so the power balance is exact even off the rotation
//! group); the orientation `R` (columns: the body axes in frame 0) with
//! `dR/dt = skew(w) R`; the centre-of-mass position `r` with `dr/dt = v`. `J` is the
//! solid box's inertia `diag(m(ly²+lz²), m(lx²+lz²), m(lx²+ly²)) / 12`.
//!
//! A point P at body vector `b` (all points here lie on the body x-axis) moves with
//! `v_P = v + w × (R b)`; a force `F` there adds `F` to `dp/dt` and `(R b) × F` to `dh/dt`.
//!
//! Every joint is a spring-damper coupling between a *first* and a *second* point (or
//! body, for the rotational ones). Its state is `q = ∫ (v_first − v_second) dt`, in the
//! coupling's frame (frame 3 for K3C: the relative velocity rotated by `R3ᵀ`; frame 0
//! for all others); its effort is `e = K q + R_d dq/dt` (diagonal `K`, `R_d`); the
//! coupling pushes the *second* point with `+e` and the *first* with `−e` (rotated back
//! to frame 0 by `R3` for K3C). Gravity `(0, −m g, 0)` acts on every centre of mass.
//!
//! | coupling | first | second | frame |
//! |---|---|---|---|
//! | K01, R01 | crank point O1 (body x = −lx1/2) | ground | 0 |
//! | K12, R12 | crank pin A1 (body x = +lx1/2) | slider centre A2 | 0 |
//! | K03, R03 | rocker point O3 (body x = −lx3/2) | ground | 0 |
//! | K3C, R3C | slider centre A2 | rocker point P3 (see below) | 3 |
//! | K23r, R23r | slider rotation `w2` | rocker rotation `w3` | 0 |
//! | K_C, R_C | drive source `(0, 0, w_drive)` | crank rotation `w1` | 0 |
//! | K34, R34 | rocker tip A33 (body x = +lx3/2) | rod end (body x = −lx4/2) | 0 |
//! | K45, R45 | rod end (body x = +lx4/2) | output slider centre O5 | 0 |
//! | K5C, R5C | output slider centre O5 | ground (the guide) | 0 |
//!
//! The rocker's material point P3 of K3C is, with `k3c_point_under_slider = 0` (the
//! authors' choice), the one under the crank pin: body vector `r1 + R1 b_A1 − r3` from
//! C3; with `k3c_point_under_slider = 1`, the one under the slider's centre: `r2 − r3`.
//!
//! # State layout (117 states)
//!
//! Link i (1..5) occupies `[18(i−1), 18 i)`: `p` (3), `h` (3), `R` (9, **row-major**:
//! `R_11, R_12, R_13, R_21, …`), `r` (3). The coupling states follow from 90, 3 each, in
//! the order K01, K12, K03, K3C, K23r, K_C, K34, K45, K5C. See [`STATE_NAMES`].
//!
//! # Outputs
//!
//! The spec's results-file columns after `t`, in its order (`crank_angle` is
//! `atan2(R1_21, R1_22)` unwrapped: that angle plus the whole turns that bring it
//! nearest to the angle the crank turned through, the drive's `theta0 + w_drive t` less
//! the drive coupling's twist `K_C.q_z`; the orientation matrices column by
//! column; each force or torque the one the named coupling exerts on the named link),
//! then `E_stored` (kinetic + spring + gravitational, zero height at y = 0), `P_in`
//! (power the drive source delivers: `Tc · (0, 0, w_drive)`) and `P_diss` (all
//! dampers), and finally the crank's angular velocity `w1_*` and angular acceleration
//! `dw1_*` (for comparing with the rigid-body reference at the crank's actual motion).
//! See [`OUTPUT_NAMES`].

use bgdsl_runtime::{Model, Scalar};

// ---------------------------------------------------------------------------------------
// Small 3-vectors and 3×3 matrices over any `Scalar` (`m[row][col]`).
// ---------------------------------------------------------------------------------------

type Vec3<T> = [T; 3];
type Mat3<T> = [[T; 3]; 3];

#[inline(always)]
fn c<T: Scalar>(x: f64) -> T {
    T::from_f64(x)
}

#[inline(always)]
fn const3<T: Scalar>(a: [f64; 3]) -> Vec3<T> {
    [c(a[0]), c(a[1]), c(a[2])]
}

#[inline(always)]
fn add<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> Vec3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
fn sub<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> Vec3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn neg<T: Scalar>(a: Vec3<T>) -> Vec3<T> {
    [-a[0], -a[1], -a[2]]
}

#[inline(always)]
fn scale<T: Scalar>(s: T, a: Vec3<T>) -> Vec3<T> {
    [s * a[0], s * a[1], s * a[2]]
}

/// `diag(d) a`.
#[inline(always)]
fn diag_mul<T: Scalar>(d: [f64; 3], a: Vec3<T>) -> Vec3<T> {
    [
        c::<T>(d[0]) * a[0],
        c::<T>(d[1]) * a[1],
        c::<T>(d[2]) * a[2],
    ]
}

#[inline(always)]
fn dot<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn cross<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> Vec3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `m a`.
#[inline(always)]
fn mat_vec<T: Scalar>(m: &Mat3<T>, a: Vec3<T>) -> Vec3<T> {
    [dot(m[0], a), dot(m[1], a), dot(m[2], a)]
}

/// `mᵀ a`.
#[inline(always)]
fn mat_t_vec<T: Scalar>(m: &Mat3<T>, a: Vec3<T>) -> Vec3<T> {
    [
        m[0][0] * a[0] + m[1][0] * a[1] + m[2][0] * a[2],
        m[0][1] * a[0] + m[1][1] * a[1] + m[2][1] * a[2],
        m[0][2] * a[0] + m[1][2] * a[1] + m[2][2] * a[2],
    ]
}

/// `skew(w) m`: each column of `m` crossed by `w` from the left.
#[inline(always)]
fn skew_mul<T: Scalar>(w: Vec3<T>, m: &Mat3<T>) -> Mat3<T> {
    let mut out = *m;
    for j in 0..3 {
        let col = cross(w, [m[0][j], m[1][j], m[2][j]]);
        for (i, row) in out.iter_mut().enumerate() {
            row[j] = col[i];
        }
    }
    out
}

/// The rotation by `angle` about Z0.
fn rot_z(angle: f64) -> Mat3<f64> {
    let (s, co) = angle.sin_cos();
    [[co, -s, 0.0], [s, co, 0.0], [0.0, 0.0, 1.0]]
}

// ---------------------------------------------------------------------------------------
// Parameters.
// ---------------------------------------------------------------------------------------

/// Every number of the spec, named as the paper names it. Stiffness and damping
/// matrices of the couplings are diagonal; the isotropic ones are one number.
#[allow(non_snake_case)]
#[derive(Clone, Debug, PartialEq)]
pub struct QuickReturnHandParams {
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
    /// Crank box edges (lx, ly, lz), m; lx is the crank radius O1–A1.
    pub l1: [f64; 3],
    /// Slider box edges, m.
    pub l2: [f64; 3],
    /// Rocker box edges, m; lx is the length O3–A33.
    pub l3: [f64; 3],
    /// Connecting rod box edges, m; lx is the distance between its two joints.
    pub l4: [f64; 3],
    /// Output slider box edges, m.
    pub l5: [f64; 3],
    /// Distance from the crank pivot O1 down to the rocker pivot O3 = (0, −d, 0), m.
    pub d: f64,
    /// Gravity along −Y0, m/s².
    pub g: f64,
    /// Speed of the drive flow source `(0, 0, w_drive)`, rad/s.
    pub w_drive: f64,
    /// Initial crank angle from X0, rad (the spec: 90°).
    pub theta0: f64,
    /// Crank O1 – ground stiffness, N/m (3 axes).
    pub K01: f64,
    /// Crank O1 – ground damping, N·s/m.
    pub R01: f64,
    /// Crank pin A1 – slider A2 stiffness, N/m.
    pub K12: f64,
    /// Crank pin A1 – slider A2 damping, N·s/m.
    pub R12: f64,
    /// Rocker O3 – ground stiffness, N/m.
    pub K03: f64,
    /// Rocker O3 – ground damping, N·s/m.
    pub R03: f64,
    /// Slider – rocker stiffness in frame 3 (diagonal), N/m; zero along the slide.
    pub K3C: [f64; 3],
    /// Slider – rocker damping in frame 3 (diagonal), N·s/m; the x entry is the
    /// viscous slide friction.
    pub R3C: [f64; 3],
    /// Slider – rocker rotational stiffness, N·m/rad (3 axes).
    pub K23r: f64,
    /// Slider – rocker rotational damping, N·m·s/rad.
    pub R23r: f64,
    /// Drive source – crank rotational stiffness, N·m/rad (3 axes).
    pub K_C: f64,
    /// Drive source – crank rotational damping, N·m·s/rad.
    pub R_C: f64,
    /// Rocker tip A33 – rod stiffness, N/m.
    pub K34: f64,
    /// Rocker tip A33 – rod damping, N·s/m.
    pub R34: f64,
    /// Rod – output slider O5 stiffness, N/m.
    pub K45: f64,
    /// Rod – output slider O5 damping, N·s/m.
    pub R45: f64,
    /// Output slider – guide stiffness in frame 0 (diagonal), N/m; zero along X0.
    pub K5C: [f64; 3],
    /// Output slider – guide damping in frame 0 (diagonal), N·s/m; the x entry is the
    /// viscous slide friction.
    pub R5C: [f64; 3],
    /// The rocker's material point of K3C: 0 (default, the authors' choice) the one
    /// under the crank pin A1; 1 the one under the slider's centre (values ≥ 0.5 count
    /// as 1).
    pub k3c_point_under_slider: f64,
}

impl Default for QuickReturnHandParams {
    fn default() -> Self {
        let edge = 0.01;
        QuickReturnHandParams {
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
            w_drive: 5.0,
            theta0: core::f64::consts::FRAC_PI_2,
            K01: 1e5,
            R01: 20.0,
            K12: 1e5,
            R12: 20.0,
            K03: 1e5,
            R03: 20.0,
            K3C: [0.0, 1e5, 1e5],
            R3C: [20.0, 20.0, 20.0],
            K23r: 100.0,
            R23r: 0.5,
            K_C: 100.0,
            R_C: 100.0,
            K34: 1e5,
            R34: 20.0,
            K45: 1e5,
            R45: 20.0,
            K5C: [0.0, 1e5, 1e5],
            R5C: [20.0, 20.0, 20.0],
            k3c_point_under_slider: 0.0,
        }
    }
}

impl QuickReturnHandParams {
    /// The near-rigid limit used to compare with the rigid-body reference: every
    /// translational coupling's stiffness and damping 100 times the default, except
    /// the slide friction (the x damping of R3C and R5C) which stays 20 N·s/m; K_C and
    /// R_C 100 times; K23r and R23r unchanged.
    pub fn stiff_limit() -> Self {
        let d = Self::default();
        let f = 100.0;
        QuickReturnHandParams {
            K01: f * d.K01,
            R01: f * d.R01,
            K12: f * d.K12,
            R12: f * d.R12,
            K03: f * d.K03,
            R03: f * d.R03,
            K3C: d.K3C.map(|k| f * k),
            R3C: [d.R3C[0], f * d.R3C[1], f * d.R3C[2]],
            K_C: f * d.K_C,
            R_C: f * d.R_C,
            K34: f * d.K34,
            R34: f * d.R34,
            K45: f * d.K45,
            R45: f * d.R45,
            K5C: d.K5C.map(|k| f * k),
            R5C: [d.R5C[0], f * d.R5C[1], f * d.R5C[2]],
            ..d
        }
    }

    /// The masses, link by link.
    pub fn masses(&self) -> [f64; N_LINKS] {
        [self.m1, self.m2, self.m3, self.m4, self.m5]
    }

    /// The box edges, link by link.
    pub fn edges(&self) -> [[f64; 3]; N_LINKS] {
        [self.l1, self.l2, self.l3, self.l4, self.l5]
    }

    /// The body-frame inertia tensor's diagonal of link `i` (0-based), kg·m².
    pub fn inertia(&self, i: usize) -> [f64; 3] {
        let m = self.masses()[i];
        let [lx, ly, lz] = self.edges()[i];
        [
            m * (ly * ly + lz * lz) / 12.0,
            m * (lx * lx + lz * lz) / 12.0,
            m * (lx * lx + ly * ly) / 12.0,
        ]
    }

    /// Stiffness and damping diagonals of each coupling, in the state order.
    pub fn couplings(&self) -> [([f64; 3], [f64; 3]); N_COUPLINGS] {
        let iso = |k: f64| [k; 3];
        [
            (iso(self.K01), iso(self.R01)),
            (iso(self.K12), iso(self.R12)),
            (iso(self.K03), iso(self.R03)),
            (self.K3C, self.R3C),
            (iso(self.K23r), iso(self.R23r)),
            (iso(self.K_C), iso(self.R_C)),
            (iso(self.K34), iso(self.R34)),
            (iso(self.K45), iso(self.R45)),
            (self.K5C, self.R5C),
        ]
    }
}

// ---------------------------------------------------------------------------------------
// State and output layout.
// ---------------------------------------------------------------------------------------

/// Number of links.
pub const N_LINKS: usize = 5;
/// States per link: p (3), h (3), R (9), r (3).
pub const LINK_STATES: usize = 18;
/// Number of spring-damper couplings.
pub const N_COUPLINGS: usize = 9;
/// Index of the first coupling state.
pub const COUPLINGS_AT: usize = N_LINKS * LINK_STATES;
/// Offsets inside a link's block.
pub const P_AT: usize = 0;
/// See [`P_AT`].
pub const H_AT: usize = 3;
/// See [`P_AT`]; `R_ij` (1-based i, j) is at `R_AT + 3 (i−1) + (j−1)`.
pub const R_AT: usize = 6;
/// See [`P_AT`].
pub const POS_AT: usize = 15;
/// Coupling numbers, in the state order.
pub const K01: usize = 0;
/// See [`K01`].
pub const K12: usize = 1;
/// See [`K01`].
pub const K03: usize = 2;
/// See [`K01`].
pub const K3C: usize = 3;
/// See [`K01`].
pub const K23R: usize = 4;
/// See [`K01`].
pub const KC: usize = 5;
/// See [`K01`].
pub const K34: usize = 6;
/// See [`K01`].
pub const K45: usize = 7;
/// See [`K01`].
pub const K5C: usize = 8;

/// Index of the first state of link `i` (1-based, as the paper numbers them).
pub const fn link_at(i: usize) -> usize {
    (i - 1) * LINK_STATES
}

/// Index of the first state of coupling `k` (one of [`K01`] … [`K5C`]).
pub const fn coupling_at(k: usize) -> usize {
    COUPLINGS_AT + 3 * k
}

macro_rules! state_names {
    ($($link:literal)+ ; $($coupling:literal)+) => {
        &[
            $(
                concat!("link", $link, ".p_x"), concat!("link", $link, ".p_y"),
                concat!("link", $link, ".p_z"),
                concat!("link", $link, ".h_x"), concat!("link", $link, ".h_y"),
                concat!("link", $link, ".h_z"),
                concat!("link", $link, ".R_11"), concat!("link", $link, ".R_12"),
                concat!("link", $link, ".R_13"), concat!("link", $link, ".R_21"),
                concat!("link", $link, ".R_22"), concat!("link", $link, ".R_23"),
                concat!("link", $link, ".R_31"), concat!("link", $link, ".R_32"),
                concat!("link", $link, ".R_33"),
                concat!("link", $link, ".r_x"), concat!("link", $link, ".r_y"),
                concat!("link", $link, ".r_z"),
            )+
            $(
                concat!($coupling, ".q_x"), concat!($coupling, ".q_y"),
                concat!($coupling, ".q_z"),
            )+
        ]
    };
}

/// The state names, in the order of the state vector.
pub const STATE_NAMES: &[&str] =
    state_names!(1 2 3 4 5; "K01" "K12" "K03" "K3C" "K23r" "K_C" "K34" "K45" "K5C");

/// The output names, in the order of the output vector.
pub const OUTPUT_NAMES: &[&str] = &[
    "crank_angle",
    "R1_11",
    "R1_21",
    "R1_31",
    "R1_12",
    "R1_22",
    "R1_32",
    "R1_13",
    "R1_23",
    "R1_33",
    "h1_x",
    "h1_y",
    "h1_z",
    "F_O1_x",
    "F_O1_y",
    "F_O1_z",
    "Tc_x",
    "Tc_y",
    "Tc_z",
    "F_A2_x",
    "F_A2_y",
    "F_A2_z",
    "r_C3_x",
    "r_C3_y",
    "r_C3_z",
    "p3_x",
    "p3_y",
    "p3_z",
    "F_O3_x",
    "F_O3_y",
    "F_O3_z",
    "R4_11",
    "R4_21",
    "R4_31",
    "R4_12",
    "R4_22",
    "R4_32",
    "R4_13",
    "R4_23",
    "R4_33",
    "r_C5_x",
    "r_C5_y",
    "r_C5_z",
    "p5_x",
    "p5_y",
    "p5_z",
    "F_O5_x",
    "F_O5_y",
    "F_O5_z",
    "F_5C_x",
    "F_5C_y",
    "F_5C_z",
    "E_stored",
    "P_in",
    "P_diss",
    "w1_x",
    "w1_y",
    "w1_z",
    "dw1_x",
    "dw1_y",
    "dw1_z",
];

/// Number of states.
pub const N_STATES: usize = COUPLINGS_AT + 3 * N_COUPLINGS;
/// Number of outputs.
pub const N_OUTPUTS: usize = 61;

const _: () = assert!(STATE_NAMES.len() == N_STATES);
const _: () = assert!(OUTPUT_NAMES.len() == N_OUTPUTS);

// ---------------------------------------------------------------------------------------
// The model.
// ---------------------------------------------------------------------------------------

/// The quick return mechanism with compliant joints, written by hand.
#[derive(Clone, Debug, Default)]
pub struct QuickReturnHand {
    /// The parameters.
    pub params: QuickReturnHandParams,
}

/// Everything the derivative and the outputs need, at one state.
struct Eval<T> {
    /// Orientation of each link.
    rot: [Mat3<T>; N_LINKS],
    /// Angular momentum of each link.
    h: [Vec3<T>; N_LINKS],
    /// Centre-of-mass velocity of each link.
    v: [Vec3<T>; N_LINKS],
    /// Angular velocity of each link.
    w: [Vec3<T>; N_LINKS],
    /// Net force on each link (couplings and gravity): dp/dt.
    force: [Vec3<T>; N_LINKS],
    /// Net torque about each centre of mass: dh/dt.
    torque: [Vec3<T>; N_LINKS],
    /// dq/dt of each coupling, in its frame.
    flow: [Vec3<T>; N_COUPLINGS],
    /// `K q + R dq/dt` of each coupling, in its frame.
    effort: [Vec3<T>; N_COUPLINGS],
}

impl QuickReturnHand {
    /// The model with parameters `params`.
    pub fn new(params: QuickReturnHandParams) -> Self {
        QuickReturnHand { params }
    }

    fn evaluate<T: Scalar>(&self, x: &[T]) -> Eval<T> {
        let p = &self.params;
        let masses = p.masses();
        let zero = c::<T>(0.0);
        let z3 = [zero; 3];
        let read3 = |at: usize| -> Vec3<T> { [x[at], x[at + 1], x[at + 2]] };

        let mut rot = [[z3; 3]; N_LINKS];
        let mut h = [z3; N_LINKS];
        let mut r = [z3; N_LINKS];
        let mut v = [z3; N_LINKS];
        let mut w = [z3; N_LINKS];
        let mut force = [z3; N_LINKS];
        let mut torque = [z3; N_LINKS];
        for i in 0..N_LINKS {
            let at = i * LINK_STATES;
            let rm = [read3(at + R_AT), read3(at + R_AT + 3), read3(at + R_AT + 6)];
            let inv_j = p.inertia(i).map(|j| 1.0 / j);
            h[i] = read3(at + H_AT);
            v[i] = scale(c(1.0 / masses[i]), read3(at + P_AT));
            w[i] = mat_vec(&rm, diag_mul(inv_j, mat_t_vec(&rm, h[i])));
            r[i] = read3(at + POS_AT);
            rot[i] = rm;
            force[i][1] = c(-masses[i] * p.g);
        }

        // A point on link i at body vector (bx, 0, 0): its arm R b from the centre of
        // mass and its velocity.
        let arm = |i: usize, bx: f64| -> Vec3<T> {
            scale(c(bx), [rot[i][0][0], rot[i][1][0], rot[i][2][0]])
        };
        let point_velocity = |i: usize, arm: Vec3<T>| add(v[i], cross(w[i], arm));
        let q = |k: usize| read3(coupling_at(k));
        let couplings = p.couplings();
        let effort_of = |k: usize, flow: Vec3<T>| {
            let (stiffness, damping) = couplings[k];
            add(diag_mul(stiffness, q(k)), diag_mul(damping, flow))
        };
        let mut flow = [z3; N_COUPLINGS];
        let mut effort = [z3; N_COUPLINGS];
        // A force f at arm a on link i.
        let push = |force: &mut [Vec3<T>; N_LINKS],
                    torque: &mut [Vec3<T>; N_LINKS],
                    i: usize,
                    a: Option<Vec3<T>>,
                    f: Vec3<T>| {
            force[i] = add(force[i], f);
            if let Some(a) = a {
                torque[i] = add(torque[i], cross(a, f));
            }
        };

        let (crank, slider, rocker, rod, output) = (0, 1, 2, 3, 4);
        let (half1, half3, half4) = (0.5 * p.l1[0], 0.5 * p.l3[0], 0.5 * p.l4[0]);

        // K01: crank O1 (first) – ground.
        let a_o1 = arm(crank, -half1);
        flow[K01] = point_velocity(crank, a_o1);
        effort[K01] = effort_of(K01, flow[K01]);
        push(&mut force, &mut torque, crank, Some(a_o1), neg(effort[K01]));

        // K12: crank pin A1 (first) – slider centre A2.
        let a_a1 = arm(crank, half1);
        flow[K12] = sub(point_velocity(crank, a_a1), v[slider]);
        effort[K12] = effort_of(K12, flow[K12]);
        push(&mut force, &mut torque, crank, Some(a_a1), neg(effort[K12]));
        push(&mut force, &mut torque, slider, None, effort[K12]);

        // K03: rocker O3 (first) – ground.
        let a_o3 = arm(rocker, -half3);
        flow[K03] = point_velocity(rocker, a_o3);
        effort[K03] = effort_of(K03, flow[K03]);
        push(
            &mut force,
            &mut torque,
            rocker,
            Some(a_o3),
            neg(effort[K03]),
        );

        // K3C: slider centre A2 (first) – rocker point P3, in frame 3.
        let a_p3 = if p.k3c_point_under_slider >= 0.5 {
            sub(r[slider], r[rocker])
        } else {
            sub(add(r[crank], a_a1), r[rocker])
        };
        let rel_0 = sub(v[slider], point_velocity(rocker, a_p3));
        flow[K3C] = mat_t_vec(&rot[rocker], rel_0);
        effort[K3C] = effort_of(K3C, flow[K3C]);
        let effort_3c_0 = mat_vec(&rot[rocker], effort[K3C]);
        push(&mut force, &mut torque, slider, None, neg(effort_3c_0));
        push(&mut force, &mut torque, rocker, Some(a_p3), effort_3c_0);

        // K23r: slider rotation (first) – rocker rotation.
        flow[K23R] = sub(w[slider], w[rocker]);
        effort[K23R] = effort_of(K23R, flow[K23R]);
        torque[slider] = sub(torque[slider], effort[K23R]);
        torque[rocker] = add(torque[rocker], effort[K23R]);

        // K_C: drive source (first) – crank rotation.
        flow[KC] = sub([zero, zero, c(p.w_drive)], w[crank]);
        effort[KC] = effort_of(KC, flow[KC]);
        torque[crank] = add(torque[crank], effort[KC]);

        // K34: rocker tip A33 (first) – rod end.
        let a_a33 = arm(rocker, half3);
        let a_rod_top = arm(rod, -half4);
        flow[K34] = sub(
            point_velocity(rocker, a_a33),
            point_velocity(rod, a_rod_top),
        );
        effort[K34] = effort_of(K34, flow[K34]);
        push(
            &mut force,
            &mut torque,
            rocker,
            Some(a_a33),
            neg(effort[K34]),
        );
        push(&mut force, &mut torque, rod, Some(a_rod_top), effort[K34]);

        // K45: rod end (first) – output slider centre O5.
        let a_rod_bottom = arm(rod, half4);
        flow[K45] = sub(point_velocity(rod, a_rod_bottom), v[output]);
        effort[K45] = effort_of(K45, flow[K45]);
        push(
            &mut force,
            &mut torque,
            rod,
            Some(a_rod_bottom),
            neg(effort[K45]),
        );
        push(&mut force, &mut torque, output, None, effort[K45]);

        // K5C: output slider centre O5 (first) – guide, frame 0.
        flow[K5C] = v[output];
        effort[K5C] = effort_of(K5C, flow[K5C]);
        push(&mut force, &mut torque, output, None, neg(effort[K5C]));

        Eval {
            rot,
            h,
            v,
            w,
            force,
            torque,
            flow,
            effort,
        }
    }
}

impl Model for QuickReturnHand {
    type Params = QuickReturnHandParams;

    const NAME: &'static str = "QuickReturnHand";
    const STATE_NAMES: &'static [&'static str] = STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = OUTPUT_NAMES;

    fn params(&self) -> &QuickReturnHandParams {
        &self.params
    }

    /// The spec's initial geometry, computed from the parameters: crank at `theta0`,
    /// slider centre at the crank pin, rocker through the pin, the rod from the rocker
    /// tip down to O5 on y = 0 to the right of the tip; everything at rest, every
    /// coupling unstretched.
    fn initial_state(&self, x0: &mut [f64]) {
        let p = &self.params;
        x0.fill(0.0);
        let (crank_radius, rocker_length, rod_length) = (p.l1[0], p.l3[0], p.l4[0]);
        let theta = p.theta0;
        let pin = [crank_radius * theta.cos(), crank_radius * theta.sin(), 0.0];
        let o3 = [0.0, -p.d, 0.0];
        let along = sub(pin, o3);
        let phi = along[1].atan2(along[0]);
        let tip = [
            o3[0] + rocker_length * phi.cos(),
            o3[1] + rocker_length * phi.sin(),
            0.0,
        ];
        let o5 = [
            tip[0] + (rod_length * rod_length - tip[1] * tip[1]).sqrt(),
            0.0,
            0.0,
        ];
        let psi = (-tip[1] / rod_length).asin();
        let links = [
            (rot_z(theta), scale(0.5, pin)),
            (rot_z(phi), pin),
            (
                rot_z(phi),
                add(o3, scale(0.5 * rocker_length, [phi.cos(), phi.sin(), 0.0])),
            ),
            (rot_z(psi), scale(0.5, add(tip, o5))),
            (rot_z(0.0), o5),
        ];
        for (i, (rm, r)) in links.iter().enumerate() {
            let at = i * LINK_STATES;
            for row in 0..3 {
                x0[at + R_AT + 3 * row..at + R_AT + 3 * row + 3].copy_from_slice(&rm[row]);
            }
            x0[at + POS_AT..at + POS_AT + 3].copy_from_slice(r);
        }
    }

    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let e = self.evaluate(x);
        for i in 0..N_LINKS {
            let at = i * LINK_STATES;
            dx[at + P_AT..at + P_AT + 3].copy_from_slice(&e.force[i]);
            dx[at + H_AT..at + H_AT + 3].copy_from_slice(&e.torque[i]);
            let dr = skew_mul(e.w[i], &e.rot[i]);
            for (row, values) in dr.iter().enumerate() {
                dx[at + R_AT + 3 * row..at + R_AT + 3 * row + 3].copy_from_slice(values);
            }
            dx[at + POS_AT..at + POS_AT + 3].copy_from_slice(&e.v[i]);
        }
        for k in 0..N_COUPLINGS {
            dx[coupling_at(k)..coupling_at(k) + 3].copy_from_slice(&e.flow[k]);
        }
    }

    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        let p = &self.params;
        let e = self.evaluate(x);
        let masses = p.masses();
        let mut out = 0;
        let mut put = |values: &[T]| {
            y[out..out + values.len()].copy_from_slice(values);
            out += values.len();
        };
        let columns = |m: &Mat3<T>| {
            [
                m[0][0], m[1][0], m[2][0], m[0][1], m[1][1], m[2][1], m[0][2], m[1][2], m[2][2],
            ]
        };
        let r1 = &e.rot[0];
        let wrapped = r1[1][0].atan2(r1[1][1]);
        let turned = p.theta0 + p.w_drive * t - x[coupling_at(KC) + 2].to_f64();
        let turns = ((turned - wrapped.to_f64()) / core::f64::consts::TAU).round();
        put(&[if turns == 0.0 {
            wrapped
        } else {
            wrapped + c::<T>(turns * core::f64::consts::TAU)
        }]);
        put(&columns(r1));
        put(&e.h[0]);
        put(&neg(e.effort[K01]));
        put(&e.effort[KC]);
        put(&e.effort[K12]);
        let link3 = link_at(3);
        put(&x[link3 + POS_AT..link3 + POS_AT + 3]);
        put(&x[link3 + P_AT..link3 + P_AT + 3]);
        put(&neg(e.effort[K03]));
        put(&columns(&e.rot[3]));
        let link5 = link_at(5);
        put(&x[link5 + POS_AT..link5 + POS_AT + 3]);
        put(&x[link5 + P_AT..link5 + P_AT + 3]);
        put(&e.effort[K45]);
        put(&neg(e.effort[K5C]));

        // Energy: kinetic ½ p·v + ½ h·w, gravitational m g y, springs ½ qᵀ K q.
        let half = c::<T>(0.5);
        let mut stored = c::<T>(0.0);
        for (i, mass) in masses.into_iter().enumerate() {
            let at = i * LINK_STATES;
            let momentum = [x[at + P_AT], x[at + P_AT + 1], x[at + P_AT + 2]];
            stored += half * (dot(momentum, e.v[i]) + dot(e.h[i], e.w[i]));
            stored += c::<T>(mass * p.g) * x[at + POS_AT + 1];
        }
        let mut dissipated = c::<T>(0.0);
        for (k, (stiffness, damping)) in p.couplings().iter().enumerate() {
            let q = [
                x[coupling_at(k)],
                x[coupling_at(k) + 1],
                x[coupling_at(k) + 2],
            ];
            stored += half * dot(q, diag_mul(*stiffness, q));
            dissipated += dot(e.flow[k], diag_mul(*damping, e.flow[k]));
        }
        let p_in = e.effort[KC][2] * c(p.w_drive);
        put(&[stored, p_in, dissipated]);

        // The crank's angular velocity and acceleration:
        // dw/dt = d/dt (M h) with M = R J⁻¹ Rᵀ, dM/dt = S M − M S (S = skew w), so
        // dw/dt = M (dh/dt − w × h).
        put(&e.w[0]);
        let inv_j = p.inertia(0).map(|j| 1.0 / j);
        let rate = sub(e.torque[0], cross(e.w[0], e.h[0]));
        put(&mat_vec(r1, diag_mul(inv_j, mat_t_vec(r1, rate))));
        debug_assert_eq!(out, N_OUTPUTS);
    }
}
