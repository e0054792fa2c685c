//! Runtime for bgdsl models.
//!
//! A model is written as a `bond_graph! { ... }` block (re-exported here, so a user
//! crate needs only this one dependency). The macro assigns causality at compile time
//! and implements [`Model`] with straight-line, allocation-free code; this crate
//! integrates it and records the results.
#![warn(missing_docs)]

pub mod graph;
pub mod model;
pub mod scalar;

pub use bgdsl_macros::bond_graph;
pub use graph::{CausalGraph, ElementCausality, ElementKind, GraphBond, GraphElement};
pub use model::Model;
pub use scalar::Scalar;

/// Items the generated code refers to. Not a public API: it may change at any time.
#[doc(hidden)]
pub mod __private {
    pub use serde;
}
