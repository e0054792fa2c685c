//! The three-stage Radau IIA method of order 5 as in Hairer & Wanner's RADAU5
//! (*Solving ODEs II*, 2nd ed., Sect. IV.8).
//!
//! **Stages.** With `Z = (z_1, z_2, z_3)`, `z_i = Y_i - x`, the stage equations
//! `Z = h (A ⊗ I) F(Z)` are solved by simplified Newton iterations with the Jacobian `J`
//! at the start of a step (or of an earlier one). The Radau IIA matrix `A` has one real
//! eigenvalue and a complex pair: `T^-1 A^-1 T = [[γ, 0, 0], [0, α, -β], [0, β, α]]`, so
//! in the variables `W = (T^-1 ⊗ I) Z` one Newton step is one real solve with
//! `E1 = (γ / h) I - J` and one complex solve with `E2 = ((α + iβ) / h) I - J`, of size
//! `n` each (HW II, eqs. (8.15)–(8.18)).
//!
//! **Newton control** (HW II, Sect. IV.8, "Stopping criterion"): the contraction rate
//! `θ_k = ||ΔW_k|| / ||ΔW_{k-1}||` is watched; the iteration stops when
//! `θ / (1 - θ) ||ΔW|| <= κ tol`, and gives up (the step is retried shorter) when `θ`
//! reaches 0.99 or when the rate predicts that the iteration cannot converge within the
//! iteration limit. On the first iteration no rate is known yet: RADAU5 uses the last
//! one measured; here that rate is used only if it was measured with the same step size
//! (the same iteration matrices), else the iteration runs at least twice unless the
//! first correction is already below the Newton tolerance. After a
//! step-size change the old rate can be far too optimistic: on POLLU a rate of 5e-8
//! measured on a step of 3e-4 let single iterations through on steps 60–90 times
//! longer, whose first corrections were a hundred times the tolerance, and the end
//! point missed the tolerance 135-fold (issue 15).
//!
//! **Starting values** come from extrapolating the collocation polynomial of the last
//! accepted step; **error estimate** is HW II eq. (8.20), with the filter
//! `(I - h γ0 J)^-1` (and a second filtered evaluation on the first step and after a
//! rejection); the **continuous extension** is the collocation polynomial itself, of
//! degree 3, through `x` and the three stage values.
//!
//! The constants are those of the method (`c`, the eigenvalues, the error weights in
//! closed form); the transformation `T` and its inverse are the published values of
//! RADAU5, checked in this module's tests against `A^-1` computed from the Butcher
//! tableau.

use super::{eval, Attempt, ImplicitMethod, LuCount, Radau5Options, StepStart};
use crate::jacobian::Jacobian;
use crate::linalg::{RadauMatrices, Singular, Structure};
use crate::model::Model;
use crate::solver::weights::{rms, scaled, Tolerances};

/// The transformation `T` (row-major) with `T^-1 A^-1 T` block diagonal. The published
/// digits are kept as printed.
#[allow(clippy::excessive_precision)]
const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294_279e-2,
        -1.412_552_950_209_542_084e-1,
        -3.002_919_410_514_742_449e-2,
    ],
    [
        2.417_179_327_071_070_190e-1,
        2.041_293_522_937_999_320e-1,
        3.829_421_127_572_619_378e-1,
    ],
    [9.660_481_826_150_929_362e-1, 1.0, 0.0],
];

/// `T^-1`.
#[allow(clippy::excessive_precision)]
const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155_351,
        3.391_992_518_158_098_695e-1,
        5.417_705_399_358_748_712e-1,
    ],
    [
        -4.178_718_591_551_904_727,
        -3.276_828_207_610_623_871e-1,
        4.766_235_545_005_504_520e-1,
    ],
    [
        -5.028_726_349_457_868_760e-1,
        2.571_926_949_855_605_429,
        -5.960_392_048_282_249_250e-1,
    ],
];

