//! Explicit integrators that allocate nothing, for hosts without the standard library
//! (a microcontroller) or without a heap: classical RK4 with a fixed step ([`Rk4`]) and
//! adaptive Dormand–Prince 5(4) ([`DormandPrince`]).
//!
//! They run the same kernel, Butcher tableaux and step-size control as the driver's
//! `Solver::Rk4` and `Solver::DormandPrince` (which need `std`), on
//! workspaces of fixed-size arrays: `N`, the length of the state vector, is a const
//! generic, and every method checks at compile time that it equals the model's
//! [`Model::N_STATES`]. A generated model has its size as an inherent constant, so
//! `Rk4::<{ Motor::N_STATES }>` names the right integrator without repeating a number.
//!
//! The caller owns the time and the state and passes them to each call, which moves
//! them forward. Each call starts afresh from the `(t, x)` it is given, so the state,
//! the parameters and the inputs of the model may all change between calls (a
//! controller's new command, a measurement that corrects the state); an adaptive
//! integrator carries over only the step size it has learnt. Failures are
//! [`SolverError`]s; on error `t` and `x` hold the last point reached.
//!
//! # Events
//!
//! They handle a model's events ([`crate::event`]) as the std driver does, with the
//! same code (its event bookkeeping, here in arrays): after every step the
//! indicators are checked; a crossing is located by re-taking the step shortened
//! ([`Rk4`]) or on the step's continuous extension ([`DormandPrince`]) to
//! [`EventOptions::time_tolerance`]; simultaneous events are handled in index order;
//! the action rewrites `x` and the method restarts from there (a fixed grid resumes on
//! its next point; the adaptive step-size control starts afresh). An action that
//! stops ends the call at the event's time, with `t` and `x` there (the state after
//! it). The same event times come out as from the driver with the same settings.
//! [`EventOptions`] (`set_event_options`) and the chattering rule bound every call.
//!
//! The number of events is a second const generic, `E`, checked at compile time
//! against `M::EVENTS.len()` like `N` against `N_STATES` (a model without events
//! takes the default, 0): `Rk4::<{ Ball::N_STATES }, { Ball::EVENTS.len() }>`. A
//! third, `K` (default [`DEFAULT_CALL_EVENTS`]), is the room for the events of one
//! call, listed with the state on both sides of each by `events()`
//! ([`CallEvents`]); more are handled all the same and counted
//! ([`CallEvents::dropped`]). A fixed bound instead of `E` would cost every model
//! the largest one's memory, and be a limit a model could exceed at run time.
//!
//! A call that starts exactly where the last one ended (the same `t` and `x`, bit for
//! bit) continues its events, as a [`Stepper`](crate::Stepper)'s advances do: an
//! event armed by a bounce at the very end of the call stays armed, and the
//! chattering counters run on. A call from any other point (a state the host has
//! set) starts them afresh, with no event at its start; so does the next call after
//! `restart_events` ([`Rk4`]) or `restart` ([`DormandPrince`]). As with the
//! `Stepper`, a crossing the host causes between calls by changing an input or a
//! parameter does not fire: the references are taken again at the start of each call.
//!
//! Handling events allocates nothing either; it costs ten numbers per event, six
//! state vectors, the list's `K` events with two states each, and for
//! [`DormandPrince`] the continuous extension's five state vectors.
//!
//! ```
//! use bgdsl_runtime::rk::{DormandPrince, Rk4};
//! use bgdsl_runtime::{DormandPrinceOptions, FixedStep, Model, Scalar};
//!
//! /// Exponential decay, dx/dt = -x.
//! struct Decay;
//! impl Model for Decay {
//!     type Params = ();
//!     const NAME: &'static str = "decay";
//!     const STATE_NAMES: &'static [&'static str] = &["x"];
//!     const OUTPUT_NAMES: &'static [&'static str] = &[];
//!     fn params(&self) -> &() { &() }
//!     fn initial_state(&self, x0: &mut [f64]) { x0[0] = 1.0 }
//!     fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) { dx[0] = -x[0] }
//!     fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
//! }
//!
//! // Steps of 0.01 to t = 1.
//! let mut rk4 = Rk4::<1>::new(FixedStep::new(0.01))?;
//! let (mut t, mut x) = (0.0, [1.0]);
//! rk4.advance_to(&Decay, &mut t, &mut x, 1.0)?;
//! assert_eq!(t, 1.0);
//! assert!((x[0] - (-1.0f64).exp()).abs() < 1e-9);
//! assert_eq!(rk4.stats().accepted, 100);
//!
//! // Adaptive steps, in ten calls of 0.1 each.
//! let mut dopri = DormandPrince::<1>::new(DormandPrinceOptions::default())?;
//! let (mut t, mut x) = (0.0, [1.0]);
//! for k in 1..=10 {
//!     dopri.advance_to(&Decay, &mut t, &mut x, 0.1 * f64::from(k))?;
//! }
//! assert!((x[0] - (-1.0f64).exp()).abs() < 1e-7);
//! # Ok::<(), bgdsl_runtime::SolverError>(())
//! ```
//!
//! A ball dropped from 1 m onto a floor, rebounding with 0.9 of its impact speed: the
//! first impact at `√(2 / g)`, the second `2 · 0.9 · √(2 / g)` later.
//!
//! ```
//! use bgdsl_runtime::rk::DormandPrince;
//! use bgdsl_runtime::{
//!     Direction, DormandPrinceOptions, EventAction, EventInfo, Model, Scalar,
//! };
//!
//! struct Ball;
//! impl Model for Ball {
//!     type Params = ();
//!     const NAME: &'static str = "ball";
//!     const STATE_NAMES: &'static [&'static str] = &["h", "v"];
//!     const OUTPUT_NAMES: &'static [&'static str] = &[];
//!     const EVENTS: &'static [EventInfo] = &[EventInfo {
//!         name: "floor",
//!         direction: Direction::Falling,
//!         doc: "",
//!     }];
//!     fn params(&self) -> &() { &() }
//!     fn initial_state(&self, x0: &mut [f64]) { x0.copy_from_slice(&[1.0, 0.0]) }
//!     fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
//!         dx[0] = x[1];
//!         dx[1] = T::from_f64(-9.81);
//!     }
//!     fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
//!     fn event_indicators(&self, _t: f64, x: &[f64], g: &mut [f64]) { g[0] = x[0] }
//!     fn apply_event(&self, _i: usize, _t: f64, x: &mut [f64]) -> EventAction {
//!         x[1] *= -0.9;
//!         EventAction::Continue
//!     }
//! }
//!
//! let mut dopri = DormandPrince::<2, 1>::new(DormandPrinceOptions::default())?;
//! let (mut t, mut x) = (0.0, [1.0, 0.0]);
//! dopri.advance_to(&Ball, &mut t, &mut x, 1.5)?;
//! let t1 = (2.0 / 9.81f64).sqrt();
//! let times = dopri.events().times();
//! assert_eq!(times.len(), 2);
//! assert!((times[0] - t1).abs() < 1e-9);
//! assert!((times[1] - (t1 + 1.8 * t1)).abs() < 1e-9);
//! # Ok::<(), bgdsl_runtime::SolverError>(())
//! ```
//!
//! An integrator whose `E` is not the model's number of events does not compile:
//!
//! ```compile_fail
//! # use bgdsl_runtime::rk::Rk4;
//! # use bgdsl_runtime::{Direction, EventInfo, FixedStep, Model, Scalar};
//! # struct Ball;
//! # impl Model for Ball {
//! #     type Params = ();
//! #     const NAME: &'static str = "ball";
//! #     const STATE_NAMES: &'static [&'static str] = &["h", "v"];
//! #     const OUTPUT_NAMES: &'static [&'static str] = &[];
//! #     const EVENTS: &'static [EventInfo] = &[EventInfo {
//! #         name: "floor",
//! #         direction: Direction::Falling,
//! #         doc: "",
//! #     }];
//! #     fn params(&self) -> &() { &() }
//! #     fn initial_state(&self, x0: &mut [f64]) { x0.copy_from_slice(&[1.0, 0.0]) }
//! #     fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
//! #         dx[0] = x[1];
//! #         dx[1] = T::from_f64(-9.81);
//! #     }
//! #     fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
//! # }
//! // `Rk4::<2>` is `Rk4::<2, 0>`: no room for the ball's event.
//! let mut rk4 = Rk4::<2>::new(FixedStep::new(0.01)).unwrap();
//! let (mut t, mut x) = (0.0, [1.0, 0.0]);
//! rk4.advance_to(&Ball, &mut t, &mut x, 1.0).unwrap();
//! ```

