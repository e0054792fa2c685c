//! The driver: owns the workspace, the sampling loop, step-size control and the
//! statistics. The explicit methods live in [`super::explicit`]; the stiff ones in
//! [`super::stiff`], whose own loop (Newton-aware step-size control, Jacobian and LU
//! reuse) the driver calls one accepted step at a time.

use super::control::{project, Grid, Run};
use super::events::{Events, HeapEvents};
use super::explicit::{check_state, non_finite, ExplicitRk, Heap};
use super::options::{DormandPrinceOptions, FixedStep, Solver};
use super::stats::Stats;
use super::stiff::{Radau5, Rodas4, Rodas5P, Rosenbrock, StiffIntegrator, StiffKernel};
use super::stiffness;
use super::tableau::{DORMAND_PRINCE_5, RK4};
use super::weights::Tolerances;
use crate::error::{SampleTimeProblem, SolverError};
use crate::event::{EventAction, EventOptions};
use crate::model::Model;
use crate::record::{Recorder, Trajectory};

/// A model paired with a solver and all the memory a run needs.
///
/// [`Simulation::new`] allocates every buffer (stage vectors, state, interpolation and
/// output buffers); [`Simulation::run`] allocates nothing, so with a recorder that does
/// not allocate (a [`Trajectory`] created with enough capacity) a run is free of heap
/// allocation. A simulation can be run any number of times.
///
/// Every method handles the model's events ([`crate::event`]): after each step the
/// indicators are checked, a crossing is located and its action applied, and the
/// method restarts from the state after it; [`Simulation::set_event_options`] bounds
/// how many events a run handles and when it gives up on chattering ones.
///
/// ```
/// use bgdsl_runtime::{Model, Scalar, Simulation, Solver, Trajectory};
///
/// /// Exponential decay, dx/dt = -x.
/// struct Decay;
/// impl Model for Decay {
///     type Params = ();
///     const NAME: &'static str = "decay";
///     const STATE_NAMES: &'static [&'static str] = &["x"];
///     const OUTPUT_NAMES: &'static [&'static str] = &["twice_x"];
///     fn params(&self) -> &() { &() }
///     fn initial_state(&self, x0: &mut [f64]) { x0[0] = 1.0 }
///     fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) { dx[0] = -x[0] }
///     fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
///         y[0] = T::from_f64(2.0) * x[0]
///     }
/// }
///
/// let mut sim = Simulation::new(&Decay, Solver::dopri5())?;
/// let mut traj = Trajectory::for_model::<Decay>(11);
/// let stats = sim.run_uniform(0.0, &[1.0], 1.0, 11, &mut traj)?;
/// assert_eq!(traj.len(), 11);
/// assert!((traj.value(10, "x").unwrap() - (-1.0f64).exp()).abs() < 1e-7);
/// assert!(stats.accepted > 0);
/// # Ok::<(), bgdsl_runtime::SolverError>(())
/// ```
pub struct Simulation<'m, M: Model> {
    model: Held<'m, M>,
    solver: Solver,
    kernel: Kernel,
    /// The current state.
    x: Vec<f64>,
    /// The current time.
    t: f64,
    /// An interpolated state.
    x_dense: Vec<f64>,
    /// The outputs at a sample.
    y: Vec<f64>,
    stats: Stats,
    /// The event bookkeeping (inactive for a model without events).
    events: Events<HeapEvents>,
    /// The state at the start of the last step (fixed-step methods re-take the step
    /// from it to locate an event).
    x_start: Vec<f64>,
    /// The next run continues the last one's events ([`Simulation::continue_events`]).
    resume_events: bool,
    /// One absolute tolerance per state ([`Simulation::set_atol`]); `None` for the
    /// solver options' `atol`.
    atol: Option<Vec<f64>>,
    /// The states that must stay `>= 0` ([`Simulation::set_non_negative`]).
    non_negative: Vec<usize>,
}

