//! Events inside the driver (see [`crate::event`] for the semantics): detection after
//! every accepted step, location of the earliest crossing by the Illinois method on a
//! function of time the driver supplies (the step's dense output, or a fixed step
//! re-taken with a shortened length), simultaneous events in index order, the
//! actions, the indicators' references after an event, and the chattering rule.
//!
//! All memory is taken by [`Events::new`]; nothing here allocates.

use super::explicit::{check_state, eval, non_finite};
use super::stats::Stats;
use crate::error::SolverError;
use crate::event::{EventAction, EventInfo, EventOptions, EventRecord};
use crate::model::Model;
use crate::record::Recorder;

/// How far ahead of an event, relative to `max(1, |t|)`, the indicators of the events
/// that fired are looked at along the new motion (one explicit Euler step), to tell an
/// indicator that leaves zero back to the side it came from (a bounce: armed again)
/// from one that stays where it crossed to.
const LOOK_AHEAD: f64 = 1e-8;

/// Iterations after which the root finder gives up refining (bisection halves a
/// bracket of any width to the tolerance well within this).
const MAX_ITERATIONS: usize = 200;

/// The event bookkeeping of a run: indicator references, located crossings, the
/// events that fire together, and the counters of the chattering rule.
#[derive(Debug)]
pub(crate) struct Events {
    info: &'static [EventInfo],
    /// The options of the run.
    pub options: EventOptions,
    /// `g` at the start of the current step.
    value: Vec<f64>,
    /// The reference's sign (-1, 0: pending, +1): the side a crossing starts from.
    sign: Vec<f64>,
    /// The indicator fired at the start of the step and is heading back to the side
    /// of its reference, though its value there is still on the other side (or 0).
    armed: Vec<bool>,
    /// `g` at the end of the step.
    g: Vec<f64>,
    /// `g` at a point inside the step, while locating.
    probe: Vec<f64>,
    /// The located crossing time of each event that fires in the step (NaN for the
    /// others).
    crossing: Vec<f64>,
    /// The sign each event of [`Events::fired`] crossed from.
    from: Vec<f64>,
    /// The events firing at the located time, in index order (`len` of them).
    fired: Vec<usize>,
    len: usize,
    /// The time each event last fired, and its repeats in a row (chattering rule).
    last: Vec<f64>,
    repeats: Vec<usize>,
    /// Events handled in this run.
    handled: usize,
    /// The state at the located event time (before the actions).
    pub x_event: Vec<f64>,
    /// The state before one action, for its record.
    before: Vec<f64>,
    /// A state inside the step; `f` at the point after an event.
    scratch: Vec<f64>,
    rate: Vec<f64>,
}

/// Which of [`Events`]' indicator vectors was just evaluated.
#[derive(Clone, Copy, Debug)]
enum IndicatorBuffer {
    Value,
    End,
    Probe,
}