mod events;

pub use events::CallEvents;

use crate::error::{SampleTimeProblem, SolverError};
use crate::event::{EventAction, EventOptions};
use crate::model::Model;
use crate::solver::control::{min_step, Adaptive, Grid, Run};
use crate::solver::explicit::{check_state, non_finite, Arrays, ExplicitRk, Storage};
use crate::solver::tableau::{DORMAND_PRINCE_5, RK4};
use crate::solver::{DormandPrinceOptions, FixedStep, Stats};
use events::Hybrid;

/// The events a call lists unless the integrator's `K` says otherwise.
pub const DEFAULT_CALL_EVENTS: usize = 4;

/// The classical fourth-order Runge–Kutta method with a fixed step, for a model with
/// `N` states and `E` events, listing up to `K` events per call, in a workspace of
/// arrays (twelve vectors of `N` numbers, ten of `E`, and the list's `K` events with
/// two states each, besides the settings and counters).
///
/// Events ([`crate::event`]) are located by re-taking the step that crossed from its
/// start with a shortened length; after an event the grid resumes (the next step ends
/// on the next grid point).
#[derive(Clone, Debug)]
pub struct Rk4<const N: usize, const E: usize = 0, const K: usize = DEFAULT_CALL_EVENTS> {
    kernel: ExplicitRk<Arrays<N, 4, 0>>,
    options: FixedStep,
    hybrid: Hybrid<N, E, K>,
    stats: Stats,
}