/// What a run does after a step, once its events are handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Flow {
    /// No event: step on.
    Continue,
    /// An event cut the step short: the method starts afresh from the state after it.
    Restart,
    /// An event's action ended the run.
    Stop,
}

/// The model a simulation integrates: the caller's, borrowed, or its own.
enum Held<'m, M> {
    Borrowed(&'m M),
    Owned(M),
}

impl<M> Held<'_, M> {
    /// Borrows only this field, so the workspace beside it can be borrowed mutably.
    fn get(&self) -> &M {
        match self {
            Held::Borrowed(model) => model,
            Held::Owned(model) => model,
        }
    }
}

impl<M: Model> core::fmt::Debug for Simulation<'_, M> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Simulation")
            .field("model", &M::NAME)
            .field("solver", &self.solver)
            .field("t", &self.t)
            .field("x", &self.x)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

/// The method's workspace. One per simulation, so the variants' sizes do not matter.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)]
enum Kernel {
    Explicit(ExplicitRk<Heap>),
    Stiff(StiffKernel),
}

impl Kernel {
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        match self {
            Kernel::Explicit(k) => k.interpolate(t, out),
            Kernel::Stiff(k) => k.interpolate(t, out),
        }
    }
}

/// The explicit kernel (the solver is an explicit one).
fn explicit(kernel: &mut Kernel) -> &mut ExplicitRk<Heap> {
    match kernel {
        Kernel::Explicit(k) => k,
        Kernel::Stiff(_) => unreachable!("an explicit solver has an explicit kernel"),
    }
}

/// The stiff kernel (the solver is a stiff one).
fn stiff(kernel: &mut Kernel) -> &mut StiffKernel {
    match kernel {
        Kernel::Stiff(k) => k,
        Kernel::Explicit(_) => unreachable!("a stiff solver has a stiff kernel"),
    }
}

/// The sample times of a run: a list, or a uniform grid computed on the fly.
#[derive(Clone, Copy, Debug)]
enum Samples<'a> {
    Listed(&'a [f64]),
    Uniform { t0: f64, t_end: f64, n: usize },
}

impl Samples<'_> {
    fn len(&self) -> usize {
        match self {
            Samples::Listed(s) => s.len(),
            Samples::Uniform { n, .. } => *n,
        }
    }

    fn get(&self, i: usize) -> f64 {
        match *self {
            Samples::Listed(s) => s[i],
            Samples::Uniform { t0, t_end, n } => {
                if i == 0 {
                    t0
                } else if i + 1 == n {
                    t_end
                } else {
                    let frac = i as f64 / (n - 1) as f64;
                    (t0 + (t_end - t0) * frac).min(t_end)
                }
            }
        }
    }

    /// Checks that there is a sample time, and that the sample times are finite,
    /// `>= t0` and non-decreasing.
    fn validate(&self, t0: f64) -> Result<(), SolverError> {
        if self.len() == 0 {
            return Err(SolverError::NoSampleTimes);
        }
        let mut previous = t0;
        for index in 0..self.len() {
            let t = self.get(index);
            let problem = if !t.is_finite() {
                Some(SampleTimeProblem::NotFinite)
            } else if t < t0 {
                Some(SampleTimeProblem::BeforeStart { t0 })
            } else if t < previous {
                Some(SampleTimeProblem::Decreasing { previous })
            } else {
                None
            };
            if let Some(problem) = problem {
                return Err(SolverError::InvalidSampleTimes { index, t, problem });
            }
            previous = t;
        }
        Ok(())
    }
}

/// `n` sample times evenly spaced from `t0` to `t_end`, both included (`n = 1` gives
/// `[t0]`, `n = 0` nothing). The last one is exactly `t_end`.
/// [`Simulation::run_uniform`] uses the same times without storing them.
pub fn sample_times_uniform(t0: f64, t_end: f64, n: usize) -> Vec<f64> {
    let samples = Samples::Uniform { t0, t_end, n };
    (0..n).map(|i| samples.get(i)).collect()
}

