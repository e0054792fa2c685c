//! The public choice of integration method and its settings.
//!
//! [`Solver`] names the methods of the driver and needs `std`; the settings of the
//! explicit methods, [`FixedStep`] and [`DormandPrinceOptions`], also configure the
//! allocation-free integrators of [`crate::rk`], and exist without it.

#[cfg(feature = "std")]
use core::str::FromStr;

#[cfg(feature = "std")]
use super::stiff::{Radau5Options, Rodas4Options, Rodas5POptions};
use crate::error::SolverError;

/// An integration method and its settings.
///
/// ```
/// use bgdsl_runtime::{DormandPrinceOptions, Solver};
///
/// let fixed = Solver::rk4(1e-3);
/// let adaptive = Solver::DormandPrince(DormandPrinceOptions {
///     rtol: 1e-8,
///     atol: 1e-10,
///     ..DormandPrinceOptions::default()
/// });
/// let by_name: Solver = "dopri5".parse().unwrap();
/// assert_eq!(by_name, Solver::default());
/// assert_eq!(fixed.name(), "rk4");
/// assert_eq!(adaptive.name(), "dopri5");
/// // For stiff models (compliant joints, fast chemistry, electrical parasitics):
/// assert_eq!(Solver::stiff(), "radau5".parse().unwrap());
/// assert_eq!(Solver::from_name("rodas5p").unwrap().name(), "rodas5p");
/// ```
///
/// More methods may be added as further variants, hence `#[non_exhaustive]`.
#[cfg(feature = "std")]
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Solver {
    /// The classical fourth-order Runge–Kutta method with a fixed step. Every sample time
    /// is hit exactly: a step that would pass one is shortened to end on it.
    Rk4(FixedStep),
    /// Dormand–Prince 5(4) with adaptive step-size control (the method of Hairer's
    /// DOPRI5). Samples between steps come from its fourth-order continuous extension,
    /// so sample times do not shorten the steps.
    DormandPrince(DormandPrinceOptions),
    /// The fifth-order Dormand–Prince formula with a fixed step and no error control,
    /// sampled like [`Solver::Rk4`]. Meant for convergence studies and for comparing
    /// against a fixed grid.
    DormandPrinceFixed(FixedStep),
    /// The three-stage Radau IIA method of order 5 for stiff models, after Hairer &
    /// Wanner's RADAU5: implicit, L-stable and stiffly accurate, solved by simplified
    /// Newton iterations with the exact Jacobian (automatic differentiation, compressed
    /// by the model's sparsity pattern), which it reuses across steps while the
    /// iteration converges fast. Samples between steps come from its collocation
    /// polynomial (order 3). The recommended method for stiff models; see
    /// [`Solver::stiff`] for the measurements behind that.
    Radau5(Radau5Options),
    /// The Rosenbrock method Rodas4 for stiff models (Hairer & Wanner's RODAS): order 4,
    /// L-stable and stiffly accurate, linearly implicit (one Jacobian per step and one
    /// LU per attempt, no Newton iteration). Samples between steps come from its
    /// continuous extension (order 3). Kept for comparison and for models whose
    /// results were pinned with it: on stiff problems it loses order (its steps grow
    /// 2–2.8x per decade of `rtol` instead of 1.8x), and [`Solver::Rodas5P`] is
    /// faster at every tolerance measured (see `docs/solvers.md`).
    Rodas4(Rodas4Options),
    /// The Rosenbrock method Rodas5P of Steinebach (2023): order 5 with an embedded
    /// method of order 4, L-stable and stiffly accurate, designed against the order
    /// reduction that costs Rodas4 its steps on stiff problems; linearly implicit
    /// like Rodas4 (8 stages: one Jacobian per step, one LU per attempt, no Newton
    /// iteration). Samples between steps come from its continuous extension (order 4).
    /// See `docs/solvers.md` for where it beats Radau5.
    Rodas5P(Rodas5POptions),
}

