//! The one explicit Runge–Kutta kernel: stages, embedded error estimate and continuous
//! extension, for any [`Tableau`]. It takes single steps; choosing their size is the
//! business of [`super::control`].
//!
//! The kernel is generic over where its vectors live ([`Storage`]): `Vec`s sized at run
//! time for the driver ([`Heap`], with `std`), or arrays sized at compile time for the
//! allocation-free integrators of [`crate::rk`] ([`Arrays`]). The arithmetic is the same
//! code either way.
//!
//! Continuous extension (dense output). For a FSAL tableau with dense weights `d`, the
//! step from `(t, x)` to `(t + h, x_new)` is interpolated, as in Hairer's DOPRI5, by
//!
//! ```text
//! u(t + theta h) = r1 + theta (r2 + (1 - theta) (r3 + theta (r4 + (1 - theta) r5)))
//! r1 = x,  r2 = x_new - x,  r3 = h k_1 - r2,  r4 = r2 - h k_s - r3,
//! r5 = h sum_j d_j k_j,
//! ```
//!
//! a quartic that matches `x`, `x_new` and the derivatives `k_1 = f(t, x)`,
//! `k_s = f(t + h, x_new)` at both ends.

use core::fmt::Debug;

use super::tableau::Tableau;
use super::weights::{scaled, ErrorWeights};
use crate::error::{NonFiniteKind, SolverError};
use crate::math;
use crate::model::{Model, ModelError};

/// A non-finite value met while stepping; [`non_finite`] turns it into
/// [`SolverError::NonFiniteState`], or into [`SolverError::InvalidModel`] when the
/// model said why its evaluation failed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NonFinite {
    pub t: f64,
    pub index: usize,
    pub value: f64,
    pub kind: NonFiniteKind,
    /// What the model said right after the evaluation that gave the value
    /// ([`Model::evaluation_error`]): an implicit solve that failed.
    pub cause: Option<ModelError>,
}

/// Where the kernel keeps its vectors.
pub(crate) trait Storage: Clone + Debug {
    /// A vector of the model's length.
    type Vector: AsRef<[f64]> + AsMut<[f64]> + Clone + Debug;
    /// The stage derivatives, one vector per stage.
    type Stages: AsRef<[Self::Vector]> + AsMut<[Self::Vector]> + Clone + Debug;
    /// A coefficient of the continuous extension: a vector of the model's length, or an
    /// empty one where the kernel keeps no dense output.
    type Dense: AsRef<[f64]> + AsMut<[f64]> + Clone + Debug;
}

/// Vectors on the heap, allocated once for the model's size: the driver's.
#[cfg(feature = "std")]
#[derive(Clone, Debug)]
pub(crate) struct Heap;

#[cfg(feature = "std")]
impl Storage for Heap {
    type Vector = Vec<f64>;
    type Stages = Vec<Vec<f64>>;
    type Dense = Vec<f64>;
}

/// Arrays for `N` states and `S` stages, with dense-output coefficients of `D`
/// numbers (`N` to keep the continuous extension, 0 to keep none): the storage of the
/// integrators of [`crate::rk`].
#[derive(Clone, Debug)]
pub(crate) struct Arrays<const N: usize, const S: usize, const D: usize>;

impl<const N: usize, const S: usize, const D: usize> Storage for Arrays<N, S, D> {
    type Vector = [f64; N];
    type Stages = [[f64; N]; S];
    type Dense = [f64; D];
}

/// Workspace and state of the explicit RK kernel, in storage `S`. All buffers are made
/// by the constructor; no method allocates.
#[derive(Clone, Debug)]
pub(crate) struct ExplicitRk<S: Storage> {
    tableau: &'static Tableau,
    /// Stage derivatives `k_1..k_s`.
    k: S::Stages,
    /// The argument of the stage being evaluated.
    stage: S::Vector,
    /// The solution proposed by the last attempted step.
    x_new: S::Vector,
    /// Whether `k[0]` holds `f(t, x)` for the current point.
    k1_valid: bool,
    /// Dense-output coefficients `r1..r5` (empty vectors if the tableau or the storage
    /// has none).
    dense: [S::Dense; 5],
    /// Start and length of the step the dense coefficients describe.
    dense_t: f64,
    dense_h: f64,
}

#[cfg(feature = "std")]
impl ExplicitRk<Heap> {
    /// A kernel for `tableau` and `n` states.
    pub fn new(tableau: &'static Tableau, n: usize) -> Self {
        let dense_len = if tableau.dense.is_some() { n } else { 0 };
        ExplicitRk {
            tableau,
            k: (0..tableau.stages()).map(|_| vec![0.0; n]).collect(),
            stage: vec![0.0; n],
            x_new: vec![0.0; n],
            k1_valid: false,
            dense: core::array::from_fn(|_| vec![0.0; dense_len]),
            dense_t: 0.0,
            dense_h: 0.0,
        }
    }
}