impl<const N: usize, const E: usize, const K: usize> Rk4<N, E, K> {
    /// An integrator with the step and step budget of `options`; fails with
    /// [`SolverError::InvalidOptions`] if a setting is out of range.
    pub fn new(options: FixedStep) -> Result<Self, SolverError> {
        options.validate()?;
        Ok(Rk4 {
            kernel: ExplicitRk::in_arrays(&RK4),
            options,
            hybrid: Hybrid::new(),
            stats: Stats::default(),
        })
    }

    /// The settings.
    pub fn options(&self) -> &FixedStep {
        &self.options
    }

    /// The work done since the integrator was made.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Sets how later calls locate events and when they give up on chattering ones
    /// ([`EventOptions`]; the defaults otherwise).
    ///
    /// # Errors
    ///
    /// An option is out of range ([`SolverError::InvalidOptions`]); the options are
    /// then unchanged.
    pub fn set_event_options(&mut self, options: EventOptions) -> Result<(), SolverError> {
        options.validate()?;
        self.hybrid.events.options = options;
        Ok(())
    }

    /// The event options calls use.
    pub fn event_options(&self) -> &EventOptions {
        &self.hybrid.events.options
    }

    /// The events of the last call, in time order ([the module's events](self#events)).
    pub fn events(&self) -> &CallEvents<N, K> {
        &self.hybrid.log
    }

    /// Makes the next call start its events afresh, wherever it starts (see [the
    /// module's events](self#events)).
    pub fn restart_events(&mut self) {
        self.hybrid.forget();
    }

