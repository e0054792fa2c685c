//! Events inside the driver (see [`crate::event`] for the semantics): detection after
//! every accepted step, location of the earliest crossing by the Illinois method on a
//! function of time the driver supplies (the step's dense output, or a fixed step
//! re-taken with a shortened length), simultaneous events in index order, the
//! actions, the indicators' references after an event, and the chattering rule.
//!
//! The bookkeeping is generic over where its vectors live ([`EventStorage`]), like the
//! explicit kernel: `Vec`s sized at run time for the driver ([`HeapEvents`], with
//! `std`), or arrays sized at compile time for the allocation-free integrators of
//! [`crate::rk`] ([`ArrayEvents`]). The logic is the same code either way.
//!
//! All memory is taken by the constructor; nothing here allocates.

use core::fmt::Debug;

use super::explicit::{check_state, eval, non_finite, ExplicitRk, Storage};
use super::stats::Stats;
use crate::error::SolverError;
use crate::event::{EventAction, EventInfo, EventOptions, EventRecord};
use crate::model::Model;

/// How far ahead of an event, relative to `max(1, |t|)`, the indicators of the events
/// that fired are looked at along the new motion (one explicit Euler step), to tell an
/// indicator that leaves zero back to the side it came from (a bounce: armed again)
/// from one that stays where it crossed to.
const LOOK_AHEAD: f64 = 1e-8;

/// Iterations after which the root finder gives up refining (bisection halves a
/// bracket of any width to the tolerance well within this).
const MAX_ITERATIONS: usize = 200;

/// Where the event bookkeeping keeps its vectors: some of one number per event, some
/// of one number per state.
pub(crate) trait EventStorage: Clone + Debug {
    /// A number per event.
    type Values: AsRef<[f64]> + AsMut<[f64]> + Clone + Debug;
    /// A flag per event.
    type Flags: AsRef<[bool]> + AsMut<[bool]> + Clone + Debug;
    /// A count or an index per event.
    type Counts: AsRef<[usize]> + AsMut<[usize]> + Clone + Debug;
    /// A state vector.
    type State: AsRef<[f64]> + AsMut<[f64]> + Clone + Debug;
}

/// Vectors on the heap, allocated once for the model's sizes: the driver's.
#[cfg(feature = "std")]
#[derive(Clone, Debug)]
pub(crate) struct HeapEvents;

#[cfg(feature = "std")]
impl EventStorage for HeapEvents {
    type Values = Vec<f64>;
    type Flags = Vec<bool>;
    type Counts = Vec<usize>;
    type State = Vec<f64>;
}

/// Arrays for `N` states and `E` events: the storage of the integrators of
/// [`crate::rk`].
#[derive(Clone, Debug)]
pub(crate) struct ArrayEvents<const N: usize, const E: usize>;

impl<const N: usize, const E: usize> EventStorage for ArrayEvents<N, E> {
    type Values = [f64; E];
    type Flags = [bool; E];
    type Counts = [usize; E];
    type State = [f64; N];
}

/// The event bookkeeping of a run: indicator references, located crossings, the
/// events that fire together, and the counters of the chattering rule.
#[derive(Clone, Debug)]
pub(crate) struct Events<S: EventStorage> {
    info: &'static [EventInfo],
    /// The options of the run.
    pub options: EventOptions,
    /// `g` at the start of the current step.
    value: S::Values,
    /// The reference's sign (-1, 0: pending, +1): the side a crossing starts from.
    sign: S::Values,
    /// The indicator fired at the start of the step and is heading back to the side
    /// of its reference, though its value there is still on the other side (or 0).
    armed: S::Flags,
    /// `g` at the end of the step.
    g: S::Values,
    /// `g` at a point inside the step, while locating.
    probe: S::Values,
    /// The located crossing time of each event that fires in the step (NaN for the
    /// others).
    crossing: S::Values,
    /// The sign each event of [`Events::fired`] crossed from.
    from: S::Values,
    /// The events firing at the located time, in index order (`len` of them).
    fired: S::Counts,
    len: usize,
    /// The time each event last fired, and its repeats in a row (chattering rule).
    last: S::Values,
    repeats: S::Counts,
    /// Events handled in this run.
    handled: usize,
    /// The state at the located event time (before the actions).
    x_event: S::State,
    /// The state before one action, for its record.
    before: S::State,
    /// A state inside the step; `f` at the point after an event.
    scratch: S::State,
    rate: S::State,
}