#[cfg(feature = "std")]
impl Solver {
    /// The names [`Solver::from_name`] accepts, in the order of the variants.
    pub const NAMES: &'static [&'static str] = &[
        "rk4",
        "dopri5",
        "dopri5-fixed",
        "radau5",
        "rodas4",
        "rodas5p",
    ];

    /// Classical RK4 with step `step` and the default step budget.
    pub fn rk4(step: f64) -> Self {
        Solver::Rk4(FixedStep::new(step))
    }

    /// Adaptive Dormand–Prince 5(4) with the default options.
    pub fn dopri5() -> Self {
        Solver::DormandPrince(DormandPrinceOptions::default())
    }

    /// Radau IIA of order 5 with the default options: the recommended method for stiff
    /// models, and [`Model::default_solver`](crate::Model::default_solver)'s at every
    /// size. Measured against [`Solver::Rodas5P`], [`Solver::Rodas4`] and
    /// [`Solver::DormandPrince`] by CPU time at equal achieved error (`docs/solvers.md`):
    /// - Radau5 is the fastest at the default `rtol` on the flagship (117 states;
    ///   Rodas5P 2.2x), on the Bari problems (1.2–3.9x) and on long runs of chains of
    ///   1,000 and 10,000 states (1.8x), mostly because it reuses Jacobians and LU
    ///   factors across steps.
    /// - Rodas5P is ahead by 8–28 % on short transients of large models, and on small
    ///   models at loose tolerances (POLLU, HIRES, ROBER).
    pub fn stiff() -> Self {
        Solver::Radau5(Radau5Options::default())
    }

    /// The solver called `name` (one of [`Solver::NAMES`], ASCII case ignored) with its
    /// default settings; the fixed-step methods get [`FixedStep::DEFAULT_STEP`].
    pub fn from_name(name: &str) -> Result<Self, SolverError> {
        let lower = name.trim().to_ascii_lowercase();
        match lower.as_str() {
            "rk4" => Ok(Solver::Rk4(FixedStep::default())),
            "dopri5" => Ok(Solver::dopri5()),
            "dopri5-fixed" => Ok(Solver::DormandPrinceFixed(FixedStep::default())),
            "radau5" => Ok(Solver::Radau5(Radau5Options::default())),
            "rodas4" => Ok(Solver::Rodas4(Rodas4Options::default())),
            "rodas5p" => Ok(Solver::Rodas5P(Rodas5POptions::default())),
            _ => Err(SolverError::UnknownSolver {
                name: name.to_owned(),
                valid: Self::NAMES,
            }),
        }
    }

    /// The solver's name, as accepted by [`Solver::from_name`].
    pub fn name(&self) -> &'static str {
        match self {
            Solver::Rk4(_) => "rk4",
            Solver::DormandPrince(_) => "dopri5",
            Solver::DormandPrinceFixed(_) => "dopri5-fixed",
            Solver::Radau5(_) => "radau5",
            Solver::Rodas4(_) => "rodas4",
            Solver::Rodas5P(_) => "rodas5p",
        }
    }

    /// The step budget of one run: at most this many steps (accepted and rejected) are
    /// attempted.
    pub fn max_steps(&self) -> usize {
        match self {
            Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => o.max_steps,
            Solver::DormandPrince(o) => o.max_steps,
            Solver::Radau5(o) => o.max_steps,
            Solver::Rodas4(o) | Solver::Rodas5P(o) => o.max_steps,
        }
    }

    /// Checks every setting against its range; [`Simulation::new`](crate::Simulation::new)
    /// calls this.
    pub fn validate(&self) -> Result<(), SolverError> {
        match self {
            Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => o.validate(),
            Solver::DormandPrince(o) => o.validate(),
            Solver::Radau5(o) => o.validate(),
            Solver::Rodas4(o) | Solver::Rodas5P(o) => o.validate(),
        }
    }
}

#[cfg(feature = "std")]
impl Default for Solver {
    /// Adaptive Dormand–Prince 5(4) with the default options.
    fn default() -> Self {
        Solver::dopri5()
    }
}

#[cfg(feature = "std")]
impl FromStr for Solver {
    type Err = SolverError;

    /// Same as [`Solver::from_name`].
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Solver::from_name(s)
    }
}

/// Settings of a fixed-step method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedStep {
    /// The step size (> 0). Steps lie on the grid `t0 + k * step`; a step is shortened
    /// only to land on a sample time.
    pub step: f64,
    /// The step budget of one run (> 0).
    pub max_steps: usize,
}

impl FixedStep {
    /// The step [`Solver::from_name`] uses for the fixed-step methods.
    pub const DEFAULT_STEP: f64 = 1e-3;
    /// The default step budget.
    pub const DEFAULT_MAX_STEPS: usize = 1_000_000;

    /// Step `step` with the default step budget.
    pub fn new(step: f64) -> Self {
        FixedStep {
            step,
            max_steps: Self::DEFAULT_MAX_STEPS,
        }
    }

    /// Checks every setting against its range.
    pub(crate) fn validate(&self) -> Result<(), SolverError> {
        check(
            "step",
            self.step,
            self.step.is_finite() && self.step > 0.0,
            "a finite number > 0",
        )?;
        check_budget(self.max_steps)
    }
}

