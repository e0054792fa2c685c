//! How the explicit methods choose their steps: fixed steps on a grid, and the adaptive
//! steps of Hairer's DOPRI5. The loops here take the kernel ([`super::explicit`]) from
//! one time to the next; the driver ([`super::driver`], with `std`) calls them between
//! its samples, the allocation-free integrators of [`crate::rk`] between a host's
//! calls. Neither allocates.

use super::explicit::{non_finite, ExplicitRk, NonFinite, Storage};
use super::options::{DormandPrinceOptions, FixedStep};
use super::stats::Stats;
use super::weights::{Atol, ErrorWeights};
use crate::error::SolverError;
use crate::math;
use crate::model::{Model, ModelError};

/// The smallest step size an adaptive method takes, s, at any time:
/// `sqrt(f64::MIN_POSITIVE)`, about 1.5e-154. Near `t = 0` the time axis resolves far
/// smaller steps, but there the iteration matrices of the implicit methods (which hold
/// `1/h`) and the squares in the error norms leave the floating-point range, and no
/// model has dynamics that fast: a step this small means the step-size control has
/// broken down (a tolerance too tight for the states' values, a singularity).
pub const MIN_STEP: f64 = 1.491_668_146_240_041_3e-154;

/// The smallest step at `t`: what the time axis resolves there, `16 eps |t|`, and at
/// least [`MIN_STEP`].
pub(crate) fn min_step(t: f64) -> f64 {
    (16.0 * f64::EPSILON * t.abs()).max(MIN_STEP)
}

/// Hairer's stiffness test (DOPRI5, *Solving ODEs I*, Sect. II.10): a step is "stiff"
/// when `h |λ|` exceeds this (the stability boundary of DOPRI5 on the negative real
/// axis is 3.3).
const STIFF_H_LAMBDA: f64 = 3.25;
/// Stiff steps in a row (no six non-stiff ones in between) that make the run fail.
pub(crate) const STIFF_STEPS: usize = 15;
/// Non-stiff steps in a row that forget the stiff ones.
const NON_STIFF_STEPS: usize = 6;

/// What an explicit integration works on: the model, the kernel with its workspace,
/// the current time and state, and the counters the work is added to.
pub(crate) struct Run<'a, M, S: Storage> {
    pub model: &'a M,
    pub kernel: &'a mut ExplicitRk<S>,
    pub t: &'a mut f64,
    pub x: &'a mut [f64],
    pub stats: &'a mut Stats,
    /// One absolute tolerance per state, overriding the options' `atol` (the driver's
    /// `Simulation::set_atol`); `None` for the options'.
    pub atol: Option<&'a [f64]>,
    /// The states that must stay `>= 0` (the driver's `Simulation::set_non_negative`).
    pub non_negative: &'a [usize],
}

/// The grid `t0 + k * h` of a fixed-step method, and its step budget.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Grid {
    t0: f64,
    h: f64,
    /// Index of the last grid point passed.
    k: u64,
    /// The end of the run (for the message when the budget runs out).
    t_end: f64,
    max_steps: usize,
}

impl Grid {
    /// Takes back the grid point a step ended on, when an event cut that step short:
    /// the next step ends on it again.
    pub fn step_back(&mut self) {
        self.k -= 1;
    }

    /// The grid of steps `o.step` from `t0`, for a run that ends at `t_end`. Fails if the
    /// step is too small to advance the time somewhere on `[t0, t_end]`, for the loop
    /// could not end.
    pub fn new(t0: f64, t_end: f64, o: &FixedStep) -> Result<Self, SolverError> {
        let h = o.step;
        if t_end > t0 && h < min_step(t0).max(min_step(t_end)) {
            return Err(SolverError::FixedStepTooSmall { t: t0, step: h });
        }
        Ok(Grid {
            t0,
            h,
            k: 0,
            t_end,
            max_steps: o.max_steps,
        })
    }
}