/// The state at any time of a step (its continuous extension).
pub(crate) type StateAt<'a> = dyn FnMut(f64, &mut [f64]) -> Result<(), SolverError> + 'a;

/// Evaluates the indicators of the events `info` at `(t, x)` into `values`, counting
/// the evaluation, and fails if one is not finite (with the model's own error, if its
/// evaluation failed).
fn indicators<M: Model>(
    info: &[EventInfo],
    model: &M,
    t: f64,
    x: &[f64],
    values: &mut [f64],
    n_event_fn: &mut usize,
) -> Result<(), SolverError> {
    model.event_indicators(t, x, values);
    *n_event_fn += 1;
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(match model.evaluation_error() {
            Some(cause) => SolverError::InvalidModel(cause),
            None => SolverError::NonFiniteIndicator {
                event: info[i].name,
                t,
                value: values[i],
            },
        }),
    }
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

#[cfg(feature = "std")]
impl Events<HeapEvents> {
    /// The bookkeeping for model `M`'s events and states.
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
}

impl<const N: usize, const E: usize> Events<ArrayEvents<N, E>> {
    /// The bookkeeping for `E` events and `N` states, in arrays, for events to be
    /// named by [`Events::bind`] (until then it is inactive).
    pub fn in_arrays() -> Self {
        Events {
            info: &[],
            options: EventOptions::default(),
            value: [0.0; E],
            sign: [0.0; E],
            armed: [false; E],
            g: [0.0; E],
            probe: [0.0; E],
            crossing: [f64::NAN; E],
            from: [0.0; E],
            fired: [0; E],
            len: 0,
            last: [f64::NAN; E],
            repeats: [0; E],
            handled: 0,
            x_event: [0.0; N],
            before: [0.0; N],
            scratch: [0.0; N],
            rate: [0.0; N],
        }
    }
}

impl<S: EventStorage> Events<S> {
    /// Binds the bookkeeping to the events `info` (as many as it has room for).
    pub fn bind(&mut self, info: &'static [EventInfo]) {
        assert_eq!(info.len(), self.value.as_ref().len(), "room for each event");
        self.info = info;
    }

    /// Whether the model has events at all (if not, the driver skips all of this).
    #[cfg(feature = "std")]
    pub fn active(&self) -> bool {
        !self.info.is_empty()
    }

    /// The width to which an event time near `t` is located.
    fn tolerance(&self, t: f64) -> f64 {
        self.options.time_tolerance + 4.0 * f64::EPSILON * t.abs()
    }

    /// The references' signs are those of the values in [`Events::value`], but for
    /// the armed events if `keep_armed`.
    fn take_references(&mut self, keep_armed: bool) {
        let (sign, value, armed) = (self.sign.as_mut(), self.value.as_ref(), self.armed.as_ref());
        for ((s, v), armed) in sign.iter_mut().zip(value).zip(armed) {
            if !(keep_armed && *armed) {
                *s = sign_of(*v);
            }
        }
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
        indicators(
            self.info,
            model,
            t,
            x,
            self.value.as_mut(),
            &mut stats.n_event_fn,
        )?;
        self.take_references(false);
        self.armed.as_mut().fill(false);
        self.last.as_mut().fill(f64::NAN);
        self.repeats.as_mut().fill(0);
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
        indicators(
            self.info,
            model,
            t,
            x,
            self.value.as_mut(),
            &mut stats.n_event_fn,
        )?;
        self.take_references(true);
        self.handled = 0;
        self.len = 0;
        Ok(())
    }

    fn fires(&self, i: usize) -> bool {
        self.fires_on(i, self.g.as_ref())
    }

    /// Whether event `i` fires with `values` as its indicators' values.
    fn fires_on(&self, i: usize, values: &[f64]) -> bool {
        self.info[i]
            .direction
            .fires(self.sign.as_ref()[i], values[i])
    }

