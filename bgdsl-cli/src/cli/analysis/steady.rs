//! `models steady`: the equilibrium of a model, written as `steady.yaml`.

use clap::Args;

use super::{execute, plan, state_value, ModelArgs};
use crate::catalog::analysis::state_index;
use crate::catalog::analysis::steady::{results_set, SteadyRequest};
use crate::catalog::Catalogue;
use crate::cli::Failure;

/// The arguments of `models steady`.
#[derive(Clone, Debug, Default, Args)]
pub struct SteadyArgs {
    /// The model and its settings.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Start Newton's method with this state at this value instead of its initial
    /// value, e.g. `--guess omega=100` (repeatable).
    #[arg(long, value_name = "STATE=VALUE")]
    pub guess: Vec<String>,
    /// Hold this state at its starting value (its own rate need not vanish): a
    /// position that grows at a steady speed, an integrator's output (repeatable,
    /// or comma-separated).
    #[arg(long, value_name = "STATE")]
    pub hold: Vec<String>,
    /// Newton iterations allowed.
    #[arg(long, value_name = "N", default_value_t = 100)]
    pub max_iterations: usize,
}

/// `models steady ...`.
pub(crate) fn steady(args: &SteadyArgs, catalogue: &'static Catalogue) -> Result<(), Failure> {
    let mut options = Vec::new();
    for g in &args.guess {
        let (name, value) = g.split_once('=').unwrap_or((g, ""));
        options.push((format!("guess.{}", name.trim()), value.trim().to_owned()));
    }
    for h in super::names(&args.hold) {
        options.push(("hold".to_owned(), h));
    }
    let (entry, plan) = plan(&args.model, catalogue, "steady", &options)?;
    let mut request = SteadyRequest::default();
    request.options.max_iterations = args.max_iterations;
    for g in &args.guess {
        request.guess.push(state_value(entry, "--guess", g)?);
    }
    for name in super::names(&args.hold) {
        request
            .held
            .push(state_index(entry, &name).map_err(super::failure)?);
    }
    execute(entry, &plan, || {
        let result = entry.model.steady(&plan, &request)?;
        Ok(results_set(entry, &result))
    })
}