    /// One step of size `h` from `(t, x)`, whatever the configured step: afterwards `t`
    /// is `t + h` and `x` the state there, or, if an event fires in the step, `t` is
    /// the event's time and `x` the state after its action. Fails if `h` is not
    /// finite or too small to advance the time, or if a stage meets a non-finite value
    /// (then `t` and `x` are left as they were), or as the events fail.
    pub fn step<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64; N],
        h: f64,
    ) -> Result<(), SolverError> {
        const { assert!(M::N_STATES == N, "N must be the model's N_STATES") };
        const { assert!(M::EVENTS.len() == E, "E must be the model's EVENTS.len()") };
        if !t.is_finite() {
            return Err(SolverError::NonFiniteStartTime { t0: *t });
        }
        if !h.is_finite() {
            return Err(SolverError::InvalidOptions {
                option: "h",
                value: h,
                expected: "a finite number > 0",
            });
        }
        if h < min_step(*t) {
            return Err(SolverError::FixedStepTooSmall { t: *t, step: h });
        }
        check_start::<M>(*t, x)?;
        self.hybrid.begin(model, *t, x, &mut self.stats)?;
        let t_a = *t;
        let t_new = t_a + h;
        self.kernel.restart();
        let n_rhs = &mut self.stats.n_rhs;
        self.kernel
            .prepare(model, t_a, x, n_rhs)
            .and_then(|()| self.kernel.attempt(model, t_a, t_new, x, n_rhs))
            .map_err(non_finite::<M>)?;
        self.hybrid.x_start = *x;
        self.kernel.accept(t_a, t_new, x, false);
        *t = t_new;
        self.stats.accepted += 1;
        self.hybrid
            .after_fixed_step(model, &mut self.kernel, t_a, t, x, &mut self.stats)?;
        self.hybrid.finish(*t, x);
        Ok(())
    }

    /// Integrates from `(t, x)` to `t_end` in steps of the configured size on the grid
    /// `t + k * step`, the last one shortened (or, within `1e-9` of a step, stretched)
    /// to end on `t_end` exactly. At most `max_steps` steps per call. An event whose
    /// action stops the run ends the call at its time (`t` is then the event's time,
    /// `x` the state after it).
    pub fn advance_to<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64; N],
        t_end: f64,
    ) -> Result<(), SolverError> {
        const { assert!(M::N_STATES == N, "N must be the model's N_STATES") };
        const { assert!(M::EVENTS.len() == E, "E must be the model's EVENTS.len()") };
        check_span(*t, t_end)?;
        check_start::<M>(*t, x)?;
        let mut grid = Grid::new(*t, t_end, &self.options)?;
        self.kernel.restart();
        let mut work = Stats::default();
        let (kernel, hybrid) = (&mut self.kernel, &mut self.hybrid);
        let mut steps = || {
            hybrid.begin(model, *t, x, &mut work)?;
            while *t < t_end {
                let t_a = *t;
                if E > 0 {
                    hybrid.x_start = *x;
                }
                let mut run = Run {
                    model,
                    kernel: &mut *kernel,
                    t: &mut *t,
                    x: &mut x[..],
                    stats: &mut work,
                    atol: None,
                    non_negative: &[],
                };
                let on_grid = run.fixed_step(&mut grid, t_end)?;
                let t_b = *t;
                match hybrid.after_fixed_step(model, kernel, t_a, t, x, &mut work)? {
                    Some(EventAction::Stop) => break,
                    // Cut short of its grid point: the next step ends on it.
                    Some(EventAction::Continue) if on_grid && *t < t_b => grid.step_back(),
                    _ => {}
                }
            }
            hybrid.finish(*t, x);
            Ok(())
        };
        let result = steps();
        self.stats.add(work);
        result
    }
}

