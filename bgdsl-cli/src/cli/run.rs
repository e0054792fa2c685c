//! `models run`: a model with its defaults, or a scenario file, with the command line's
//! overrides; validated whole before anything is written.

use std::io::{BufRead, IsTerminal, Write};
use std::path::Path;

use super::info::print;
use super::progress::Progress;
use super::{Failure, RunArgs};
use crate::catalog::{run_study, run_sweep, size, Catalogue};
use crate::scenario::{self, resolve, Job, Origin, Overrides, Plan, Scenario};
use crate::study::shard::Shard;

/// Whether the target names a scenario file rather than a model.
fn is_scenario(target: &str) -> bool {
    let path = Path::new(target);
    path.is_file()
        || matches!(
            path.extension().and_then(|e| e.to_str()),
            Some("yaml" | "yml")
        )
}

/// The plan of `target` (a model name or a scenario file) with `overrides`, and the
/// name its results folder starts with (the model's, or the scenario file's without
/// its extension): what `run` and every analysis command resolve first.
///
/// # Errors
///
/// [`Failure::Invalid`] with every problem of the scenario and the flags.
pub(super) fn resolve_target(
    target: &str,
    overrides: &Overrides,
    catalogue: &'static Catalogue,
) -> Result<(Plan, String), Failure> {
    let (plan, name) = if is_scenario(target) {
        let path = Path::new(target);
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
            overrides,
            &name,
        );
        (plan, name)
    } else {
        let scenario = Scenario {
            model: target.to_owned(),
            ..Scenario::default()
        };
        let plan = resolve(catalogue, None, &scenario, overrides, target).map_err(|mut d| {
            if let Some(first) = d.0.first_mut() {
                if first.origin == Origin::Nowhere && first.message.starts_with("unknown model") {
                    first
                        .message
                        .push_str(" (or give a scenario file, ending in .yaml)");
                }
            }
            d
        });
        (plan, target.to_owned())
    };
    Ok((plan.map_err(Failure::Invalid)?, name))
}

/// `models run <model | scenario.yaml> ...`.
pub(super) fn run(args: &RunArgs, catalogue: &'static Catalogue) -> Result<(), Failure> {
    let overrides = Overrides {
        step: args.step,
        interval: args.interval,
        phase: args.phase.clone(),
        ..args.model.overrides()
    };
    let (plan, _) = resolve_target(&args.model.target, &overrides, catalogue)?;
    let mut plan = plan;
    if let Some(shard) = args.shard {
        shard_out_dir(&mut plan, shard, args.model.out.is_none())?;
    }

    // The size guard (`--yes` skips it, and the sweep's timing probe with it).
    let too_large = match &plan.job {
        _ if args.yes => None,
        Job::Run(run) => size::run_too_large(plan.entry, run),
        Job::Sweep(sweep) => size::sweep_too_large(plan.entry, sweep),
        Job::Study(study) => size::study_too_large(study, args.shard),
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
        Job::Study(study) => {
            let outcome =
                run_study(plan.entry, study, args.shard, &progress).map_err(Failure::Run)?;
            let first = outcome.files.into_iter().next();
            (
                outcome.summary,
                outcome.failure,
                outcome.figures_error,
                first,
            )
        }
        Job::Sweep(sweep) => {
            let outcome =
                run_sweep(plan.entry, sweep, args.shard, &progress).map_err(Failure::Run)?;
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

/// Checks that `--shard` applies (a sweep or a study with at least as many items as
/// shards) and, without `--out`, names the shard's folder `<out>-shard-K-of-N`.
fn shard_out_dir(plan: &mut Plan, shard: Shard, default_dir: bool) -> Result<(), Failure> {
    let (items, what, base) = match &mut plan.job {
        Job::Run(_) => {
            return Err(Failure::Usage(
                "--shard splits a sweep or a Monte Carlo study; this scenario is one run"
                    .to_owned(),
            ))
        }
        Job::Sweep(sweep) => (sweep.points().len(), "sweep points", &mut sweep.base),
        Job::Study(study) => (study.samples, "samples", &mut study.base),
    };
    shard
        .check_items(items, what)
        .map_err(|e| Failure::Usage(format!("--shard {shard}: {e}")))?;
    if default_dir {
        let mut name = base.out_dir.as_os_str().to_owned();
        name.push(format!("-shard-{}-of-{}", shard.index, shard.count));
        base.out_dir = name.into();
    }
    Ok(())
}

/// `models merge DIR... [--out DIR]`.
pub(super) fn merge(
    dirs: &[std::path::PathBuf],
    out: Option<std::path::PathBuf>,
) -> Result<(), Failure> {
    let out = out.unwrap_or_else(|| merged_dir(dirs));
    crate::interrupt::install_handler();
    let progress = Progress::new();
    let outcome = crate::catalog::merge(dirs, &out, &progress)
        .map_err(|errors| Failure::Usage(errors.join("\n")))?
        .map_err(Failure::Run)?;
    print(&outcome.summary)?;
    match (outcome.failure, outcome.figures_error) {
        (Some(reason), _) => Err(Failure::Partial {
            reason,
            file: outcome.files.into_iter().next(),
        }),
        (None, Some(error)) => Err(Failure::Other(format!(
            "the results were written, but drawing the figures failed: {error}"
        ))),
        (None, None) => Ok(()),
    }
}

/// The default folder of a merge: the first shard's without `-shard-K-of-N`.
fn merged_dir(dirs: &[std::path::PathBuf]) -> std::path::PathBuf {
    let first = dirs.first().cloned().unwrap_or_default();
    let text = first.to_string_lossy();
    match text.rfind("-shard-") {
        Some(at) => text[..at].into(),
        None => format!("{text}-merged").into(),
    }
}
