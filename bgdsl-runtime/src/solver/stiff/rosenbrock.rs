//! Rosenbrock (linearly implicit) methods as data, and the one kernel that runs them.
//!
//! In the form of Hairer & Wanner (*Solving ODEs II*, 2nd ed., Sect. IV.7, eq. (7.4')
//! with the variables `u_i = sum_j γ_ij k_j`, as in their code RODAS), a step of size
//! `h` from `(t, x)` solves, for `i = 1..s`,
//!
//! ```text
//! (1/(h γ) I - J) u_i = f(t + α_i h, x + sum_{j<i} a_ij u_j) + sum_{j<i} (c_ij / h) u_j
//!                       + γ_i h ∂f/∂t
//! x_new = x + sum_i m_i u_i,     error estimate  sum_i e_i u_i
//! ```
//!
//! with `J = ∂f/∂x (t, x)`: one LU of `1/(h γ) I - J` and `s` solves per step, no
//! Newton iteration. The continuous extension is
//! `u(θ) = (1 - θ) x + θ (x_new + (1 - θ) (sum d2_j u_j + θ sum d3_j u_j))`.

use super::{eval, Attempt, ImplicitMethod, LuCount, StepStart};
use crate::jacobian::Jacobian;
use crate::linalg::{RealMatrix, Singular, Structure};
use crate::model::Model;
use crate::solver::weights::{rms, scaled, Tolerances};

/// A Rosenbrock method with `s` stages in the `u` variables above.
#[derive(Debug)]
pub(crate) struct RosenbrockTableau {
    /// The diagonal `γ`.
    pub gamma: f64,
    /// Nodes `α_1..α_s`.
    pub alpha: &'static [f64],
    /// `γ_i = sum_j γ_ij` (weights of `∂f/∂t`).
    pub gamma_i: &'static [f64],
    /// Strictly lower `a_ij`: row `i` has `i` entries.
    pub a: &'static [&'static [f64]],
    /// Strictly lower `c_ij`: row `i` has `i` entries.
    pub c: &'static [&'static [f64]],
    /// Solution weights `m_i`.
    pub m: &'static [f64],
    /// Error weights `e_i = m_i - m̂_i`.
    pub e: &'static [f64],
    /// Dense-output weights `d2`, `d3`.
    pub dense: [&'static [f64]; 2],
}

const A51: f64 = 1.221_224_509_226_641;
const A52: f64 = 6.019_134_481_288_629;
const A53: f64 = 12.537_083_329_320_87;
const A54: f64 = -0.687_886_036_105_895;