/// Dormand–Prince 5(4) with adaptive step-size control (the method and PI controller of
/// Hairer's DOPRI5, as [`DormandPrinceOptions`] describes), for a model with `N`
/// states and `E` events, listing up to `K` events per call, in a workspace of arrays
/// (twenty vectors of `N` numbers, with the continuous extension events are located
/// on, ten of `E`, and the list's `K` events with two states each, besides the
/// settings, the step-size state and the counters).
///
/// Events ([`crate::event`]) are located on the continuous extension of the step that
/// crossed; after an event the step-size control starts afresh (a new first step).
#[derive(Clone, Debug)]
pub struct DormandPrince<const N: usize, const E: usize = 0, const K: usize = DEFAULT_CALL_EVENTS> {
    kernel: ExplicitRk<Arrays<N, 7, N>>,
    options: DormandPrinceOptions,
    /// One absolute tolerance per state ([`DormandPrince::set_atol`]), else `None`.
    atol: Option<[f64; N]>,
    /// The step-size controller and the next step size, once a step has been taken.
    adaptive: Option<Adaptive>,
    hybrid: Hybrid<N, E, K>,
    stats: Stats,
}

impl<const N: usize, const E: usize, const K: usize> DormandPrince<N, E, K> {
    /// An integrator with the tolerances and step-size control of `options`; fails with
    /// [`SolverError::InvalidOptions`] if a setting is out of range.
    pub fn new(options: DormandPrinceOptions) -> Result<Self, SolverError> {
        options.validate()?;
        Ok(DormandPrince {
            kernel: ExplicitRk::in_arrays(&DORMAND_PRINCE_5),
            options,
            atol: None,
            adaptive: None,
            hybrid: Hybrid::new(),
            stats: Stats::default(),
        })
    }

    /// The settings.
    pub fn options(&self) -> &DormandPrinceOptions {
        &self.options
    }

    /// The work done since the integrator was made.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Sets how later calls locate events and when they give up on chattering ones
    /// ([`EventOptions`]; the defaults otherwise).
    ///
    /// # Errors
    ///
    /// An option is out of range ([`SolverError::InvalidOptions`]); the options are
    /// then unchanged.
    pub fn set_event_options(&mut self, options: EventOptions) -> Result<(), SolverError> {
        options.validate()?;
        self.hybrid.events.options = options;
        Ok(())
    }

    /// The event options calls use.
    pub fn event_options(&self) -> &EventOptions {
        &self.hybrid.events.options
    }

    /// Gives every state of model `M` its own absolute tolerance for later calls, in
    /// place of the options' `atol`: the error norm weighs state `i` by
    /// `atol[i] + rtol max(|x_i|, |x_new_i|)`, as
    /// [`Simulation::set_atol`](crate::Simulation::set_atol) does in the driver (the
    /// same steps, bit for bit). `None` goes back to the options' `atol`. The array
    /// lives in the integrator: nothing is allocated. `M` names the states in errors.
    ///
    /// ```
    /// # use bgdsl_runtime::{Model, Scalar};
    /// # struct Decay;
    /// # impl Model for Decay {
    /// #     type Params = ();
    /// #     const NAME: &'static str = "decay";
    /// #     const STATE_NAMES: &'static [&'static str] = &["fast", "slow"];
    /// #     const OUTPUT_NAMES: &'static [&'static str] = &[];
    /// #     fn params(&self) -> &() { &() }
    /// #     fn initial_state(&self, x0: &mut [f64]) { x0.fill(1.0) }
    /// #     fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
    /// #         dx[0] = -T::from_f64(10.0) * x[0];
    /// #         dx[1] = -x[1];
    /// #     }
    /// #     fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    /// # }
    /// use bgdsl_runtime::rk::DormandPrince;
    /// use bgdsl_runtime::DormandPrinceOptions;
    ///
    /// let mut dopri = DormandPrince::<2>::new(DormandPrinceOptions::default())?;
    /// dopri.set_atol::<Decay>(Some([1e-12, 1e-6]))?;
    /// let err = dopri.set_atol::<Decay>(Some([1e-12, f64::NAN])).unwrap_err();
    /// assert_eq!(
    ///     err.to_string(),
    ///     "invalid absolute tolerance NaN for state `slow`: expected a finite number >= 0"
    /// );
    /// let (mut t, mut x) = (0.0, [1.0, 1.0]);
    /// dopri.advance_to(&Decay, &mut t, &mut x, 1.0)?;
    /// assert!((x[1] - (-1.0f64).exp()).abs() < 1e-5);
    /// # Ok::<(), bgdsl_runtime::SolverError>(())
    /// ```
    ///
    /// # Errors
    ///
    /// [`SolverError::InvalidAtol`] naming the first state whose entry is negative, not
    /// finite, or 0 with `rtol = 0`; the tolerances are then unchanged.
    pub fn set_atol<M: Model>(&mut self, atol: Option<[f64; N]>) -> Result<(), SolverError> {
        const { assert!(M::N_STATES == N, "N must be the model's N_STATES") };
        if let Some(atol) = &atol {
            crate::solver::check_atol(self.options.rtol, atol, M::STATE_NAMES)?;
        }
        self.atol = atol;
        Ok(())
    }