impl Default for FixedStep {
    fn default() -> Self {
        FixedStep::new(Self::DEFAULT_STEP)
    }
}

/// Settings of the adaptive Dormand–Prince 5(4) method.
///
/// A step is accepted when the error estimate, measured in the norm
/// `sqrt(mean((err_i / (atol + rtol * max(|x_i|, |x_new_i|)))^2))`, is at most 1. The
/// next step size follows the PI controller of Hairer's DOPRI5
/// (`h_new = h * safety * err^-(1/5 - 0.75 beta) * err_prev^beta`, clamped to
/// `[min_factor, max_factor] * h` and to `max_step`; after a rejection the step does
/// not grow).
///
/// ```
/// use bgdsl_runtime::DormandPrinceOptions;
/// let tight = DormandPrinceOptions { rtol: 1e-10, atol: 1e-12, ..Default::default() };
/// assert_eq!(tight.max_steps, 1_000_000);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DormandPrinceOptions {
    /// Relative tolerance (>= 0; default `1e-6`).
    pub rtol: f64,
    /// Absolute tolerance (>= 0, and `rtol + atol > 0`; default `1e-9`).
    pub atol: f64,
    /// The first step size; `None` (the default) chooses it with the heuristic of
    /// Hairer, Nørsett & Wanner, *Solving ODEs I*, Sect. II.4, at the cost of one extra
    /// derivative evaluation.
    pub initial_step: Option<f64>,
    /// The largest step size (> 0; default infinite). The step that lands on the last
    /// sample time may exceed it by up to 1 %.
    pub max_step: f64,
    /// The step budget of one run, counting accepted and rejected steps (> 0; default
    /// 1,000,000).
    pub max_steps: usize,
    /// Safety factor of the step-size controller (in (0, 1); default 0.9).
    pub safety: f64,
    /// The smallest factor by which one step may shrink the step size (in (0, 1];
    /// default 0.2).
    pub min_factor: f64,
    /// The largest factor by which one step may grow the step size (>= 1; default 10).
    pub max_factor: f64,
    /// The weight of the previous error in the PI controller (in [0, 0.2]; default
    /// 0.04, as in DOPRI5; 0 gives the standard I controller).
    pub beta: f64,
    /// Hairer's stiffness test (default `true`): after every accepted step the estimate
    /// `h |λ|` (from the two last stages, *Solving ODEs I*, Sect. II.10) is compared
    /// with 3.25, just inside the method's stability boundary; 15 such steps in a row
    /// (without six others in between), once `stiffness_after` steps are accepted,
    /// mean the step size is held by stability, not accuracy. If at that step size the
    /// run would use up its budget (`max_steps`) before its end, it fails with
    /// [`SolverError::StiffnessDetected`] instead of crawling through it; a run that
    /// can finish goes on (a mildly stiff model is cheaper to finish than to redo). The
    /// stiff steps are counted in [`Stats::n_stiff_steps`](crate::Stats). `false`
    /// turns the test off (and the count).
    pub detect_stiffness: bool,
    /// Accepted steps (since the start, or the last event) before the stiffness test
    /// may fail a run (default 1,000, DOPRI5's `NSTIFF`): a short run on a mildly
    /// stiff model is cheaper to finish than to redo with a stiff method.
    pub stiffness_after: usize,
}

impl Default for DormandPrinceOptions {
    fn default() -> Self {
        DormandPrinceOptions {
            rtol: 1e-6,
            atol: 1e-9,
            initial_step: None,
            max_step: f64::INFINITY,
            max_steps: 1_000_000,
            safety: 0.9,
            min_factor: 0.2,
            max_factor: 10.0,
            beta: 0.04,
            detect_stiffness: true,
            stiffness_after: 1000,
        }
    }
}

impl DormandPrinceOptions {
    /// Checks every setting against its range.
    pub(crate) fn validate(&self) -> Result<(), SolverError> {
        let non_negative = "a finite number >= 0";
        check(
            "rtol",
            self.rtol,
            self.rtol.is_finite() && self.rtol >= 0.0,
            non_negative,
        )?;
        check(
            "atol",
            self.atol,
            self.atol.is_finite() && self.atol >= 0.0,
            non_negative,
        )?;
        check(
            "atol",
            self.atol,
            self.rtol > 0.0 || self.atol > 0.0,
            "a number > 0 when rtol is 0",
        )?;
        check_step_control(StepControl {
            initial_step: self.initial_step,
            max_step: self.max_step,
            max_steps: self.max_steps,
            safety: self.safety,
            min_factor: self.min_factor,
            max_factor: self.max_factor,
        })?;
        check(
            "beta",
            self.beta,
            (0.0..=0.2).contains(&self.beta),
            "a number in [0, 0.2]",
        )
    }
}

