//! Events and discrete modes: the types a [`Model`] describes its switching with, and
//! the options that bound how the driver handles them.
//!
//! A model's event `i` has an indicator `g_i(t, x)` ([`Model::event_indicators`]) and an
//! action ([`Model::apply_event`]). After every accepted step the driver evaluates the
//! indicators at the step's end; an event fires when its indicator crosses zero in its
//! [`Direction`]. The driver then locates the crossing on the method's dense output
//! (fixed-step methods: by re-taking the step with a shortened length) to
//! [`EventOptions::time_tolerance`], applies the action to the state there, and
//! restarts the method from the new state with nothing carried across the event (no
//! step-size history, no Jacobian, no extrapolated start values).
//!
//! A discrete mode ([`ModeInfo`]) is a trailing state whose derivative is exactly 0,
//! so every integrator holds it constant between events; an action switches it by
//! rewriting the state. **A discontinuity goes through a mode**, never through an `if`
//! on a continuous signal, so the right-hand side is smooth inside every step.
//!
//! # What the driver does, precisely
//!
//! - **References.** Each indicator's reference is its value at the start of a run
//!   (no event fires at `t0`), after every step without an event, and after every
//!   event (re-evaluated at `(t*, x+)`). A reference of exactly 0 fires in no direction
//!   ([`Direction::fires`]): it takes its sign from the indicator's next non-zero
//!   value. A [`Stepper`](crate::Stepper)'s advance continues the one before: an
//!   event armed by a bounce (below) at its very end stays armed and the chattering
//!   counters run on, while every other reference is taken again with the model as it
//!   now stands (a crossing the host caused by changing an input does not fire);
//!   `set_state` and `restore` start afresh.
//! - **Bounces.** An event that fired and, after its action, sits at zero or on the
//!   side it crossed to (a ball at the floor, `h ≈ -1e-13`, its speed reversed) is
//!   looked at `1e-8 · max(1, |t|)` s later along the new motion (one explicit Euler
//!   step). If it heads back to the side it came from, its reference is that side: a
//!   step that ends with it crossed again (a whole flight inside one step) fires, and
//!   the driver finds the point where it was back by halving the step towards `t*`.
//!   If not, it must leave the side it stands on before it can fire again.
//! - **Location.** The earliest crossing in the step, by the Illinois method on the
//!   method's dense output (DOPRI5's continuous extension, Radau5's collocation
//!   polynomial, Rodas4's interpolant; RK4 and fixed-step DOPRI5 re-take the step from
//!   its start with a shortened length), to a bracket of
//!   [`EventOptions::time_tolerance`] plus 4 ulps of `t`. The event time is the
//!   bracket's right end, where the indicator has crossed.
//! - **Simultaneous events**, crossing within the tolerance of the earliest, are
//!   handled in index order, each action on the state the one before left. Later
//!   crossings in the same step are found again after the restart.
//! - **Samples** before `t*` come from the dense output; a sample at exactly `t*`
//!   records the state after the event.
//! - **Restart.** The step is cut at `t*` and the method starts afresh from `(t*, x+)`:
//!   explicit methods without their FSAL derivative and step-size history, with a new
//!   first step (a fixed-step method's next step ends on its next grid point); stiff
//!   ones with a new Jacobian, new LU factors, no controller history and no start
//!   values extrapolated from the step before.
//! - **Stop** ([`EventAction::Stop`]) ends the run at `t*` with a sample there (the
//!   state after) and returns `Ok`; [`Simulation::time`](crate::Simulation::time) is
//!   `t*`.
//! - **Limits.** A step is seen only at its end: an indicator that crosses and
//!   crosses back within one step (and is not armed by a bounce) is not seen. An
//!   action that moves another indicator across zero does not fire it (its reference
//!   is taken after the action).
//!
//! # The chattering rule
//!
//! The runtime never loops forever on events. A run ends with
//! [`SolverError::Chattering`](crate::SolverError::Chattering) when one event fires
//! [`EventOptions::max_repeats`] times in a row, each within
//! [`EventOptions::min_interval`]` · max(1, |t|)` of its previous firing, or fires again
//! at a time it cannot be told apart from its previous firing (within the time
//! tolerance: the solution has no room to move between them); and with
//! [`SolverError::TooManyEvents`](crate::SolverError::TooManyEvents) after
//! [`EventOptions::max_events`] events in one run. Zeno behaviour (a ball bouncing
//! ever faster) is physics the model must resolve, with a rest or stick mode.

use crate::model::Model;

/// Which way an event's indicator must cross zero to fire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    /// From negative to zero or positive: `g_prev < 0` and `g_new >= 0`.
    Rising,
    /// From positive to zero or negative: `g_prev > 0` and `g_new <= 0`.
    Falling,
    /// Either way.
    Both,
}

impl Direction {
    /// Whether an indicator whose reference value is `previous` and whose value is now
    /// `new` has crossed zero in this direction. A reference of exactly 0 never fires
    /// (it takes its sign from the indicator's next non-zero value).
    pub fn fires(self, previous: f64, new: f64) -> bool {
        let rising = previous < 0.0 && new >= 0.0;
        let falling = previous > 0.0 && new <= 0.0;
        match self {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Both => rising || falling,
        }
    }
}