    /// The per-state absolute tolerances of [`DormandPrince::set_atol`], if set.
    pub fn atol(&self) -> Option<&[f64; N]> {
        self.atol.as_ref()
    }

    /// The events of the last call, in time order ([the module's events](self#events)).
    pub fn events(&self) -> &CallEvents<N, K> {
        &self.hybrid.log
    }

    /// The size of the next step the controller will attempt; `None` before the first
    /// step and after [`DormandPrince::restart`], when the next call chooses one
    /// (`initial_step`, or the heuristic of Hairer, Nørsett & Wanner).
    pub fn step_size(&self) -> Option<f64> {
        self.adaptive.map(|a| a.h)
    }

    /// Forgets the step size and the controller's history, so that the next call starts
    /// as the first did, and starts the events afresh (see [the module's
    /// events](self#events)). For after a jump in the model's inputs or state that the
    /// learnt step size says nothing about (rejected steps would also find that out,
    /// at some cost).
    pub fn restart(&mut self) {
        self.adaptive = None;
        self.hybrid.forget();
    }

    /// One accepted step from `(t, x)` towards `t_end`, never past it, with the
    /// step-size control of [`DormandPrince::advance_to`]. Attempts whose error is too
    /// large are rejected and retried shorter. If an event fires in the step, the step
    /// ends at the event (`t` its time, `x` the state after its action). Fails if the
    /// step size falls below the resolution of the time axis or a value is non-finite,
    /// or if `max_steps` attempts do not produce an accepted step, or as the events
    /// fail.
    ///
    /// Like every call, it evaluates the derivatives at `(t, x)` afresh: stepping one
    /// step at a time costs one evaluation per step more than
    /// [`DormandPrince::advance_to`], whose steps reuse the last stage of the step
    /// before (the method is "first same as last").
    pub fn step<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64; N],
        t_end: f64,
    ) -> Result<(), SolverError> {
        self.integrate(model, t, x, t_end, true)
    }

    /// Integrates from `(t, x)` to `t_end` (`t` is then `t_end` exactly), with steps
    /// chosen so that each meets the tolerances; the last one ends on `t_end`. At most
    /// `max_steps` attempts per call. Each call evaluates the derivatives at `(t, x)`
    /// afresh, so the model may have changed since the last one. An event whose
    /// action stops the run ends the call at its time (`t` is then the event's time,
    /// `x` the state after it).
    pub fn advance_to<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64; N],
        t_end: f64,
    ) -> Result<(), SolverError> {
        self.integrate(model, t, x, t_end, false)
    }

    /// [`DormandPrince::step`] (`once`) or [`DormandPrince::advance_to`].
    fn integrate<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64; N],
        t_end: f64,
        once: bool,
    ) -> Result<(), SolverError> {
        const { assert!(M::N_STATES == N, "N must be the model's N_STATES") };
        const { assert!(M::EVENTS.len() == E, "E must be the model's EVENTS.len()") };
        check_span(*t, t_end)?;
        check_start::<M>(*t, x)?;
        let mut work = Stats::default();
        let result = self.hybrid.begin(model, *t, x, &mut work).and_then(|()| {
            if *t == t_end {
                return Ok(());
            }
            self.kernel.restart();
            let mut run = Run {
                model,
                kernel: &mut self.kernel,
                t: &mut *t,
                x: &mut x[..],
                stats: &mut work,
                atol: self.atol.as_ref().map(|a| &a[..]),
                non_negative: &[],
            };
            let (adaptive, hybrid) = (&mut self.adaptive, &mut self.hybrid);
            adaptive_steps(&mut run, adaptive, &self.options, t_end, once, hybrid)
        });
        if result.is_ok() {
            self.hybrid.finish(*t, x);
        }
        self.stats.add(work);
        result
    }
}