/// The tolerance transformation `rtol' = c rtol^p` (see [`Radau5Options`]): the error
/// estimate is `O(h^4)` and the global error `O(h^5)`, so an estimate held to `rtol'`
/// gives an error proportional to `rtol'^(5/4)`, and `p = 4/5` makes it proportional to
/// `rtol`. RADAU5's `p = 2/3` (with `c = 0.1`) made it shrink as `rtol^(5/6)`: 5–7x per
/// decade of `rtol`, and 2–100x above the tolerance asked for at `rtol <= 1e-6`. `c`
/// puts the end-point error of the Bari test set's problems (HIRES, POLLU, VDPOL,
/// OREGO, ROBER) at 0.01–1 times `atol + rtol |x|` for `rtol` in 1e-4…1e-10
/// (`docs/work-precision.md`).
const TRANSFORM_FACTOR: f64 = 0.3;
/// See [`TRANSFORM_FACTOR`].
const TRANSFORM_EXPONENT: f64 = 0.8;

/// The method's scalar constants, in closed form.
#[derive(Clone, Copy, Debug)]
struct Constants {
    /// Nodes `c_1, c_2` (`c_3 = 1`).
    c1: f64,
    c2: f64,
    /// The real eigenvalue `γ` of `A^-1` and the complex pair `α ± iβ`.
    gamma: f64,
    alpha: f64,
    beta: f64,
    /// Error-estimate weights `e_i / γ0` of HW II eq. (8.20), as in RADAU5.
    dd: [f64; 3],
}

impl Constants {
    fn new() -> Self {
        let sq6 = 6f64.sqrt();
        let (cbrt81, cbrt9) = (81f64.cbrt(), 9f64.cbrt());
        // Eigenvalues of A: 1/γ and (α' ± iβ').
        let gamma_a = (6.0 + cbrt81 - cbrt9) / 30.0;
        let alpha_a = (12.0 - cbrt81 + cbrt9) / 60.0;
        let beta_a = (cbrt81 + cbrt9) * 3f64.sqrt() / 60.0;
        let modulus = alpha_a * alpha_a + beta_a * beta_a;
        Constants {
            c1: (4.0 - sq6) / 10.0,
            c2: (4.0 + sq6) / 10.0,
            gamma: 1.0 / gamma_a,
            alpha: alpha_a / modulus,
            beta: beta_a / modulus,
            dd: [
                -(13.0 + 7.0 * sq6) / 3.0,
                (-13.0 + 7.0 * sq6) / 3.0,
                -1.0 / 3.0,
            ],
        }
    }
}

/// Workspace and state of Radau IIA (5). Allocated by [`Radau5::new`]; nothing else
/// allocates.
#[derive(Debug)]
pub(crate) struct Radau5 {
    k: Constants,
    /// Transformed tolerances (see [`Radau5Options`]).
    tol: Tolerances,
    max_iterations: usize,
    /// The Newton stopping tolerance the options set, if they set one.
    newton_tol_option: Option<f64>,
    newton_tol: f64,
    /// The step-size controller's safety factor.
    safety: f64,
    reuse_below: f64,
    /// `E1 = (γ/h) I - J` and `E2 = ((α + iβ)/h) I - J`, factored.
    e: RadauMatrices,
    /// `fac1 = γ/h`, `alphn = α/h`, `betan = β/h` of the factored matrices.
    fac1: f64,
    alphn: f64,
    betan: f64,
    /// Stage increments `Z` and their transforms `W = T^-1 Z`.
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    /// Stage derivatives, then Newton corrections `ΔW`.
    r: [Vec<f64>; 3],
    /// Scratch: a stage argument; error-estimate vectors.
    stage: Vec<f64>,
    err_rhs: Vec<f64>,
    err_v: Vec<f64>,
    /// Error weights `atol'_i + rtol' |x_i|` of the current step.
    scale: Vec<f64>,
    /// `1 / scale_i^2`, valid when `scale_positive` (every one finite): the norms of the
    /// step multiply instead of dividing.
    inv_scale2: Vec<f64>,
    scale_positive: bool,
    x_new: Vec<f64>,
    /// Newton-form coefficients of the last accepted step's collocation polynomial
    /// `u(s) = x_new + s (d1 + (s - c2 + 1) (d2 + (s - c1 + 1) d3))`,
    /// `s = (t - t_new) / h`.
    dense: [Vec<f64>; 3],
    dense_t: f64,
    dense_h: f64,
    /// Whether `dense` describes a step of this run (for starting values).
    have_dense: bool,
    /// `θ / (1 - θ)` of the last Newton iteration, carried to the next step's first
    /// convergence test (RADAU5's `FACCON`).
    faccon: f64,
    /// The step size `faccon` was measured with: it is trusted on a first iteration only
    /// for the same step size (0: none).
    faccon_h: f64,
}