impl<const N: usize, const S: usize, const D: usize> ExplicitRk<Arrays<N, S, D>> {
    /// A kernel for `tableau`, which must have `S` stages, and `N` states, in arrays.
    /// With `D = N` it keeps the continuous extension of a tableau that has one; with
    /// `D = 0` none ([`ExplicitRk::accept`] must then be told `dense = false`).
    pub const fn in_arrays(tableau: &'static Tableau) -> Self {
        assert!(
            tableau.stages() == S,
            "the stage storage does not match the tableau"
        );
        assert!(
            D == 0 || D == N,
            "dense storage is for no state or every state"
        );
        ExplicitRk {
            tableau,
            k: [[0.0; N]; S],
            stage: [0.0; N],
            x_new: [0.0; N],
            k1_valid: false,
            dense: [[0.0; D]; 5],
            dense_t: 0.0,
            dense_h: 0.0,
        }
    }
}

impl<S: Storage> ExplicitRk<S> {
    /// Forgets the first stage: the next step starts from a point the kernel has not
    /// seen.
    pub fn restart(&mut self) {
        self.k1_valid = false;
    }

    /// Makes `k_1 = f(t, x)` available (evaluating it unless FSAL already did).
    pub fn prepare<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        n_rhs: &mut usize,
    ) -> Result<(), NonFinite> {
        if !self.k1_valid {
            eval(model, t, x, self.k.as_mut()[0].as_mut(), n_rhs)?;
            self.k1_valid = true;
        }
        Ok(())
    }

    /// Computes the stages of the step from `(t, x)` to `t_new` and the proposed
    /// solution [`ExplicitRk::x_new`]. Needs [`ExplicitRk::prepare`] first. Fails on the
    /// first non-finite stage derivative or a non-finite proposed state.
    pub fn attempt<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        t_new: f64,
        x: &[f64],
        n_rhs: &mut usize,
    ) -> Result<(), NonFinite> {
        debug_assert!(self.k1_valid, "prepare() must precede attempt()");
        let tab = self.tableau;
        let s = tab.stages();
        let h = t_new - t;
        let k = self.k.as_mut();
        for i in 1..s {
            let t_i = if tab.c[i] == 1.0 {
                t_new
            } else {
                t + tab.c[i] * h
            };
            let (done, rest) = k.split_at_mut(i);
            if tab.fsal && i == s - 1 {
                // The last row of A is b: the stage argument is the new solution.
                combine(self.x_new.as_mut(), x, h, tab.b, done);
                check_state(self.x_new.as_ref(), t_new)?;
                eval(model, t_i, self.x_new.as_ref(), rest[0].as_mut(), n_rhs)?;
            } else {
                combine(self.stage.as_mut(), x, h, tab.a[i], done);
                eval(model, t_i, self.stage.as_ref(), rest[0].as_mut(), n_rhs)?;
            }
        }
        if !tab.fsal {
            combine(self.x_new.as_mut(), x, h, tab.b, k);
            check_state(self.x_new.as_ref(), t_new)?;
        }
        Ok(())
    }

    /// The solution proposed by the last attempted step.
    pub fn x_new(&self) -> &[f64] {
        self.x_new.as_ref()
    }

    /// The embedded error estimate of the last attempted step of length `h`, in the norm
    /// `sqrt(mean((err_i / (atol_i + rtol * max(|x_i|, |x_new_i|)))^2))`; `0` for a
    /// method without an embedded formula.
    pub fn error_norm(&self, x: &[f64], h: f64, w: &ErrorWeights<'_>) -> f64 {
        let Some(est) = &self.tableau.error else {
            return 0.0;
        };
        let n = x.len();
        if n == 0 {
            return 0.0;
        }
        let (stages, x_new) = (self.k.as_ref(), self.x_new.as_ref());
        let mut sum = 0.0;
        for i in 0..n {
            let mut e = 0.0;
            for (w, k) in est.weights.iter().zip(stages) {
                if *w != 0.0 {
                    e += w * k.as_ref()[i];
                }
            }
            let r = scaled(h * e, w.over(i, x[i], x_new[i]));
            sum += r * r;
        }
        math::sqrt(sum / n as f64)
    }

    /// Accepts the last attempted step from `(t, x)` to `t_new`: stores the
    /// dense-output coefficients if `dense` (and the tableau has them), then moves the
    /// proposed solution into `x`.
    pub fn accept(&mut self, t: f64, t_new: f64, x: &mut [f64], dense: bool) {
        let tab = self.tableau;
        let s = tab.stages();
        if let (true, Some(d)) = (dense, tab.dense) {
            debug_assert_eq!(self.dense[0].as_ref().len(), x.len(), "no dense storage");
            let h = t_new - t;
            let (stages, x_new) = (self.k.as_ref(), self.x_new.as_ref());
            let (first, last) = (stages[0].as_ref(), stages[s - 1].as_ref());
            let [r1, r2, r3, r4, r5] = self.dense.each_mut().map(|r| r.as_mut());
            for i in 0..x.len() {
                let diff = x_new[i] - x[i];
                let bspl = h * first[i] - diff;
                r1[i] = x[i];
                r2[i] = diff;
                r3[i] = bspl;
                r4[i] = diff - h * last[i] - bspl;
                let mut sum = 0.0;
                for (dj, k) in d.iter().zip(stages) {
                    if *dj != 0.0 {
                        sum += dj * k.as_ref()[i];
                    }
                }
                r5[i] = h * sum;
            }
            self.dense_t = t;
            self.dense_h = h;
        }
        x.copy_from_slice(self.x_new.as_ref());
        if tab.fsal {
            self.k.as_mut().swap(0, s - 1);
            self.k1_valid = true;
        } else {
            self.k1_valid = false;
        }
    }

    /// Writes the continuous extension of the last step accepted with `dense = true` at
    /// time `t` (within that step) into `out`.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        let theta = (t - self.dense_t) / self.dense_h;
        let theta1 = 1.0 - theta;
        let [r1, r2, r3, r4, r5] = self.dense.each_ref().map(|r| r.as_ref());
        for (i, o) in out.iter_mut().enumerate() {
            *o = r1[i] + theta * (r2[i] + theta1 * (r3[i] + theta * (r4[i] + theta1 * r5[i])));
        }
    }

    /// The starting step size of Hairer, Nørsett & Wanner, *Solving ODEs I*, Sect. II.4
    /// ("Starting step size", steps (a)–(f)), in the error norm of
    /// [`ExplicitRk::error_norm`], for a method whose error estimate is
    /// `O(h^(q + 1))`. Needs [`ExplicitRk::prepare`] first; costs one evaluation.
    pub fn initial_step<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        w: &ErrorWeights<'_>,
        max_step: f64,
        n_rhs: &mut usize,
    ) -> Result<f64, NonFinite> {
        let q = self
            .tableau
            .error
            .as_ref()
            .map_or(self.tableau.order, |e| e.order);
        let n = x.len().max(1) as f64;
        let norm = |v: &dyn Fn(usize) -> f64| {
            let sum: f64 = (0..x.len())
                .map(|i| math::powi(scaled(v(i), w.at(i, x[i])), 2))
                .sum();
            math::sqrt(sum / n)
        };
        let f0 = self.k.as_ref()[0].as_ref();
        let d0 = norm(&|i| x[i]);
        let d1 = norm(&|i| f0[i]);
        let mut h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        if !(h0.is_finite() && h0 > 0.0) {
            h0 = 1e-6;
        }
        let h0 = h0.min(max_step);
        // One explicit Euler step, into the scratch stage buffers.
        let stage = self.stage.as_mut();
        for i in 0..x.len() {
            stage[i] = x[i] + h0 * f0[i];
        }
        let (first, rest) = self.k.as_mut().split_at_mut(1);
        eval(model, t + h0, stage, rest[0].as_mut(), n_rhs)?;
        let (f0, f1) = (first[0].as_ref(), rest[0].as_ref());
        let d2 = norm(&|i| f1[i] - f0[i]) / h0;
        let d12 = d1.max(d2);
        let h1 = if d12 <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            math::powf(0.01 / d12, 1.0 / f64::from(q + 1))
        };
        let h = (100.0 * h0).min(h1).min(max_step);
        // A zero scale (atol = 0 at a zero state) can make the estimate degenerate.
        Ok(if h.is_finite() && h > 0.0 { h } else { h0 })
    }
}