impl<'m, M: Model> Simulation<'m, M> {
    /// A simulation of `model` with the model's own [`Model::default_solver`].
    pub fn with_default_solver(model: &'m M) -> Result<Self, SolverError> {
        Self::new(model, model.default_solver())
    }

    /// Checks the solver's options and allocates the workspace for `model`.
    pub fn new(model: &'m M, solver: Solver) -> Result<Self, SolverError> {
        Self::with_model(Held::Borrowed(model), solver)
    }

    /// Like [`Simulation::new`], but the simulation owns the model, so the host can
    /// change it between runs ([`Simulation::model_mut`]): its inputs, its parameters.
    pub fn owning(model: M, solver: Solver) -> Result<Self, SolverError> {
        Self::with_model(Held::Owned(model), solver)
    }

    fn with_model(held: Held<'m, M>, solver: Solver) -> Result<Self, SolverError> {
        let model = held.get();
        solver.validate()?;
        let n = M::N_STATES;
        let kernel = match solver {
            Solver::Rk4(_) => Kernel::Explicit(ExplicitRk::new(&RK4, n)),
            Solver::DormandPrince(_) | Solver::DormandPrinceFixed(_) => {
                Kernel::Explicit(ExplicitRk::new(&DORMAND_PRINCE_5, n))
            }
            Solver::Radau5(o) => {
                let method = |structure: &_| Radau5::new(n, structure, &o);
                let integrator = StiffIntegrator::new(model, method, o.common());
                Kernel::Stiff(StiffKernel::Radau5(Box::new(integrator)))
            }
            Solver::Rodas4(o) => {
                let method = |structure: &_| Rosenbrock::<Rodas4>::new(n, structure, &o);
                let integrator = StiffIntegrator::new(model, method, o.common());
                Kernel::Stiff(StiffKernel::Rodas4(Box::new(integrator)))
            }
            Solver::Rodas5P(o) => {
                let method = |structure: &_| Rosenbrock::<Rodas5P>::new(n, structure, &o);
                let integrator = StiffIntegrator::new(model, method, o.common());
                Kernel::Stiff(StiffKernel::Rodas5P(Box::new(integrator)))
            }
        };
        Ok(Simulation {
            model: held,
            solver,
            kernel,
            x: vec![0.0; n],
            t: 0.0,
            x_dense: vec![0.0; n],
            y: vec![0.0; M::N_OUTPUTS],
            stats: Stats::default(),
            events: Events::new::<M>(),
            x_start: vec![0.0; n],
            resume_events: false,
            atol: None,
            non_negative: Vec::new(),
        })
    }

    /// The model.
    pub fn model(&self) -> &M {
        self.model.get()
    }

    /// The model, to change between runs, if the simulation owns it
    /// ([`Simulation::owning`]); `None` for a borrowed one.
    pub fn model_mut(&mut self) -> Option<&mut M> {
        match &mut self.model {
            Held::Borrowed(_) => None,
            Held::Owned(model) => Some(model),
        }
    }

    /// The solver and its settings.
    pub fn solver(&self) -> &Solver {
        &self.solver
    }

    /// Sets how later runs locate events and when they give up on chattering ones
    /// ([`EventOptions`]; the defaults otherwise).
    ///
    /// # Errors
    ///
    /// An option is out of range ([`SolverError::InvalidOptions`]); the options are
    /// then unchanged.
    pub fn set_event_options(&mut self, options: EventOptions) -> Result<(), SolverError> {
        options.validate()?;
        self.events.options = options;
        Ok(())
    }

    /// Makes the next run continue the events of the last one, which ended where the
    /// next starts (a [`Stepper`](crate::Stepper)'s next advance): see
    /// [`crate::event`]'s references.
    pub(crate) fn continue_events(&mut self) {
        self.resume_events = true;
    }