/// The adaptive method's step-size state: the PI controller and the next step size,
/// with the tolerances and the budget the steps are held to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Adaptive {
    control: Controller,
    /// The size of the next step to attempt.
    pub h: f64,
    rtol: f64,
    atol: f64,
    /// Steps (accepted and rejected, as counted in the run's [`Stats`]) allowed.
    max_steps: usize,
    /// Hairer's stiffness test is on; the stiff and non-stiff steps in a row.
    detect_stiffness: bool,
    stiff_in_a_row: usize,
    non_stiff_in_a_row: usize,
    /// Accepted steps since the start, and how many before the test may fail the run.
    accepted: usize,
    stiffness_after: usize,
}

impl<'a, M: Model, S: Storage> Run<'a, M, S> {
    /// The error weights of adaptive steps with tolerances `rtol` and (unless the run
    /// has its own per state) `atol`.
    fn weights(&self, rtol: f64, atol: f64) -> ErrorWeights<'a> {
        ErrorWeights {
            rtol,
            atol: match self.atol {
                Some(each) => Atol::Each(each),
                None => Atol::All(atol),
            },
        }
    }

    /// One fixed step on `grid` from the current time towards `ts` (which is later): a
    /// step that would pass `ts` is shortened to end on it, and a grid point within
    /// `1e-9` steps (or `8 ε |ts|`) of `ts` is taken to be `ts`. Returns whether it
    /// ended on a grid point (and moved the grid on past it). Fails at the first
    /// non-finite value, or when the budget of accepted steps runs out.
    pub fn fixed_step(&mut self, grid: &mut Grid, ts: f64) -> Result<bool, SolverError> {
        let h = grid.h;
        // A grid point this close to a sample time is the sample time.
        let merge = (1e-9 * h).max(8.0 * f64::EPSILON * ts.abs());
        if self.stats.accepted >= grid.max_steps {
            return Err(SolverError::StepBudgetExhausted {
                t: *self.t,
                t_end: grid.t_end,
                steps: self.stats.accepted,
            });
        }
        let on = grid.t0 + (grid.k + 1) as f64 * h;
        let (t_new, on_grid) = if on < ts - merge {
            (on, true)
        } else {
            (ts, on <= ts + merge)
        };
        let t = *self.t;
        let (kernel, stats) = (&mut *self.kernel, &mut *self.stats);
        kernel
            .prepare(self.model, t, self.x, &mut stats.n_rhs)
            .and_then(|()| kernel.attempt(self.model, t, t_new, self.x, &mut stats.n_rhs))
            .map_err(non_finite::<M>)?;
        kernel.accept(t, t_new, self.x, false);
        *self.t = t_new;
        stats.accepted += 1;
        if on_grid {
            grid.k += 1;
        }
        Ok(on_grid)
    }

    /// Evaluates `f(t, x)` at the current point unless the kernel holds it.
    pub fn prepare(&mut self) -> Result<(), SolverError> {
        self.kernel
            .prepare(self.model, *self.t, self.x, &mut self.stats.n_rhs)
            .map_err(non_finite::<M>)
    }

    /// Prepares adaptive steps from the current point with options `o` (checked by
    /// the caller): evaluates `f(t, x)` unless the kernel holds it, and chooses the
    /// first step size (`o.initial_step`, or the heuristic of
    /// [`ExplicitRk::initial_step`], which costs one evaluation).
    pub fn start_adaptive(&mut self, o: &DormandPrinceOptions) -> Result<Adaptive, SolverError> {
        self.prepare()?;
        let w = self.weights(o.rtol, o.atol);
        let (t, x) = (*self.t, &*self.x);
        let h = match o.initial_step {
            Some(h) => h.min(o.max_step),
            None => self
                .kernel
                .initial_step(self.model, t, x, &w, o.max_step, &mut self.stats.n_rhs)
                .map_err(non_finite::<M>)?
                // The heuristic knows nothing of |t|: far from t = 0 it can propose a
                // step the time axis does not resolve.
                .max(100.0 * min_step(t))
                .min(o.max_step),
        };
        Ok(Adaptive {
            control: Controller::new(o),
            h,
            rtol: o.rtol,
            atol: o.atol,
            max_steps: o.max_steps,
            detect_stiffness: o.detect_stiffness,
            stiff_in_a_row: 0,
            non_stiff_in_a_row: 0,
            accepted: 0,
            stiffness_after: o.stiffness_after,
        })
    }

    /// Takes one accepted adaptive step towards `t_end`, retrying with shorter steps
    /// as long as the error estimate is too large or the attempt meets a non-finite
    /// value. A step that would end within 1 % of `t_end` is stretched or shortened to
    /// end on it, so the step never passes `t_end`. The kernel keeps the dense-output
    /// coefficients of the step if `dense(t_new)` says so. Needs
    /// [`Run::start_adaptive`] (or an accepted step) first, with `f(t, x)` in the kernel.
    ///
    /// Fails when the step size falls below the resolution of the time axis (with the
    /// non-finite value that caused it, if one did) or when the run's budget of steps
    /// runs out.
    pub fn adaptive_step(
        &mut self,
        a: &mut Adaptive,
        t_end: f64,
        dense: impl FnOnce(f64) -> bool,
    ) -> Result<(), SolverError> {
        // The non-finite value that made the last attempt fail, if that is why it failed.
        let mut failure: Option<NonFinite> = None;
        // The model's own error from an attempt of this step that failed on it: the
        // run's error if the step size underflows, whatever later attempts failed on.
        let mut model_failure: Option<ModelError> = None;
        loop {
            let t = *self.t;
            // Stretch a step that would end within 1 % of the end.
            let (t_new, h_try) = if t + 1.01 * a.h >= t_end {
                (t_end, t_end - t)
            } else {
                (t + a.h, a.h)
            };
            if h_try.is_nan() || h_try < min_step(t) {
                return Err(match (model_failure, failure) {
                    (Some(cause), _) => SolverError::InvalidModel(cause),
                    (None, Some(nf)) => non_finite::<M>(nf),
                    (None, None) => SolverError::StepSizeTooSmall { t, h: h_try },
                });
            }
            if self.stats.steps() >= a.max_steps {
                return Err(SolverError::StepBudgetExhausted {
                    t,
                    t_end,
                    steps: self.stats.steps(),
                });
            }
            if let Err(nf) =
                self.kernel
                    .attempt(self.model, t, t_new, self.x, &mut self.stats.n_rhs)
            {
                // Probably a step out of the model's domain: retry a shorter one.
                self.stats.rejected += 1;
                if nf.cause.is_some() {
                    model_failure.clone_from(&nf.cause);
                }
                failure = Some(nf);
                a.h = a.control.after_failure(h_try);
                continue;
            }
            failure = None;
            let w = self.weights(a.rtol, a.atol);
            let err = self.kernel.error_norm(self.x, h_try, &w);
            if err <= 1.0 {
                let x_new = self.kernel.x_new();
                if let Some(factor) = negative_step(self.non_negative, self.x, x_new, &w) {
                    // A constrained state went below zero beyond its tolerance.
                    self.stats.rejected += 1;
                    a.control.last_rejected = true;
                    a.h = h_try * factor;
                    continue;
                }
                let h_lambda = if a.detect_stiffness {
                    self.kernel.stiffness_estimate(h_try)
                } else {
                    None
                };
                self.stats.accepted += 1;
                self.kernel.accept(t, t_new, self.x, dense(t_new));
                *self.t = t_new;
                a.h = a.control.after_accept(h_try, err);
                if project(self.non_negative, self.x) {
                    // The derivative at the projected state, for the next step.
                    self.kernel.restart();
                    self.prepare()?;
                }
                a.accepted += 1;
                if let Some(h_lambda) = h_lambda {
                    if h_lambda > STIFF_H_LAMBDA {
                        self.stats.n_stiff_steps += 1;
                        a.non_stiff_in_a_row = 0;
                        a.stiff_in_a_row += 1;
                        // Steps still needed at this step size, against those left.
                        let needed = (t_end - t_new) / h_try;
                        let left = a.max_steps.saturating_sub(self.stats.steps());
                        if a.stiff_in_a_row >= STIFF_STEPS
                            && a.accepted >= a.stiffness_after
                            && needed > left as f64
                        {
                            return Err(SolverError::StiffnessDetected {
                                t: t_new,
                                h: h_try,
                                h_lambda,
                                steps: a.stiff_in_a_row,
                                needed,
                                left,
                            });
                        }
                    } else {
                        a.non_stiff_in_a_row += 1;
                        if a.non_stiff_in_a_row >= NON_STIFF_STEPS {
                            a.stiff_in_a_row = 0;
                        }
                    }
                }
                return Ok(());
            }
            self.stats.rejected += 1;
            a.h = a.control.after_reject(h_try, err);
        }
    }
}

