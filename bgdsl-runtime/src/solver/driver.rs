//! The driver: owns the workspace, the sampling loop, step-size control and the
//! statistics. The explicit methods live in [`super::explicit`]; the stiff ones in
//! [`super::stiff`], whose own loop (Newton-aware step-size control, Jacobian and LU
//! reuse) the driver calls one accepted step at a time.

use super::explicit::{check_state, ExplicitRk, NonFinite};
use super::options::{DormandPrinceOptions, FixedStep, Solver};
use super::stiff::{Radau5, Rosenbrock, StiffIntegrator, StiffKernel, RODAS4};
use super::tableau::{DORMAND_PRINCE_5, RK4};
use crate::error::{SampleTimeProblem, SolverError};
use crate::model::Model;
use crate::record::{Recorder, Trajectory};

/// The work done by one run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct Stats {
    /// Steps accepted.
    pub accepted: usize,
    /// Steps rejected: error estimate too large, a non-finite value met, or (stiff
    /// methods) a Newton iteration that failed or a singular iteration matrix.
    pub rejected: usize,
    /// Evaluations of [`Model::derivatives`] on `f64`, by the method itself (the
    /// evaluations for Jacobians are counted in [`Stats::n_jac_rhs`]).
    pub n_rhs: usize,
    /// Jacobians evaluated (stiff methods; 0 for the explicit ones).
    pub n_jac: usize,
    /// LU factorizations of iteration matrices (stiff methods). Radau5 factors two
    /// matrices each time, one real and one complex (about four times the work of the
    /// real one): both are counted. Rodas4 factors one per attempted step.
    pub n_lu: usize,
    /// Of [`Stats::n_lu`], the factorizations by the sparse code (with pivots fixed at
    /// set-up) that failed its stability test and were done again with partial
    /// pivoting (stiff methods on models whose Jacobian is sparse enough; see
    /// [`JacobianEvaluator`](crate::JacobianEvaluator)).
    pub n_lu_fallback: usize,
    /// Directional derivatives of [`Model::derivatives`] spent on Jacobians (stiff
    /// methods): one per colour of the sparsity pattern, or of the numerical pattern
    /// plus one for the check once that is known (see
    /// [`JacobianEvaluator`](crate::JacobianEvaluator); none for a hand-written
    /// [`Model::jacobian`]), evaluated [`LANES`](crate::jacobian::LANES) at a time on
    /// dual numbers; plus, for Rodas4, one `f64` evaluation for `∂f/∂t`.
    pub n_jac_rhs: usize,
}

impl Stats {
    /// Steps attempted: accepted plus rejected. This is what `max_steps` limits.
    pub fn steps(&self) -> usize {
        self.accepted + self.rejected
    }
}

