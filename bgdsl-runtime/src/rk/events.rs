//! Events in the integrators of [`crate::rk`]: the driver's event bookkeeping
//! ([`Events`]) in arrays, and the list of a call's events.

use crate::error::SolverError;
use crate::event::{EventAction, EventRecord};
use crate::model::Model;
use crate::solver::events::{ArrayEvents, Events};
use crate::solver::explicit::{ExplicitRk, Storage};
use crate::solver::Stats;

/// The events of an integrator's last call ([`Rk4::events`](super::Rk4::events),
/// [`DormandPrince::events`](super::DormandPrince::events)), in time order, with the
/// state on both sides of each: room for `K` events of a model with `N` states, in
/// arrays; beyond `K` the events are handled all the same but only counted
/// ([`CallEvents::dropped`]).
#[derive(Clone, Debug)]
pub struct CallEvents<const N: usize, const K: usize> {
    t: [f64; K],
    index: [usize; K],
    name: [&'static str; K],
    action: [EventAction; K],
    before: [[f64; N]; K],
    after: [[f64; N]; K],
    len: usize,
    dropped: usize,
}

impl<const N: usize, const K: usize> Default for CallEvents<N, K> {
    fn default() -> Self {
        CallEvents {
            t: [0.0; K],
            index: [0; K],
            name: [""; K],
            action: [EventAction::Continue; K],
            before: [[0.0; N]; K],
            after: [[0.0; N]; K],
            len: 0,
            dropped: 0,
        }
    }
}

impl<const N: usize, const K: usize> CallEvents<N, K> {
    /// Keeps an event, or counts it if the room is full.
    pub(crate) fn push(&mut self, record: &EventRecord<'_>) {
        let k = self.len;
        if k == K {
            self.dropped += 1;
            return;
        }
        self.t[k] = record.t;
        self.index[k] = record.index;
        self.name[k] = record.name;
        self.action[k] = record.action;
        self.before[k].copy_from_slice(record.before);
        self.after[k].copy_from_slice(record.after);
        self.len += 1;
    }

    /// Forgets the events (the start of a call).
    pub(crate) fn clear(&mut self) {
        self.len = 0;
        self.dropped = 0;
    }

    /// The number of events kept (at most `K`).
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no event is kept.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The events of the call beyond the first `K`, handled but not kept.
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// Event number `i` of the call.
    pub fn get(&self, i: usize) -> Option<EventRecord<'_>> {
        (i < self.len).then(|| EventRecord {
            t: self.t[i],
            index: self.index[i],
            name: self.name[i],
            before: &self.before[i],
            after: &self.after[i],
            action: self.action[i],
        })
    }

    /// The events kept, in time order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = EventRecord<'_>> + '_ {
        (0..self.len).map(|i| self.get(i).expect("within the kept events"))
    }

    /// The times of the events kept.
    pub fn times(&self) -> &[f64] {
        &self.t[..self.len]
    }
}

/// What an integrator of [`crate::rk`] keeps for the events of a model with `N` states
/// and `E` events, `K` of them listed per call: the bookkeeping the driver uses too
/// ([`Events`], here in arrays), the list of the call's events, the start of the
/// current step, and where the last call ended.
#[derive(Clone, Debug)]
pub(crate) struct Hybrid<const N: usize, const E: usize, const K: usize> {
    pub events: Events<ArrayEvents<N, E>>,
    pub log: CallEvents<N, K>,
    /// The state at the start of the current step (a fixed step is re-taken from it).
    pub x_start: [f64; N],
    /// The time and state the last call ended at, if it succeeded: a call that starts
    /// there continues its events.
    end: Option<(f64, [f64; N])>,
}

impl<const N: usize, const E: usize, const K: usize> Hybrid<N, E, K> {
    /// Nothing handled yet; the events' names are bound at each call.
    pub fn new() -> Self {
        Hybrid {
            events: Events::in_arrays(),
            log: CallEvents::default(),
            x_start: [0.0; N],
            end: None,
        }
    }

    /// Starts a call at `(t, x)`: forgets the last call's list and, for a model with
    /// events, continues the last call's events if it ended at exactly this point (bit
    /// for bit), or starts them afresh.
    pub fn begin<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64; N],
        stats: &mut Stats,
    ) -> Result<(), SolverError> {
        self.log.clear();
        let end = self.end.take();
        if E == 0 {
            return Ok(());
        }
        self.events.bind(M::EVENTS);
        let same = |(t_end, x_end): (f64, [f64; N])| {
            t_end.to_bits() == t.to_bits()
                && x_end.iter().zip(x).all(|(a, b)| a.to_bits() == b.to_bits())
        };
        if end.is_some_and(same) {
            self.events.resume(model, t, x, stats)
        } else {
            self.events.reset(model, t, x, stats)
        }
    }

    /// Ends a call that succeeded at `(t, x)`: the next may continue from there.
    pub fn finish(&mut self, t: f64, x: &[f64; N]) {
        self.end = Some((t, *x));
    }

    /// Forgets where the last call ended: the next starts its events afresh.
    pub fn forget(&mut self) {
        self.end = None;
    }

    /// Handles the events of the fixed step just taken by `kernel` from
    /// `(t_a, x_start)` to `(t, x)`: if one fires, locates it by re-taking the step
    /// shortened, moves `(t, x)` there, applies the actions and restarts the kernel.
    /// Returns the actions' verdict, or `None` if nothing fired.
    pub fn after_fixed_step<M: Model, S: Storage>(
        &mut self,
        model: &M,
        kernel: &mut ExplicitRk<S>,
        t_a: f64,
        t: &mut f64,
        x: &mut [f64],
        stats: &mut Stats,
    ) -> Result<Option<EventAction>, SolverError> {
        if E == 0 || self.events.check(model, t_a, *t, x, None, stats)?.is_none() {
            return Ok(None);
        }
        let t_star = self
            .events
            .locate_by_restep(model, kernel, t_a, &self.x_start, *t, stats)?;
        kernel.restart();
        self.fire(model, t_star, t, x, stats).map(Some)
    }

    /// Handles the events of the adaptive step just taken by `kernel` from `t_a` to
    /// `(t, x)`, locating a crossing on the step's continuous extension (the kernel must
    /// have kept it); as [`Hybrid::after_fixed_step`] otherwise.
    pub fn after_dense_step<M: Model, S: Storage>(
        &mut self,
        model: &M,
        kernel: &mut ExplicitRk<S>,
        t_a: f64,
        t: &mut f64,
        x: &mut [f64],
        stats: &mut Stats,
    ) -> Result<Option<EventAction>, SolverError> {
        if E == 0 {
            return Ok(None);
        }
        let mut dense = |s: f64, out: &mut [f64]| {
            kernel.interpolate(s, out);
            Ok(())
        };
        let found = self
            .events
            .check(model, t_a, *t, x, Some(&mut dense), stats)?;
        let Some(t_b) = found else {
            return Ok(None);
        };
        let t_star = self
            .events
            .locate(model, t_a, t_b, dense, &mut stats.n_event_fn)?;
        kernel.restart();
        self.fire(model, t_star, t, x, stats).map(Some)
    }

    /// Moves the call to the located event at `t_star` and applies the actions,
    /// listing each event.
    fn fire<M: Model>(
        &mut self,
        model: &M,
        t_star: f64,
        t: &mut f64,
        x: &mut [f64],
        stats: &mut Stats,
    ) -> Result<EventAction, SolverError> {
        *t = t_star;
        let log = &mut self.log;
        self.events
            .fire(model, t_star, x, |record| log.push(record), stats)
    }
}