/// Whether the step from `x` to `x_new` takes a state of `non_negative` below zero by
/// more than its error weight (in `w`): then the factor (in `[0.1, 0.9]`) to shorten
/// the step by, 0.9 times the fraction of the step at which the first such state
/// crosses zero on the straight line from `x` to `x_new` (as SUNDIALS' CVODE does for
/// its constraints).
pub(crate) fn negative_step(
    non_negative: &[usize],
    x: &[f64],
    x_new: &[f64],
    w: &ErrorWeights<'_>,
) -> Option<f64> {
    let mut fraction: Option<f64> = None;
    for &i in non_negative {
        if x_new[i] < 0.0 && -x_new[i] > w.at(i, x[i]) {
            let crossing = (x[i].max(0.0) / (x[i].max(0.0) - x_new[i])).min(1.0);
            fraction = Some(fraction.map_or(crossing, |f: f64| f.min(crossing)));
        }
    }
    fraction.map(|f| (0.9 * f).clamp(0.1, 0.9))
}

/// Sets the states of `non_negative` that are below zero (within their tolerance, else
/// the step was rejected) to zero; returns whether any was.
pub(crate) fn project(non_negative: &[usize], x: &mut [f64]) -> bool {
    let mut changed = false;
    for &i in non_negative {
        if x[i] < 0.0 {
            x[i] = 0.0;
            changed = true;
        }
    }
    changed
}

