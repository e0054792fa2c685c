//! The quick return mechanism of the seed paper (`shared/quick-return-spec.md`): the
//! flagship run and everything around it that does not depend on how the model is
//! written. Every item here is generic over any [`Model`](bgdsl_runtime::Model) whose
//! outputs carry the spec's column names.
//!
//! - [`results`]: the spec's results file, recorded ([`results::Results`], a
//!   [`Recorder`](bgdsl_runtime::Recorder)) and written whole as CSV.
//! - [`summary`]: what a run measured over its settled part (stroke, quick-return time
//!   ratio, period, peak drive torque and joint forces) and what it cost.
//! - [`run`]: the flagship run, 0–5 s sampled every 1 ms, and its error type.
//! - [`model`]: the mechanism itself, written with `bond_graph!`.

pub mod model;
pub mod results;
pub mod run;
pub mod summary;

pub use model::{assembly, Assembly, QuickReturn, QuickReturnParams};
