//! Implicit methods for stiff models: Radau IIA of order 5 ([`radau`]) and the
//! Rosenbrock method Rodas4 ([`rosenbrock`]), on one stepping loop ([`StiffIntegrator`]).
//!
//! The loop owns what the methods share: the Jacobian (exact, by
//! [`JacobianEvaluator`], or the model's own), `f(t, x)` at the current point, the
//! step-size controller (RADAU5's, with Gustafsson's predictive variant), the decisions
//! to recompute the Jacobian and to refactor, the limits (step budget, wall time, step
//! underflow, repeated singular matrices) and the statistics. A method
//! ([`ImplicitMethod`]) factors its iteration matrices for a step size, attempts one
//! step (returning an error estimate, or why it failed), and evaluates its continuous
//! extension.
//!
//! All memory is allocated by [`StiffIntegrator::new`]; stepping allocates nothing.

mod options;
mod radau;
mod rosenbrock;

use std::time::Instant;

use super::control::min_step;
pub(crate) use super::explicit::eval;
use super::explicit::{check_state, non_finite, NonFinite};
use super::stats::Stats;
use super::weights::{scaled, Tolerances};
use crate::error::SolverError;
use crate::jacobian::{Jacobian, JacobianEvaluator, SparsityPattern};
use crate::linalg::{Factored, Singular, Structure};
use crate::model::{Model, ModelError};

pub(crate) use options::Common;
pub use options::{Radau5Options, Rodas4Options};
pub(crate) use radau::Radau5;
pub(crate) use rosenbrock::{Rosenbrock, RODAS4};

/// The result of one step attempt.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Attempt {
    /// The step was computed; [`ImplicitMethod::x_new`] holds the proposed solution.
    Done {
        /// The error estimate in the method's norm (accept when at most 1).
        err: f64,
        /// The safety factor of the step-size controller for this step.
        safety: f64,
        /// Whether the Jacobian is good enough to be kept for the next step.
        keep_jacobian: bool,
    },
    /// The Newton iteration diverged or converged too slowly: retry with the step size
    /// multiplied by `factor`.
    NewtonFailed {
        /// The step-size factor for the retry (< 1).
        factor: f64,
        /// The iterations done.
        iterations: usize,
    },
    /// A stage produced a non-finite value: the step is too long, or left the model's
    /// domain.
    NonFinite(NonFinite),
}

/// What an attempt starts from.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepStart<'a> {
    /// The current time and state.
    pub t: f64,
    pub x: &'a [f64],
    /// The step size (the iteration matrices are factored for it).
    pub h: f64,
    /// `f(t, x)`.
    pub f0: &'a [f64],
    /// `∂f/∂t (t, x)` (only for methods with [`ImplicitMethod::NEEDS_DFDT`]).
    pub dfdt: &'a [f64],
    /// No step has been accepted yet in this run.
    pub first: bool,
    /// The previous attempt was rejected.
    pub after_reject: bool,
}

/// An implicit (or linearly implicit) one-step method with error estimate and
/// continuous extension.
pub(crate) trait ImplicitMethod {
    /// Whether [`StepStart::dfdt`] must be computed with the Jacobian.
    const NEEDS_DFDT: bool;
    /// The exponent `1 / (q + 1)` of the step-size controller for an error estimate of
    /// order `q`.
    const ERROR_EXPONENT: f64;

    /// Sets the tolerances the method's error norm (and Newton stopping test) is
    /// measured in: the user's, which the method may transform (Radau5 does).
    fn set_tolerances(&mut self, tol: &Tolerances);

    /// Forgets the previous steps: a new run starts.
    fn restart(&mut self);

    /// Factors the iteration matrices for step size `h` and Jacobian `jac`, which may
    /// differ from the last call's only if `new_jacobian` (its pattern may have changed
    /// only then too: see [`Jacobian::generation`]); counts the LU factorizations done
    /// in `count`.
    fn factor(
        &mut self,
        h: f64,
        jac: &Jacobian,
        new_jacobian: bool,
        count: &mut LuCount,
    ) -> Result<(), Singular>;

