//! Runtime for bgdsl models.
//!
//! A model is written as a `bond_graph! { ... }` block (re-exported here, so a user
//! crate needs only this one dependency). The macro assigns causality at compile time
//! and implements [`Model`] with straight-line, allocation-free code; this crate
//! integrates it and records the results.
#![warn(missing_docs)]

// Generated code names this crate `::bgdsl_runtime`; this makes that work inside it too.
extern crate self as bgdsl_runtime;

pub mod dot;
pub mod dual;
pub mod error;
pub mod graph;
pub mod jacobian;
mod linalg;
pub mod model;
pub mod multibond;
pub mod record;
pub mod scalar;
pub mod solver;

pub use bgdsl_macros::bond_graph;
pub use dot::Dot;
pub use dual::{Dual, DualN};
pub use error::{CsvError, CsvStage, NonFiniteKind, SampleTimeProblem, SolverError};
pub use graph::{CausalGraph, ElementCausality, ElementKind, GraphBond, GraphElement};
pub use jacobian::{Colouring, JacobianEvaluator, SparsityError, SparsityPattern};
pub use model::{Model, ParameterInfo, PowerBalance};
pub use record::{Recorder, Trajectory};
pub use scalar::Scalar;
pub use solver::{
    sample_times_uniform, simulate, DormandPrinceOptions, FixedStep, Radau5Options, Rodas4Options,
    Simulation, Solver, Stats,
};

/// The README's examples, compiled and run as doctests so they cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;

/// Items the generated code refers to. Not a public API: it may change at any time.
#[doc(hidden)]
pub mod __private {
    pub use serde;
}
