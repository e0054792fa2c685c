//! What can go wrong while setting up a simulation, integrating it, or writing its
//! results: errors as data, each rendered by [`Display`](core::fmt::Display) as one
//! sentence that says when and why.

use core::fmt;
use core::time::Duration;
#[cfg(feature = "std")]
use std::{io, path::PathBuf};

/// Why a simulation could not be set up or could not reach its last sample time.
///
/// Every variant carries the numbers needed to act on it (the time, the step size, the
/// state's name as in [`Model::STATE_NAMES`](crate::Model::STATE_NAMES)); the
/// [`Display`](core::fmt::Display) implementation turns them into a sentence.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SolverError {
    /// A state, or the derivative of a state, became NaN or infinite.
    ///
    /// A fixed-step method reports this at once. The adaptive method first retries with
    /// smaller steps (a step that leaves the model's domain is merely too long) and
    /// reports it when the step size can shrink no further.
    NonFiniteState {
        /// The time at which the non-finite value was produced (for a derivative: the
        /// time of the stage that evaluated it).
        t: f64,
        /// The state's name, from [`Model::STATE_NAMES`](crate::Model::STATE_NAMES).
        state: &'static str,
        /// The offending value (NaN, `inf` or `-inf`).
        value: f64,
        /// Whether the state itself or its derivative was non-finite.
        kind: NonFiniteKind,
    },
    /// Dormand–Prince's adaptive step size fell below the resolution of the time axis,
    /// `16 * f64::EPSILON * |t|` (and at least [`MIN_STEP`](crate::solver::MIN_STEP)).
    /// Only the explicit adaptive method fails this way: the implicit ones report
    /// [`SolverError::StepUnderflow`] (naming the state and its tolerance), the
    /// fixed-step ones [`SolverError::FixedStepTooSmall`].
    StepSizeTooSmall {
        /// The time reached.
        t: f64,
        /// The step size that was too small.
        h: f64,
    },
    /// A fixed step (of [`Solver::Rk4`](crate::Solver::Rk4),
    /// [`Solver::DormandPrinceFixed`](crate::Solver::DormandPrinceFixed) or
    /// [`rk::Rk4`](crate::rk::Rk4)) is below the resolution of the time axis where the
    /// run starts or ends (`16 * f64::EPSILON * |t|`, at least
    /// [`MIN_STEP`](crate::solver::MIN_STEP)): the steps would not advance the time.
    FixedStepTooSmall {
        /// Where the run (or the step) starts.
        t: f64,
        /// The step asked for.
        step: f64,
    },
    /// The step budget (`max_steps`, counting accepted and rejected steps) ran out
    /// before the last sample time.
    StepBudgetExhausted {
        /// The time reached.
        t: f64,
        /// The last sample time, which was not reached.
        t_end: f64,
        /// The number of steps attempted (the budget).
        steps: usize,
    },
    /// The start time is NaN or infinite.
    NonFiniteStartTime {
        /// The start time given.
        t0: f64,
    },
    /// A sample time is not finite, lies before the start time, or is smaller than the
    /// sample time before it.
    InvalidSampleTimes {
        /// Position of the offending sample time in the list.
        index: usize,
        /// The offending sample time.
        t: f64,
        /// What is wrong with it.
        problem: SampleTimeProblem,
    },
    /// The run was asked for no sample time at all, so it would record nothing.
    NoSampleTimes,
    /// A fixed-step explicit method failed (non-finite values, a vanishing step) on a
    /// model that is stiff for its step: at the start, `step × spectral_radius` lies
    /// beyond the method's stability limit, so the integration blows up. A stiff
    /// solver (radau5, rodas4) suits the model; an explicit one needs a step below
    /// `stable_step`.
    #[cfg(feature = "std")]
    ProbablyStiff {
        /// The failure itself.
        cause: Box<SolverError>,
        /// The method's name.
        method: &'static str,
        /// The step it took, s.
        step: f64,
        /// The estimated magnitude of the largest eigenvalue of the model's Jacobian at
        /// the start, 1/s ([`stiffness::spectral_radius`](crate::solver::stiffness::spectral_radius)).
        spectral_radius: f64,
        /// The largest step at which the method is stable on that eigenvalue, s.
        stable_step: f64,
    },
    /// The initial state does not have one value per state of the model.
    StateLengthMismatch {
        /// The model's name.
        model: &'static str,
        /// The number of states of the model.
        expected: usize,
        /// The length of the initial state given.
        found: usize,
    },
    /// A solver option is out of its range.
    InvalidOptions {
        /// The option's name as a field of the options struct, e.g. `"rtol"`.
        option: &'static str,
        /// The value given.
        value: f64,
        /// The range the value must lie in, as a phrase: `"a finite number > 0"`.
        expected: &'static str,
    },
    /// A solver was asked for by a name that no solver has.
    #[cfg(feature = "std")]
    UnknownSolver {
        /// The name given.
        name: String,
        /// The names that exist.
        valid: &'static [&'static str],
    },
    /// The Newton iteration of an implicit method kept failing (diverging, or
    /// converging too slowly to finish within its iteration limit), each failure
    /// halving the step or more, until the step size fell below the resolution of the
    /// time axis.
    NewtonDiverged {
        /// The time reached.
        t: f64,
        /// The step size of the last attempt.
        h: f64,
        /// The Newton iterations of the last attempt.
        iterations: usize,
    },
    /// The iteration matrix of an implicit method (a multiple of the identity minus the
    /// Jacobian) was singular to working precision for five step sizes in a row, or
    /// still singular when the step size could shrink no further.
    SingularMatrix {
        /// The time reached.
        t: f64,
        /// The step size of the last attempt.
        h: f64,
    },
    /// An entry of the Jacobian ∂(dx/dt)/∂x was NaN or infinite.
    NonFiniteJacobian {
        /// The time at which the Jacobian was evaluated.
        t: f64,
        /// The state whose derivative was differentiated (the row).
        state: &'static str,
        /// The state it was differentiated with respect to (the column).
        wrt: &'static str,
        /// The offending value.
        value: f64,
    },
    /// An entry of the model's hand-written Jacobian
    /// ([`Model::jacobian`](crate::Model::jacobian)) was NaN or infinite (the
    /// derivatives themselves were finite).
    NonFiniteHandWrittenJacobian {
        /// The time at which the Jacobian was evaluated.
        t: f64,
        /// The state whose rate was differentiated (the row `i` of `∂ẋ_i/∂x_j`).
        state: &'static str,
        /// The state it was differentiated with respect to (the column `j`).
        wrt: &'static str,
        /// The offending value.
        value: f64,
    },
    /// The step size of an implicit method fell below the smallest step, its error
    /// estimate (or, with a zero error weight, its Newton iteration) not meeting the
    /// tolerance with a longer step: rejected attempts at one time, or accepted steps
    /// ever shorter. The smallest step is `max(16 * f64::EPSILON * |t|, MIN_STEP)` (see
    /// [`MIN_STEP`](crate::solver::MIN_STEP)). The usual cause is a tolerance tighter
    /// than the state's values can be computed to: an absolute tolerance like 1e-200 on
    /// a state that is zero; the error names the state with the smallest error weight.
    StepUnderflow {
        /// The time reached.
        t: f64,
        /// The step size of the last attempt.
        h: f64,
        /// Attempts of this step rejected in a row.
        rejected: usize,
        /// The state with the smallest error weight `atol_i + rtol |x_i|` at `t`.
        state: &'static str,
        /// That state's value at `t`.
        value: f64,
        /// Its error weight: the absolute error it is held to.
        weight: f64,
        /// Whether that weight is below the rounding error of the computation,
        /// `1e4 * f64::EPSILON * max_j |x_j|` (or zero): then the tolerance, not the
        /// model, is the likely cause.
        too_tight: bool,
    },
    /// Dormand–Prince found the model stiff (Hairer's test, *Solving ODEs I*,
    /// Sect. II.10 and DOPRI5's `NSTIFF`): the estimate `h |λ|` of where its steps sit
    /// on the stability region's boundary exceeded 3.25 on `steps` accepted steps in
    /// a row (without six non-stiff ones in between), so the steps are limited by
    /// stability, not accuracy, and at that step size the run would use up its step
    /// budget before its end. Turned off by `DormandPrinceOptions::detect_stiffness`.
    StiffnessDetected {
        /// The time reached.
        t: f64,
        /// The step size of the last step.
        h: f64,
        /// The estimate `h |λ|` of the last step.
        h_lambda: f64,
        /// The stiff steps in a row counted (at least 15).
        steps: usize,
        /// The steps still needed to reach the end at that step size.
        needed: f64,
        /// The steps left of the budget (`max_steps`), fewer than `needed`.
        left: usize,
    },
    /// A per-state absolute tolerance ([`Simulation::set_atol`](crate::Simulation::set_atol))
    /// is negative or not finite, or zero where the relative tolerance is zero too.
    InvalidAtol {
        /// The state's name.
        state: &'static str,
        /// The value given.
        value: f64,
        /// The range the value must lie in.
        expected: &'static str,
    },
    /// A list given for the model's states does not have one entry per state.
    #[cfg(feature = "std")]
    StateListLength {
        /// What the list is, e.g. `"atol"`.
        what: &'static str,
        /// The model's number of states.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A state index is out of range.
    #[cfg(feature = "std")]
    UnknownState {
        /// What the index was given for, e.g. `"set_non_negative"`.
        what: &'static str,
        /// The index.
        index: usize,
        /// The model's number of states.
        n_states: usize,
    },
    /// A setting the chosen solver cannot honour, e.g. per-state tolerances for a
    /// fixed-step method, which has no error control.
    #[cfg(feature = "std")]
    UnsupportedSetting {
        /// The setting, e.g. `"set_atol"`.
        setting: &'static str,
        /// The solver's name.
        solver: &'static str,
        /// Why, as a phrase.
        why: &'static str,
    },
    /// The run took longer than its wall-time limit (`max_wall_time`).
    WallTimeExceeded {
        /// The time reached.
        t: f64,
        /// The wall time used when the limit was noticed (checked before every step
        /// attempt).
        elapsed: Duration,
        /// The limit.
        limit: Duration,
    },
    /// The recorder asked the run to stop ([`Recorder::stop_requested`](crate::Recorder::stop_requested)).
    Stopped {
        /// The time of the last sample recorded.
        t: f64,
    },
    /// The model refused the state a run starts from ([`Model::check`](crate::Model::check)):
    /// a given inverse that is not one; or an evaluation of the model failed and the
    /// model said why ([`Model::evaluation_error`](crate::Model::evaluation_error)): an
    /// algebraic loop that did not converge, singular constraints. Every solver ends a
    /// run with this, rather than a non-finite derivative or a step-size underflow,
    /// when it meets a non-finite derivative (or Jacobian entry, or output) and the
    /// model has an error to give; an adaptive or implicit method first retries with
    /// shorter steps, as for any non-finite value, and gives the model's error if the
    /// step size underflows.
    InvalidModel(crate::model::ModelError),
    /// An event kept firing: [`EventOptions::max_repeats`](crate::EventOptions::max_repeats)
    /// times in a row, each within
    /// [`EventOptions::min_interval`](crate::EventOptions::min_interval) of its previous
    /// firing, or again at a time that cannot be told apart from its previous firing.
    /// Zeno behaviour (a ball bouncing ever faster) or an action that leaves the state
    /// where the event fires again: the model needs a rest or stick mode.
    Chattering {
        /// The event's name ([`EventInfo::name`](crate::EventInfo::name)).
        event: &'static str,
        /// The time of its last firing.
        t: f64,
        /// Its firings in a row counted as repeats.
        count: usize,
        /// The time since its previous firing, s (0 when it could not be resolved).
        interval: f64,
    },
    /// An event indicator ([`Model::event_indicators`](crate::Model::event_indicators))
    /// evaluated to NaN or infinity, so whether its event fires cannot be told.
    NonFiniteIndicator {
        /// The event's name.
        event: &'static str,
        /// The time of the evaluation.
        t: f64,
        /// The offending value.
        value: f64,
    },
    /// A run handled more than [`EventOptions::max_events`](crate::EventOptions::max_events)
    /// events.
    TooManyEvents {
        /// The event that went over the limit.
        event: &'static str,
        /// Its time.
        t: f64,
        /// The limit.
        limit: usize,
    },
}