impl Radau5 {
    /// The method for `n` states whose iteration matrices have `structure`, with
    /// settings `o` (already validated).
    pub fn new(n: usize, structure: &Structure, o: &Radau5Options) -> Self {
        let v = || vec![0.0; n];
        let mut method = Radau5 {
            k: Constants::new(),
            tol: Tolerances::uniform(o.rtol, o.atol, n),
            max_iterations: o.max_newton_iterations,
            newton_tol_option: o.newton_tol,
            newton_tol: 0.0,
            safety: o.safety,
            reuse_below: o.reuse_jacobian_below,
            e: RadauMatrices::new(structure),
            fac1: 0.0,
            alphn: 0.0,
            betan: 0.0,
            z: [v(), v(), v()],
            w: [v(), v(), v()],
            r: [v(), v(), v()],
            stage: v(),
            err_rhs: v(),
            err_v: v(),
            scale: v(),
            inv_scale2: v(),
            scale_positive: false,
            x_new: v(),
            dense: [v(), v(), v()],
            dense_t: 0.0,
            dense_h: 1.0,
            have_dense: false,
            faccon: 1.0,
            faccon_h: 0.0,
        };
        method.set_tolerances(&Tolerances::uniform(o.rtol, o.atol, n));
        method
    }

    /// Starting values of `Z` and `W` for a step of size `h`: zero on the first step,
    /// else the last step's collocation polynomial extrapolated to the new nodes.
    fn starting_values(&mut self, h: f64) {
        let [z1, z2, z3] = &mut self.z;
        let [w1, w2, w3] = &mut self.w;
        if !self.have_dense {
            for v in [z1, z2, z3, w1, w2, w3] {
                v.fill(0.0);
            }
            return;
        }
        let k = &self.k;
        let (c1m1, c2m1) = (k.c1 - 1.0, k.c2 - 1.0);
        let q = h / self.dense_h;
        let (s1, s2, s3) = (k.c1 * q, k.c2 * q, q);
        let n = z1.len();
        let [d1, d2, d3] = &self.dense;
        let (d1, d2, d3) = (&d1[..n], &d2[..n], &d3[..n]);
        let (z2, z3, w1, w2, w3) = (
            &mut z2[..n],
            &mut z3[..n],
            &mut w1[..n],
            &mut w2[..n],
            &mut w3[..n],
        );
        let poly = |s: f64, i: usize| s * (d1[i] + (s - c2m1) * (d2[i] + (s - c1m1) * d3[i]));
        for i in 0..n {
            let (a, b, c) = (poly(s1, i), poly(s2, i), poly(s3, i));
            z1[i] = a;
            z2[i] = b;
            z3[i] = c;
            w1[i] = TI[0][0] * a + TI[0][1] * b + TI[0][2] * c;
            w2[i] = TI[1][0] * a + TI[1][1] * b + TI[1][2] * c;
            w3[i] = TI[2][0] * a + TI[2][1] * b + TI[2][2] * c;
        }
    }

