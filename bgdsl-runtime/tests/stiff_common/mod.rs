//! Stiff reference problems shared by the `stiff_*` tests, written as a user would
//! write them by hand: `derivatives` generic over the scalar, the Jacobian's sparsity
//! pattern declared, no hand-written Jacobian (the solver differentiates them exactly).
//!
//! The problems and their reference values are those of the *Test Set for IVP Solvers*
//! of the University of Bari (F. Mazzia, C. Magherini et al., release 2.4, 2008,
//! <https://archimede.uniba.it/~testset/>), whose references were computed with RADAU5
//! or RADAU in quadruple precision at tolerances near 1e-18.
#![allow(dead_code)]

use bgdsl_runtime::{Model, Scalar, Simulation, Solver, Stats};

/// Robertson's chemical kinetics (HW II, Sect. IV.1, eq. (1.4); Bari test set
/// "ROBER"), on `[0, 1e11]` from `(1, 0, 0)`.
pub struct Robertson;

impl Model for Robertson {
    type Params = ();
    const NAME: &'static str = "robertson";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2", "y3"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
        Some(&[&[0, 1, 2], &[0, 1, 2], &[1]]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let c = T::from_f64;
        let r1 = c(0.04) * y[0];
        let r2 = c(1e4) * y[1] * y[2];
        let r3 = c(3e7) * y[1] * y[1];
        dy[0] = r2 - r1;
        dy[1] = r1 - r2 - r3;
        dy[2] = r3;
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// ROBER at `t = 1e11` (Bari test set, problem ROBER, "Reference solution"), with the
/// published digits.
#[allow(clippy::excessive_precision)]
pub const ROBERTSON_REF: [f64; 3] = [
    0.2083340149701255e-7,
    0.8333360770334713e-13,
    0.9999999791665050,
];

/// Van der Pol's equation in Liénard's scaled form (HW II, Sect. IV.1, eq. (1.5'); Bari
/// test set "VDPOL"): `y1' = y2`, `y2' = ((1 - y1^2) y2 - y1) / ε` with `ε = 1e-6`
/// (that is `μ = 1000` in `y'' - μ (1 - y^2) y' + y = 0` with time scaled by `μ`), on
/// `[0, 2]` from `(2, 0)`.
pub struct VanDerPol;

pub const VDP_EPS: f64 = 1e-6;

impl Model for VanDerPol {
    type Params = ();
    const NAME: &'static str = "van_der_pol";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[2.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let one = T::from_f64(1.0);
        dy[0] = y[1];
        dy[1] = ((one - y[0] * y[0]) * y[1] - y[0]) / T::from_f64(VDP_EPS);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// Van der Pol as [`VanDerPol`] with its `ε = 1 / μ²` chosen: `StiffVanDerPol(1e-12)` is
/// `μ = 1e6` (the Bari set's VDPOL has `μ = 1e3`).
pub struct StiffVanDerPol(pub f64);

impl Model for StiffVanDerPol {
    type Params = ();
    const NAME: &'static str = "van_der_pol_mu_1e6";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[2.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let one = T::from_f64(1.0);
        dy[0] = y[1];
        dy[1] = ((one - y[0] * y[0]) * y[1] - y[0]) / T::from_f64(self.0);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// VDPOL at `t = 2` (Bari test set, problem VDPOL, "Reference solution").
pub const VDP_REF: [f64; 2] = [0.1706167732170483e1, -0.8928097010247975];

/// HIRES, "High Irradiance RESponse" of plant morphogenesis (Schäfer 1975; HW II,
/// Sect. IV.10; Bari test set "HIRES"), 8 states on `[0, 321.8122]`.
pub struct Hires;

impl Model for Hires {
    type Params = ();
    const NAME: &'static str = "hires";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2", "y3", "y4", "y5", "y6", "y7", "y8"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&[
        &[0, 1, 2],
        &[0, 1],
        &[2, 3, 4],
        &[1, 2, 3],
        &[4, 5, 6],
        &[3, 4, 5, 6, 7],
        &[5, 6, 7],
        &[5, 6, 7],
    ]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let c = T::from_f64;
        dy[0] = c(-1.71) * y[0] + c(0.43) * y[1] + c(8.32) * y[2] + c(0.0007);
        dy[1] = c(1.71) * y[0] - c(8.75) * y[1];
        dy[2] = c(-10.03) * y[2] + c(0.43) * y[3] + c(0.035) * y[4];
        dy[3] = c(8.32) * y[1] + c(1.71) * y[2] - c(1.12) * y[3];
        dy[4] = c(-1.745) * y[4] + c(0.43) * (y[5] + y[6]);
        let r = c(280.0) * y[5] * y[7];
        dy[5] = -r + c(0.69) * y[3] + c(1.71) * y[4] - c(0.43) * y[5] + c(0.69) * y[6];
        dy[6] = r - c(1.81) * y[6];
        dy[7] = -dy[6];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// HIRES at `t = 321.8122` (Bari test set, problem HIRES, "Reference solution").
pub const HIRES_REF: [f64; 8] = [
    0.7371312573325668e-3,
    0.1442485726316185e-3,
    0.5888729740967575e-4,
    0.1175651343283149e-2,
    0.2386356198831331e-2,
    0.6238968252742796e-2,
    0.2849998395185769e-2,
    0.2850001604814231e-2,
];
pub const HIRES_T_END: f64 = 321.8122;

/// The Oregonator, Field & Noyes' model of the Belousov–Zhabotinskii reaction (HW II,
/// Sect. IV.1, eq. (1.5) and Fig. 1.6; Bari test set "OREGO"), on `[0, 360]` from
/// `(1, 2, 3)`: relaxation oscillations over six orders of magnitude.
pub struct Oregonator;

impl Model for Oregonator {
    type Params = ();
    const NAME: &'static str = "oregonator";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2", "y3"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
        Some(&[&[0, 1], &[0, 1, 2], &[0, 2]]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 2.0, 3.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let c = T::from_f64;
        let one = c(1.0);
        dy[0] = c(77.27) * (y[1] + y[0] * (one - c(8.375e-6) * y[0] - y[1]));
        dy[1] = (y[2] - (one + y[0]) * y[1]) / c(77.27);
        dy[2] = c(0.161) * (y[0] - y[2]);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// OREGO at `t = 360` (Bari test set, problem OREGO, "Reference solution").
pub const OREGO_REF: [f64; 3] = [
    0.1000814870318523e1,
    0.1228178521549917e4,
    0.1320554942846706e3,
];

/// The air-pollution model of the Dutch National Institute of Public Health (Verwer
/// 1994; Bari test set "POLLU"): 20 species, 25 reactions, on `[0, 60]`. The rate
/// constants, initial values and reactions are those of the test set's problem
/// description.
pub struct Pollution;

/// POLLU's rate constants `k_1..k_25` (Bari test set, problem POLLU).
#[allow(clippy::excessive_precision)]
const POLLU_K: [f64; 25] = [
    0.35, 0.266e2, 0.123e5, 0.86e-3, 0.82e-3, 0.15e5, 0.13e-3, 0.24e5, 0.165e5, 0.9e4, 0.22e-1,
    0.12e5, 0.188e1, 0.163e5, 0.48e7, 0.35e-3, 0.175e-1, 0.1e9, 0.444e12, 0.124e4, 0.21e1, 0.578e1,
    0.474e-1, 0.178e4, 0.312e1,
];

impl Model for Pollution {
    type Params = ();
    const NAME: &'static str = "pollution";
    const STATE_NAMES: &'static [&'static str] = &[
        "y1", "y2", "y3", "y4", "y5", "y6", "y7", "y8", "y9", "y10", "y11", "y12", "y13", "y14",
        "y15", "y16", "y17", "y18", "y19", "y20",
    ];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&[
        &[0, 1, 3, 4, 5, 9, 10, 12, 18, 19],
        &[0, 1, 3, 4, 9, 10, 18],
        &[0, 2, 3, 15, 18],
        &[0, 1, 2, 3],
        &[1, 4, 5, 6, 8, 13, 16],
        &[0, 1, 4, 5, 6, 8, 15, 16],
        &[5, 6, 13],
        &[5, 6, 8],
        &[5, 8],
        &[1, 8, 9, 10],
        &[0, 1, 5, 8, 10, 12],
        &[1, 10],
        &[0, 10, 12],
        &[1, 9, 13],
        &[0, 5],
        &[3, 15],
        &[5, 16],
        &[5, 16],
        &[0, 3, 18, 19],
        &[0, 18, 19],
    ]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0);
        x0[1] = 0.2;
        x0[3] = 0.04;
        x0[6] = 0.1;
        x0[7] = 0.3;
        x0[8] = 0.01;
        x0[16] = 0.007;
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let k = |i: usize| T::from_f64(POLLU_K[i - 1]);
        // The reaction rates r_1..r_25 (index 0 unused), in the test set's numbering.
        let r = [
            T::from_f64(0.0),
            k(1) * y[0],
            k(2) * y[1] * y[3],
            k(3) * y[4] * y[1],
            k(4) * y[6],
            k(5) * y[6],
            k(6) * y[6] * y[5],
            k(7) * y[8],
            k(8) * y[8] * y[5],
            k(9) * y[10] * y[1],
            k(10) * y[10] * y[0],
            k(11) * y[12],
            k(12) * y[9] * y[1],
            k(13) * y[13],
            k(14) * y[0] * y[5],
            k(15) * y[2],
            k(16) * y[3],
            k(17) * y[3],
            k(18) * y[15],
            k(19) * y[15],
            k(20) * y[16] * y[5],
            k(21) * y[18],
            k(22) * y[18],
            k(23) * y[0] * y[3],
            k(24) * y[18] * y[0],
            k(25) * y[19],
        ];
        dy[0] = -r[1] - r[10] - r[14] - r[23] - r[24]
            + r[2]
            + r[3]
            + r[9]
            + r[11]
            + r[12]
            + r[22]
            + r[25];
        dy[1] = -r[2] - r[3] - r[9] - r[12] + r[1] + r[21];
        dy[2] = -r[15] + r[1] + r[17] + r[19] + r[22];
        dy[3] = -r[2] - r[16] - r[17] - r[23] + r[15];
        dy[4] = -r[3] + r[4] + r[4] + r[6] + r[7] + r[13] + r[20];
        dy[5] = -r[6] - r[8] - r[14] - r[20] + r[3] + r[18] + r[18];
        dy[6] = -r[4] - r[5] - r[6] + r[13];
        dy[7] = r[4] + r[5] + r[6] + r[7];
        dy[8] = -r[7] - r[8];
        dy[9] = -r[12] + r[7] + r[9];
        dy[10] = -r[9] - r[10] + r[8] + r[11];
        dy[11] = r[9];
        dy[12] = -r[11] + r[10];
        dy[13] = -r[13] + r[12];
        dy[14] = r[14];
        dy[15] = -r[18] - r[19] + r[16];
        dy[16] = -r[20];
        dy[17] = r[20];
        dy[18] = -r[21] - r[22] - r[24] + r[23] + r[25];
        dy[19] = -r[25] + r[24];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// POLLU at `t = 60` (Bari test set, problem POLLU, "Reference solution": RADAU5 in
/// quadruple precision, `rtol = atol = h0 = 1.1e-18`).
#[allow(clippy::excessive_precision)]
pub const POLLU_REF: [f64; 20] = [
    0.5646255480022769e-1,
    0.1342484130422339,
    0.4139734331099427e-8,
    0.5523140207484359e-2,
    0.2018977262302196e-6,
    0.1464541863493966e-6,
    0.7784249118997964e-1,
    0.3245075353396018,
    0.7494013383880406e-2,
    0.1622293157301561e-7,
    0.1135863833257075e-7,
    0.2230505975721359e-2,
    0.2087162882798630e-3,
    0.1396921016840158e-4,
    0.8964884856898295e-2,
    0.4352846369330103e-17,
    0.6899219696263405e-2,
    0.1007803037365946e-3,
    0.1772146513969984e-5,
    0.5682943292316392e-4,
];

/// E5, the pyrolysis problem of Enright, Hull & Lindberg's stiff DETEST set (1975;
/// HW II, Sect. IV.10; Bari test set "E5"), 4 states on `[0, 1e13]` from
/// `(1.76e-3, 0, 0, 0)`. The solution spans 290 orders of magnitude (`y1` ends near
/// 1e-291) and keeps the linear invariant `y2 - y3 - y4 = 0` (`y2' = y3' + y4'`), which
/// every Runge–Kutta and Rosenbrock method with the exact Jacobian preserves up to
/// rounding and the Newton iteration's residual.
pub struct E5;

/// E5's constants `A, B, C, M` (Bari test set, problem E5).
const E5_A: f64 = 7.89e-10;
const E5_B: f64 = 1.1e7;
const E5_C: f64 = 1.13e3;
const E5_M: f64 = 1e6;

impl Model for E5 {
    type Params = ();
    const NAME: &'static str = "e5";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2", "y3", "y4"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
        Some(&[&[0, 2], &[0, 1, 2], &[0, 1, 2, 3], &[0, 2, 3]]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.76e-3, 0.0, 0.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let c = T::from_f64;
        let decay = c(E5_A) * y[0];
        let r_b = c(E5_B) * y[0] * y[2];
        let r_mc = c(E5_M * E5_C) * y[1] * y[2];
        let r_c = c(E5_C) * y[3];
        dy[0] = -decay - r_b;
        dy[1] = decay - r_mc;
        dy[3] = r_b - r_c;
        // As the test set writes it: `y3' = y2' - y4'`, so that the invariant's rate
        // `y2' - y3' - y4'` is zero up to one rounding of the small `y2'` and `y4'`
        // (summing the four rates instead leaves the rounding of the large `r_b` and
        // `r_c`, which integrated over `1e13` swamps `y2`).
        dy[2] = dy[1] - dy[3];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// E5 at `t = 1e13` (Bari test set, problem E5, "Reference solution": RADAU in
/// quadruple precision, `rtol = h0 = 1.1e-18`, `atol = 1.1e-40`). The published `y2`
/// and `y3` differ by 1.4e-3 relative, although the invariant `y2 - y3 - y4 = 0` and
/// `y4 ≈ 0` (it decays at rate `C = 1130` once `y1` is gone) make them equal: the
/// reference is good to about three digits in `y2` and `y3`, and accuracy measured
/// against it saturates there.
#[allow(clippy::excessive_precision)]
pub const E5_REF: [f64; 4] = [
    0.1152903278711829e-290,
    0.8867655517642120e-22,
    0.8854814626268838e-22,
    0.0,
];

/// The end time of E5.
pub const E5_T_END: f64 = 1e13;

/// The rows of `∂f/∂x` that are not zero at `x` (each row's columns, increasing), by
/// central differences of `f` at a point with all components nonzero: compared with a
/// declared `JACOBIAN_SPARSITY` to check it (a dependence missing from the declaration
/// would make the solver's Jacobian wrong).
pub fn observed_pattern<M: Model>(model: &M, x: &[f64]) -> Vec<Vec<usize>> {
    let n = x.len();
    let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
    let mut rows = vec![Vec::new(); n];
    let mut xp = x.to_vec();
    for j in 0..n {
        let dx = 1e-3 * x[j].abs();
        xp[j] = x[j] + dx;
        model.derivatives(0.0, &xp, &mut plus);
        xp[j] = x[j] - dx;
        model.derivatives(0.0, &xp, &mut minus);
        xp[j] = x[j];
        for (i, row) in rows.iter_mut().enumerate() {
            if plus[i] != minus[i] {
                row.push(j);
            }
        }
    }
    rows
}

/// Integrates `model` from its initial state over `[0, t_end]` with `solver`; returns
/// the final state and the work done.
pub fn solve<M: Model>(model: &M, solver: Solver, t_end: f64) -> (Vec<f64>, Stats) {
    let mut sim = Simulation::new(model, solver).unwrap();
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let stats = sim
        .run(0.0, &x0, &[t_end], &mut ())
        .unwrap_or_else(|e| panic!("{} with {}: {e}", M::NAME, solver.name()));
    (sim.state().to_vec(), stats)
}

/// The largest error relative to `atol + rtol |ref_i|`, the measure the tolerances ask
/// for.
pub fn scaled_error(x: &[f64], reference: &[f64], rtol: f64, atol: f64) -> f64 {
    x.iter()
        .zip(reference)
        .map(|(x, r)| (x - r).abs() / (atol + rtol * r.abs()))
        .fold(0.0, f64::max)
}

/// The largest relative error `|x_i - ref_i| / |ref_i|`.
pub fn relative_error(x: &[f64], reference: &[f64]) -> f64 {
    x.iter()
        .zip(reference)
        .map(|(x, r)| ((x - r) / r).abs())
        .fold(0.0, f64::max)
}
