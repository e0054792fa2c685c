//! Analysis of bgdsl models beyond simulation: what a modeller asks of a model once it
//! runs (issue 16).
//!
//! Every derivative here is exact: a generated model's equations are generic over the
//! number type, so ∂f/∂x, ∂f/∂p and ∂f/∂u come from dual numbers, not from finite
//! differences. Hand-written models that do not route their parameter reads through
//! `Scalar::parameter` fall back to central differences, and
//! the results say so.
#![warn(missing_docs)]

pub mod error;
pub mod fit;
pub mod periodic;
pub mod sensitivity;

pub use error::AnalysisError;
