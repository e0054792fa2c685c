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