/// Checks per-state absolute tolerances (one per name of `names`, in order) against
/// relative tolerance `rtol`: each finite and `>= 0`, and `> 0` where `rtol` is 0.
/// Shared by `Simulation::set_atol` and the allocation-free
/// [`DormandPrince::set_atol`](crate::rk::DormandPrince::set_atol).
pub(crate) fn check_atol(
    rtol: f64,
    atol: &[f64],
    names: &'static [&'static str],
) -> Result<(), SolverError> {
    for (i, &a) in atol.iter().enumerate() {
        let expected = if !(a.is_finite() && a >= 0.0) {
            "a finite number >= 0"
        } else if a == 0.0 && rtol == 0.0 {
            "a number > 0 (rtol is 0)"
        } else {
            continue;
        };
        return Err(SolverError::InvalidAtol {
            state: names.get(i).copied().unwrap_or("?"),
            value: a,
            expected,
        });
    }
    Ok(())
}

pub(super) fn check(
    option: &'static str,
    value: f64,
    ok: bool,
    expected: &'static str,
) -> Result<(), SolverError> {
    if ok {
        Ok(())
    } else {
        Err(SolverError::InvalidOptions {
            option,
            value,
            expected,
        })
    }
}

/// The step-size control settings every adaptive method shares.
pub(super) struct StepControl {
    pub(super) initial_step: Option<f64>,
    pub(super) max_step: f64,
    pub(super) max_steps: usize,
    pub(super) safety: f64,
    pub(super) min_factor: f64,
    pub(super) max_factor: f64,
}

/// Checks the settings every adaptive method shares.
pub(super) fn check_step_control(control: StepControl) -> Result<(), SolverError> {
    if let Some(h) = control.initial_step {
        check(
            "initial_step",
            h,
            h.is_finite() && h > 0.0,
            "a finite number > 0",
        )?;
    }
    check(
        "max_step",
        control.max_step,
        control.max_step > 0.0,
        "a number > 0 (infinity allowed)",
    )?;
    check_budget(control.max_steps)?;
    check(
        "safety",
        control.safety,
        control.safety > 0.0 && control.safety < 1.0,
        "a number in (0, 1)",
    )?;
    check(
        "min_factor",
        control.min_factor,
        control.min_factor > 0.0 && control.min_factor <= 1.0,
        "a number in (0, 1]",
    )?;
    check(
        "max_factor",
        control.max_factor,
        control.max_factor.is_finite() && control.max_factor >= 1.0,
        "a finite number >= 1",
    )
}

pub(super) fn check_budget(max_steps: usize) -> Result<(), SolverError> {
    check(
        "max_steps",
        max_steps as f64,
        max_steps > 0,
        "an integer > 0",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for name in Solver::NAMES {
            assert_eq!(Solver::from_name(name).unwrap().name(), *name);
        }
        assert_eq!(Solver::from_name(" RK4 ").unwrap(), Solver::rk4(1e-3));
    }

    #[test]
    fn unknown_name_lists_the_valid_ones() {
        let err = Solver::from_name("euler").unwrap_err();
        assert_eq!(
            err.to_string(),
            "unknown solver `euler`; the solvers are: rk4, dopri5, dopri5-fixed, radau5, rodas4, \
             rodas5p"
        );
    }

    #[test]
    fn out_of_range_options_are_rejected() {
        assert!(Solver::default().validate().is_ok());
        let bad = Solver::DormandPrince(DormandPrinceOptions {
            rtol: -1.0,
            ..Default::default()
        });
        assert!(matches!(
            bad.validate(),
            Err(SolverError::InvalidOptions { option: "rtol", .. })
        ));
        let zero = Solver::DormandPrince(DormandPrinceOptions {
            rtol: 0.0,
            atol: 0.0,
            ..Default::default()
        });
        assert!(zero.validate().is_err());
        assert!(Solver::rk4(0.0).validate().is_err());
        assert!(Solver::rk4(f64::NAN).validate().is_err());
        let no_budget = Solver::Rk4(FixedStep {
            step: 0.1,
            max_steps: 0,
        });
        assert!(matches!(
            no_budget.validate(),
            Err(SolverError::InvalidOptions {
                option: "max_steps",
                ..
            })
        ));
    }
}
