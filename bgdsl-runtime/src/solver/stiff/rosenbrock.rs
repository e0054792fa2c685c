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
//! `u(θ) = (1 - θ) x + θ (x_new + (1 - θ) (D_1 + θ (D_2 + θ D_3 ...)))` with
//! `D_k = sum_j d_kj u_j` (two combinations for Rodas4, three for Rodas5P).

use core::marker::PhantomData;

use super::{eval, Attempt, ImplicitMethod, LuCount, RosenbrockOptions, StepStart};
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
    /// The order of the embedded method: the error estimate is `O(h^(order + 1))`.
    pub estimate_order: u32,
    /// Dense-output weights `d_k` (see the module's documentation).
    pub dense: &'static [&'static [f64]],
}

/// A Rosenbrock method as a type, so that the stepping loop's constants (the
/// controller's exponent) follow the tableau.
pub(crate) trait Scheme {
    /// The method's coefficients.
    const TABLEAU: &'static RosenbrockTableau;
}

/// [`RODAS4`] as a type.
#[derive(Debug)]
pub(crate) struct Rodas4;

impl Scheme for Rodas4 {
    const TABLEAU: &'static RosenbrockTableau = &RODAS4;
}

/// [`RODAS5P`] as a type.
#[derive(Debug)]
pub(crate) struct Rodas5P;

