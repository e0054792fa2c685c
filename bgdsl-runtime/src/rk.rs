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
//! They do not handle events ([`Model::EVENTS`]): they integrate a model's modes as
//! the constants they are between events, but neither detect nor locate crossings nor
//! apply actions. A host on these integrators evaluates
//! [`Model::event_indicators`] between its calls itself; the std driver
//! ([`Simulation`](crate::Simulation), [`Stepper`](crate::Stepper)) handles events
//! fully.
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

use crate::error::{SampleTimeProblem, SolverError};
use crate::model::Model;
use crate::solver::control::{min_step, Adaptive, Grid, Run};
use crate::solver::explicit::{check_state, non_finite, Arrays, ExplicitRk, Storage};
use crate::solver::tableau::{DORMAND_PRINCE_5, RK4};
use crate::solver::{DormandPrinceOptions, FixedStep, Stats};

/// The classical fourth-order Runge–Kutta method with a fixed step, for a model with
/// `N` states, in a workspace of arrays (six vectors of `N` numbers, besides the
/// settings and counters).
#[derive(Clone, Debug)]
pub struct Rk4<const N: usize> {
    kernel: ExplicitRk<Arrays<N, 4>>,
    options: FixedStep,
    stats: Stats,
}

impl<const N: usize> Rk4<N> {
    /// An integrator with the step and step budget of `options`; fails with
    /// [`SolverError::InvalidOptions`] if a setting is out of range.
    pub fn new(options: FixedStep) -> Result<Self, SolverError> {
        options.validate()?;
        Ok(Rk4 {
            kernel: ExplicitRk::in_arrays(&RK4),
            options,
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

    /// One step of size `h` from `(t, x)`, whatever the configured step: afterwards `t`
    /// is `t + h` and `x` the state there. Fails if `h` is not finite or too small to
    /// advance the time, or if a stage meets a non-finite value (then `t` and `x` are
    /// left as they were).
    pub fn step<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64; N],
        h: f64,
    ) -> Result<(), SolverError> {
        const { assert!(M::N_STATES == N, "N must be the model's N_STATES") };
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
            return Err(SolverError::StepSizeTooSmall { t: *t, h });
        }
        check_start::<M>(*t, x)?;
        let t_new = *t + h;
        self.kernel.restart();
        let n_rhs = &mut self.stats.n_rhs;
        self.kernel
            .prepare(model, *t, x, n_rhs)
            .and_then(|()| self.kernel.attempt(model, *t, t_new, x, n_rhs))
            .map_err(non_finite::<M>)?;
        self.kernel.accept(*t, t_new, x, false);
        *t = t_new;
        self.stats.accepted += 1;
        Ok(())
    }

    /// Integrates from `(t, x)` to `t_end` in steps of the configured size on the grid
    /// `t + k * step`, the last one shortened (or, within `1e-9` of a step, stretched)
    /// to end on `t_end` exactly. At most `max_steps` steps per call.
    pub fn advance_to<M: Model>(
        &mut self,
        model: &M,
        t: &mut f64,
        x: &mut [f64; N],
        t_end: f64,
    ) -> Result<(), SolverError> {
        const { assert!(M::N_STATES == N, "N must be the model's N_STATES") };
        check_span(*t, t_end)?;
        check_start::<M>(*t, x)?;
        let mut grid = Grid::new(*t, t_end, &self.options)?;
        self.kernel.restart();
        let mut work = Stats::default();
        let result = Run {
            model,
            kernel: &mut self.kernel,
            t,
            x,
            stats: &mut work,
        }
        .fixed_steps_to(&mut grid, t_end);
        self.stats.add(work);
        result
    }
}

/// Dormand–Prince 5(4) with adaptive step-size control (the method and PI controller of
/// Hairer's DOPRI5, as [`DormandPrinceOptions`] describes), for a model with `N`
/// states, in a workspace of arrays (nine vectors of `N` numbers, besides the
/// settings, the step-size state and the counters).
#[derive(Clone, Debug)]
pub struct DormandPrince<const N: usize> {
    kernel: ExplicitRk<Arrays<N, 7>>,
    options: DormandPrinceOptions,
    /// The step-size controller and the next step size, once a step has been taken.
    adaptive: Option<Adaptive>,
    stats: Stats,
}

impl<const N: usize> DormandPrince<N> {
    /// An integrator with the tolerances and step-size control of `options`; fails with
    /// [`SolverError::InvalidOptions`] if a setting is out of range.
    pub fn new(options: DormandPrinceOptions) -> Result<Self, SolverError> {
        options.validate()?;
        Ok(DormandPrince {
            kernel: ExplicitRk::in_arrays(&DORMAND_PRINCE_5),
            options,
            adaptive: None,
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

    /// The size of the next step the controller will attempt; `None` before the first
    /// step and after [`DormandPrince::restart`], when the next call chooses one
    /// (`initial_step`, or the heuristic of Hairer, Nørsett & Wanner).
    pub fn step_size(&self) -> Option<f64> {
        self.adaptive.map(|a| a.h)
    }

    /// Forgets the step size and the controller's history, so that the next call starts
    /// as the first did. For after a jump in the model's inputs or state that the
    /// learnt step size says nothing about (rejected steps would also find that out,
    /// at some cost).
    pub fn restart(&mut self) {
        self.adaptive = None;
    }

    /// One accepted step from `(t, x)` towards `t_end`, never past it, with the
    /// step-size control of [`DormandPrince::advance_to`]. Attempts whose error is too
    /// large are rejected and retried shorter. Fails if the step size falls below the
    /// resolution of the time axis or a value is non-finite, or if `max_steps`
    /// attempts do not produce an accepted step.
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
    /// afresh, so the model may have changed since the last one.
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
        check_span(*t, t_end)?;
        check_start::<M>(*t, x)?;
        if *t == t_end {
            return Ok(());
        }
        self.kernel.restart();
        let mut work = Stats::default();
        let mut run = Run {
            model,
            kernel: &mut self.kernel,
            t,
            x,
            stats: &mut work,
        };
        let result = adaptive_steps(&mut run, &mut self.adaptive, &self.options, t_end, once);
        self.stats.add(work);
        result
    }
}

/// Adaptive steps of `run` to `t_end` (or one step, if `once`), continuing with the
/// step-size state in `adaptive` or, if there is none yet, starting it.
fn adaptive_steps<M: Model, S: Storage>(
    run: &mut Run<'_, M, S>,
    adaptive: &mut Option<Adaptive>,
    options: &DormandPrinceOptions,
    t_end: f64,
    once: bool,
) -> Result<(), SolverError> {
    let a = match adaptive {
        Some(a) => {
            run.prepare()?;
            a
        }
        None => adaptive.insert(run.start_adaptive(options)?),
    };
    loop {
        run.adaptive_step(a, t_end, |_| false)?;
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