    /// Gives every state its own absolute tolerance for later runs, replacing the
    /// solver options' `atol` (one per state, in the order of
    /// [`Model::STATE_NAMES`]): each error weight is then `atol[i] + rtol |x_i|`
    /// ([`Solver::Radau5`] transforms them as it does its `atol`). An entry may be 0
    /// when `rtol > 0`, for a state only relative accuracy makes sense for; such a
    /// state must not be zero where it changes (a zero weight asks for an exact
    /// value, and the run fails with [`SolverError::StepUnderflow`] naming it).
    ///
    /// ```
    /// # use bgdsl_runtime::{Model, Scalar, Simulation, Solver};
    /// # struct Decay;
    /// # impl Model for Decay {
    /// #     type Params = ();
    /// #     const NAME: &'static str = "decay";
    /// #     const STATE_NAMES: &'static [&'static str] = &["fast", "slow"];
    /// #     const OUTPUT_NAMES: &'static [&'static str] = &[];
    /// #     fn params(&self) -> &() { &() }
    /// #     fn initial_state(&self, x0: &mut [f64]) { x0.fill(1.0) }
    /// #     fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
    /// #         dx[0] = -T::from_f64(1e3) * x[0];
    /// #         dx[1] = -x[1];
    /// #     }
    /// #     fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    /// # }
    /// let mut sim = Simulation::new(&Decay, Solver::stiff())?;
    /// sim.set_atol(&[1e-12, 1e-6])?;
    /// let err = sim.set_atol(&[1e-12, -1.0]).unwrap_err();
    /// assert_eq!(
    ///     err.to_string(),
    ///     "invalid absolute tolerance -1 for state `slow`: expected a finite number >= 0"
    /// );
    /// # Ok::<(), bgdsl_runtime::SolverError>(())
    /// ```
    ///
    /// # Errors
    ///
    /// [`SolverError::StateListLength`] when `atol` does not have one entry per state;
    /// [`SolverError::InvalidAtol`] naming the first state whose entry is negative, not
    /// finite, or 0 with `rtol = 0`; [`SolverError::UnsupportedSetting`] for the
    /// fixed-step methods, which control no error. The tolerances are then unchanged.
    pub fn set_atol(&mut self, atol: &[f64]) -> Result<(), SolverError> {
        let rtol = match self.solver {
            Solver::DormandPrince(o) => o.rtol,
            Solver::Radau5(o) => o.rtol,
            Solver::Rodas4(o) | Solver::Rodas5P(o) => o.rtol,
            Solver::Rk4(_) | Solver::DormandPrinceFixed(_) => {
                return Err(SolverError::UnsupportedSetting {
                    setting: "set_atol",
                    solver: self.solver.name(),
                    why: "a fixed-step method controls no error",
                })
            }
        };
        if atol.len() != M::N_STATES {
            return Err(SolverError::StateListLength {
                what: "atol",
                expected: M::N_STATES,
                found: atol.len(),
            });
        }
        super::options::check_atol(rtol, atol, M::STATE_NAMES)?;
        if let Kernel::Stiff(k) = &mut self.kernel {
            k.set_tolerances(&Tolerances {
                rtol,
                atol: atol.to_vec(),
            });
        }
        self.atol = Some(atol.to_vec());
        Ok(())
    }

    /// The per-state absolute tolerances of [`Simulation::set_atol`], if set.
    pub fn atol(&self) -> Option<&[f64]> {
        self.atol.as_deref()
    }