/// One event of a model: its indicator g(t, x) and the action the model takes when it
/// crosses zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EventInfo {
    /// The event's name (`hit`; prefixed in a submodel: `stop.hit`).
    pub name: &'static str,
    /// The way its indicator must cross zero.
    pub direction: Direction,
    /// Its documentation.
    pub doc: &'static str,
}

/// The value type of a discrete mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ModeKind {
    /// `bool`: stored as 0.0 or 1.0.
    Bool,
    /// `i64`: stored as an integer value.
    Integer,
    /// `f64`: any number.
    Real,
}

/// One discrete mode: a trailing state held constant between events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModeInfo {
    /// The mode's name, as in [`Model::STATE_NAMES`] (`stuck`, `belt.friction.stuck`).
    pub name: &'static str,
    /// Its value type.
    pub kind: ModeKind,
    /// Its documentation.
    pub doc: &'static str,
}

/// What the run does after an event's action.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EventAction {
    /// The run goes on from the state after the event.
    Continue,
    /// The run ends at the event's time (recording a sample of the state after it) and
    /// returns successfully.
    Stop,
}

/// One event as it happened: handed to [`Recorder::event`](crate::Recorder::event) and
/// kept by [`Trajectory`](crate::Trajectory) and [`Stepper`](crate::Stepper).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventRecord<'a> {
    /// The event's time t*.
    pub t: f64,
    /// The event's position in [`Model::EVENTS`].
    pub index: usize,
    /// Its name ([`EventInfo::name`]).
    pub name: &'static str,
    /// The state just before the event (the left limit at t*).
    pub before: &'a [f64],
    /// The state just after it (its action applied).
    pub after: &'a [f64],
    /// Whether the run went on or stopped.
    pub action: EventAction,
}

/// How the driver locates events and when it gives up on a model that keeps firing
/// them (see [the chattering rule](self#the-chattering-rule)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventOptions {
    /// The width to which an event's time is located, s (plus a few ulps of `t`).
    /// Crossings within this distance of the earliest one in a step are simultaneous.
    /// Default 1e-12.
    pub time_tolerance: f64,
    /// The most events one run may handle before
    /// [`SolverError::TooManyEvents`](crate::SolverError::TooManyEvents). Default
    /// 100,000.
    pub max_events: usize,
    /// An event's firing counts as a repeat when it follows the same event's previous
    /// firing by less than `min_interval · max(1, |t|)`, s. Default 1e-9.
    pub min_interval: f64,
    /// The repeats in a row after which the run ends with
    /// [`SolverError::Chattering`](crate::SolverError::Chattering). Default 50.
    pub max_repeats: usize,
}

impl Default for EventOptions {
    fn default() -> Self {
        EventOptions {
            time_tolerance: 1e-12,
            max_events: 100_000,
            min_interval: 1e-9,
            max_repeats: 50,
        }
    }
}

impl EventOptions {
    /// Checks the options' ranges.
    ///
    /// # Errors
    ///
    /// [`SolverError::InvalidOptions`](crate::SolverError::InvalidOptions) naming the
    /// first option out of range.
    pub fn validate(&self) -> Result<(), crate::SolverError> {
        let positive = |option, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(crate::SolverError::InvalidOptions {
                    option,
                    value,
                    expected: "a finite number > 0",
                })
            }
        };
        positive("time_tolerance", self.time_tolerance)?;
        if !(self.min_interval.is_finite() && self.min_interval >= 0.0) {
            return Err(crate::SolverError::InvalidOptions {
                option: "min_interval",
                value: self.min_interval,
                expected: "a finite number >= 0",
            });
        }
        if self.max_repeats == 0 {
            return Err(crate::SolverError::InvalidOptions {
                option: "max_repeats",
                value: 0.0,
                expected: "an integer >= 1",
            });
        }
        Ok(())
    }
}

/// The change of stored energy an event makes: `H(after) − H(before)` from
/// [`Model::power_balance`] at time `t`; `None` for a model without an energy account.
/// With it an energy balance over a run with events closes:
/// `stored(t) − stored(t0) = ∫ input − ∫ dissipated + Σ event_energy`.
pub fn event_energy<M: Model>(model: &M, t: f64, before: &[f64], after: &[f64]) -> Option<f64> {
    let h_before = model.power_balance::<f64>(t, before)?.stored;
    let h_after = model.power_balance::<f64>(t, after)?.stored;
    Some(h_after - h_before)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_fire_on_their_own_crossings_only() {
        assert!(Direction::Rising.fires(-1.0, 0.0));
        assert!(!Direction::Rising.fires(1.0, -1.0));
        assert!(Direction::Falling.fires(1.0, 0.0));
        assert!(!Direction::Falling.fires(-1.0, 1.0));
        assert!(Direction::Both.fires(-1.0, 1.0) && Direction::Both.fires(1.0, -1.0));
        // A reference at exactly 0 fires in no direction.
        for d in [Direction::Rising, Direction::Falling, Direction::Both] {
            assert!(!d.fires(0.0, 1.0) && !d.fires(0.0, -1.0));
        }
    }

    #[test]
    fn default_options_are_valid_and_bad_ones_are_named() {
        assert!(EventOptions::default().validate().is_ok());
        let bad = EventOptions {
            time_tolerance: 0.0,
            ..EventOptions::default()
        };
        assert!(matches!(
            bad.validate(),
            Err(crate::SolverError::InvalidOptions {
                option: "time_tolerance",
                ..
            })
        ));
    }
}
