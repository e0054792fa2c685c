//! Analysis of bgdsl models beyond simulation: what a modeller asks of a model once it
//! runs (issue 16).
//!
//! - [`partials`]: exact ∂f/∂x, ∂g/∂x, ∂f/∂p, ∂g/∂p, ∂f/∂u, ∂g/∂u.
//! - [`steady`]: equilibria by Newton's method, with the states a singular Jacobian
//!   leaves undetermined named.
//! - [`linear`]: the linear model `(A, B, C, D)` at an operating point, labelled.
//! - [`modes`]: eigenvalues with natural frequency, damping ratio, dominant states.
//! - [`bode`]: frequency responses `H(jω) = C (jωI − A)⁻¹ B + D`.
//! - [`export`]: `linear.json`, a CSV per matrix, a MATLAB/Octave script.
//! - [`periodic`]: periodic steady states by shooting, Floquet multipliers.
//! - [`sensitivity`]: forward parameter sensitivities along a trajectory.
//! - [`fit`]: least-squares parameter estimation (Levenberg–Marquardt) with intervals.
//!
//! Every derivative is exact: a generated model's equations are generic over the
//! number type, so they come from dual numbers, not from finite differences. A model
//! that does not keep parameter tangents (`Model::EXACT_PARAMETER_DERIVATIVES` is
//! `false`: hand-written, or calling a user's `f64` function of its parameters) is
//! differentiated in its parameters and inputs by central differences, and the results
//! say so ([`Method`]).
#![warn(missing_docs)]

pub mod bode;
pub mod error;
pub mod export;
pub mod fit;
pub mod linear;
pub mod modes;
pub mod partials;
pub mod periodic;
pub mod sensitivity;
pub mod steady;

pub use bode::{frequency_response, log_grid, FrequencyResponse};
pub use error::AnalysisError;
pub use linear::{linearize, Channel, LinearModel};
pub use modes::{modes, Mode};
pub use partials::{
    input_partials, parameter_jacobian, parameter_jacobian_in, parameter_partials, state_partials,
    Method, Partials, PartialsWorkspace,
};
pub use steady::{equilibrium, Equilibrium, SteadyOptions};