impl Scheme for Rodas5P {
    const TABLEAU: &'static RosenbrockTableau = &RODAS5P;
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
    estimate_order: 3,
    dense: &[
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

const P61: f64 = -7.502_846_399_306_121;
const P62: f64 = 2.561_846_144_803_919;
const P63: f64 = -11.627_539_656_261_098;
const P64: f64 = -0.182_687_676_599_422_56;
const P65: f64 = 0.030_198_172_008_377_946;

/// Rodas5P: the stiffly accurate, L-stable Rosenbrock method of order 5 (8 stages,
/// embedded order 4) of G. Steinebach, "Construction of Rosenbrock–Wanner method Rodas5P
/// and numerical benchmarks within the Julia Differential Equations package", *BIT
/// Numerical Mathematics* 63, 27 (2023), with its order-4 dense output. Built on the
/// structure of Di Marzo's Rodas5 (stages 6–8 at the end point, each evaluated at the
/// previous stage's solution), its coefficients are chosen to satisfy further
/// conditions against order reduction on stiff problems and index-1 DAEs
/// (Prothero–Robinson). The values are the published ones, as also used by Julia's
/// OrdinaryDiffEq (`Rodas5PTableau`), in the `u` variables of Hairer & Wanner (the
/// same convention as [`RODAS4`]): `m = (a_6, 1, 1, 1)`, and the error estimate is
/// `u_8`.
pub(crate) const RODAS5P: RosenbrockTableau = RosenbrockTableau {
    gamma: 0.211_937_563_194_290_14,
    alpha: &[
        0.0,
        0.635_812_689_582_870_4,
        0.409_579_839_339_753_5,
        0.976_930_672_506_071_6,
        0.428_840_360_955_866_4,
        1.0,
        1.0,
        1.0,
    ],
    gamma_i: &[
        0.211_937_563_194_290_14,
        -0.423_875_126_388_580_27,
        -0.338_462_712_623_592_4,
        1.804_645_287_288_273_4,
        2.325_825_639_765_069,
        0.0,
        0.0,
        0.0,
    ],
    a: &[
        &[],
        &[3.0],
        &[2.849_394_379_747_939, 0.458_422_422_044_639_23],
        &[
            -6.954_028_509_809_101,
            2.489_845_061_869_568,
            -10.358_996_098_473_584,
        ],
        &[
            2.802_998_627_562_896_4,
            0.507_246_473_622_820_6,
            -0.398_831_254_177_052_4,
            -0.047_211_872_304_046_41,
        ],
        &[P61, P62, P63, P64, P65],
        &[P61, P62, P63, P64, P65, 1.0],
        &[P61, P62, P63, P64, P65, 1.0, 1.0],
    ],
    c: &[
        &[],
        &[-14.155_112_264_123_755],
        &[-17.972_960_358_859_52, -2.859_693_295_451_294],
        &[
            147.121_502_757_117_16,
            -1.412_214_027_182_13,
            71.689_402_513_023_58,
        ],
        &[
            165.435_170_248_716_76,
            -0.459_282_345_649_112_6,
            42.909_383_369_586_03,
            -5.961_986_721_573_306,
        ],
        &[
            24.854_864_614_690_072,
            -3.000_922_700_283_218_6,
            47.493_111_002_076_8,
            5.581_419_782_155_812_5,
            -0.661_069_182_524_947_1,
        ],
        &[
            30.912_732_140_285_99,
            -3.120_824_334_993_797_4,
            77.799_546_460_708_92,
            34.286_460_282_947_83,
            -19.097_331_116_725_623,
            -28.087_943_162_872_662,
        ],
        &[
            37.802_771_233_905_63,
            -3.257_196_902_907_227_6,
            112.269_188_494_963_27,
            66.934_723_124_404_7,
            -40.066_189_370_910_02,
            -54.667_802_628_779_68,
            -9.488_616_523_096_27,
        ],
    ],
    m: &[P61, P62, P63, P64, P65, 1.0, 1.0, 1.0],
    e: &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
    estimate_order: 4,
    dense: &[
        &[
            25.948_786_856_663_858,
            -2.557_972_484_584_623_5,
            10.433_815_404_888_879,
            -2.367_925_102_268_520_4,
            0.524_948_541_321_073,
            1.124_108_831_045_040_4,
            0.427_287_619_443_187_4,
            -0.172_022_210_701_554_93,
        ],
        &[
            -9.915_688_506_951_71,
            -0.968_994_459_411_515_4,
            3.043_803_724_297_845_3,
            -24.495_224_566_215_796,
            20.176_138_334_709_044,
            15.980_663_614_246_51,
            -6.789_040_303_419_874,
            -6.710_236_069_923_372,
        ],
        &[
            11.419_903_575_922_262,
            2.887_964_514_613_699_4,
            72.921_379_959_960_29,
            80.125_118_346_226_43,
            -52.072_871_366_152_654,
            -59.789_936_252_667_29,
            -0.155_826_842_827_519_13,
            4.883_087_185_713_722,
        ],
    ],
};

/// Workspace and state of the Rosenbrock kernel. Allocated by [`Rosenbrock::new`].
#[derive(Debug)]
pub(crate) struct Rosenbrock<S> {
    tab: &'static RosenbrockTableau,
    scheme: PhantomData<S>,
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
    /// Continuous extension of the last accepted step: `x`, `x_new`, the dense
    /// combinations `D_k` (as many as the tableau has).
    dense: Vec<Vec<f64>>,
    dense_t: f64,
    dense_h: f64,
    /// Refine each stage's solve ([`RosenbrockOptions::refine_stages`]): the shift
    /// `1/(h γ)` factored, the stage's right-hand side and its residual (empty when
    /// not refining).
    refine: bool,
    shift: f64,
    b: Vec<f64>,
    residual: Vec<f64>,
}

impl<S: Scheme> Rosenbrock<S> {
    /// The kernel for `n` states whose iteration matrices have `structure`, with the
    /// tolerances, the controller's safety factor and the refinement of `options`.
    pub fn new(n: usize, structure: &Structure, options: &RosenbrockOptions) -> Self {
        let tab = S::TABLEAU;
        let (rtol, atol, safety) = (options.rtol, options.atol, options.safety);
        let refine = options.refine_stages;
        let v = || vec![0.0; n];
        let scratch = || vec![0.0; if refine { n } else { 0 }];
        Rosenbrock {
            tab,
            scheme: PhantomData,
            tol: Tolerances::uniform(rtol, atol, n),
            safety,
            lu: RealMatrix::new(structure),
            u: (0..tab.alpha.len()).map(|_| v()).collect(),
            stage: v(),
            rhs: v(),
            x_new: v(),
            dense: (0..2 + tab.dense.len()).map(|_| v()).collect(),
            dense_t: 0.0,
            dense_h: 1.0,
            refine,
            shift: 0.0,
            b: scratch(),
            residual: scratch(),
        }
    }
}

impl<S: Scheme> ImplicitMethod for Rosenbrock<S> {
    const NEEDS_DFDT: bool = true;
    /// `1 / (q + 1)` for an embedded method of order `q`.
    const ERROR_EXPONENT: f64 = 1.0 / (S::TABLEAU.estimate_order as f64 + 1.0);

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
        self.shift = 1.0 / (h * self.tab.gamma);
        count.add(self.lu.factor(self.shift, jac, new_jacobian)?);
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
            if self.refine {
                self.b.copy_from_slice(&self.rhs);
                self.lu.solve(&mut self.rhs);
                residual(
                    start.jac,
                    self.shift,
                    &self.b,
                    &self.rhs,
                    &mut self.residual,
                );
                self.lu.solve(&mut self.residual);
                for (u, d) in self.rhs.iter_mut().zip(&self.residual) {
                    *u += d;
                }
            } else {
                self.lu.solve(&mut self.rhs);
            }
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
        let (ends, combinations) = self.dense.split_at_mut(2);
        ends[0].copy_from_slice(x);
        ends[1].copy_from_slice(&self.x_new);
        for (out, w) in combinations.iter_mut().zip(self.tab.dense) {
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
        let (ends, combinations) = self.dense.split_at(2);
        let (x0, x1) = (&ends[0], &ends[1]);
        for (i, o) in out.iter_mut().enumerate() {
            let d = combinations
                .iter()
                .rev()
                .fold(0.0, |acc, dk| dk[i] + s * acc);
            *o = s1 * x0[i] + s * (x1[i] + s1 * d);
        }
    }
}

/// `r = b - (σ u - J u)`, each row summed in compensated arithmetic: products split
/// exactly by a fused multiply-add, sums by Knuth's TwoSum, the rounding errors
/// accumulated apart (Ogita, Rump & Oishi, "Accurate sum and dot product", SIAM J. Sci.
/// Comput. 26 (2005), algorithm Dot2): as accurate as if computed in twice the working
/// precision, then rounded.
fn residual(jac: &Jacobian, shift: f64, b: &[f64], u: &[f64], r: &mut [f64]) {
    for (i, ri) in r.iter_mut().enumerate() {
        let mut acc = Dot2::new(b[i]);
        acc.add_product(-shift, u[i]);
        let (cols, values) = jac.row(i);
        for (&j, &v) in cols.iter().zip(values) {
            acc.add_product(v, u[j]);
        }
        *ri = acc.value();
    }
}

/// A compensated sum of products (see [`residual`]).
struct Dot2 {
    sum: f64,
    error: f64,
}

impl Dot2 {
    fn new(start: f64) -> Self {
        Dot2 {
            sum: start,
            error: 0.0,
        }
    }

    /// Adds `a b`.
    fn add_product(&mut self, a: f64, b: f64) {
        let p = a * b;
        let p_error = a.mul_add(b, -p);
        let s = self.sum + p;
        let z = s - self.sum;
        let s_error = (self.sum - (s - z)) + (p - z);
        self.sum = s;
        self.error += p_error + s_error;
    }

    fn value(&self) -> f64 {
        self.sum + self.error
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

    /// The local error of `tab` on `y' = λ y + cos t` (non-autonomous, so the `γ_i`
    /// weights matter) from `t0` on the exact solution through `(0, 1)`, and its
    /// estimate.
    fn local_errors(tab: &RosenbrockTableau, t0: f64, h: f64) -> (f64, f64) {
        let lambda = -0.7;
        let f = |t: f64, y: f64| lambda * y + t.cos();
        let c = 1.0 - lambda / (1.0 + lambda * lambda);
        let exact = |t: f64| {
            c * (lambda * t).exp() + (t.sin() - lambda * t.cos()) / (1.0 + lambda * lambda)
        };
        let (y1, e) = step(tab, f, lambda, -t0.sin(), t0, exact(t0), h);
        ((y1 - exact(t0 + h)).abs(), e.abs())
    }

    /// The measured orders of the local error and of its estimate when `h` halves, from
    /// `t = 0` (where `∂f/∂t = -sin t` vanishes) and from `t = 0.8` (where it does not).
    fn local_orders(tab: &RosenbrockTableau, h: f64) -> [(f64, f64); 2] {
        [0.0, 0.8].map(|t0| {
            let (e1, est1) = local_errors(tab, t0, h);
            let (e2, est2) = local_errors(tab, t0, h / 2.0);
            ((e1 / e2).log2(), (est1 / est2).log2())
        })
    }

    /// The local error of Rodas4 is `O(h^5)` (order 4) and its estimate `O(h^4)`
    /// (order 3).
    #[test]
    fn rodas4_has_order_4_and_an_order_3_estimate() {
        for (order, order_est) in local_orders(&RODAS4, 0.02) {
            assert!(order > 4.7, "local error order {order}");
            assert!(
                (3.8..4.2).contains(&order_est),
                "estimate order {order_est}"
            );
        }
    }

    /// The local error of Rodas5P is `O(h^6)` (order 5) and its estimate `O(h^5)`
    /// (order 4). Larger steps than for Rodas4: at `h = 0.01` the local error is near
    /// rounding.
    #[test]
    fn rodas5p_has_order_5_and_an_order_4_estimate() {
        for (order, order_est) in local_orders(&RODAS5P, 0.1) {
            assert!((5.7..6.5).contains(&order), "local error order {order}");
            assert!(
                (4.7..5.3).contains(&order_est),
                "estimate order {order_est}"
            );
        }
    }

    /// The tableaus are consistent: stages at the end point are evaluated at the
    /// previous stage's solution (stiff accuracy), the solution weights are the last
    /// stage's, and the nodes are the row sums of `α = a γ_ij` for the first stage
    /// (`α_2 = a_21 γ`).
    #[test]
    fn tableaus_are_stiffly_accurate() {
        for tab in [&RODAS4, &RODAS5P] {
            let s = tab.alpha.len();
            assert_eq!(tab.a.len(), s);
            assert_eq!(tab.c.len(), s);
            assert_eq!(tab.m.len(), s);
            for (i, row) in tab.a.iter().enumerate() {
                assert_eq!(row.len(), i);
                assert_eq!(tab.c[i].len(), i);
            }
            assert_eq!(&tab.m[..s - 1], tab.a[s - 1]);
            assert_eq!(tab.m[s - 1], 1.0);
            assert!((tab.a[1][0] * tab.gamma - tab.alpha[1]).abs() < 1e-15);
            assert_eq!(tab.gamma_i[0], tab.gamma);
            for d in tab.dense {
                assert_eq!(d.len(), s);
            }
        }
    }

    /// Stiffly accurate and L-stable: on `y' = λ y` with `z = h λ -> -∞` the
    /// stability function vanishes like `1 / z` (Rodas5P's `R(z) ≈ -12.5 / z`).
    #[test]
    fn rodas4_and_rodas5p_are_l_stable() {
        for tab in [&RODAS4, &RODAS5P] {
            for z in [-1e6, -1e10] {
                let (y1, _) = step(tab, |_, y| z * y, z, 0.0, 0.0, 1.0, 1.0);
                assert!(y1.abs() < 20.0 / z.abs(), "R({z}) = {y1}");
            }
        }
    }

    /// The compensated sum of products is exact where plain summation loses
    /// everything: `1e16 + 1 - 1e16 = 1`, and `(1 + 2^-30)(1 - 2^-30) - 1 = -2^-60`,
    /// whose product rounds to 1 in `f64`.
    #[test]
    fn compensated_products_keep_what_rounding_drops() {
        let mut acc = Dot2::new(1e16);
        acc.add_product(1.0, 1.0);
        acc.add_product(-1e16, 1.0);
        assert_eq!(acc.value(), 1.0);
        let e = 2f64.powi(-30);
        assert_eq!((1.0 + e) * (1.0 - e), 1.0);
        let mut acc = Dot2::new(-1.0);
        acc.add_product(1.0 + e, 1.0 - e);
        assert_eq!(acc.value(), -2f64.powi(-60));
    }

    /// The continuous extension reproduces both ends of the step.
    #[test]
    fn dense_output_matches_the_step_ends() {
        let mut r = Rosenbrock::<Rodas4>::new(
            1,
            &Structure::banded(Band::dense(1)),
            &RosenbrockOptions::default(),
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