    /// The error estimate of HW II eq. (8.20): `(γ/h I - J)^-1 (f0 + (dd · Z) / h)`
    /// (RADAU5's scaling), and on the first step or after a rejection, the estimate
    /// filtered once more through `f` (HW II p. 124).
    fn error_estimate<M: Model>(
        &mut self,
        model: &M,
        start: &StepStart<'_>,
        n_rhs: &mut usize,
    ) -> f64 {
        let n = start.x.len();
        let dd = self.k.dd.map(|d| d / start.h);
        let [z1, z2, z3] = &self.z;
        let (z1, z2, z3, f0) = (&z1[..n], &z2[..n], &z3[..n], &start.f0[..n]);
        let (err_rhs, err_v) = (&mut self.err_rhs[..n], &mut self.err_v[..n]);
        for i in 0..n {
            let v = dd[0] * z1[i] + dd[1] * z2[i] + dd[2] * z3[i];
            err_rhs[i] = v;
            err_v[i] = v + f0[i];
        }
        self.e.solve_real(&mut self.err_v);
        let mut err = self.error_norm().max(1e-10);
        if err >= 1.0 && (start.first || start.after_reject) {
            for i in 0..n {
                self.stage[i] = start.x[i] + self.err_v[i];
            }
            // A non-finite value here only says that the unfiltered estimate was
            // large: keep that one.
            if eval(model, start.t, &self.stage, &mut self.err_v, n_rhs).is_ok() {
                for (e, r) in self.err_v.iter_mut().zip(&self.err_rhs) {
                    *e += r;
                }
                self.e.solve_real(&mut self.err_v);
                err = self.error_norm().max(1e-10);
            }
        }
        err
    }

    /// Fills the weights of a step from `x` and their inverse squares.
    fn set_weights(&mut self, x: &[f64]) {
        self.tol.weights().fill(x, &mut self.scale);
        let mut positive = true;
        for (inv, s) in self.inv_scale2.iter_mut().zip(&self.scale) {
            *inv = 1.0 / (s * s);
            // A zero weight, or one whose square underflows or is so small that its
            // inverse overflows: then the norms divide, through `scaled`.
            positive &= inv.is_finite();
        }
        self.scale_positive = positive;
    }

    /// The weighted RMS norm of the error estimate `err_v`.
    fn error_norm(&self) -> f64 {
        let n = self.err_v.len();
        if self.scale_positive {
            let zero = &self.z[0][..0];
            (sum_of_weighted_squares(&self.inv_scale2, &self.err_v, zero, zero) / n.max(1) as f64)
                .sqrt()
        } else {
            rms(
                self.err_v
                    .iter()
                    .zip(&self.scale)
                    .map(|(e, s)| scaled(*e, *s)),
                n,
            )
        }
    }

    /// The weighted RMS norm of the Newton correction `ΔW` (in `r`).
    fn correction_norm(&self) -> f64 {
        let [r1, r2, r3] = &self.r;
        let n = r1.len();
        let sum = if self.scale_positive {
            sum_of_weighted_squares(&self.inv_scale2, r1, r2, r3)
        } else {
            let mut sum = 0.0;
            for (i, s) in self.scale.iter().enumerate() {
                // A zero weight, or one whose square underflows.
                let (a, b, c) = (scaled(r1[i], *s), scaled(r2[i], *s), scaled(r3[i], *s));
                sum += a * a + b * b + c * c;
            }
            sum
        };
        (sum / (3 * n).max(1) as f64).sqrt()
    }
}

