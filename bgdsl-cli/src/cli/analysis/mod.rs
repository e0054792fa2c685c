//! The analysis commands (`steady`, `linearize`, `bode`, `periodic`, `fit`): what they
//! share. Each reads its model the way `models run` does ([`ModelArgs`]: a model or a
//! scenario file, `--set`, the solver flags), resolved once by [`plan`] into the run's
//! plan; [`execute`] then begins the results folder, runs the analysis (through
//! [`CatalogModel`](crate::catalog::CatalogModel)), writes its set with
//! [`catalog::analysis::write_set`](crate::catalog::analysis::write_set) and prints the
//! summary. A new analysis command adds its arguments struct, a method on
//! `CatalogModel` and one call of [`plan`] and [`execute`].

pub mod bode;
pub mod fit;
pub mod linearize;
pub mod periodic;
pub mod steady;

use super::run::resolve_target;
use super::Failure;
use crate::catalog::analysis::{self, AnalysisFailure, AnalysisSet};
use crate::catalog::{Catalogue, Entry, RunPlan};
use crate::provenance::folder::{command_line_settings, default_out_dir};
use crate::scenario::Job;

pub use super::ModelArgs;

/// The plan an analysis command works on: the model's entry and its run plan, with
/// the output folder `--out` or `out/NAME-COMMAND[-SETTINGS]`, where SETTINGS are the
/// command line's overrides (as `models run` names folders) followed by `options`
/// (the analysis's own, e.g. `at=steady`).
///
/// # Errors
///
/// [`Failure::Invalid`] with every problem of the scenario and flags (nothing is
/// written); [`Failure::Usage`] for a sweep or a study.
pub fn plan(
    args: &ModelArgs,
    catalogue: &'static Catalogue,
    command: &str,
    options: &[(String, String)],
) -> Result<(&'static Entry, RunPlan), Failure> {
    let overrides = args.overrides();
    let (plan, name) = resolve_target(&args.target, &overrides, catalogue)?;
    let mut run = match plan.job {
        Job::Run(run) => run,
        Job::Sweep(_) | Job::Study(_) => {
            return Err(Failure::Usage(format!(
                "`{command}` analyses one model; {} is a sweep or a Monte Carlo study: \
                 give a scenario without `sweep:` or `monte_carlo:`",
                args.target
            )))
        }
    };
    if args.out.is_none() {
        let mut settings = command_line_settings(&overrides, &run.params);
        settings.extend(options.iter().cloned());
        run.out_dir = default_out_dir(&format!("{name}-{command}"), &settings);
    }
    run.title = format!("{name}: {command} ({})", plan.entry.description);
    Ok((plan.entry, run))
}

/// The failure of an analysis command: a usage error (status 2) for what the user
/// gave wrong, status 1 for an analysis that failed or results not written.
pub fn failure(e: AnalysisFailure) -> Failure {
    match e {
        AnalysisFailure::Usage(message) => Failure::Usage(message),
        AnalysisFailure::Run(e) => Failure::Run(e),
        e => Failure::Other(e.to_string()),
    }
}

/// Begins `plan`'s folder, runs `analyse`, writes the set it returns and prints the
/// summary: the one path of every analysis command. A failure leaves the output
/// folder as it was and writes nothing.
///
/// # Errors
///
/// As [`failure`].
pub fn execute(
    entry: &Entry,
    plan: &RunPlan,
    analyse: impl FnOnce() -> Result<AnalysisSet, AnalysisFailure>,
) -> Result<(), Failure> {
    crate::interrupt::install_handler();
    let folder = analysis::begin(plan).map_err(Failure::Run)?;
    let set = analyse().map_err(failure)?;
    let outcome = analysis::write_set(folder, entry, plan, set).map_err(failure)?;
    super::info::print(&outcome.summary)
}

/// The `NAME=VALUE` of a `--guess` flag: a state index and a number.
///
/// # Errors
///
/// [`Failure::Usage`] for a malformed flag or an unknown state.
pub fn state_value(entry: &Entry, flag: &str, text: &str) -> Result<(usize, f64), Failure> {
    let Some((name, value)) = text.split_once('=') else {
        return Err(Failure::Usage(format!(
            "{flag} {text}: give STATE=VALUE, e.g. {flag} {}=0",
            entry.model.state_names().first().unwrap_or(&"x")
        )));
    };
    let index = analysis::state_index(entry, name.trim()).map_err(failure)?;
    let value: f64 = value
        .trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| {
            Failure::Usage(format!("{flag} {text}: `{value}` is not a finite number"))
        })?;
    Ok((index, value))
}

/// The names of a repeatable, comma-separated flag (`--outputs y,z --outputs w`).
pub fn names(values: &[String]) -> Vec<String> {
    values
        .iter()
        .flat_map(|v| v.split(','))
        .map(|s| s.trim().to_owned())
        .filter(|s| !s.is_empty())
        .collect()
}