/// The step-size controller of Hairer's DOPRI5 (HNW I, Sect. II.4 and IV.2): a PI
/// controller `h_new = h * safety * err^-alpha * err_prev^beta` with
/// `alpha = 1/5 - 0.75 beta`, clamped to `[min_factor, max_factor] * h` and
/// `max_step`, with no growth right after a rejection.
#[derive(Clone, Copy, Debug)]
struct Controller {
    alpha: f64,
    beta: f64,
    safety: f64,
    min_factor: f64,
    max_factor: f64,
    max_step: f64,
    /// The error of the last accepted step (at least 1e-4).
    err_prev: f64,
    pub last_rejected: bool,
}

impl Controller {
    fn new(o: &DormandPrinceOptions) -> Self {
        // The error estimate of DOPRI5 is O(h^5).
        let q1 = 5.0;
        Controller {
            alpha: 1.0 / q1 - 0.75 * o.beta,
            beta: o.beta,
            safety: o.safety,
            min_factor: o.min_factor,
            max_factor: o.max_factor,
            max_step: o.max_step,
            err_prev: 1e-4,
            last_rejected: false,
        }
    }

    fn after_accept(&mut self, h: f64, err: f64) -> f64 {
        let factor =
            self.safety * math::powf(err, -self.alpha) * math::powf(self.err_prev, self.beta);
        let mut factor = factor.clamp(self.min_factor, self.max_factor);
        if self.last_rejected {
            factor = factor.min(1.0);
        }
        self.err_prev = err.max(1e-4);
        self.last_rejected = false;
        (h * factor).min(self.max_step)
    }

    fn after_reject(&mut self, h: f64, err: f64) -> f64 {
        self.last_rejected = true;
        let factor = self.safety * math::powf(err, -self.alpha);
        h * factor.max(self.min_factor)
    }

    fn after_failure(&mut self, h: f64) -> f64 {
        self.last_rejected = true;
        h * self.min_factor
    }
}
