//! Integrating a [`Model`](crate::Model): the solvers and the driver that runs them.
//!
//! - [`Solver`] chooses the method: fixed-step classical RK4, adaptive Dormand–Prince
//!   5(4) with dense output, Dormand–Prince with a fixed step, or, for stiff models,
//!   the implicit Radau IIA method of order 5 ([`Solver::Radau5`]) or the Rosenbrock
//!   method Rodas4 ([`Solver::Rodas4`]), both with exact Jacobians by automatic
//!   differentiation and dense output.
//! - [`Simulation`] pairs a model with a solver, allocates the workspace once, and
//!   [`Simulation::run`]s from an initial state through a list of sample times, calling a
//!   [`Recorder`](crate::Recorder) at each; nothing in the stepping loop allocates.
//! - Failures are [`SolverError`](crate::SolverError)s that say when and why.
//!
//! Internally the methods are data (Butcher tableaux, module `tableau`) driven through
//! one explicit Runge–Kutta kernel (module `explicit`, which also evaluates the
//! continuous extension); the driver (module `driver`) owns step-size control, sampling
//! and the statistics. The stiff methods (module `stiff`) run on their own stepping loop,
//! which the driver calls one accepted step at a time: their step-size control is bound
//! up with the Newton iteration and with reusing Jacobians and LU factors.

mod driver;
mod explicit;
mod options;
mod stiff;
mod tableau;

pub use driver::{sample_times_uniform, simulate, Simulation, Stats};
pub use options::{DormandPrinceOptions, FixedStep, Solver};
pub use stiff::{Radau5Options, Rodas4Options};