/// A model paired with a solver and all the memory a run needs.
///
/// [`Simulation::new`] allocates every buffer (stage vectors, state, interpolation and
/// output buffers); [`Simulation::run`] allocates nothing, so with a recorder that does
/// not allocate (a [`Trajectory`] created with enough capacity) a run is free of heap
/// allocation. A simulation can be run any number of times.
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
    model: &'m M,
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
    Explicit(ExplicitRk),
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
fn explicit(kernel: &mut Kernel) -> &mut ExplicitRk {
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

    /// Checks that the sample times are finite, `>= t0` and non-decreasing.
    fn validate(&self, t0: f64) -> Result<(), SolverError> {
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

/// The smallest step the time axis resolves at `t`.
pub(super) fn min_step(t: f64) -> f64 {
    16.0 * f64::EPSILON * t.abs().max(f64::MIN_POSITIVE)
}

impl<'m, M: Model> Simulation<'m, M> {
    /// A simulation of `model` with the model's own [`Model::default_solver`].
    pub fn with_default_solver(model: &'m M) -> Result<Self, SolverError> {
        Self::new(model, model.default_solver())
    }

    /// Checks the solver's options and allocates the workspace for `model`.
    pub fn new(model: &'m M, solver: Solver) -> Result<Self, SolverError> {
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
                let method = |structure: &_| {
                    Rosenbrock::new(&RODAS4, n, structure, o.rtol, o.atol, o.safety)
                };
                let integrator = StiffIntegrator::new(model, method, o.common());
                Kernel::Stiff(StiffKernel::Rosenbrock(Box::new(integrator)))
            }
        };
        Ok(Simulation {
            model,
            solver,
            kernel,
            x: vec![0.0; n],
            t: 0.0,
            x_dense: vec![0.0; n],
            y: vec![0.0; M::N_OUTPUTS],
            stats: Stats::default(),
        })
    }

    /// The model.
    pub fn model(&self) -> &'m M {
        self.model
    }

    /// The solver and its settings.
    pub fn solver(&self) -> &Solver {
        &self.solver
    }

    /// The time the last run reached: its last sample time, or where it failed.
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

    /// Integrates from `(t0, x0)` through `sample_times` (finite, `>= t0`,
    /// non-decreasing), calling `recorder` at every sample time with the time, the state
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
        if let Kernel::Explicit(k) = &mut self.kernel {
            k.restart();
        }
        match self.solver {
            Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => {
                self.run_fixed(o, samples, recorder)?
            }
            Solver::DormandPrince(o) => self.run_adaptive(&o, samples, recorder)?,
            Solver::Radau5(_) | Solver::Rodas4(_) => self.run_stiff(samples, recorder)?,
        }
        Ok(self.stats)
    }

    /// Fixed steps on the grid `t0 + k * step`, each shortened to end on a sample time
    /// it would pass.
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
        let t0 = self.t;
        let t_end = samples.get(n - 1);
        let h = o.step;
        // Every grid step must advance the time, or the loop could not end.
        if t_end > t0 && h < min_step(t0).max(min_step(t_end)) {
            return Err(SolverError::StepSizeTooSmall { t: t0, h });
        }
        // Index of the last grid point passed.
        let mut k: u64 = 0;
        for i in 0..n {
            let ts = samples.get(i);
            // A grid point this close to a sample time is the sample time.
            let merge = (1e-9 * h).max(8.0 * f64::EPSILON * ts.abs());
            while self.t < ts {
                if self.stats.accepted >= o.max_steps {
                    return Err(SolverError::StepBudgetExhausted {
                        t: self.t,
                        t_end,
                        steps: self.stats.accepted,
                    });
                }
                let grid = t0 + (k + 1) as f64 * h;
                let (t_new, on_grid) = if grid < ts - merge {
                    (grid, true)
                } else {
                    (ts, grid <= ts + merge)
                };
                let t = self.t;
                let stats = &mut self.stats;
                let kernel = explicit(&mut self.kernel);
                kernel
                    .prepare(self.model, t, &self.x, &mut stats.n_rhs)
                    .and_then(|()| kernel.attempt(self.model, t, t_new, &self.x, &mut stats.n_rhs))
                    .map_err(non_finite::<M>)?;
                kernel.accept(t, t_new, &mut self.x, false);
                self.t = t_new;
                stats.accepted += 1;
                if on_grid {
                    k += 1;
                }
            }
            self.emit(ts, false, recorder)?;
        }
        Ok(())
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
        let model = self.model;
        let (rtol, atol) = (o.rtol, o.atol);
        explicit(&mut self.kernel)
            .prepare(model, self.t, &self.x, &mut self.stats.n_rhs)
            .map_err(non_finite::<M>)?;
        let mut h = match o.initial_step {
            Some(h) => h.min(o.max_step),
            None => explicit(&mut self.kernel)
                .initial_step(
                    model,
                    self.t,
                    &self.x,
                    rtol,
                    atol,
                    o.max_step,
                    &mut self.stats.n_rhs,
                )
                .map_err(non_finite::<M>)?,
        };
        let mut control = Controller::new(o);
        // The non-finite value that made the last step fail, if that is why it failed.
        let mut failure: Option<NonFinite> = None;
        loop {
            let t = self.t;
            // Stretch a step that would end within 1 % of the last sample time.
            let (t_new, h_try) = if t + 1.01 * h >= t_end {
                (t_end, t_end - t)
            } else {
                (t + h, h)
            };
            if h_try.is_nan() || h_try < min_step(t) {
                return Err(match failure {
                    Some(nf) => non_finite::<M>(nf),
                    None => SolverError::StepSizeTooSmall { t, h: h_try },
                });
            }
            if self.stats.steps() >= o.max_steps {
                return Err(SolverError::StepBudgetExhausted {
                    t,
                    t_end,
                    steps: self.stats.steps(),
                });
            }
            if let Err(nf) =
                explicit(&mut self.kernel).attempt(model, t, t_new, &self.x, &mut self.stats.n_rhs)
            {
                // Probably a step out of the model's domain: retry a shorter one.
                self.stats.rejected += 1;
                failure = Some(nf);
                h = control.after_failure(h_try);
                continue;
            }
            failure = None;
            let kernel = explicit(&mut self.kernel);
            let err = kernel.error_norm(&self.x, h_try, rtol, atol);
            if err <= 1.0 {
                self.stats.accepted += 1;
                let dense = samples.get(next) < t_new;
                kernel.accept(t, t_new, &mut self.x, dense);
                self.t = t_new;
                while next < n && samples.get(next) <= t_new {
                    let ts = samples.get(next);
                    self.emit(ts, ts < t_new, recorder)?;
                    next += 1;
                }
                if next == n {
                    return Ok(());
                }
                h = control.after_accept(h_try, err);
            } else {
                self.stats.rejected += 1;
                h = control.after_reject(h_try, err);
            }
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
        let model = self.model;
        stiff(&mut self.kernel).start(model, self.t, &self.x, t_end, &mut self.stats)?;
        loop {
            stiff(&mut self.kernel).step(
                model,
                &mut self.t,
                &mut self.x,
                t_end,
                &mut self.stats,
            )?;
            let t_new = self.t;
            while next < n && samples.get(next) <= t_new {
                let ts = samples.get(next);
                self.emit(ts, ts < t_new, recorder)?;
                next += 1;
            }
            if next == n {
                return Ok(());
            }
        }
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
            &self.x_dense
        } else {
            &self.x
        };
        self.model.outputs::<f64>(t, x, &mut self.y);
        recorder.record(t, x, &self.y);
        if recorder.stop_requested() {
            return Err(SolverError::Stopped { t });
        }
        Ok(())
    }
}