    /// Makes later runs keep the states `states` (indices into
    /// [`Model::STATE_NAMES`]) non-negative, as concentrations, masses and amounts
    /// must be: a step that takes one below zero by more than its error weight
    /// (`atol_i + rtol |x_i|`) is rejected and retried shorter (0.9 times the fraction
    /// of the step at which the state crosses zero, at least 0.1 of it), and a step
    /// that takes one below zero within it is accepted with that state set to zero
    /// (the derivative is evaluated afresh there). This is the approach of SUNDIALS'
    /// constraints option and of Shampine et al., "Non-negative solutions of ODEs"
    /// (Appl. Math. Comput. 170, 2005). Samples between steps come from the method's
    /// continuous extension, which may dip below zero within the tolerance: they are
    /// recorded with those states set to zero too. An empty list removes the
    /// constraint.
    ///
    /// # Errors
    ///
    /// [`SolverError::UnknownState`] for an index out of range;
    /// [`SolverError::UnsupportedSetting`] for the fixed-step methods, which cannot
    /// reject a step. The constraint is then unchanged.
    pub fn set_non_negative(&mut self, states: &[usize]) -> Result<(), SolverError> {
        if matches!(self.solver, Solver::Rk4(_) | Solver::DormandPrinceFixed(_)) {
            return Err(SolverError::UnsupportedSetting {
                setting: "set_non_negative",
                solver: self.solver.name(),
                why: "a fixed-step method cannot reject a step that goes below zero",
            });
        }
        if let Some(&index) = states.iter().find(|&&i| i >= M::N_STATES) {
            return Err(SolverError::UnknownState {
                what: "set_non_negative",
                index,
                n_states: M::N_STATES,
            });
        }
        self.non_negative.clear();
        self.non_negative.extend_from_slice(states);
        self.non_negative.sort_unstable();
        self.non_negative.dedup();
        if let Kernel::Stiff(k) = &mut self.kernel {
            k.set_non_negative(&self.non_negative);
        }
        Ok(())
    }

    /// The states runs keep non-negative ([`Simulation::set_non_negative`]), sorted.
    pub fn non_negative(&self) -> &[usize] {
        &self.non_negative
    }

    /// The event options runs use.
    pub fn event_options(&self) -> &EventOptions {
        &self.events.options
    }

    /// The time the last run reached: its last sample time, the time of an event that
    /// stopped it, or where it failed.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The state at [`Simulation::time`].
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// The work done by the last run, also when it failed.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Integrates from `(t0, x0)` through `sample_times` (at least one, finite, `>= t0`,
    /// non-decreasing; else [`SolverError::NoSampleTimes`] or
    /// [`SolverError::InvalidSampleTimes`] before any step), calling `recorder` at every sample time with the time, the state
    /// and the outputs ([`Model::outputs`]). Sample times equal to `t0` record `x0`.
    ///
    /// On error the recorder holds the samples before the failure and
    /// [`Simulation::time`], [`Simulation::state`] and [`Simulation::stats`] tell where
    /// the run stopped.
    pub fn run<R: Recorder + ?Sized>(
        &mut self,
        t0: f64,
        x0: &[f64],
        sample_times: &[f64],
        recorder: &mut R,
    ) -> Result<Stats, SolverError> {
        self.run_samples(t0, x0, Samples::Listed(sample_times), recorder)
    }

    /// Like [`Simulation::run`] with the `n` sample times of
    /// [`sample_times_uniform(t0, t_end, n)`](sample_times_uniform), computed on the fly.
    pub fn run_uniform<R: Recorder + ?Sized>(
        &mut self,
        t0: f64,
        x0: &[f64],
        t_end: f64,
        n: usize,
        recorder: &mut R,
    ) -> Result<Stats, SolverError> {
        self.run_samples(t0, x0, Samples::Uniform { t0, t_end, n }, recorder)
    }

