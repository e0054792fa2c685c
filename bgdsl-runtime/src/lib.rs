//! Runtime for bgdsl models.
//!
//! A model is written as a `bond_graph! { ... }` block (re-exported here, so a user
//! crate needs only this one dependency). The macro assigns causality at compile time
//! and implements [`Model`] with straight-line, allocation-free code; this crate
//! integrates it and records the results.
//!
//! # Without the standard library
//!
//! The `std` feature (on by default) brings the simulation driver, the stiff solvers,
//! exact Jacobians, trajectories and CSV files, Graphviz export and the `Stepper`.
//! Without it the crate is `#![no_std]` and needs no allocator: what remains is what a
//! model needs to be defined and stepped on a microcontroller, namely the [`Model`]
//! and [`WithInputs`] traits and everything `bond_graph!` generates code against
//! ([`Scalar`], with `libm` for the elementary functions of `f64`; [`Dual`] numbers;
//! [`multibond`]; the [`CausalGraph`] description), and the allocation-free
//! explicit integrators of [`rk`]. `core` has no `f64::sqrt`, `sin`, ...: code of
//! one's own that calls them on `f64` imports [`Scalar`], whose methods of the same
//! names stand in for them.
#![cfg_attr(not(feature = "std"), no_std)]
#![warn(missing_docs)]
// The documentation is written for the whole crate: without `std`, links to the parts
// that need it (the driver, the stiff solvers, the recorders) have nothing to point at.
#![cfg_attr(not(feature = "std"), allow(rustdoc::broken_intra_doc_links))]

// Generated code names this crate `::bgdsl_runtime`; this makes that work inside it too.
extern crate self as bgdsl_runtime;

#[cfg(feature = "std")]
pub mod dot;
pub mod dual;
pub mod error;
pub mod event;
pub mod graph;
pub mod implicit;
#[cfg(feature = "std")]
pub mod jacobian;
pub mod lift;
#[cfg(feature = "std")]
mod linalg;
mod math;
pub mod model;
pub mod multibond;
#[cfg(feature = "std")]
pub mod param_dual;
#[cfg(feature = "std")]
pub mod record;
pub mod rk;
pub mod scalar;
pub mod solver;
mod spread;
#[cfg(feature = "std")]
pub mod stepper;
pub mod tangent;

pub use bgdsl_macros::bond_graph;
/// Unit strings parsed into SI base-unit exponents and a factor (the `bgdsl-units` crate).
pub use bgdsl_units as units;
#[cfg(feature = "std")]
pub use dot::Dot;
pub use dual::{Dual, DualN};
#[cfg(feature = "std")]
pub use error::{CsvError, CsvStage};
pub use error::{NonFiniteKind, SampleTimeProblem, SolverError};
pub use event::{
    event_energy, Direction, EventAction, EventInfo, EventOptions, EventRecord, ModeInfo, ModeKind,
};
pub use graph::{CausalGraph, ElementCausality, ElementKind, GraphBond, GraphElement};
#[cfg(feature = "std")]
pub use jacobian::{
    Colouring, Jacobian, JacobianEvaluator, SparsityError, SparsityPattern, DENSE_HAND_WRITTEN_MAX,
};
#[cfg(feature = "std")]
pub use linalg::ShiftedLu;
pub use model::{
    unit_of, BodyInfo, FromParams, InputInfo, Model, ModelError, ParameterInfo, PowerBalance,
    SignalInfo, WithInputs,
};
#[cfg(feature = "std")]
pub use param_dual::ParamDual;
#[cfg(feature = "std")]
pub use record::{EventLog, Recorder, Trajectory};
pub use scalar::Scalar;
#[cfg(feature = "std")]
pub use solver::{
    sample_times_uniform, simulate, Radau5Options, Rodas4Options, Rodas5POptions,
    RosenbrockOptions, Simulation, Solver,
};
pub use solver::{DormandPrinceOptions, FixedStep, Stats};
#[cfg(feature = "std")]
pub use stepper::{Snapshot, SnapshotError, Stepper};
pub use tangent::Tangent;

/// The README's examples, compiled and run as doctests so they cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;

/// The LU kernels of the stiff solvers, for the benches (`benches/lu.rs`). Not a public
/// API: it may change at any time.
#[doc(hidden)]
#[cfg(feature = "std")]
pub mod __bench {
    pub use crate::linalg::bench::Matrices;
}

/// Items the generated code refers to. Not a public API: it may change at any time.
#[doc(hidden)]
pub mod __private {
    pub use serde;
    /// The codegen-unit slots of a chunked model's evaluation (`src/spread.rs`).
    pub mod spread {
        pub use crate::spread::*;
    }
}
