//! The analysis commands (`steady`, `linearize`, `bode`, `periodic`, `fit`): what they
//! share. Each reads its model the way `models run` does ([`ModelArgs`]: a model or a
//! scenario file, `--set`, the solver flags), resolved once by [`plan`] into the run's
//! plan, then calls its analysis through [`CatalogModel`](crate::catalog::CatalogModel)
//! and writes its results set with
//! [`catalog::analysis::write_set`](crate::catalog::analysis::write_set), whose summary
//! [`finish`] prints.

pub mod bode;
pub mod fit;
pub mod linearize;
pub mod periodic;
pub mod steady;

use std::path::PathBuf;

use clap::Args;

use super::run::is_scenario;
use super::Failure;
use crate::catalog::analysis::{self, AnalysisFailure, AnalysisSet};
use crate::catalog::{Catalogue, Entry, RunPlan};
use crate::provenance::folder::{command_line_settings, default_out_dir};
use crate::scenario::{self, resolve, Job, Origin, Overrides, Scenario};

/// The model and its settings, as `models run` reads them; every analysis command
/// takes these.
#[derive(Clone, Debug, Default, Args)]
pub struct ModelArgs {
    /// A model name (see `models list`) or a scenario file (.yaml): its parameters,
    /// initial state, time span and solver are used; a sweep or Monte Carlo study is
    /// refused.
    #[arg(value_name = "MODEL | SCENARIO.yaml")]
    pub target: String,
    /// The output directory [default: out/NAME-COMMAND, or out/NAME-COMMAND-SETTINGS
    /// with overrides or options, as `models run` names its folders]. Replaced whole
    /// when the analysis succeeds; untouched when it fails.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Set a parameter, e.g. `--set R=2` or `--set l1=[0.2,0.01,0.01]` (repeatable;
    /// overrides the scenario).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// The solver of any run the analysis makes (an operating point at a time, an
    /// orbit): rk4, dopri5, dopri5-fixed, radau5, rodas4 or rodas5p.
    #[arg(long, value_name = "NAME")]
    pub solver: Option<String>,
    /// Relative tolerance of an adaptive solver, in [1e-14, 0.1].
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub rtol: Option<f64>,
    /// Absolute tolerance of an adaptive solver, > 0.
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub atol: Option<f64>,
    /// The start time, s: where the initial state is, and the time at which an
    /// equilibrium's rates are evaluated [default: 0, or the scenario's `time.start`].
    #[arg(long = "t-start", value_name = "X", allow_negative_numbers = true)]
    pub t_start: Option<f64>,
    /// The end of the time span, s (for the analyses that run the model).
    #[arg(long = "t-end", value_name = "X", allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// The solver's step budget, > 0.
    #[arg(long = "max-steps", value_name = "N")]
    pub max_steps: Option<usize>,
    /// Draw no figures.
    #[arg(long)]
    pub no_plots: bool,
}

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
    let overrides = Overrides {
        set: args.set.clone(),
        solver: args.solver.clone(),
        rtol: args.rtol,
        atol: args.atol,
        t_start: args.t_start,
        t_end: args.t_end,
        max_steps: args.max_steps,
        no_plots: args.no_plots,
        out: args.out.clone(),
        command_line: std::env::args_os()
            .map(|a| a.to_string_lossy().into_owned())
            .collect(),
        ..Overrides::default()
    };
    let (plan, name) = if is_scenario(&args.target) {
        let path = std::path::Path::new(&args.target);
        let loaded = scenario::load(path).map_err(Failure::Invalid)?;
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scenario")
            .to_owned();
        let plan = resolve(
            catalogue,
            Some(&loaded.source),
            &loaded.scenario,
            &overrides,
            &name,
        );
        (plan, name)
    } else {
        let scenario = Scenario {
            model: args.target.clone(),
            ..Scenario::default()
        };
        let plan =
            resolve(catalogue, None, &scenario, &overrides, &args.target).map_err(|mut d| {
                if let Some(first) = d.0.first_mut() {
                    if first.origin == Origin::Nowhere && first.message.starts_with("unknown model")
                    {
                        first
                            .message
                            .push_str(" (or give a scenario file, ending in .yaml)");
                    }
                }
                d
            });
        (plan, args.target.clone())
    };
    let plan = plan.map_err(Failure::Invalid)?;
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