/// Rodas4: the stiffly accurate, L-stable Rosenbrock method of order 4 (6 stages,
/// embedded order 3) of Hairer & Wanner, *Solving ODEs II*, 2nd ed., Sect. VI.4; the
/// coefficients are the published ones of their code RODAS (`METH = 1`), with its
/// order-3 dense output. Stiff accuracy shows in the data: stage 6 is evaluated at the
/// embedded solution `x + sum_{j<6} a_6j u_j`, `m = (a_6, 1)`, and the error estimate is
/// `u_6`.
pub(crate) const RODAS4: RosenbrockTableau = RosenbrockTableau {
    gamma: 0.25,
    alpha: &[0.0, 0.386, 0.21, 0.63, 1.0, 1.0],
    gamma_i: &[0.25, -0.1043, 0.1035, -0.362_000_000_000_002_3e-1, 0.0, 0.0],
    a: &[
        &[],
        &[1.544],
        &[0.946_678_528_081_582_6, 0.255_701_169_898_328_4],
        &[
            3.314_825_187_068_521,
            2.896_124_015_972_201,
            0.998_641_913_997_781_7,
        ],
        &[A51, A52, A53, A54],
        &[A51, A52, A53, A54, 1.0],
    ],
    c: &[
        &[],
        &[-5.6688],
        &[-2.430_093_356_833_875, -0.206_359_915_709_191_5],
        &[
            -0.107_352_905_815_137_5,
            -9.594_562_251_023_355,
            -20.470_286_148_096_16,
        ],
        &[
            7.496_443_313_967_647,
            -10.246_804_314_643_52,
            -33.999_903_528_199_05,
            11.708_908_932_061_6,
        ],
        &[
            8.083_246_795_921_522,
            -7.981_132_988_064_893,
            -31.521_594_328_743_71,
            16.319_305_431_231_36,
            -6.058_818_238_834_054,
        ],
    ],
    m: &[A51, A52, A53, A54, 1.0, 1.0],
    e: &[0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
    dense: [
        &[
            10.126_235_083_445_86,
            -7.487_995_877_610_167,
            -34.800_918_615_557_47,
            -7.992_771_707_568_823,
            1.025_137_723_295_662,
            0.0,
        ],
        &[
            -0.676_280_339_280_125_3,
            6.087_714_651_680_015,
            16.430_843_208_924_78,
            24.767_225_114_183_86,
            -6.594_389_125_716_872,
            0.0,
        ],
    ],
};

/// Workspace and state of the Rosenbrock kernel. Allocated by [`Rosenbrock::new`].
#[derive(Debug)]
pub(crate) struct Rosenbrock {
    tab: &'static RosenbrockTableau,
    tol: Tolerances,
    safety: f64,
    /// `1/(h γ) I - J`, factored.
    lu: RealMatrix,
    /// Stage values `u_1..u_s`.
    u: Vec<Vec<f64>>,
    /// Stage argument; stage right-hand side.
    stage: Vec<f64>,
    rhs: Vec<f64>,
    x_new: Vec<f64>,
    /// Continuous extension of the last accepted step: `x`, `x_new`, the two dense
    /// combinations.
    dense: [Vec<f64>; 4],
    dense_t: f64,
    dense_h: f64,
}

impl Rosenbrock {
    /// The kernel for `tab`, `n` states whose iteration matrices have `structure`, tolerances
    /// `rtol`, `atol` and the step-size controller's `safety` factor.
    pub fn new(
        tab: &'static RosenbrockTableau,
        n: usize,
        structure: &Structure,
        rtol: f64,
        atol: f64,
        safety: f64,
    ) -> Self {
        let v = || vec![0.0; n];
        Rosenbrock {
            tab,
            tol: Tolerances::uniform(rtol, atol, n),
            safety,
            lu: RealMatrix::new(structure),
            u: (0..tab.alpha.len()).map(|_| v()).collect(),
            stage: v(),
            rhs: v(),
            x_new: v(),
            dense: [v(), v(), v(), v()],
            dense_t: 0.0,
            dense_h: 1.0,
        }
    }
}

impl ImplicitMethod for Rosenbrock {
    const NEEDS_DFDT: bool = true;
    /// The embedded method has order 3: the estimate is `O(h^4)`.
    const ERROR_EXPONENT: f64 = 0.25;

    fn set_tolerances(&mut self, tol: &Tolerances) {
        self.tol.clone_from(tol);
    }

    fn restart(&mut self) {
        self.lu.restart();
    }

    fn factor(
        &mut self,
        h: f64,
        jac: &Jacobian,
        new_jacobian: bool,
        count: &mut LuCount,
    ) -> Result<(), Singular> {
        count.add(
            self.lu
                .factor(1.0 / (h * self.tab.gamma), jac, new_jacobian)?,
        );
        Ok(())
    }

    fn attempt<M: Model>(
        &mut self,
        model: &M,
        start: &StepStart<'_>,
        n_rhs: &mut usize,
    ) -> Attempt {
        let (t, h, x) = (start.t, start.h, start.x);
        let tab = self.tab;
        let n = x.len();
        for i in 0..tab.alpha.len() {
            let (done, rest) = self.u.split_at_mut(i);
            if i == 0 {
                self.rhs.copy_from_slice(start.f0);
            } else {
                self.stage.copy_from_slice(x);
                for (a, u) in tab.a[i].iter().zip(done.iter()) {
                    if *a != 0.0 {
                        for (s, uj) in self.stage.iter_mut().zip(u) {
                            *s += a * uj;
                        }
                    }
                }
                let t_i = if tab.alpha[i] == 1.0 {
                    t + h
                } else {
                    t + tab.alpha[i] * h
                };
                if let Err(nf) = eval(model, t_i, &self.stage, &mut self.rhs, n_rhs) {
                    return Attempt::NonFinite(nf);
                }
            }
            for (c, u) in tab.c[i].iter().zip(done.iter()) {
                let c = c / h;
                for (r, uj) in self.rhs.iter_mut().zip(u) {
                    *r += c * uj;
                }
            }
            let g = tab.gamma_i[i] * h;
            if g != 0.0 {
                for (r, d) in self.rhs.iter_mut().zip(start.dfdt) {
                    *r += g * d;
                }
            }
            self.lu.solve(&mut self.rhs);
            rest[0].copy_from_slice(&self.rhs);
        }
        self.x_new.copy_from_slice(x);
        for (m, u) in tab.m.iter().zip(&self.u) {
            for (xn, uj) in self.x_new.iter_mut().zip(u) {
                *xn += m * uj;
            }
        }
        let w = self.tol.weights();
        let u = &self.u;
        let x_new = &self.x_new;
        let err = rms(
            (0..n).map(|i| {
                let e: f64 = tab.e.iter().zip(u).map(|(w, uj)| w * uj[i]).sum();
                scaled(e, w.over(i, x[i], x_new[i]))
            }),
            n,
        );
        Attempt::Done {
            err,
            safety: self.safety,
            keep_jacobian: false,
        }
    }

    fn x_new(&self) -> &[f64] {
        &self.x_new
    }

    fn accept(&mut self, t: f64, h: f64, x: &mut [f64]) {
        let [x0, x1, d2, d3] = &mut self.dense;
        x0.copy_from_slice(x);
        x1.copy_from_slice(&self.x_new);
        for (out, w) in [d2, d3].into_iter().zip(self.tab.dense) {
            out.fill(0.0);
            for (wj, u) in w.iter().zip(&self.u) {
                if *wj != 0.0 {
                    for (o, uj) in out.iter_mut().zip(u) {
                        *o += wj * uj;
                    }
                }
            }
        }
        self.dense_t = t;
        self.dense_h = h;
        x.copy_from_slice(&self.x_new);
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let s = (t - self.dense_t) / self.dense_h;
        let s1 = 1.0 - s;
        let [x0, x1, d2, d3] = &self.dense;
        for (i, o) in out.iter_mut().enumerate() {
            *o = s1 * x0[i] + s * (x1[i] + s1 * (d2[i] + s * d3[i]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Band;

    /// One fixed step of `tab` for the scalar problem `y' = f(t, y)` with exact
    /// derivatives; returns the solution and the error estimate.
    fn step(
        tab: &RosenbrockTableau,
        f: impl Fn(f64, f64) -> f64,
        fy: f64,
        ft: f64,
        t: f64,
        y: f64,
        h: f64,
    ) -> (f64, f64) {
        let s = tab.alpha.len();
        let mut u = vec![0.0; s];
        let w = 1.0 / (h * tab.gamma) - fy;
        for i in 0..s {
            let arg = y + (0..i).map(|j| tab.a[i][j] * u[j]).sum::<f64>();
            let mut r = f(t + tab.alpha[i] * h, arg);
            r += (0..i).map(|j| tab.c[i][j] / h * u[j]).sum::<f64>();
            r += tab.gamma_i[i] * h * ft;
            u[i] = r / w;
        }
        let y1 = y + (0..s).map(|i| tab.m[i] * u[i]).sum::<f64>();
        let e = (0..s).map(|i| tab.e[i] * u[i]).sum::<f64>();
        (y1, e)
    }

    /// On `y' = λ y + cos t` (non-autonomous, so the `γ_i` weights matter) the local
    /// error of Rodas4 is `O(h^5)` (order 4) and its estimate `O(h^4)` (order 3).
    #[test]
    fn rodas4_has_order_4_and_an_order_3_estimate() {
        let lambda = -0.7;
        let f = |t: f64, y: f64| lambda * y + t.cos();
        // Exact solution through (0, 1).
        let c = 1.0 - lambda / (1.0 + lambda * lambda);
        let exact = |t: f64| {
            c * (lambda * t).exp() + (t.sin() - lambda * t.cos()) / (1.0 + lambda * lambda)
        };
        // From t = 0, where ∂f/∂t = -sin t vanishes, and from t = 0.8, where it does not.
        let local = |h: f64| {
            let (y1, e) = step(&RODAS4, f, lambda, 0.0, 0.0, exact(0.0), h);
            ((y1 - exact(h)).abs(), e.abs())
        };
        let t0 = 0.8f64;
        let local_at = |h: f64| {
            let (y1, e) = step(&RODAS4, f, lambda, -(t0.sin()), t0, exact(t0), h);
            ((y1 - exact(t0 + h)).abs(), e.abs())
        };
        for local in [&local as &dyn Fn(f64) -> (f64, f64), &local_at] {
            let (e1, est1) = local(0.02);
            let (e2, est2) = local(0.01);
            let order = (e1 / e2).log2();
            let order_est = (est1 / est2).log2();
            assert!(
                order > 4.7,
                "local error order {order} (errors {e1:e}, {e2:e})"
            );
            assert!(
                (3.8..4.2).contains(&order_est),
                "estimate order {order_est}"
            );
        }
    }

    /// Stiffly accurate and L-stable: on `y' = λ y` with `h λ -> -∞` the step
    /// annihilates the solution.
    #[test]
    fn rodas4_is_l_stable() {
        for z in [-1e6, -1e10] {
            let (y1, _) = step(&RODAS4, |_, y| z * y, z, 0.0, 0.0, 1.0, 1.0);
            assert!(y1.abs() < 1e-5, "R({z}) = {y1}");
        }
    }

    /// The continuous extension reproduces both ends of the step.
    #[test]
    fn dense_output_matches_the_step_ends() {
        let mut r = Rosenbrock::new(
            &RODAS4,
            1,
            &Structure::banded(Band::dense(1)),
            1e-6,
            1e-9,
            0.9,
        );
        r.u = (0..6).map(|i| vec![0.1 * i as f64 + 0.05]).collect();
        r.x_new = vec![2.5];
        let mut x = vec![1.5];
        r.accept(3.0, 0.5, &mut x);
        let mut out = [0.0];
        r.interpolate(3.0, &mut out);
        assert!((out[0] - 1.5).abs() < 1e-15);
        r.interpolate(3.5, &mut out);
        assert!((out[0] - 2.5).abs() < 1e-15);
    }
}
