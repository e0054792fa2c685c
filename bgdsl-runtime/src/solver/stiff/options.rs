//! Settings of the stiff methods.

use std::time::Duration;

use super::super::options::{check, check_step_control, StepControl};
use crate::error::SolverError;

/// Settings of [`Solver::Radau5`](crate::Solver::Radau5), the three-stage Radau IIA
/// method of order 5 (Hairer & Wanner's RADAU5).
///
/// **What `rtol` and `atol` mean.** The end-point error is about `atol + rtol |x_i|` or
/// below, component by component: on the Bari test set's stiff problems (HIRES, POLLU,
/// VDPOL, OREGO, ROBER) 0.01–1 times it for `rtol` in 1e-4…1e-10, between scipy's Radau
/// (which over-delivers 20–1000-fold) and its BDF and SUNDIALS' CVODE (which miss it by
/// up to 30-fold); see `docs/tolerances.md` and `docs/work-precision.md`.
///
/// **Error control.** The embedded error estimate is of order 3 while the solution is of
/// order 5, so the tolerances are transformed before use: `rtol' = 0.3 rtol^(4/5)`,
/// `atol'_i = rtol' atol_i / rtol`, which makes the achieved error proportional to
/// `rtol`. A step is accepted when the error estimate, in the norm
/// `sqrt(mean((err_i / (atol'_i + rtol' |x_i|))^2))`, is below 1. (RADAU5's
/// transformation, `rtol' = 0.1 rtol^(2/3)`, used until issue 15, let the error shrink
/// only 5–7x per decade of `rtol` and missed the tolerance up to 135-fold on POLLU.)
///
/// **Newton iteration.** It stops when the predicted error of the iterate,
/// `θ / (1 - θ) ||ΔW||` in the transformed norm, is below `newton_tol`; a first iteration
/// may stop only if the contraction rate `θ` was measured with the same step size, or if
/// the correction is itself below `newton_tol`.
///
/// **Step size.** `h_new = h / clamp(err^(1/4) / fac, 1 / max_factor, 1 / min_factor)`
/// with `fac = min(safety, safety (1 + 2 nit) / (newt + 2 nit))` (fewer Newton iterations,
/// bolder steps), combined with the predictive controller of Gustafsson (HW II,
/// Sect. IV.8, eq. (8.25)) when `predictive`.
///
/// **Work reuse.** The Jacobian is kept for the next step while the simplified Newton
/// iteration contracts faster than `reuse_jacobian_below`; then, if the proposed step
/// changes by a factor within `[hold_step_min, hold_step_max]`, the step is not changed
/// at all and the LU factors are reused too. A rejected step or a failed Newton
/// iteration recomputes a Jacobian that is not current.
///
/// ```
/// use std::time::Duration;
/// use bgdsl_runtime::{Radau5Options, Solver};
/// let solver = Solver::Radau5(Radau5Options {
///     rtol: 1e-8,
///     max_wall_time: Some(Duration::from_secs(2)),
///     ..Radau5Options::default()
/// });
/// assert_eq!(solver.name(), "radau5");
/// assert!(solver.validate().is_ok());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radau5Options {
    /// Relative tolerance (in `(10 eps, 1)`; default `1e-6`).
    pub rtol: f64,
    /// Absolute tolerance (> 0; default `1e-9`).
    pub atol: f64,
    /// The first step size; `None` (the default) chooses it with the heuristic of
    /// Hairer, Nørsett & Wanner, *Solving ODEs I*, Sect. II.4, at the cost of one extra
    /// derivative evaluation.
    pub initial_step: Option<f64>,
    /// The largest step size (> 0; default infinite).
    pub max_step: f64,
    /// The step budget of one run, counting accepted and rejected steps (> 0; default
    /// 100,000 as in RADAU5).
    pub max_steps: usize,
    /// The longest a run may take, checked before every step attempt; `None` (the
    /// default) sets no limit.
    pub max_wall_time: Option<Duration>,
    /// Safety factor of the step-size controller (in (0, 1); default 0.9).
    pub safety: f64,
    /// The smallest factor by which one step may shrink the step size (in (0, 1];
    /// default 0.2).
    pub min_factor: f64,
    /// The largest factor by which one step may grow the step size (>= 1; default 8).
    pub max_factor: f64,
    /// Gustafsson's predictive step-size controller (default `true`); `false` gives the
    /// classical controller.
    pub predictive: bool,
    /// The most simplified Newton iterations per step (>= 1; default 7).
    pub max_newton_iterations: usize,
    /// Stopping tolerance of the Newton iteration in the (transformed) error norm;
    /// `None` (the default) takes RADAU5's `max(10 eps / rtol', min(0.03, sqrt(rtol')))`.
    pub newton_tol: Option<f64>,
    /// The Jacobian is kept for the next step when the Newton iteration's contraction
    /// rate was below this (in [0, 1); default 0.03; 0 recomputes it after every
    /// accepted step). RADAU5's default is 0.001, "for small systems"; Hairer & Wanner
    /// advise 0.1 when Jacobians are costly. Jacobians of mechanism models are (one of
    /// the 117-state quick return model costs about ten Newton iterations): 0.03 halves
    /// their number there, at the same accuracy, and costs small systems little.
    pub reuse_jacobian_below: f64,
    /// With the Jacobian kept, a proposed change of the step size by a factor in
    /// `[hold_step_min, hold_step_max]` is not made, so the LU factors are reused (in
    /// (0, 1]; default 1).
    pub hold_step_min: f64,
    /// See `hold_step_min` (>= 1; default 1.2).
    pub hold_step_max: f64,
}

