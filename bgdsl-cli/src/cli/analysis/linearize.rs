//! `models linearize`: the linear model `(A, B, C, D)` at an operating point, with its
//! modes (`linear.json`, `A.csv`–`D.csv`, `linear.m`, `modes.csv`, the eigenvalue
//! plane).

use clap::Args;

use super::{execute, names, plan, state_value, ModelArgs};
use crate::catalog::analysis::linear::{results_set, LinearRequest};
use crate::catalog::analysis::OperatingPoint;
use crate::catalog::{Catalogue, Entry};
use crate::cli::Failure;

/// Where and between what a linear model is taken: shared by `linearize` and `bode`.
#[derive(Clone, Debug, Default, Args)]
pub struct PointArgs {
    /// The operating point: `initial` (the initial state at the start time), `steady`
    /// (the equilibrium found from it, as `models steady` finds it) or a time in
    /// seconds (the state a run from the initial state reaches then, with the model's
    /// or the scenario's solver).
    #[arg(
        long,
        value_name = "initial|steady|TIME",
        default_value = "initial",
        allow_hyphen_values = true
    )]
    pub at: OperatingPoint,
    /// For `--at steady`: start Newton's method with this state at this value
    /// (repeatable), as `models steady --guess`.
    #[arg(long, value_name = "STATE=VALUE")]
    pub guess: Vec<String>,
}

impl PointArgs {
    /// The request for `entry` with these inputs and outputs, and the folder-name
    /// options (`at=steady`, `inputs=…`).
    pub(super) fn request(
        &self,
        entry: &Entry,
        inputs: Vec<String>,
        outputs: Vec<String>,
    ) -> Result<LinearRequest, Failure> {
        let mut request = LinearRequest {
            at: self.at,
            inputs,
            outputs,
            ..LinearRequest::default()
        };
        for g in &self.guess {
            request.steady.guess.push(state_value(entry, "--guess", g)?);
        }
        Ok(request)
    }

    /// The options that name the default folder.
    pub(super) fn options(&self) -> Vec<(String, String)> {
        let mut options = Vec::new();
        if self.at != OperatingPoint::Initial {
            options.push(("at".to_owned(), self.at.to_string()));
        }
        for g in &self.guess {
            let (name, value) = g.split_once('=').unwrap_or((g, ""));
            options.push((format!("guess.{}", name.trim()), value.trim().to_owned()));
        }
        options
    }
}

/// The arguments of `models linearize`.
#[derive(Clone, Debug, Default, Args)]
pub struct LinearizeArgs {
    /// The model and its settings.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The operating point.
    #[command(flatten)]
    pub point: PointArgs,
    /// The inputs of the linear model (columns of B and D): declared inputs or scalar
    /// parameters (a vector parameter's component as `name[i]`), comma-separated or
    /// repeated [default: every declared input; none for a model without inputs].
    #[arg(long, value_name = "U,V")]
    pub inputs: Vec<String>,
    /// The outputs of the linear model (rows of C and D), comma-separated or repeated
    /// [default: every output].
    #[arg(long, value_name = "Y,Z")]
    pub outputs: Vec<String>,
}

/// `models linearize ...`.
pub(crate) fn linearize(
    args: &LinearizeArgs,
    catalogue: &'static Catalogue,
) -> Result<(), Failure> {
    let inputs = names(&args.inputs);
    let outputs = names(&args.outputs);
    let mut options = args.point.options();
    if !inputs.is_empty() {
        options.push(("inputs".to_owned(), inputs.join("+")));
    }
    if !outputs.is_empty() {
        options.push(("outputs".to_owned(), outputs.join("+")));
    }
    let (entry, plan) = plan(&args.model, catalogue, "linearize", &options)?;
    let request = args.point.request(entry, inputs, outputs)?;
    execute(entry, &plan, || {
        let linear = entry.model.linearize(&plan, &request)?;
        Ok(results_set(entry, request.at, &linear))
    })
}