/// The step-size controller of Hairer's DOPRI5 (HNW I, Sect. II.4 and IV.2): a PI
/// controller `h_new = h * safety * err^-alpha * err_prev^beta` with
/// `alpha = 1/5 - 0.75 beta`, clamped to `[min_factor, max_factor] * h` and
/// `max_step`, with no growth right after a rejection.
#[derive(Clone, Copy, Debug)]
struct Controller {
    alpha: f64,
    beta: f64,
    safety: f64,
    min_factor: f64,
    max_factor: f64,
    max_step: f64,
    /// The error of the last accepted step (at least 1e-4).
    err_prev: f64,
    last_rejected: bool,
}

impl Controller {
    fn new(o: &DormandPrinceOptions) -> Self {
        // The error estimate of DOPRI5 is O(h^5).
        let q1 = 5.0;
        Controller {
            alpha: 1.0 / q1 - 0.75 * o.beta,
            beta: o.beta,
            safety: o.safety,
            min_factor: o.min_factor,
            max_factor: o.max_factor,
            max_step: o.max_step,
            err_prev: 1e-4,
            last_rejected: false,
        }
    }

    fn after_accept(&mut self, h: f64, err: f64) -> f64 {
        let factor = self.safety * err.powf(-self.alpha) * self.err_prev.powf(self.beta);
        let mut factor = factor.clamp(self.min_factor, self.max_factor);
        if self.last_rejected {
            factor = factor.min(1.0);
        }
        self.err_prev = err.max(1e-4);
        self.last_rejected = false;
        (h * factor).min(self.max_step)
    }

    fn after_reject(&mut self, h: f64, err: f64) -> f64 {
        self.last_rejected = true;
        let factor = self.safety * err.powf(-self.alpha);
        h * factor.max(self.min_factor)
    }

    fn after_failure(&mut self, h: f64) -> f64 {
        self.last_rejected = true;
        h * self.min_factor
    }
}

/// Names the state of a kernel's non-finite value.
pub(super) fn non_finite<M: Model>(nf: NonFinite) -> SolverError {
    SolverError::NonFiniteState {
        t: nf.t,
        state: M::STATE_NAMES.get(nf.index).copied().unwrap_or("?"),
        value: nf.value,
        kind: nf.kind,
    }
}

/// Simulates `model` from its declared initial state at `t0` to `t_end` with `solver`,
/// recording `n` evenly spaced samples ([`sample_times_uniform`]) into a
/// [`Trajectory`].
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