/// Which value was non-finite in [`SolverError::NonFiniteState`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NonFiniteKind {
    /// The state itself (the initial state, or the result of a step).
    State,
    /// The derivative of the state, as returned by
    /// [`Model::derivatives`](crate::Model::derivatives).
    Derivative,
}

/// What is wrong with a sample time, in [`SolverError::InvalidSampleTimes`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleTimeProblem {
    /// The sample time is NaN or infinite.
    NotFinite,
    /// The sample time lies before the start time.
    BeforeStart {
        /// The start time.
        t0: f64,
    },
    /// The sample time is smaller than the one before it.
    Decreasing {
        /// The sample time before it.
        previous: f64,
    },
}

/// Formats a number readably at any magnitude: plain between 1e-4 and 1e15,
/// scientific outside; both forms are the shortest that read back exactly.
struct Num(f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

impl fmt::Display for SolverError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolverError::NonFiniteState {
                t,
                state,
                value,
                kind: NonFiniteKind::Derivative,
            } => write!(
                f,
                "at t = {}, the derivative of state `{state}` evaluated to {}: the model's \
                 equations are undefined there or the solution escapes to infinity",
                Num(*t),
                Num(*value)
            ),
            SolverError::NonFiniteState {
                t,
                state,
                value,
                kind: NonFiniteKind::State,
            } => write!(
                f,
                "at t = {}, state `{state}` became {}: the solution escapes to infinity or \
                 the initial state is not finite",
                Num(*t),
                Num(*value)
            ),
            SolverError::StepSizeTooSmall { t, h } => write!(
                f,
                "at t = {}, dopri5's step size fell to {}, below the resolution of the time \
                 axis (16 * eps * |t|): the solution may have a singularity there (it escapes \
                 to infinity or jumps), or the model is too stiff for this explicit method \
                 (use a stiff solver: Solver::stiff(), radau5)",
                Num(*t),
                Num(*h)
            ),
            SolverError::FixedStepTooSmall { t, step } => write!(
                f,
                "the fixed step {} is below the resolution of the time axis at t = {} \
                 (16 * eps * |t|): the steps would not advance the time; use a larger step",
                Num(*step),
                Num(*t)
            ),
            SolverError::StepBudgetExhausted { t, t_end, steps } => write!(
                f,
                "the budget of {steps} steps was used up at t = {}, before the last sample \
                 time {}: raise `max_steps`, loosen the tolerances, or use a larger step",
                Num(*t),
                Num(*t_end)
            ),
            SolverError::NonFiniteStartTime { t0 } => {
                write!(f, "the start time {} is not a finite number", Num(*t0))
            }
            #[cfg(feature = "std")]
            SolverError::ProbablyStiff {
                cause,
                method,
                step,
                spectral_radius,
                stable_step,
            } => write!(
                f,
                "{cause}. The model is probably stiff: its Jacobian at the start has an \
                 eigenvalue of magnitude ~{spectral_radius:.2e} 1/s (estimated), on which \
                 {method} is stable only with steps below ~{stable_step:.2e} s (the step was \
                 {} s); use a stiff solver, radau5 or rodas4",
                Num(*step),
            ),
            SolverError::NoSampleTimes => f.write_str(
                "no sample times: a run records at least one sample (ask for n >= 1, or a \
                 non-empty list)",
            ),
            SolverError::InvalidSampleTimes { index, t, problem } => {
                write!(f, "sample time #{index} ({}) ", Num(*t))?;
                match problem {
                    SampleTimeProblem::NotFinite => write!(f, "is not a finite number"),
                    SampleTimeProblem::BeforeStart { t0 } => {
                        write!(f, "lies before the start time {}", Num(*t0))
                    }
                    SampleTimeProblem::Decreasing { previous } => write!(
                        f,
                        "is smaller than the sample time before it ({}); sample times must \
                         be in increasing order",
                        Num(*previous)
                    ),
                }
            }
            SolverError::StateLengthMismatch {
                model,
                expected,
                found,
            } => write!(
                f,
                "the initial state has {found} values but model `{model}` has {expected} \
                 states"
            ),
            SolverError::InvalidOptions {
                option,
                value,
                expected,
            } => write!(
                f,
                "invalid solver option `{option}` = {}: expected {expected}",
                Num(*value)
            ),
            #[cfg(feature = "std")]
            SolverError::UnknownSolver { name, valid } => {
                write!(f, "unknown solver `{name}`; the solvers are: ")?;
                for (i, v) in valid.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    f.write_str(v)?;
                }
                Ok(())
            }
            SolverError::NewtonDiverged { t, h, iterations } => write!(
                f,
                "at t = {}, the Newton iteration of the implicit method failed to converge \
                 (last attempt: {iterations} iterations) even as the step size shrank to {}, \
                 below the resolution of the time axis: the solution may have a singularity \
                 there, or the model's equations may be discontinuous or not differentiable",
                Num(*t),
                Num(*h)
            ),
            SolverError::SingularMatrix { t, h } => write!(
                f,
                "at t = {}, the iteration matrix of the implicit method (step size {}) was \
                 singular to working precision five times in a row: the model's Jacobian \
                 is degenerate there (entries so large that the step size does not \
                 register next to them, or parameters out of range)",
                Num(*t),
                Num(*h)
            ),
            SolverError::NonFiniteJacobian {
                t,
                state,
                wrt,
                value,
            } => write!(
                f,
                "at t = {}, the derivative of state `{state}`'s rate with respect to state \
                 `{wrt}` evaluated to {}: the model's equations are not differentiable \
                 there (e.g. sqrt, cbrt or powf at 0)",
                Num(*t),
                Num(*value)
            ),
            SolverError::NonFiniteHandWrittenJacobian {
                t,
                state,
                wrt,
                value,
            } => write!(
                f,
                "at t = {}, the model's hand-written Jacobian (Model::jacobian) has a \
                 non-finite entry ∂ẋ_i/∂x_j = {} for i = `{state}`, j = `{wrt}`, while the \
                 derivatives are finite there: check that entry of Model::jacobian",
                Num(*t),
                Num(*value)
            ),
            SolverError::StepUnderflow {
                t,
                h,
                rejected,
                state,
                value,
                weight,
                too_tight,
            } => {
                write!(
                    f,
                    "at t = {}, the step size underflowed to {}, below the smallest step \
                     there (16 eps |t|, at least 1.5e-154)",
                    Num(*t),
                    Num(*h)
                )?;
                if *rejected > 0 {
                    write!(f, " after {rejected} rejected attempts in a row")?;
                }
                f.write_str(
                    ": the implicit method could not meet the tolerance with a longer step. ",
                )?;
                if *too_tight {
                    write!(
                        f,
                        "The tolerance is probably too tight: state `{state}` (= {}) is held \
                         to an absolute error of {} (its atol + rtol |x|), below the rounding \
                         error of the computation; raise its atol (Simulation::set_atol) or \
                         rtol",
                        Num(*value),
                        Num(*weight)
                    )
                } else {
                    write!(
                        f,
                        "The solution probably has a singularity there, or a layer thinner \
                         than the time axis resolves (the tightest error weight, state \
                         `{state}`'s at {}, is {})",
                        Num(*value),
                        Num(*weight)
                    )
                }
            }
            SolverError::StiffnessDetected {
                t,
                h,
                h_lambda,
                steps,
                needed,
                left,
            } => write!(
                f,
                "at t = {}, dopri5 found the model stiff: for {steps} steps in a row its \
                 step size ({} s, h|λ| ≈ {h_lambda:.2}) was held by stability, not \
                 accuracy (Hairer's stiffness test), and at that size the ~{needed:.1e} \
                 steps still needed exceed the {left} left of its budget; use a stiff \
                 solver (Solver::stiff(), radau5), or set \
                 `DormandPrinceOptions::detect_stiffness` to false to go on",
                Num(*t),
                Num(*h)
            ),
            SolverError::InvalidAtol {
                state,
                value,
                expected,
            } => write!(
                f,
                "invalid absolute tolerance {} for state `{state}`: expected {expected}",
                Num(*value)
            ),
            #[cfg(feature = "std")]
            SolverError::StateListLength {
                what,
                expected,
                found,
            } => write!(
                f,
                "`{what}` has {found} values but the model has {expected} states: give \
                 one per state, in the order of Model::STATE_NAMES"
            ),
            #[cfg(feature = "std")]
            SolverError::UnknownState {
                what,
                index,
                n_states,
            } => write!(
                f,
                "`{what}` names state #{index}, but the model has {n_states} states \
                 (indices 0..{n_states})"
            ),
            #[cfg(feature = "std")]
            SolverError::UnsupportedSetting {
                setting,
                solver,
                why,
            } => write!(f, "`{setting}` is not available with {solver}: {why}"),
            SolverError::WallTimeExceeded { t, elapsed, limit } => write!(
                f,
                "at t = {}, the run had taken {:.3} s, more than its wall-time limit of \
                 {:.3} s: raise `max_wall_time` or loosen the tolerances; if the steps \
                 are tiny, the model may be less smooth than it should be",
                Num(*t),
                elapsed.as_secs_f64(),
                limit.as_secs_f64()
            ),
            SolverError::Stopped { t } => {
                write!(f, "stopped on request after the sample at t = {}", Num(*t))
            }
            SolverError::InvalidModel(error) => write!(f, "{error}"),
            SolverError::Chattering {
                event,
                t,
                count,
                interval,
            } => {
                write!(f, "at t = {}, event `{event}` chattered: ", Num(*t))?;
                if *interval > 0.0 {
                    write!(
                        f,
                        "it fired {count} times in a row, each within `min_interval` of \
                         the one before (the last {} s after it)",
                        Num(*interval)
                    )?;
                } else {
                    write!(
                        f,
                        "it fired again within the time tolerance of its previous \
                         firing ({count} quick firings in a row)"
                    )?;
                }
                f.write_str(
                    "; the model switches ever faster (Zeno behaviour, or an action that \
                     leaves the state where the event fires again): give it a rest or \
                     stick mode that ends the switching, or widen \
                     `EventOptions::min_interval` / `max_repeats` if the switching is real",
                )
            }
            SolverError::NonFiniteIndicator { event, t, value } => write!(
                f,
                "at t = {}, the indicator of event `{event}` evaluated to {}: its \
                 condition is undefined at the state reached",
                Num(*t),
                Num(*value)
            ),
            SolverError::TooManyEvents { event, t, limit } => write!(
                f,
                "at t = {}, event `{event}` went over the limit of {limit} events in one \
                 run: raise `EventOptions::max_events`, or shorten the run",
                Num(*t)
            ),
        }
    }
}

impl core::error::Error for SolverError {}

/// A trajectory could not be written to a CSV file. The destination was left as it
/// was: the file is written whole or not at all.
#[cfg(feature = "std")]
#[derive(Debug)]
#[non_exhaustive]
pub struct CsvError {
    /// The file that was to be written.
    pub path: PathBuf,
    /// The operation that failed.
    pub stage: CsvStage,
    /// The underlying I/O error.
    pub source: io::Error,
}

/// The operation that failed in a [`CsvError`].
#[cfg(feature = "std")]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CsvStage {
    /// Creating the temporary file next to the destination.
    CreateTemporary,
    /// Writing or flushing the temporary file.
    Write,
    /// Renaming the temporary file onto the destination.
    Rename,
}

#[cfg(feature = "std")]
impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.stage {
            CsvStage::CreateTemporary => "creating a temporary file in its directory",
            CsvStage::Write => "writing the temporary file",
            CsvStage::Rename => "renaming the temporary file onto it",
        };
        write!(
            f,
            "could not write CSV file `{}`: {what} failed: {}",
            self.path.display(),
            self.source
        )
    }
}

#[cfg(feature = "std")]
impl std::error::Error for CsvError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}