impl Default for Radau5Options {
    fn default() -> Self {
        Radau5Options {
            rtol: 1e-6,
            atol: 1e-9,
            initial_step: None,
            max_step: f64::INFINITY,
            max_steps: 100_000,
            max_wall_time: None,
            safety: 0.9,
            min_factor: 0.2,
            max_factor: 8.0,
            predictive: true,
            max_newton_iterations: 7,
            newton_tol: None,
            reuse_jacobian_below: 0.03,
            hold_step_min: 1.0,
            hold_step_max: 1.2,
        }
    }
}

impl Radau5Options {
    pub(crate) fn validate(&self) -> Result<(), SolverError> {
        check(
            "rtol",
            self.rtol,
            self.rtol > 10.0 * f64::EPSILON && self.rtol < 1.0,
            "a number in (10 * f64::EPSILON, 1)",
        )?;
        self.common().validate()?;
        check(
            "max_newton_iterations",
            self.max_newton_iterations as f64,
            self.max_newton_iterations >= 1,
            "an integer >= 1",
        )?;
        if let Some(tol) = self.newton_tol {
            check(
                "newton_tol",
                tol,
                tol.is_finite() && tol > 0.0,
                "a finite number > 0",
            )?;
        }
        check(
            "reuse_jacobian_below",
            self.reuse_jacobian_below,
            (0.0..1.0).contains(&self.reuse_jacobian_below),
            "a number in [0, 1)",
        )?;
        check(
            "hold_step_min",
            self.hold_step_min,
            self.hold_step_min > 0.0 && self.hold_step_min <= 1.0,
            "a number in (0, 1]",
        )?;
        check(
            "hold_step_max",
            self.hold_step_max,
            self.hold_step_max.is_finite() && self.hold_step_max >= 1.0,
            "a finite number >= 1",
        )
    }

    pub(crate) fn common(&self) -> Common {
        Common {
            rtol: self.rtol,
            atol: self.atol,
            initial_step: self.initial_step,
            max_step: self.max_step,
            max_steps: self.max_steps,
            max_wall_time: self.max_wall_time,
            safety: self.safety,
            min_factor: self.min_factor,
            max_factor: self.max_factor,
            predictive: self.predictive,
            hold_step: (self.hold_step_min, self.hold_step_max),
        }
    }
}