/// `Σ_i (a_i^2 + b_i^2 + c_i^2) w_i` over the length of `w`, in four interleaved partial
/// sums (so that the loop vectorizes); `b` and `c` may be empty (then not summed).
fn sum_of_weighted_squares(w: &[f64], a: &[f64], b: &[f64], c: &[f64]) -> f64 {
    let n = w.len();
    let a = &a[..n];
    let mut acc = [0.0f64; 4];
    let mut tail = 0.0;
    if b.is_empty() {
        let (wc, ac) = (w.chunks_exact(4), a.chunks_exact(4));
        let (wr, ar) = (wc.remainder(), ac.remainder());
        for (w, a) in wc.zip(ac) {
            for l in 0..4 {
                acc[l] += a[l] * a[l] * w[l];
            }
        }
        for (w, a) in wr.iter().zip(ar) {
            tail += a * a * w;
        }
    } else {
        let (b, c) = (&b[..n], &c[..n]);
        let (wc, ac, bc, cc) = (
            w.chunks_exact(4),
            a.chunks_exact(4),
            b.chunks_exact(4),
            c.chunks_exact(4),
        );
        let rest = n - wc.remainder().len();
        for (((w, a), b), c) in wc.zip(ac).zip(bc).zip(cc) {
            for l in 0..4 {
                acc[l] += (a[l] * a[l] + b[l] * b[l] + c[l] * c[l]) * w[l];
            }
        }
        for i in rest..n {
            tail += (a[i] * a[i] + b[i] * b[i] + c[i] * c[i]) * w[i];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

impl ImplicitMethod for Radau5 {
    const NEEDS_DFDT: bool = false;
    /// The error estimate is `O(h^4)`.
    const ERROR_EXPONENT: f64 = 0.25;

    /// The transformation of [`Radau5Options`]: `rtol' = 0.3 rtol^(4/5)`,
    /// `atol'_i = rtol' atol_i / rtol`, and the Newton tolerance from `rtol'`.
    fn set_tolerances(&mut self, tol: &Tolerances) {
        let rtol = TRANSFORM_FACTOR * tol.rtol.powf(TRANSFORM_EXPONENT);
        self.tol.rtol = rtol;
        for (a, user) in self.tol.atol.iter_mut().zip(&tol.atol) {
            *a = rtol * (user / tol.rtol);
        }
        self.newton_tol = self
            .newton_tol_option
            .unwrap_or_else(|| (10.0 * f64::EPSILON / rtol).max(0.03f64.min(rtol.sqrt())));
    }

    fn restart(&mut self) {
        self.have_dense = false;
        self.faccon = 1.0;
        self.faccon_h = 0.0;
        self.e.restart();
    }

    fn factor(
        &mut self,
        h: f64,
        jac: &Jacobian,
        new_jacobian: bool,
        count: &mut LuCount,
    ) -> Result<(), Singular> {
        self.fac1 = self.k.gamma / h;
        self.alphn = self.k.alpha / h;
        self.betan = self.k.beta / h;
        let shifts = [self.fac1, self.alphn, self.betan];
        let factored = self.e.factor(shifts, jac, new_jacobian)?;
        count.add(factored);
        count.add(factored);
        Ok(())
    }

    fn attempt<M: Model>(
        &mut self,
        model: &M,
        start: &StepStart<'_>,
        n_rhs: &mut usize,
    ) -> Attempt {
        let (t, h, x) = (start.t, start.h, start.x);
        let n = x.len();
        self.set_weights(x);
        self.starting_values(h);
        let nodes = [self.k.c1, self.k.c2, 1.0];
        let nit = self.max_iterations;
        self.faccon = self.faccon.max(f64::EPSILON).powf(0.8);
        let mut theta = self.reuse_below;
        let (mut dyno_old, mut thq_old) = (1.0, 1.0);
        let mut iterations = 0;
        loop {
            if iterations >= nit {
                return Attempt::NewtonFailed {
                    factor: 0.5,
                    iterations,
                };
            }
            // F(Z), transformed by T^-1.
            for (s, (z, r)) in self.z.iter().zip(&mut self.r).enumerate() {
                for ((st, xi), zi) in self.stage.iter_mut().zip(x).zip(z) {
                    *st = xi + zi;
                }
                let t_s = if s == 2 { t + h } else { t + nodes[s] * h };
                if let Err(nf) = eval(model, t_s, &self.stage, r, n_rhs) {
                    return Attempt::NonFinite(nf);
                }
            }
            let [r1, r2, r3] = &mut self.r;
            let [w1, w2, w3] = &self.w;
            let (r1, r2, r3) = (&mut r1[..n], &mut r2[..n], &mut r3[..n]);
            let (w1, w2, w3) = (&w1[..n], &w2[..n], &w3[..n]);
            let (fac1, alphn, betan) = (self.fac1, self.alphn, self.betan);
            for i in 0..n {
                let (a1, a2, a3) = (r1[i], r2[i], r3[i]);
                let (f1, f2, f3) = (
                    TI[0][0] * a1 + TI[0][1] * a2 + TI[0][2] * a3,
                    TI[1][0] * a1 + TI[1][1] * a2 + TI[1][2] * a3,
                    TI[2][0] * a1 + TI[2][1] * a2 + TI[2][2] * a3,
                );
                // Right-hand sides of the Newton step: Λ/h W - T^-1 F, negated.
                r1[i] = f1 - fac1 * w1[i];
                r2[i] = f2 - alphn * w2[i] + betan * w3[i];
                r3[i] = f3 - betan * w2[i] - alphn * w3[i];
            }
            self.e.solve_both(r1, r2, r3);
            iterations += 1;
            let dyno = self.correction_norm();
            if !dyno.is_finite() {
                return Attempt::NewtonFailed {
                    factor: 0.5,
                    iterations,
                };
            }
            if iterations > 1 && iterations < nit {
                let thq = dyno / dyno_old;
                theta = if iterations == 2 {
                    thq
                } else {
                    (thq * thq_old).sqrt()
                };
                thq_old = thq;
                if theta < 0.99 {
                    self.faccon = theta / (1.0 - theta);
                    self.faccon_h = h;
                    let remaining = (nit - 1 - iterations) as i32;
                    let predicted = self.faccon * dyno * theta.powi(remaining) / self.newton_tol;
                    if predicted >= 1.0 {
                        // Convergence within the limit is not expected: retry with the
                        // step the rate suggests.
                        let q = predicted.clamp(1e-4, 20.0);
                        let factor = 0.8 * q.powf(-1.0 / (4.0 + f64::from(remaining)));
                        return Attempt::NewtonFailed { factor, iterations };
                    }
                } else {
                    return Attempt::NewtonFailed {
                        factor: 0.5,
                        iterations,
                    };
                }
            }
            dyno_old = dyno.max(f64::EPSILON);
            let [w1, w2, w3] = &mut self.w;
            let [z1, z2, z3] = &mut self.z;
            let [r1, r2, r3] = &self.r;
            let (w1, w2, w3) = (&mut w1[..n], &mut w2[..n], &mut w3[..n]);
            let (z1, z2, z3) = (&mut z1[..n], &mut z2[..n], &mut z3[..n]);
            let (r1, r2, r3) = (&r1[..n], &r2[..n], &r3[..n]);
            for i in 0..n {
                let (a, b, c) = (w1[i] + r1[i], w2[i] + r2[i], w3[i] + r3[i]);
                w1[i] = a;
                w2[i] = b;
                w3[i] = c;
                z1[i] = T[0][0] * a + T[0][1] * b + T[0][2] * c;
                z2[i] = T[1][0] * a + T[1][1] * b + T[1][2] * c;
                z3[i] = T[2][0] * a + b;
            }
            // A first correction below the Newton tolerance ends the iteration whatever
            // the rate (and a rate from two rounding-level corrections means nothing).
            let rate_known = iterations > 1 || self.faccon_h == h;
            let negligible = iterations == 1 && dyno <= self.newton_tol;
            if negligible || rate_known && self.faccon * dyno <= self.newton_tol {
                break;
            }
        }
        for ((xn, xi), z3) in self.x_new.iter_mut().zip(x).zip(&self.z[2]) {
            *xn = xi + z3;
        }
        let err = self.error_estimate(model, start, n_rhs);
        // Fewer Newton iterations, bolder steps (RADAU5's `FAC`).
        let nit = nit as f64;
        let safety_iter = (1.0 + 2.0 * nit) / (iterations as f64 + 2.0 * nit);
        Attempt::Done {
            err,
            safety: self.safety * safety_iter.min(1.0),
            keep_jacobian: theta <= self.reuse_below,
        }
    }

    fn x_new(&self) -> &[f64] {
        &self.x_new
    }

    fn accept(&mut self, t: f64, h: f64, x: &mut [f64]) {
        let k = &self.k;
        // Reciprocals of the node differences: products vectorize, quotients cost more.
        let (c1m1, c2m1, c1mc2) = (1.0 / (k.c1 - 1.0), 1.0 / (k.c2 - 1.0), 1.0 / (k.c1 - k.c2));
        let (rc1, rc2) = (1.0 / k.c1, 1.0 / k.c2);
        let n = x.len();
        let [z1, z2, z3] = &self.z;
        let [d1, d2, d3] = &mut self.dense;
        let (z1, z2, z3) = (&z1[..n], &z2[..n], &z3[..n]);
        let (d1, d2, d3) = (&mut d1[..n], &mut d2[..n], &mut d3[..n]);
        for i in 0..n {
            // Divided differences of u(s) - x_new at s = 0, c2 - 1, c1 - 1, -1.
            d1[i] = (z2[i] - z3[i]) * c2m1;
            let ak = (z1[i] - z2[i]) * c1mc2;
            let acont3 = (ak - z1[i] * rc1) * rc2;
            d2[i] = (ak - d1[i]) * c1m1;
            d3[i] = d2[i] - acont3;
        }
        self.dense_t = t + h;
        self.dense_h = h;
        self.have_dense = true;
        x.copy_from_slice(&self.x_new);
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let k = &self.k;
        let (c1m1, c2m1) = (k.c1 - 1.0, k.c2 - 1.0);
        let s = (t - self.dense_t) / self.dense_h;
        let n = out.len();
        let [d1, d2, d3] = &self.dense;
        let (d1, d2, d3, x) = (&d1[..n], &d2[..n], &d3[..n], &self.x_new[..n]);
        for (i, o) in out.iter_mut().enumerate() {
            *o = x[i] + s * (d1[i] + (s - c2m1) * (d2[i] + (s - c1m1) * d3[i]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Band;

    /// The Radau IIA (order 5) Butcher matrix (HW II, Table IV.5.6).
    fn butcher() -> [[f64; 3]; 3] {
        let s = 6f64.sqrt();
        [
            [
                (88.0 - 7.0 * s) / 360.0,
                (296.0 - 169.0 * s) / 1800.0,
                (-2.0 + 3.0 * s) / 225.0,
            ],
            [
                (296.0 + 169.0 * s) / 1800.0,
                (88.0 + 7.0 * s) / 360.0,
                (-2.0 - 3.0 * s) / 225.0,
            ],
            [(16.0 - s) / 36.0, (16.0 + s) / 36.0, 1.0 / 9.0],
        ]
    }

    fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        c
    }

    #[test]
    fn transformation_block_diagonalizes_the_inverse_butcher_matrix() {
        let k = Constants::new();
        // T^-1 A^-1 T = Λ  <=>  A (T Λ) = T, checked without inverting A.
        let lambda = [
            [k.gamma, 0.0, 0.0],
            [0.0, k.alpha, -k.beta],
            [0.0, k.beta, k.alpha],
        ];
        let lhs = mul(&butcher(), &mul(&T, &lambda));
        let id = mul(&T, &TI);
        for i in 0..3 {
            for j in 0..3 {
                assert!((lhs[i][j] - T[i][j]).abs() < 1e-14, "A T Λ != T at {i},{j}");
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((id[i][j] - want).abs() < 1e-14, "T TI != I at {i},{j}");
            }
        }
        // The nodes are the row sums of A.
        let a = butcher();
        for (i, c) in [k.c1, k.c2, 1.0].iter().enumerate() {
            assert!((a[i].iter().sum::<f64>() - c).abs() < 1e-15);
        }
    }

    #[test]
    fn dense_output_interpolates_the_stage_values() {
        let n = 1;
        let mut m = Radau5::new(
            n,
            &Structure::banded(Band::dense(n)),
            &Radau5Options::default(),
        );
        // Stage increments of some smooth function.
        let (h, t) = (0.5, 2.0);
        let u = |s: f64| (1.3 * s).sin() + s * s;
        let k = m.k;
        m.z = [
            vec![u(k.c1) - u(0.0)],
            vec![u(k.c2) - u(0.0)],
            vec![u(1.0) - u(0.0)],
        ];
        m.x_new = vec![u(1.0)];
        let mut x = vec![u(0.0)];
        m.accept(t, h, &mut x);
        let mut out = [0.0];
        for theta in [0.0, k.c1, k.c2, 1.0] {
            m.interpolate(t + theta * h, &mut out);
            assert!((out[0] - u(theta)).abs() < 1e-14, "θ = {theta}");
        }
    }
}