    /// Evaluates the indicators at the end `(t_b, x)` of an accepted step from `t_a`
    /// and, if none fires there and the step has a continuous extension (`inside`:
    /// the state at any time of the step), at [`EventOptions::interior_points`] evenly
    /// spaced points inside it, where an indicator that crosses and crosses back
    /// within the step shows. Returns the end of the bracket to locate on: `t_b`, or
    /// the first inside point where an event fires; `None` if none fires, and then
    /// the end becomes the references. Events armed by a bounce at `t_a` are left to
    /// the end's check (they are on their far side just after `t_a`).
    pub fn check<M: Model>(
        &mut self,
        model: &M,
        t_a: f64,
        t_b: f64,
        x: &[f64],
        inside: Option<&mut StateAt<'_>>,
        stats: &mut Stats,
    ) -> Result<Option<f64>, SolverError> {
        indicators(
            self.info,
            model,
            t_b,
            x,
            self.g.as_mut(),
            &mut stats.n_event_fn,
        )?;
        if (0..self.info.len()).any(|i| self.fires(i)) {
            return Ok(Some(t_b));
        }
        if let Some(state_at) = inside {
            let points = self.options.interior_points;
            for k in 1..=points {
                let t = t_a + (t_b - t_a) * (k as f64 / (points + 1) as f64);
                state_at(t, self.scratch.as_mut())?;
                let (x, probe) = (self.scratch.as_ref(), self.probe.as_mut());
                indicators(self.info, model, t, x, probe, &mut stats.n_event_fn)?;
                let probe = self.probe.as_ref();
                let fires = |i: usize| !self.armed.as_ref()[i] && self.fires_on(i, probe);
                if (0..self.info.len()).any(fires) {
                    let (g, probe) = (self.g.as_mut(), self.probe.as_ref());
                    g.copy_from_slice(probe);
                    return Ok(Some(t));
                }
            }
        }
        self.value.as_mut().copy_from_slice(self.g.as_ref());
        self.take_references(false);
        self.armed.as_mut().fill(false);
        Ok(None)
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
            self.crossing.as_mut()[i] = f64::NAN;
            if !self.fires(i) {
                continue;
            }
            let s = self.sign.as_ref()[i];
            let (mut lo, mut g_lo) = (t_a, self.value.as_ref()[i]);
            if self.armed.as_ref()[i] {
                match self.find_left(model, i, t_a, t_b, &mut state_at, n_event_fn)? {
                    Some((t, g)) => (lo, g_lo) = (t, g),
                    None => {
                        return Err(SolverError::Chattering {
                            event: self.info[i].name,
                            t: t_a,
                            count: self.repeats.as_ref()[i] + 1,
                            interval: 0.0,
                        })
                    }
                }
            }
            let g_hi = self.g.as_ref()[i];
            let t_i = self.bracket(
                model,
                i,
                s,
                (lo, g_lo),
                (t_b, g_hi),
                &mut state_at,
                n_event_fn,
            )?;
            self.crossing.as_mut()[i] = t_i;
            earliest = earliest.min(t_i);
        }
        let simultaneous = earliest + self.tolerance(earliest);
        self.len = 0;
        for i in 0..m {
            self.from.as_mut()[i] = self.sign.as_ref()[i];
            if self.crossing.as_ref()[i] <= simultaneous {
                self.fired.as_mut()[self.len] = i;
                self.len += 1;
            }
        }
        state_at(earliest, self.x_event.as_mut())?;
        Ok(earliest)
    }

    /// [`Events::locate`] on a fixed step from `(t_a, x_a)` to `t_b` taken by
    /// `kernel`, by re-taking the step from its start with a shortened length.
    #[allow(clippy::too_many_arguments)]
    pub fn locate_by_restep<M: Model, K: Storage>(
        &mut self,
        model: &M,
        kernel: &mut ExplicitRk<K>,
        t_a: f64,
        x_a: &[f64],
        t_b: f64,
        stats: &mut Stats,
    ) -> Result<f64, SolverError> {
        let n_rhs = &mut stats.n_rhs;
        // `f(t_a, x_a)`, evaluated once: an attempt leaves the first stage alone.
        kernel.restart();
        let mut prepared = false;
        let restep = |t: f64, out: &mut [f64]| {
            if !prepared {
                kernel
                    .prepare(model, t_a, x_a, n_rhs)
                    .map_err(non_finite::<M>)?;
                prepared = true;
            }
            kernel
                .attempt(model, t_a, t, x_a, n_rhs)
                .map_err(non_finite::<M>)?;
            out.copy_from_slice(kernel.x_new());
            Ok(())
        };
        self.locate(model, t_a, t_b, restep, &mut stats.n_event_fn)
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
        state_at(t, self.scratch.as_mut())?;
        let (x, probe) = (self.scratch.as_ref(), self.probe.as_mut());
        indicators(self.info, model, t, x, probe, n_event_fn)?;
        Ok(probe[i])
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
        let s = self.sign.as_ref()[i];
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
    /// limits of the chattering rule first, and handed to `on_event`. Returns
    /// [`EventAction::Stop`] if any action asked for it.
    pub fn apply<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &mut [f64],
        mut on_event: impl FnMut(&EventRecord<'_>),
        stats: &mut Stats,
    ) -> Result<EventAction, SolverError> {
        let mut result = EventAction::Continue;
        for k in 0..self.len {
            let i = self.fired.as_ref()[k];
            let name = self.info[i].name;
            if self.handled >= self.options.max_events {
                return Err(SolverError::TooManyEvents {
                    event: name,
                    t,
                    limit: self.options.max_events,
                });
            }
            let (last, repeats) = (&mut self.last.as_mut()[i], &mut self.repeats.as_mut()[i]);
            let interval = t - *last;
            if interval < self.options.min_interval * t.abs().max(1.0) {
                *repeats += 1;
            } else {
                *repeats = 0;
            }
            *last = t;
            if *repeats >= self.options.max_repeats {
                return Err(SolverError::Chattering {
                    event: name,
                    t,
                    count: *repeats,
                    interval,
                });
            }
            self.before.as_mut().copy_from_slice(x);
            let action = model.apply_event(i, t, x);
            check_state(x, t).map_err(non_finite::<M>)?;
            self.handled += 1;
            stats.events += 1;
            on_event(&EventRecord {
                t,
                index: i,
                name,
                before: self.before.as_ref(),
                after: x,
                action,
            });
            if action == EventAction::Stop {
                result = EventAction::Stop;
            }
        }
        Ok(result)
    }

    /// Moves the run to the event [`Events::locate`] found at `t`: `x` becomes the
    /// state there, the actions are applied ([`Events::apply`]) and the references
    /// taken afresh ([`Events::rearm`]; also before a stop, so that a run that
    /// continues from there finds them). Returns [`EventAction::Stop`] if an action
    /// asked for it.
    pub fn fire<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &mut [f64],
        on_event: impl FnMut(&EventRecord<'_>),
        stats: &mut Stats,
    ) -> Result<EventAction, SolverError> {
        x.copy_from_slice(self.x_event.as_ref());
        let action = self.apply(model, t, x, on_event, stats)?;
        self.rearm(model, t, x, stats)?;
        Ok(action)
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
        indicators(
            self.info,
            model,
            t,
            x,
            self.value.as_mut(),
            &mut stats.n_event_fn,
        )?;
        self.take_references(false);
        self.armed.as_mut().fill(false);
        let (value, from) = (self.value.as_ref(), self.from.as_ref());
        let stuck = |i: usize| value[i] * from[i] <= 0.0;
        let fired = &self.fired.as_ref()[..self.len];
        if !fired.iter().any(|&i| stuck(i)) {
            return Ok(());
        }
        eval(model, t, x, self.rate.as_mut(), &mut stats.n_rhs).map_err(non_finite::<M>)?;
        let tau = LOOK_AHEAD * t.abs().max(1.0);
        let scratch = self.scratch.as_mut();
        for ((s, x), f) in scratch.iter_mut().zip(x).zip(self.rate.as_ref()) {
            *s = x + tau * f;
        }
        let probe = self.probe.as_mut();
        indicators(
            self.info,
            model,
            t + tau,
            scratch,
            probe,
            &mut stats.n_event_fn,
        )?;
        let (sign, armed) = (self.sign.as_mut(), self.armed.as_mut());
        for &i in fired {
            if stuck(i) && probe[i] * from[i] > 0.0 {
                sign[i] = from[i];
                armed[i] = true;
            }
        }
        Ok(())
    }
}