    fn run_samples<R: Recorder + ?Sized>(
        &mut self,
        t0: f64,
        x0: &[f64],
        samples: Samples<'_>,
        recorder: &mut R,
    ) -> Result<Stats, SolverError> {
        self.stats = Stats::default();
        let resume_events = core::mem::take(&mut self.resume_events);
        if x0.len() != M::N_STATES {
            return Err(SolverError::StateLengthMismatch {
                model: M::NAME,
                expected: M::N_STATES,
                found: x0.len(),
            });
        }
        if !t0.is_finite() {
            return Err(SolverError::NonFiniteStartTime { t0 });
        }
        samples.validate(t0)?;
        self.t = t0;
        self.x.copy_from_slice(x0);
        check_state(&self.x, t0).map_err(non_finite::<M>)?;
        self.model
            .get()
            .check(t0, &self.x)
            .map_err(SolverError::InvalidModel)?;
        if let Kernel::Explicit(k) = &mut self.kernel {
            k.restart();
        }
        if self.events.active() {
            let model = self.model.get();
            if resume_events {
                self.events.resume(model, t0, &self.x, &mut self.stats)?;
            } else {
                self.events.reset(model, t0, &self.x, &mut self.stats)?;
            }
        }
        match self.solver {
            Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => self
                .run_fixed(o, samples, recorder)
                .map_err(|cause| self.diagnose_fixed(cause, o.step, t0, x0))?,
            Solver::DormandPrince(o) => self.run_adaptive(&o, samples, recorder)?,
            Solver::Radau5(_) | Solver::Rodas4(_) | Solver::Rodas5P(_) => {
                self.run_stiff(samples, recorder)?
            }
        }
        Ok(self.stats)
    }

    /// A fixed-step failure that stiffness explains (non-finite values, with `step`
    /// beyond the method's stability limit on the largest eigenvalue of the Jacobian at
    /// the start `(t0, x0)`) becomes [`SolverError::ProbablyStiff`]; any other (a step
    /// below the time axis' resolution, events, budgets) is returned as it is.
    fn diagnose_fixed(&self, cause: SolverError, step: f64, t0: f64, x0: &[f64]) -> SolverError {
        let explicable = matches!(cause, SolverError::NonFiniteState { .. });
        if !explicable {
            // Events, budgets: nothing stiffness explains (and no estimate to allocate).
            return cause;
        }
        let bound = match self.solver {
            Solver::Rk4(_) => stiffness::RK4_STABILITY,
            _ => stiffness::DOPRI5_STABILITY,
        };
        match stiffness::spectral_radius(self.model.get(), t0, x0) {
            Some(rho) if rho * step > bound => SolverError::ProbablyStiff {
                cause: Box::new(cause),
                method: self.solver.name(),
                step,
                spectral_radius: rho,
                stable_step: bound / rho,
            },
            _ => cause,
        }
    }

    /// Fixed steps on the grid `t0 + k * step`, each shortened to end on a sample time
    /// it would pass, or cut short by an event (the grid then resumes: the next step
    /// ends on the next grid point).
    fn run_fixed<R: Recorder + ?Sized>(
        &mut self,
        o: FixedStep,
        samples: Samples<'_>,
        recorder: &mut R,
    ) -> Result<(), SolverError> {
        let n = samples.len();
        if n == 0 {
            return Ok(());
        }
        let mut grid = Grid::new(self.t, samples.get(n - 1), &o)?;
        let mut next = 0;
        loop {
            while next < n && samples.get(next) <= self.t {
                self.emit(samples.get(next), false, recorder)?;
                next += 1;
            }
            if next == n {
                return Ok(());
            }
            let t_a = self.t;
            if self.events.active() {
                self.x_start.copy_from_slice(&self.x);
            }
            let on_grid = self
                .explicit_run()
                .fixed_step(&mut grid, samples.get(next))?;
            let t_b = self.t;
            match self.handle_events(t_a, true, samples, &mut next, recorder)? {
                Flow::Continue => {}
                Flow::Stop => return Ok(()),
                Flow::Restart => {
                    if on_grid && self.t < t_b {
                        grid.step_back();
                    }
                    explicit(&mut self.kernel).restart();
                }
            }
        }
    }