/// Adaptive steps of `run` to `t_end` (or one step, if `once`), continuing with the
/// step-size state in `adaptive` or, if there is none yet, starting it; the events of
/// each step are handled by `hybrid` (after one, the step-size control starts afresh).
fn adaptive_steps<M: Model, S: Storage, const N: usize, const E: usize, const K: usize>(
    run: &mut Run<'_, M, S>,
    adaptive: &mut Option<Adaptive>,
    options: &DormandPrinceOptions,
    t_end: f64,
    once: bool,
    hybrid: &mut Hybrid<N, E, K>,
) -> Result<(), SolverError> {
    let a = match adaptive {
        Some(a) => {
            run.prepare()?;
            a
        }
        None => adaptive.insert(run.start_adaptive(options)?),
    };
    loop {
        let t_a = *run.t;
        // Locating an event needs the step's continuous extension.
        run.adaptive_step(a, t_end, |_| E > 0)?;
        let (model, kernel) = (run.model, &mut *run.kernel);
        match hybrid.after_dense_step(model, kernel, t_a, run.t, run.x, run.stats)? {
            None => {}
            Some(EventAction::Stop) => return Ok(()),
            // Nothing carries across an event: a new first step, a new controller.
            Some(EventAction::Continue) => *a = run.start_adaptive(options)?,
        }
        if once || *run.t >= t_end {
            return Ok(());
        }
    }
}

/// Checks the span of a call: a finite start, and an end that is finite and not
/// before it (reported as the call's one sample time).
fn check_span(t: f64, t_end: f64) -> Result<(), SolverError> {
    let problem = if !t.is_finite() {
        return Err(SolverError::NonFiniteStartTime { t0: t });
    } else if !t_end.is_finite() {
        SampleTimeProblem::NotFinite
    } else if t_end < t {
        SampleTimeProblem::BeforeStart { t0: t }
    } else {
        return Ok(());
    };
    Err(SolverError::InvalidSampleTimes {
        index: 0,
        t: t_end,
        problem,
    })
}