    /// Attempts one step, counting its evaluations of the model in `n_rhs`.
    fn attempt<M: Model>(&mut self, model: &M, start: &StepStart<'_>, n_rhs: &mut usize)
        -> Attempt;

    /// The solution proposed by the last attempt that returned [`Attempt::Done`].
    fn x_new(&self) -> &[f64];

    /// Accepts that step, from `t` with size `h`: stores its continuous extension and
    /// moves the proposed solution into `x`.
    fn accept(&mut self, t: f64, h: f64, x: &mut [f64]);

    /// Writes the continuous extension of the last accepted step at `t` (within it)
    /// into `out`.
    fn interpolate(&self, t: f64, out: &mut [f64]);
}

/// LU factorizations done, and how many of them fell back to partial pivoting.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LuCount {
    pub lu: usize,
    pub fallback: usize,
}

impl LuCount {
    /// Counts one factorization that produced `f`.
    pub fn add(&mut self, f: Factored) {
        self.lu += 1;
        if f == Factored::FellBack {
            self.fallback += 1;
        }
    }
}

/// Why the last attempt failed, for the error reported if the step size underflows.
#[derive(Clone, Debug)]
enum Failure {
    Newton { iterations: usize },
    NonFinite(NonFinite),
    Singular,
}

/// Consecutive singular iteration matrices after which a run gives up (as RADAU5).
const MAX_SINGULAR: usize = 5;

/// The stepping loop of the stiff methods: step-size control, Jacobian and LU reuse,
/// limits and statistics, around an [`ImplicitMethod`].
#[derive(Debug)]
pub(crate) struct StiffIntegrator<S> {
    method: S,
    settings: Common,
    /// The user's tolerances (the method keeps its own, possibly transformed, copy).
    tol: Tolerances,
    evaluator: JacobianEvaluator,
    /// The Jacobian.
    jac: Jacobian,
    /// `∂f/∂t` (empty unless the method needs it).
    dfdt: Vec<f64>,
    /// `f(t, x)` at the current point.
    f0: Vec<f64>,
    /// `f` at the proposed new point; scratch for the initial step and `∂f/∂t`.
    f_new: Vec<f64>,
    /// Scratch state.
    scratch: Vec<f64>,
    /// The next step size to try.
    h: f64,
    /// The step size the iteration matrices are factored for.
    factored_h: Option<f64>,
    /// The Jacobian was evaluated at the current point.
    jac_current: bool,
    /// The Jacobian, evaluated at an earlier point, is to be used for the next attempt.
    jac_keep: bool,
    /// The Jacobian changed since the last factorization.
    jac_new: bool,
    first: bool,
    last_rejected: bool,
    /// Step size and error of the last accepted step (Gustafsson's controller).
    h_acc: f64,
    err_acc: f64,
    singular_in_a_row: usize,
    failure: Option<Failure>,
    /// The model's own error ([`Model::evaluation_error`]) from an attempt of the
    /// current step that failed on it: the run's error if the step size underflows,
    /// whatever the later attempts failed on.
    model_failure: Option<ModelError>,
    started: Instant,
}

impl<S: ImplicitMethod> StiffIntegrator<S> {
    /// The loop for `model` around the method `make` builds for the structure of the
    /// model's iteration matrices (from its Jacobian's sparsity pattern), with all its
    /// memory.
    pub fn new<M: Model>(model: &M, make: impl FnOnce(&Structure) -> S, settings: Common) -> Self {
        let n = M::N_STATES;
        let evaluator = JacobianEvaluator::new(model);
        let structure = Structure::of_pattern(evaluator.pattern());
        StiffIntegrator {
            method: make(&structure),
            settings,
            tol: Tolerances::uniform(settings.rtol, settings.atol, n),
            evaluator,
            jac: Jacobian::new(SparsityPattern::dense(n).into()),
            dfdt: vec![0.0; if S::NEEDS_DFDT { n } else { 0 }],
            f0: vec![0.0; n],
            f_new: vec![0.0; n],
            scratch: vec![0.0; n],
            h: 0.0,
            factored_h: None,
            jac_current: false,
            jac_keep: false,
            jac_new: true,
            first: true,
            last_rejected: false,
            h_acc: 0.0,
            err_acc: 1.0,
            singular_in_a_row: 0,
            failure: None,
            model_failure: None,
            started: Instant::now(),
        }
    }

