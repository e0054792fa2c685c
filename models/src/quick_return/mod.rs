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
//! - [`figures`]: the paper's Figs. 3–19 and two more (the output slider against the
//!   rigid kinematics, the energy balance), drawn from the results as PNG and SVG.
//! - [`model`]: the mechanism itself, written with `bond_graph!`.
//! - [`torque_driven`]: the same mechanism with the crank driven by a torque input,
//!   for a host's speed controller.

pub mod configuration_springs;
pub mod figures;
pub mod model;
pub mod results;
pub mod run;
pub mod summary;
pub mod torque_driven;

pub use model::{assembly, Assembly, QuickReturn, QuickReturnParams};