/// Settings of [`Solver::Rodas4`](crate::Solver::Rodas4), the stiffly accurate
/// Rosenbrock method of order 4 with an embedded method of order 3 (Hairer & Wanner's
/// RODAS).
///
/// A step is accepted when its error estimate, in the norm
/// `sqrt(mean((err_i / (atol + rtol * max(|x_i|, |x_new_i|)))^2))`, is at most 1. The
/// step size follows `h_new = h / clamp(err^(1/4) / safety, 1 / max_factor,
/// 1 / min_factor)`, with Gustafsson's predictive controller when `predictive`. A
/// Rosenbrock method needs the exact Jacobian at the start of every step: it is
/// computed once per accepted step (and kept through rejections), with one LU per
/// attempted step.
///
/// ```
/// use bgdsl_runtime::{Rodas4Options, Solver};
/// let solver = Solver::Rodas4(Rodas4Options { rtol: 1e-5, ..Default::default() });
/// assert_eq!(solver.name(), "rodas4");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rodas4Options {
    /// Relative tolerance (>= 0, < 1; default `1e-6`).
    pub rtol: f64,
    /// Absolute tolerance (> 0; default `1e-9`).
    pub atol: f64,
    /// The first step size; `None` (the default) chooses it as for
    /// [`Radau5Options::initial_step`].
    pub initial_step: Option<f64>,
    /// The largest step size (> 0; default infinite).
    pub max_step: f64,
    /// The step budget of one run, counting accepted and rejected steps (> 0; default
    /// 100,000).
    pub max_steps: usize,
    /// The longest a run may take, checked before every step attempt; `None` (the
    /// default) sets no limit.
    pub max_wall_time: Option<Duration>,
    /// Safety factor of the step-size controller (in (0, 1); default 0.9).
    pub safety: f64,
    /// The smallest factor by which one step may shrink the step size (in (0, 1];
    /// default 0.2).
    pub min_factor: f64,
    /// The largest factor by which one step may grow the step size (>= 1; default 6, as
    /// in RODAS).
    pub max_factor: f64,
    /// Gustafsson's predictive step-size controller (default `true`).
    pub predictive: bool,
}

impl Default for Rodas4Options {
    fn default() -> Self {
        Rodas4Options {
            rtol: 1e-6,
            atol: 1e-9,
            initial_step: None,
            max_step: f64::INFINITY,
            max_steps: 100_000,
            max_wall_time: None,
            safety: 0.9,
            min_factor: 0.2,
            max_factor: 6.0,
            predictive: true,
        }
    }
}

impl Rodas4Options {
    pub(crate) fn validate(&self) -> Result<(), SolverError> {
        check(
            "rtol",
            self.rtol,
            (0.0..1.0).contains(&self.rtol),
            "a number in [0, 1)",
        )?;
        self.common().validate()
    }

    pub(crate) fn common(&self) -> Common {
        Common {
            rtol: self.rtol,
            atol: self.atol,
            initial_step: self.initial_step,
            max_step: self.max_step,
            max_steps: self.max_steps,
            max_wall_time: self.max_wall_time,
            safety: self.safety,
            min_factor: self.min_factor,
            max_factor: self.max_factor,
            predictive: self.predictive,
            // A Rosenbrock method refactors every step anyway.
            hold_step: (1.0, 1.0),
        }
    }
}

/// The settings the shared stepping loop reads.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Common {
    pub rtol: f64,
    pub atol: f64,
    pub initial_step: Option<f64>,
    pub max_step: f64,
    pub max_steps: usize,
    pub max_wall_time: Option<Duration>,
    pub safety: f64,
    pub min_factor: f64,
    pub max_factor: f64,
    pub predictive: bool,
    pub hold_step: (f64, f64),
}

impl Common {
    fn validate(&self) -> Result<(), SolverError> {
        check(
            "atol",
            self.atol,
            self.atol.is_finite() && self.atol > 0.0,
            "a finite number > 0 (the stiff methods scale their norms by atol + rtol |x|, \
             which must not vanish)",
        )?;
        check_step_control(StepControl {
            initial_step: self.initial_step,
            max_step: self.max_step,
            max_steps: self.max_steps,
            safety: self.safety,
            min_factor: self.min_factor,
            max_factor: self.max_factor,
        })
    }
}