    /// Starts a run at `(t, x)` towards `t_end`: evaluates `f(t, x)` and chooses the
    /// first step size. Starts the wall clock.
    pub fn start<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        self.started = Instant::now();
        self.restart(model, t, x, t_end, stats)
    }

    /// Starts afresh at `(t, x)` within a run (after an event, whose action changed the
    /// state): forgets the Jacobian, the LU factors, the step-size controller's history
    /// and the method's start values from the previous step, evaluates `f(t, x)` and
    /// chooses a new first step size. The wall clock runs on.
    pub fn restart<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        self.method.restart();
        self.evaluator.restart();
        self.factored_h = None;
        self.jac_current = false;
        self.jac_keep = false;
        self.first = true;
        self.last_rejected = false;
        self.h_acc = 0.0;
        self.err_acc = 1.0;
        self.singular_in_a_row = 0;
        self.failure = None;
        self.model_failure = None;
        eval(model, t, x, &mut self.f0, &mut stats.n_rhs).map_err(non_finite::<M>)?;
        let h = match self.settings.initial_step {
            Some(h) => h,
            None => self
                .initial_step(model, t, x, &mut stats.n_rhs)
                .map_err(non_finite::<M>)?,
        };
        self.h = h.min(self.settings.max_step).min(t_end - t);
        Ok(())
    }

    /// Takes one accepted step from `(t, x)` (both updated), rejecting and retrying as
    /// needed. Fails when a limit is reached or the step size underflows.
    pub fn step<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64],
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        let s = self.settings;
        let (shrink_most, grow_most) = (1.0 / s.min_factor, 1.0 / s.max_factor);
        loop {
            let t0 = *t;
            if let Some(limit) = s.max_wall_time {
                let elapsed = self.started.elapsed();
                if elapsed > limit {
                    return Err(SolverError::WallTimeExceeded {
                        t: t0,
                        elapsed,
                        limit,
                    });
                }
            }
            if stats.steps() >= s.max_steps {
                return Err(SolverError::StepBudgetExhausted {
                    t: t0,
                    t_end,
                    steps: stats.steps(),
                });
            }
            // Stretch a step that would end within 1 % of the last sample time.
            let (t_new, h) = if t0 + 1.01 * self.h >= t_end {
                (t_end, t_end - t0)
            } else {
                (t0 + self.h, self.h)
            };
            if h.is_nan() || h < min_step(t0) {
                return Err(self.underflow_error::<M>(t0, h));
            }
            if !self.jac_current && !self.jac_keep {
                self.jacobian(model, t0, x, stats)?;
            }
            self.jac_keep = false;
            if self.factored_h != Some(h) {
                let mut count = LuCount::default();
                let new_jacobian = self.jac_new;
                self.jac_new = false;
                let factored = self.method.factor(h, &self.jac, new_jacobian, &mut count);
                stats.n_lu += count.lu;
                stats.n_lu_fallback += count.fallback;
                match factored {
                    Ok(()) => {
                        self.factored_h = Some(h);
                        self.singular_in_a_row = 0;
                    }
                    Err(Singular { .. }) => {
                        stats.rejected += 1;
                        self.factored_h = None;
                        self.singular_in_a_row += 1;
                        if self.singular_in_a_row >= MAX_SINGULAR {
                            return Err(SolverError::SingularMatrix { t: t0, h });
                        }
                        self.fail(Failure::Singular, h, 0.5);
                        continue;
                    }
                }
            }
            let start = StepStart {
                t: t0,
                x,
                h,
                f0: &self.f0,
                dfdt: &self.dfdt,
                first: self.first,
                after_reject: self.last_rejected,
            };
            let (err, safety, keep_jacobian) =
                match self.method.attempt(model, &start, &mut stats.n_rhs) {
                    Attempt::Done {
                        err,
                        safety,
                        keep_jacobian,
                    } => (err, safety, keep_jacobian),
                    Attempt::NewtonFailed { factor, iterations } => {
                        stats.rejected += 1;
                        self.fail(Failure::Newton { iterations }, h, factor);
                        continue;
                    }
                    Attempt::NonFinite(nf) => {
                        stats.rejected += 1;
                        self.fail(Failure::NonFinite(nf), h, 0.5);
                        continue;
                    }
                };
            let mut quot = if err.is_nan() {
                shrink_most
            } else {
                (err.powf(S::ERROR_EXPONENT) / safety).clamp(grow_most, shrink_most)
            };
            if err.is_nan() || err > 1.0 {
                // Error too large (or NaN): reject, shrink.
                stats.rejected += 1;
                self.failure = None;
                self.last_rejected = true;
                self.h = if self.first { 0.1 * h } else { h / quot };
                continue;
            }
            // The derivative at the new point, needed by the next step: a non-finite
            // value means the step left the model's domain.
            let x_new = self.method.x_new();
            let checked = check_state(x_new, t_new)
                .and_then(|()| eval(model, t_new, x_new, &mut self.f_new, &mut stats.n_rhs));
            if let Err(nf) = checked {
                stats.rejected += 1;
                self.fail(Failure::NonFinite(nf), h, 0.5);
                continue;
            }
            if s.predictive && !self.first {
                let gus = (self.h_acc / h) * (err * err / self.err_acc).powf(S::ERROR_EXPONENT)
                    / s.safety;
                quot = quot.max(gus.clamp(grow_most, shrink_most));
            }
            self.h_acc = h;
            self.err_acc = err.max(1e-2);
            self.method.accept(t0, h, x);
            *t = t_new;
            core::mem::swap(&mut self.f0, &mut self.f_new);
            stats.accepted += 1;
            self.failure = None;
            self.model_failure = None;
            self.first = false;
            self.jac_current = false;
            self.jac_keep = keep_jacobian;
            let mut h_next = (h / quot).min(s.max_step);
            if self.last_rejected {
                h_next = h_next.min(h);
            }
            self.last_rejected = false;
            // With the Jacobian kept, a small change of step size is not worth a new
            // factorization.
            let ratio = h_next / h;
            if keep_jacobian && ratio >= s.hold_step.0 && ratio <= s.hold_step.1 {
                h_next = h;
            }
            self.h = h_next;
            return Ok(());
        }
    }

    /// The continuous extension of the last accepted step at `t`.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        self.method.interpolate(t, out);
    }

    /// Records a failed attempt and shrinks the step.
    fn fail(&mut self, failure: Failure, h: f64, factor: f64) {
        if let Failure::NonFinite(NonFinite {
            cause: Some(cause), ..
        }) = &failure
        {
            self.model_failure = Some(cause.clone());
        }
        self.failure = Some(failure);
        self.last_rejected = true;
        self.h = h * factor;
    }

    /// The error for a step size that fell below the resolution of the time axis: the
    /// reason the last attempt failed, if it failed.
    fn underflow_error<M: Model>(&self, t: f64, h: f64) -> SolverError {
        if let Some(cause) = &self.model_failure {
            return SolverError::InvalidModel(cause.clone());
        }
        match self.failure.clone() {
            Some(Failure::Newton { iterations }) => {
                SolverError::NewtonDiverged { t, h, iterations }
            }
            Some(Failure::NonFinite(nf)) => non_finite::<M>(nf),
            Some(Failure::Singular) => SolverError::SingularMatrix { t, h },
            None => SolverError::StepSizeTooSmall { t, h },
        }
    }

    /// Evaluates the Jacobian (and `∂f/∂t` if the method needs it) at `(t, x)`.
    fn jacobian<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        let n = x.len();
        let derivatives = self
            .evaluator
            .evaluate_numerical(model, t, x, self.jac.values_mut());
        stats.n_jac_rhs += derivatives;
        stats.n_jac += 1;
        // The first non-finite entry, row by row. Differentiation writes only the
        // entries of a sparse pattern (the rest stay zero): only those are looked at.
        let pattern = self.evaluator.pattern();
        let jac = self.jac.values();
        let non_finite = if derivatives > 0 && !pattern.is_dense() {
            (0..n).find_map(|i| {
                let j = pattern
                    .row(i)
                    .iter()
                    .find(|&&j| !jac[i * n + j].is_finite())?;
                Some(i * n + j)
            })
        } else {
            jac.iter().position(|v| !v.is_finite())
        };
        if let Some(k) = non_finite {
            if let Some(cause) = model.evaluation_error() {
                return Err(SolverError::InvalidModel(cause));
            }
            let name = |i: usize| M::STATE_NAMES.get(i).copied().unwrap_or("?");
            return Err(SolverError::NonFiniteJacobian {
                t,
                state: name(k / n),
                wrt: name(k % n),
                value: jac[k],
            });
        }
        if S::NEEDS_DFDT {
            self.time_derivative(model, t, x, stats)?;
        }
        self.jac_current = true;
        self.jac_new = true;
        self.factored_h = None;
        Ok(())
    }

    /// `∂f/∂t` by a forward difference (a backward one if `f` is not finite ahead),
    /// with the increment of Hairer's RODAS, `sqrt(eps * max(1e-5, |t|))`.
    fn time_derivative<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        let delta = (f64::EPSILON * t.abs().max(1e-5)).sqrt();
        let mut result = Ok(());
        for dt in [delta, -delta] {
            // The increment as represented in floating point.
            let t1 = t + dt;
            let dt = t1 - t;
            result = eval(model, t1, x, &mut self.f_new, &mut stats.n_jac_rhs);
            if result.is_ok() {
                for ((d, f1), f0) in self.dfdt.iter_mut().zip(&self.f_new).zip(&self.f0) {
                    *d = (f1 - f0) / dt;
                }
                return Ok(());
            }
        }
        result.map_err(non_finite::<M>)
    }

    /// The starting step size of Hairer, Nørsett & Wanner, *Solving ODEs I*, Sect. II.4
    /// (steps (a)–(f)), for an error estimate of order `1 / ERROR_EXPONENT - 1`, in the
    /// norm with weights `atol + rtol |x_i|`. Costs one evaluation.
    fn initial_step<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        n_rhs: &mut usize,
    ) -> Result<f64, NonFinite> {
        let w = self.tol.weights();
        let count = x.len().max(1) as f64;
        let norm = |v: &dyn Fn(usize) -> f64| {
            let sum: f64 = (0..x.len())
                .map(|i| scaled(v(i), w.at(i, x[i])).powi(2))
                .sum();
            (sum / count).sqrt()
        };
        let f0 = &self.f0;
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
        let h0 = h0.min(self.settings.max_step);
        for i in 0..x.len() {
            self.scratch[i] = x[i] + h0 * f0[i];
        }
        let checked = eval(model, t + h0, &self.scratch, &mut self.f_new, n_rhs);
        if checked.is_err() {
            // An explicit Euler step left the domain: start small, as RADAU5 does.
            return Ok(1e-6f64.min(h0));
        }
        let (f0, f1) = (&self.f0, &self.f_new);
        let d2 = norm(&|i| f1[i] - f0[i]) / h0;
        let d12 = d1.max(d2);
        let h1 = if d12 <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d12).powf(S::ERROR_EXPONENT)
        };
        let h = (100.0 * h0).min(h1);
        Ok(if h.is_finite() && h > 0.0 { h } else { h0 })
    }
}

/// The stiff method of a [`Simulation`](crate::Simulation), with its loop.
#[derive(Debug)]
pub(crate) enum StiffKernel {
    Radau5(Box<StiffIntegrator<Radau5>>),
    Rosenbrock(Box<StiffIntegrator<Rosenbrock>>),
}

impl StiffKernel {
    pub fn start<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        match self {
            StiffKernel::Radau5(k) => k.start(model, t, x, t_end, stats),
            StiffKernel::Rosenbrock(k) => k.start(model, t, x, t_end, stats),
        }
    }

    pub fn restart<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        match self {
            StiffKernel::Radau5(k) => k.restart(model, t, x, t_end, stats),
            StiffKernel::Rosenbrock(k) => k.restart(model, t, x, t_end, stats),
        }
    }

    pub fn step<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64],
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        match self {
            StiffKernel::Radau5(k) => k.step(model, t, x, t_end, stats),
            StiffKernel::Rosenbrock(k) => k.step(model, t, x, t_end, stats),
        }
    }

    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        match self {
            StiffKernel::Radau5(k) => k.interpolate(t, out),
            StiffKernel::Rosenbrock(k) => k.interpolate(t, out),
        }
    }
}