/// `out = x + h * sum_j w_j k_j`, skipping zero weights.
fn combine<V: AsRef<[f64]>>(out: &mut [f64], x: &[f64], h: f64, w: &[f64], k: &[V]) {
    out.copy_from_slice(x);
    for (wj, kj) in w.iter().zip(k) {
        if *wj != 0.0 {
            let c = h * wj;
            for (o, kv) in out.iter_mut().zip(kj.as_ref()) {
                *o += c * kv;
            }
        }
    }
}

/// Evaluates `out = f(t, x)`, counting it, and checks it is finite (asking the model
/// why if it is not).
pub(crate) fn eval<M: Model>(
    model: &M,
    t: f64,
    x: &[f64],
    out: &mut [f64],
    n_rhs: &mut usize,
) -> Result<(), NonFinite> {
    model.derivatives::<f64>(t, x, out);
    *n_rhs += 1;
    match out.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(NonFinite {
            t,
            index,
            value: out[index],
            kind: NonFiniteKind::Derivative,
            cause: model.evaluation_error(),
        }),
    }
}

/// Checks that a state is finite.
pub(crate) fn check_state(x: &[f64], t: f64) -> Result<(), NonFinite> {
    match x.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(NonFinite {
            t,
            index,
            value: x[index],
            kind: NonFiniteKind::State,
            cause: None,
        }),
    }
}

/// Names the state of a kernel's non-finite value, or gives the model's own error when
/// it said why its evaluation failed.
pub(crate) fn non_finite<M: Model>(nf: NonFinite) -> SolverError {
    if let Some(cause) = nf.cause {
        return SolverError::InvalidModel(cause);
    }
    SolverError::NonFiniteState {
        t: nf.t,
        state: M::STATE_NAMES.get(nf.index).copied().unwrap_or("?"),
        value: nf.value,
        kind: nf.kind,
    }
}