    /// Adaptive steps with the PI controller of Hairer's DOPRI5; samples inside a step
    /// come from the continuous extension, and the last step ends on the last sample.
    fn run_adaptive<R: Recorder + ?Sized>(
        &mut self,
        o: &DormandPrinceOptions,
        samples: Samples<'_>,
        recorder: &mut R,
    ) -> Result<(), SolverError> {
        let n = samples.len();
        let mut next = 0;
        while next < n && samples.get(next) <= self.t {
            self.emit(samples.get(next), false, recorder)?;
            next += 1;
        }
        if next == n {
            return Ok(());
        }
        let t_end = samples.get(n - 1);
        let mut adaptive = self.explicit_run().start_adaptive(o)?;
        // Locating events needs every step's dense output.
        let always_dense = self.events.active();
        loop {
            // Interpolate only for a step that passes a sample time.
            let sample = samples.get(next);
            let t_a = self.t;
            self.explicit_run()
                .adaptive_step(&mut adaptive, t_end, |t_new| always_dense || sample < t_new)?;
            let flow = self.handle_events(t_a, false, samples, &mut next, recorder)?;
            if flow == Flow::Stop {
                return Ok(());
            }
            let t_new = self.t;
            while next < n && samples.get(next) <= t_new {
                let ts = samples.get(next);
                self.emit(ts, ts < t_new, recorder)?;
                next += 1;
            }
            if next == n {
                return Ok(());
            }
            if flow == Flow::Restart {
                explicit(&mut self.kernel).restart();
                adaptive = self.explicit_run().start_adaptive(o)?;
            }
        }
    }

