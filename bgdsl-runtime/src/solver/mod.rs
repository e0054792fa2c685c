//! Integrating a [`Model`](crate::Model): the solvers and the driver that runs them.
//!
//! - [`Solver`] chooses the method: fixed-step classical RK4, adaptive Dormand–Prince
//!   5(4) with dense output, Dormand–Prince with a fixed step, or, for stiff models,
//!   the implicit Radau IIA method of order 5 ([`Solver::Radau5`]) or the Rosenbrock
//!   methods Rodas5P ([`Solver::Rodas5P`]) and Rodas4 ([`Solver::Rodas4`]), all with
//!   exact Jacobians by automatic differentiation and dense output.
//! - [`Simulation`] pairs a model with a solver, allocates the workspace once, and
//!   [`Simulation::run`]s from an initial state through a list of sample times, calling a
//!   [`Recorder`](crate::Recorder) at each; nothing in the stepping loop allocates.
//! - Failures are [`SolverError`](crate::SolverError)s that say when and why.
//!
//! Internally the methods are data (Butcher tableaux, module `tableau`) driven through
//! one explicit Runge–Kutta kernel (module `explicit`, which also evaluates the
//! continuous extension) by the step-size control of module `control` (the fixed grid,
//! and DOPRI5's PI controller); the driver (module `driver`) owns sampling and the
//! statistics. The stiff methods (module `stiff`) run on their own stepping loop,
//! which the driver calls one accepted step at a time: their step-size control is bound
//! up with the Newton iteration and with reusing Jacobians and LU factors.
//!
//! Without the `std` feature only the settings of the explicit methods
//! ([`FixedStep`], [`DormandPrinceOptions`]) and [`Stats`] are here: the kernel and
//! its step-size control then run through the allocation-free integrators of
//! [`crate::rk`].

pub(crate) mod control;
#[cfg(feature = "std")]
mod driver;
pub(crate) mod events;
pub(crate) mod explicit;
mod options;
mod stats;
#[cfg(feature = "std")]
mod stiff;
#[cfg(feature = "std")]
pub mod stiffness;
pub(crate) mod tableau;
pub(crate) mod weights;

pub use control::MIN_STEP;
#[cfg(feature = "std")]
pub use driver::{sample_times_uniform, simulate, Simulation};
pub(crate) use options::check_atol;
#[cfg(feature = "std")]
pub use options::Solver;
pub use options::{DormandPrinceOptions, FixedStep};
pub use stats::Stats;
#[cfg(feature = "std")]
pub use stiff::{Radau5Options, Rodas4Options, Rodas5POptions, RosenbrockOptions};