/// The sign of `v`: -1, 0 or +1.
fn sign_of(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

impl Events {
    /// The bookkeeping for model `M`'s events and `n` states.
    pub fn new<M: Model>() -> Self {
        let (m, n) = (M::EVENTS.len(), M::N_STATES);
        Events {
            info: M::EVENTS,
            options: EventOptions::default(),
            value: vec![0.0; m],
            sign: vec![0.0; m],
            armed: vec![false; m],
            g: vec![0.0; m],
            probe: vec![0.0; m],
            crossing: vec![f64::NAN; m],
            from: vec![0.0; m],
            fired: vec![0; m],
            len: 0,
            last: vec![f64::NAN; m],
            repeats: vec![0; m],
            handled: 0,
            x_event: vec![0.0; n],
            before: vec![0.0; n],
            scratch: vec![0.0; n],
            rate: vec![0.0; n],
        }
    }

    /// Whether the model has events at all (if not, the driver skips all of this).
    pub fn active(&self) -> bool {
        !self.info.is_empty()
    }

    /// The width to which an event time near `t` is located.
    fn tolerance(&self, t: f64) -> f64 {
        self.options.time_tolerance + 4.0 * f64::EPSILON * t.abs()
    }

    /// Starts a run at `(t, x)`: the references are the indicators there (no event at
    /// the start), the counters zero.
    pub fn reset<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        model.event_indicators(t, x, &mut self.value);
        stats.n_event_fn += 1;
        self.finite(model, t, IndicatorBuffer::Value)?;
        for (s, v) in self.sign.iter_mut().zip(&self.value) {
            *s = sign_of(*v);
        }
        self.armed.fill(false);
        self.last.fill(f64::NAN);
        self.repeats.fill(0);
        self.handled = 0;
        self.len = 0;
        Ok(())
    }

    /// Starts a run that continues the last one from where it ended (a stepper's next
    /// advance): an event armed by a bounce at the very end stays armed, and the
    /// chattering counters run on; every other reference is the indicator at `(t, x)`
    /// as the model now stands, so a crossing the host caused between the runs (an
    /// input changed) does not fire.
    pub fn resume<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        model.event_indicators(t, x, &mut self.value);
        stats.n_event_fn += 1;
        self.finite(model, t, IndicatorBuffer::Value)?;
        for ((s, v), armed) in self.sign.iter_mut().zip(&self.value).zip(&self.armed) {
            if !armed {
                *s = sign_of(*v);
            }
        }
        self.handled = 0;
        self.len = 0;
        Ok(())
    }

    /// Fails if an indicator just evaluated into `buffer` is not finite (with the
    /// model's own error, if its evaluation failed).
    fn finite<M: Model>(
        &self,
        model: &M,
        t: f64,
        buffer: IndicatorBuffer,
    ) -> Result<(), SolverError> {
        let values = match buffer {
            IndicatorBuffer::Value => &self.value,
            IndicatorBuffer::End => &self.g,
            IndicatorBuffer::Probe => &self.probe,
        };
        match values.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(i) => Err(match model.evaluation_error() {
                Some(cause) => SolverError::InvalidModel(cause),
                None => SolverError::NonFiniteIndicator {
                    event: self.info[i].name,
                    t,
                    value: values[i],
                },
            }),
        }
    }

    fn fires(&self, i: usize) -> bool {
        self.info[i].direction.fires(self.sign[i], self.g[i])
    }

    /// Evaluates the indicators at the end `(t, x)` of an accepted step. Returns whether
    /// an event fires in the step; if none does, the end becomes the references.
    pub fn check<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        stats: &mut Stats,
    ) -> Result<bool, SolverError> {
        model.event_indicators(t, x, &mut self.g);
        stats.n_event_fn += 1;
        self.finite(model, t, IndicatorBuffer::End)?;
        if (0..self.info.len()).any(|i| self.fires(i)) {
            return Ok(true);
        }
        self.value.copy_from_slice(&self.g);
        for (s, v) in self.sign.iter_mut().zip(&self.g) {
            *s = sign_of(*v);
        }
        self.armed.fill(false);
        Ok(false)
    }

    /// Locates the earliest crossing in the step `[t_a, t_b]` that [`Events::check`]
    /// found to fire, on `state_at(t, x)` (the state at any `t` of the step), and the
    /// events simultaneous with it; leaves the state there in [`Events::x_event`].
    /// Returns the event time.
    ///
    /// Fails with [`SolverError::Chattering`] for an event that fired at `t_a` and
    /// crosses again within the time tolerance of it, and with what `state_at` fails
    /// with.
    pub fn locate<M: Model>(
        &mut self,
        model: &M,
        t_a: f64,
        t_b: f64,
        mut state_at: impl FnMut(f64, &mut [f64]) -> Result<(), SolverError>,
        n_event_fn: &mut usize,
    ) -> Result<f64, SolverError> {
        let mut earliest = f64::INFINITY;
        let m = self.info.len();
        for i in 0..m {
            self.crossing[i] = f64::NAN;
            if !self.fires(i) {
                continue;
            }
            let s = self.sign[i];
            let (mut lo, mut g_lo) = (t_a, self.value[i]);
            if self.armed[i] {
                match self.find_left(model, i, t_a, t_b, &mut state_at, n_event_fn)? {
                    Some((t, g)) => (lo, g_lo) = (t, g),
                    None => {
                        return Err(SolverError::Chattering {
                            event: self.info[i].name,
                            t: t_a,
                            count: self.repeats[i] + 1,
                            interval: 0.0,
                        })
                    }
                }
            }
            let t_i = self.bracket(
                model,
                i,
                s,
                (lo, g_lo),
                (t_b, self.g[i]),
                &mut state_at,
                n_event_fn,
            )?;
            self.crossing[i] = t_i;
            earliest = earliest.min(t_i);
        }
        let simultaneous = earliest + self.tolerance(earliest);
        self.len = 0;
        for i in 0..m {
            self.from[i] = self.sign[i];
            if self.crossing[i] <= simultaneous {
                self.fired[self.len] = i;
                self.len += 1;
            }
        }
        state_at(earliest, &mut self.x_event)?;
        Ok(earliest)
    }

    /// Evaluates event `i`'s indicator at time `t` of the step.
    fn g_at<M: Model>(
        &mut self,
        model: &M,
        i: usize,
        t: f64,
        state_at: &mut impl FnMut(f64, &mut [f64]) -> Result<(), SolverError>,
        n_event_fn: &mut usize,
    ) -> Result<f64, SolverError> {
        state_at(t, &mut self.scratch)?;
        model.event_indicators(t, &self.scratch, &mut self.probe);
        *n_event_fn += 1;
        self.finite(model, t, IndicatorBuffer::Probe)?;
        Ok(self.probe[i])
    }

    /// For an armed event (it fired at `t_a` and heads back to its reference's side):
    /// a point of the step where it is on that side, searched from the middle of the
    /// step towards `t_a` by halving; `None` when there is none farther than the time
    /// tolerance from `t_a`.
    fn find_left<M: Model>(
        &mut self,
        model: &M,
        i: usize,
        t_a: f64,
        t_b: f64,
        state_at: &mut impl FnMut(f64, &mut [f64]) -> Result<(), SolverError>,
        n_event_fn: &mut usize,
    ) -> Result<Option<(f64, f64)>, SolverError> {
        let s = self.sign[i];
        let tol = self.tolerance(t_a);
        let mut d = 0.5 * (t_b - t_a);
        while d > tol {
            let t = t_a + d;
            let g = self.g_at(model, i, t, state_at, n_event_fn)?;
            if g * s > 0.0 {
                return Ok(Some((t, g)));
            }
            d *= 0.5;
        }
        Ok(None)
    }

    /// The Illinois method (regula falsi with the retained end's value halved when the
    /// same end is kept twice) on event `i`'s indicator over `[lo, hi]`, where it is on
    /// side `s` at `lo` and has crossed at `hi`, until the bracket is within the time
    /// tolerance; a point is kept at least half the tolerance inside the bracket, and
    /// a step that does not halve the bracket twice in a row is followed by bisection.
    /// Returns the bracket's right end, where the indicator has crossed.
    #[allow(clippy::too_many_arguments)]
    fn bracket<M: Model>(
        &mut self,
        model: &M,
        i: usize,
        s: f64,
        (mut lo, mut g_lo): (f64, f64),
        (mut hi, mut g_hi): (f64, f64),
        state_at: &mut impl FnMut(f64, &mut [f64]) -> Result<(), SolverError>,
        n_event_fn: &mut usize,
    ) -> Result<f64, SolverError> {
        let crossed = |g: f64| if s < 0.0 { g >= 0.0 } else { g <= 0.0 };
        let mut kept = 0i8;
        let mut slow = 0;
        for _ in 0..MAX_ITERATIONS {
            let width = hi - lo;
            let tol = self.tolerance(hi);
            if width <= tol {
                break;
            }
            let secant = hi - g_hi * width / (g_hi - g_lo);
            let t = if slow >= 2 || secant.is_nan() {
                slow = 0;
                lo + 0.5 * width
            } else {
                // The bracket is wider than the tolerance, so this range is not empty.
                let margin = 0.5 * tol;
                secant.clamp(lo + margin, hi - margin)
            };
            let g = self.g_at(model, i, t, state_at, n_event_fn)?;
            if crossed(g) {
                (hi, g_hi) = (t, g);
                if kept == 1 {
                    g_lo *= 0.5;
                }
                kept = 1;
            } else {
                (lo, g_lo) = (t, g);
                if kept == -1 {
                    g_hi *= 0.5;
                }
                kept = -1;
            }
            if hi - lo > 0.5 * width {
                slow += 1;
            } else {
                slow = 0;
            }
        }
        Ok(hi)
    }

    /// Applies the actions of the events located by [`Events::locate`], in index order,
    /// each to the state the one before left, at time `t`: `x` holds the state before
    /// them and is rewritten to the state after. Each is counted, checked against the
    /// limits of the chattering rule first, and handed to `recorder`. Returns
    /// [`EventAction::Stop`] if any action asked for it.
    pub fn apply<M: Model, R: Recorder + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &mut [f64],
        recorder: &mut R,
        stats: &mut Stats,
    ) -> Result<EventAction, SolverError> {
        let mut result = EventAction::Continue;
        for k in 0..self.len {
            let i = self.fired[k];
            let name = self.info[i].name;
            if self.handled >= self.options.max_events {
                return Err(SolverError::TooManyEvents {
                    event: name,
                    t,
                    limit: self.options.max_events,
                });
            }
            let interval = t - self.last[i];
            if interval < self.options.min_interval * t.abs().max(1.0) {
                self.repeats[i] += 1;
            } else {
                self.repeats[i] = 0;
            }
            self.last[i] = t;
            if self.repeats[i] >= self.options.max_repeats {
                return Err(SolverError::Chattering {
                    event: name,
                    t,
                    count: self.repeats[i],
                    interval,
                });
            }
            self.before.copy_from_slice(x);
            let action = model.apply_event(i, t, x);
            check_state(x, t).map_err(non_finite::<M>)?;
            self.handled += 1;
            stats.events += 1;
            recorder.event(&EventRecord {
                t,
                index: i,
                name,
                before: &self.before,
                after: x,
                action,
            });
            if action == EventAction::Stop {
                result = EventAction::Stop;
            }
        }
        Ok(result)
    }

    /// Takes the references afresh at `(t, x)` after the actions. An event that fired
    /// and is now at zero or still on the side it crossed to is looked at a moment
    /// later along the new motion: if it heads back to the side it came from (a ball
    /// bouncing off the floor), it is armed to fire again when it returns; otherwise
    /// its reference is where it stands (it must leave that side before it can fire
    /// again).
    pub fn rearm<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        model.event_indicators(t, x, &mut self.value);
        stats.n_event_fn += 1;
        self.finite(model, t, IndicatorBuffer::Value)?;
        for (s, v) in self.sign.iter_mut().zip(&self.value) {
            *s = sign_of(*v);
        }
        self.armed.fill(false);
        let stuck = |e: &Self, i: usize| e.value[i] * e.from[i] <= 0.0;
        if !self.fired[..self.len].iter().any(|&i| stuck(self, i)) {
            return Ok(());
        }
        eval(model, t, x, &mut self.rate, &mut stats.n_rhs).map_err(non_finite::<M>)?;
        let tau = LOOK_AHEAD * t.abs().max(1.0);
        for ((s, x), f) in self.scratch.iter_mut().zip(x).zip(&self.rate) {
            *s = x + tau * f;
        }
        model.event_indicators(t + tau, &self.scratch, &mut self.probe);
        stats.n_event_fn += 1;
        self.finite(model, t + tau, IndicatorBuffer::Probe)?;
        for k in 0..self.len {
            let i = self.fired[k];
            if stuck(self, i) && self.probe[i] * self.from[i] > 0.0 {
                self.sign[i] = self.from[i];
                self.armed[i] = true;
            }
        }
        Ok(())
    }
}
