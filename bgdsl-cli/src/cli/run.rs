//! `models run`: a model with its defaults, or a scenario file, with the command line's
//! overrides; validated whole before anything is written.

use std::io::{BufRead, IsTerminal, Write};
use std::path::Path;

use super::info::print;
use super::progress::Progress;
use super::{Failure, RunArgs};
use crate::catalog::{run_sweep, size, Catalogue};
use crate::scenario::{self, resolve, Job, Origin, Overrides, Scenario};

/// Whether the target names a scenario file rather than a model.
fn is_scenario(target: &str) -> bool {
    let path = Path::new(target);
    path.is_file()
        || matches!(
            path.extension().and_then(|e| e.to_str()),
            Some("yaml" | "yml")
        )
}

/// `models run <model | scenario.yaml> ...`.
pub(super) fn run(args: &RunArgs, catalogue: &'static Catalogue) -> Result<(), Failure> {
    let overrides = Overrides {
        set: args.set.clone(),
        solver: args.solver.clone(),
        rtol: args.rtol,
        atol: args.atol,
        t_start: args.t_start,
        t_end: args.t_end,
        step: args.step,
        max_steps: args.max_steps,
        interval: args.interval,
        no_plots: args.no_plots,
        out: args.out.clone(),
        command_line: std::env::args_os()
            .map(|a| a.to_string_lossy().into_owned())
            .collect(),
    };
    let plan = if is_scenario(&args.target) {
        let path = Path::new(&args.target);
        let loaded = scenario::load(path).map_err(Failure::Invalid)?;
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scenario")
            .to_owned();
        resolve(
            catalogue,
            Some(&loaded.source),
            &loaded.scenario,
            &overrides,
            &name,
        )
    } else {
        let scenario = Scenario {
            model: args.target.clone(),
            ..Scenario::default()
        };
        resolve(catalogue, None, &scenario, &overrides, &args.target).map_err(|mut d| {
            if let Some(first) = d.0.first_mut() {
                if first.origin == Origin::Nowhere && first.message.starts_with("unknown model") {
                    first
                        .message
                        .push_str(" (or give a scenario file, ending in .yaml)");
                }
            }
            d
        })
    }
    .map_err(Failure::Invalid)?;

    // The size guard (`--yes` skips it, and the sweep's timing probe with it).
    let too_large = match &plan.job {
        _ if args.yes => None,
        Job::Run(run) => size::run_too_large(plan.entry, run),
        Job::Sweep(sweep) => size::sweep_too_large(plan.entry, sweep),
    };
    if let Some(estimate) = too_large {
        confirm(&estimate)?;
    }

    crate::interrupt::install_handler();
    let progress = Progress::new();
    let (summary, failure, figures_error, first_file) = match &plan.job {
        Job::Run(run) => {
            let outcome = plan
                .entry
                .model
                .run(plan.entry, run, &progress)
                .map_err(Failure::Run)?;
            let first = outcome.files.into_iter().next();
            (
                outcome.summary,
                outcome.failure,
                outcome.figures_error,
                first,
            )
        }
        Job::Sweep(sweep) => {
            let outcome = run_sweep(plan.entry, sweep, &progress).map_err(Failure::Run)?;
            let first = outcome.files.into_iter().next();
            (
                outcome.summary,
                outcome.failure,
                outcome.figures_error,
                first,
            )
        }
    };
    print(&summary)?;
    match (failure, figures_error) {
        (Some(reason), _) => Err(Failure::Partial {
            reason,
            file: first_file,
        }),
        (None, Some(error)) => Err(Failure::Other(format!(
            "the results were written, but drawing the figures failed: {error}"
        ))),
        (None, None) => Ok(()),
    }
}

/// Lets a run that the size guard stops go on when the user says so at a terminal
/// (stdin and stderr both terminals); otherwise a usage error that says what the
/// estimate is and how to allow it (`--yes`).
fn confirm(estimate: &str) -> Result<(), Failure> {
    let refused = || Failure::Usage(format!("{estimate}; pass --yes to run it all the same"));
    if !(std::io::stdin().is_terminal() && std::io::stderr().is_terminal()) {
        return Err(refused());
    }
    let mut stderr = std::io::stderr();
    let _ = write!(stderr, "{estimate}.\nRun it? [y/N] ");
    let _ = stderr.flush();
    let mut answer = String::new();
    std::io::stdin()
        .lock()
        .read_line(&mut answer)
        .map_err(|e| Failure::Other(format!("reading the answer failed: {e}")))?;
    if matches!(answer.trim(), "y" | "Y" | "yes" | "Yes" | "YES") {
        Ok(())
    } else {
        Err(refused())
    }
}