    /// The explicit kernel with the model, the current point and the statistics.
    fn explicit_run(&mut self) -> Run<'_, M, Heap> {
        Run {
            model: self.model.get(),
            kernel: explicit(&mut self.kernel),
            t: &mut self.t,
            x: &mut self.x,
            stats: &mut self.stats,
            atol: self.atol.as_deref(),
            non_negative: &self.non_negative,
        }
    }

    /// Steps of a stiff method, each one accepted step of its own loop (which owns the
    /// step-size control); samples inside a step come from the method's continuous
    /// extension, and the last step ends on the last sample.
    fn run_stiff<R: Recorder + ?Sized>(
        &mut self,
        samples: Samples<'_>,
        recorder: &mut R,
    ) -> Result<(), SolverError> {
        let n = samples.len();
        let mut next = 0;
        while next < n && samples.get(next) <= self.t {
            self.emit(samples.get(next), false, recorder)?;
            next += 1;
        }
        if next == n {
            return Ok(());
        }
        let t_end = samples.get(n - 1);
        stiff(&mut self.kernel).start(self.model.get(), self.t, &self.x, t_end, &mut self.stats)?;
        loop {
            let t_a = self.t;
            stiff(&mut self.kernel).step(
                self.model.get(),
                &mut self.t,
                &mut self.x,
                t_end,
                &mut self.stats,
            )?;
            let flow = self.handle_events(t_a, false, samples, &mut next, recorder)?;
            if flow == Flow::Stop {
                return Ok(());
            }
            let t_new = self.t;
            while next < n && samples.get(next) <= t_new {
                let ts = samples.get(next);
                self.emit(ts, ts < t_new, recorder)?;
                next += 1;
            }
            if next == n {
                return Ok(());
            }
            if flow == Flow::Restart {
                let model = self.model.get();
                stiff(&mut self.kernel).restart(model, self.t, &self.x, t_end, &mut self.stats)?;
            }
        }
    }

    /// Handles the events of the step just accepted from `t_a`: detects them at its
    /// end, locates the earliest crossing (on the step's dense output, or, for a
    /// fixed-step method (`refit`), by re-taking the step from `t_a` with a shortened
    /// length), records the samples before it from the dense output, moves the run to
    /// the event and applies the actions. On [`Flow::Stop`] the samples at the event's
    /// time (or one there, if none is asked for) are recorded, with the state after it.
    fn handle_events<R: Recorder + ?Sized>(
        &mut self,
        t_a: f64,
        refit: bool,
        samples: Samples<'_>,
        next: &mut usize,
        recorder: &mut R,
    ) -> Result<Flow, SolverError> {
        let model = self.model.get();
        if !self.events.active() {
            return Ok(Flow::Continue);
        }
        let (events, stats) = (&mut self.events, &mut self.stats);
        let found = if refit {
            events.check(model, t_a, self.t, &self.x, None, stats)?
        } else {
            let kernel = &self.kernel;
            let mut dense = |t: f64, out: &mut [f64]| {
                kernel.interpolate(t, out);
                Ok(())
            };
            events.check(model, t_a, self.t, &self.x, Some(&mut dense), stats)?
        };
        let Some(t_b) = found else {
            return Ok(Flow::Continue);
        };
        let t_star = if refit {
            let kernel = explicit(&mut self.kernel);
            events.locate_by_restep(model, kernel, t_a, &self.x_start, t_b, stats)?
        } else {
            let kernel = &self.kernel;
            let dense = |t: f64, out: &mut [f64]| {
                kernel.interpolate(t, out);
                Ok(())
            };
            events.locate(model, t_a, t_b, dense, &mut stats.n_event_fn)?
        };
        let n = samples.len();
        while *next < n && samples.get(*next) < t_star {
            self.emit(samples.get(*next), true, recorder)?;
            *next += 1;
        }
        self.t = t_star;
        let model = self.model.get();
        // Rearmed also before a stop: a stepper's next advance continues from here.
        let action = self.events.fire(
            model,
            t_star,
            &mut self.x,
            |record| recorder.event(record),
            &mut self.stats,
        )?;
        if action == EventAction::Stop {
            let mut recorded = false;
            while *next < n && samples.get(*next) <= t_star {
                self.emit(samples.get(*next), false, recorder)?;
                *next += 1;
                recorded = true;
            }
            if !recorded {
                self.emit(t_star, false, recorder)?;
            }
            return Ok(Flow::Stop);
        }
        Ok(Flow::Restart)
    }

    /// Records the sample at `t`: the current state, or (`dense`) the continuous
    /// extension of the last step.
    /// Fails with [`SolverError::Stopped`] when the recorder asks the run to stop.
    fn emit<R: Recorder + ?Sized>(
        &mut self,
        t: f64,
        dense: bool,
        recorder: &mut R,
    ) -> Result<(), SolverError> {
        let x = if dense {
            self.kernel.interpolate(t, &mut self.x_dense);
            // The continuous extension may dip below zero within the tolerance.
            project(&self.non_negative, &mut self.x_dense);
            &self.x_dense
        } else {
            &self.x
        };
        let model = self.model.get();
        model.outputs::<f64>(t, x, &mut self.y);
        if self.y.iter().any(|v| !v.is_finite()) {
            if let Some(cause) = model.evaluation_error() {
                return Err(SolverError::InvalidModel(cause));
            }
        }
        recorder.record(t, x, &self.y);
        if recorder.stop_requested() {
            return Err(SolverError::Stopped { t });
        }
        Ok(())
    }
}

/// Simulates `model` from its declared initial state at `t0` to `t_end` with `solver`,
/// recording `n` evenly spaced samples ([`sample_times_uniform`]) into a
/// [`Trajectory`]. `n = 0` is [`SolverError::NoSampleTimes`] (a run that records
/// nothing is a mistake, not an empty success).
pub fn simulate<M: Model>(
    model: &M,
    solver: Solver,
    t0: f64,
    t_end: f64,
    n: usize,
) -> Result<Trajectory, SolverError> {
    let mut sim = Simulation::new(model, solver)?;
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut trajectory = Trajectory::for_model::<M>(n);
    sim.run_uniform(t0, &x0, t_end, n, &mut trajectory)?;
    Ok(trajectory)
}