/// Checks that the state a call starts from is finite.
fn check_start<M: Model>(t: f64, x: &[f64]) -> Result<(), SolverError> {
    check_state(x, t).map_err(non_finite::<M>)
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::{Scalar, Simulation, Solver};

    /// A pendulum with damping, `θ'' = −sin θ − 0.1 θ'`: nonlinear, so the steps vary.
    struct Pendulum;

    impl Model for Pendulum {
        type Params = ();
        const NAME: &'static str = "pendulum";
        const STATE_NAMES: &'static [&'static str] = &["theta", "omega"];
        const OUTPUT_NAMES: &'static [&'static str] = &[];
        fn params(&self) -> &() {
            &()
        }
        fn initial_state(&self, x0: &mut [f64]) {
            x0.copy_from_slice(&[2.5, 0.0]);
        }
        fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
            dx[0] = x[1];
            dx[1] = -x[0].sin() - T::from_f64(0.1) * x[1];
        }
        fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    }

    /// The driver's final state and work for one run from `(0, [2.5, 0])` to `t_end`.
    fn driver(solver: Solver, t_end: f64) -> (Vec<f64>, Stats) {
        let mut sim = Simulation::new(&Pendulum, solver).unwrap();
        let stats = sim.run(0.0, &[2.5, 0.0], &[t_end], &mut ()).unwrap();
        (sim.state().to_vec(), stats)
    }

    #[test]
    fn rk4_steps_exactly_as_the_driver_does() {
        let options = FixedStep::new(0.03);
        let mut rk4 = Rk4::<2>::new(options).unwrap();
        let (mut t, mut x) = (0.0, [2.5, 0.0]);
        rk4.advance_to(&Pendulum, &mut t, &mut x, 10.0).unwrap();
        let (expected, stats) = driver(Solver::Rk4(options), 10.0);
        assert_eq!(t, 10.0);
        assert_eq!(x.as_slice(), expected.as_slice());
        assert_eq!(rk4.stats(), stats);
    }

    #[test]
    fn dormand_prince_steps_exactly_as_the_driver_does() {
        let options = DormandPrinceOptions {
            rtol: 1e-8,
            atol: 1e-10,
            ..DormandPrinceOptions::default()
        };
        let mut dopri = DormandPrince::<2>::new(options).unwrap();
        let (mut t, mut x) = (0.0, [2.5, 0.0]);
        dopri.advance_to(&Pendulum, &mut t, &mut x, 10.0).unwrap();
        let (expected, stats) = driver(Solver::DormandPrince(options), 10.0);
        assert_eq!(t, 10.0);
        assert_eq!(x.as_slice(), expected.as_slice());
        assert_eq!(dopri.stats(), stats);
        assert!(
            stats.rejected > 0,
            "the controller was exercised: {stats:?}"
        );
    }

    #[test]
    fn calls_in_ticks_restart_the_derivative_but_keep_the_step_size() {
        let mut dopri = DormandPrince::<2>::new(DormandPrinceOptions::default()).unwrap();
        let (mut t, mut x) = (0.0, [2.5, 0.0]);
        dopri.advance_to(&Pendulum, &mut t, &mut x, 1.0).unwrap();
        let (h, before) = (dopri.step_size().unwrap(), dopri.stats());
        dopri.advance_to(&Pendulum, &mut t, &mut x, 2.0).unwrap();
        let after = dopri.stats();
        // One evaluation to restart, six per attempt, none to choose a step size.
        assert_eq!(
            after.n_rhs - before.n_rhs,
            1 + 6 * (after.steps() - before.steps())
        );
        assert!(h > 0.0);
        dopri.restart();
        assert_eq!(dopri.step_size(), None);
        let before = dopri.stats();
        dopri.advance_to(&Pendulum, &mut t, &mut x, 3.0).unwrap();
        let after = dopri.stats();
        // After a restart, one more to choose the first step size again.
        assert_eq!(
            after.n_rhs - before.n_rhs,
            2 + 6 * (after.steps() - before.steps())
        );
    }

    #[test]
    fn a_single_step_goes_no_further_than_asked() {
        let mut rk4 = Rk4::<2>::new(FixedStep::new(0.1)).unwrap();
        let (mut t, mut x) = (0.0, [2.5, 0.0]);
        rk4.step(&Pendulum, &mut t, &mut x, 0.25).unwrap();
        assert_eq!(t, 0.25);
        assert_eq!(rk4.stats().accepted, 1);
        assert_eq!(rk4.stats().n_rhs, 4);
        let mut nan_time = f64::NAN;
        assert!(matches!(
            rk4.step(&Pendulum, &mut nan_time, &mut x, 0.1),
            Err(SolverError::NonFiniteStartTime { .. })
        ));
        assert!(matches!(
            rk4.step(&Pendulum, &mut t, &mut x, f64::INFINITY),
            Err(SolverError::InvalidOptions { option: "h", .. })
        ));
    }
}
