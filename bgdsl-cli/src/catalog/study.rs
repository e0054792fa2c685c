//! Monte Carlo studies: every sample run like a sweep point (rayon over the cores), the
//! results written as one set (see the [catalogue's documentation](crate::catalog)):
//! `samples.csv`, `trajectories.csv`, `bands.csv`, one band chart per column and
//! `index.html`; or, with `--shard K/N`, one block of the samples into a shard folder
//! that [`merge`] joins with the others into exactly those files.

use core::fmt::Write as _;
use std::ops::Range;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use crate::study::distribution::{draw, Distribution};
use crate::study::manifest::{study_hash, Manifest};
use crate::study::shard::Shard;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_yaml::Value;

use super::folder::RunFolder;
use super::run::{settle_drawing, Observer};
use super::{CatalogModel, Column, Entry, Plots, RunError, RunPlan};
use crate::provenance::{self, RunRecord, StudyRecord};

mod files;
mod merge;

pub(super) use files::read_table;
use files::{write_shard, write_study};
pub use merge::merge;
pub(super) use merge::merged_record;

/// A parameter a study draws.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnParameter {
    /// Its name (a scalar parameter).
    pub name: String,
    /// Its unit, possibly empty.
    pub unit: String,
    /// Where its values come from.
    pub distribution: Distribution,
}

/// A validated Monte Carlo study.
#[derive(Clone, Debug)]
pub struct StudyPlan {
    /// The run every sample starts from (its `plots` decide whether charts are drawn).
    pub base: RunPlan,
    /// The number of samples.
    pub samples: usize,
    /// The seed of every sample's stream.
    pub seed: u64,
    /// The drawn parameters, in the scenario's order (the order of the draws).
    pub parameters: Vec<DrawnParameter>,
    /// The banded columns (`output.record`, by default every output).
    pub columns: Vec<(String, Column)>,
}

impl StudyPlan {
    /// The distributions, in order.
    pub fn distributions(&self) -> Vec<Distribution> {
        self.parameters
            .iter()
            .map(|p| p.distribution.clone())
            .collect()
    }

    /// The run of sample `index`.
    pub fn plan_at(&self, index: usize) -> RunPlan {
        let mut plan = self.base.clone();
        let values = draw(self.seed, index, &self.distributions());
        for (p, v) in self.parameters.iter().zip(values) {
            plan.params
                .insert(Value::String(p.name.clone()), Value::from(v));
        }
        plan
    }

    /// Every setting that changes a result, as text, for the study's hash.
    fn canonical(&self, entry: &Entry) -> String {
        let columns: Vec<&str> = self.columns.iter().map(|(n, _)| n.as_str()).collect();
        format!(
            "monte_carlo\n{}\n{}samples {} seed {}\n{:?}\n{columns:?}\n",
            entry.name,
            canonical_run(&self.base),
            self.samples,
            self.seed,
            self.parameters
        )
    }
}

/// A run's settings that change its numbers, as text (for study hashes): parameters,
/// initial state, sample times, solver (with per-state tolerances and non-negative
/// states, when set: without them the text is as before, so older hashes still hold).
pub(super) fn canonical_run(plan: &RunPlan) -> String {
    let mut text = format!(
        "{:?}\n{:?}\n{:?}\n{:?}\n",
        plan.params, plan.initial, plan.times, plan.solver
    );
    if let Some(atol) = &plan.atol {
        text.push_str(&format!("atol {atol:?}\n"));
    }
    if !plan.non_negative.is_empty() {
        text.push_str(&format!("non_negative {:?}\n", plan.non_negative));
    }
    text
}

/// The program's name, version and commit, for manifests: shards join only when one
/// build of one program ran them all.
pub(super) fn program(plan: &RunPlan) -> String {
    let p = &plan.context.program;
    format!("{} {} (commit {})", p.name, p.version, p.commit)
}

/// A distribution as a scenario writes it (a CSV column as its `values`).
fn as_scenario(distribution: &Distribution) -> Value {
    let pair = |a: &str, x: f64, b: &str, y: f64| {
        let mut m = serde_yaml::Mapping::new();
        m.insert(a.into(), x.into());
        m.insert(b.into(), y.into());
        Value::Mapping(m)
    };
    let (kind, settings) = match *distribution {
        Distribution::Uniform { lo, hi } => ("uniform", Value::from(vec![lo, hi])),
        Distribution::Normal { mean, sd } => ("normal", pair("mean", mean, "sd", sd)),
        Distribution::LogNormal { mu, sigma } => ("lognormal", pair("mu", mu, "sigma", sigma)),
        Distribution::Values(ref values) => ("values", Value::from(values.clone())),
    };
    let mut m = serde_yaml::Mapping::new();
    m.insert(kind.into(), settings);
    Value::Mapping(m)
}

/// Every output of `model`, as `output.record` names them.
pub fn all_outputs(model: &dyn CatalogModel) -> Vec<(String, Column)> {
    model
        .output_names()
        .iter()
        .enumerate()
        .map(|(i, n)| ((*n).to_owned(), Column::Output(i)))
        .collect()
}

/// What the files of a study need besides the numbers: kept in a shard's manifest so
/// that `merge` writes what the one-process run writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyShape {
    /// The title of `index.html`.
    pub title: String,
    /// The model's name.
    pub model: String,
    /// The drawn parameters' names and units.
    pub parameters: Vec<(String, String)>,
    /// The banded columns' names and units.
    pub columns: Vec<(String, String)>,
    /// Whether charts are drawn.
    pub plots: bool,
    /// The columns whose band charts are drawn when a scenario lists them (`plots:
    /// [...]`); `None`: every banded column's.
    #[serde(default)]
    pub only: Option<Vec<String>>,
}

/// One sample's numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleRow {
    /// Its index in the study.
    pub index: usize,
    /// The drawn values, one per parameter.
    pub drawn: Vec<f64>,
    /// The banded columns at every time (row-major), `None` when the run failed.
    pub trajectory: Option<Vec<f64>>,
}

/// What a study (or a shard of one) produced.
#[derive(Clone, Debug)]
pub struct StudyOutcome {
    /// The summary, as printed and in `index.html`.
    pub summary: String,
    /// Every file written, the samples table first.
    pub files: Vec<PathBuf>,
    /// Why some samples have no values, when some have none.
    pub failure: Option<String>,
    /// Why the charts could not be drawn, when they could not.
    pub figures_error: Option<String>,
    /// Wall time of the runs.
    pub wall: Duration,
}

/// Passes only the stop request on (a study's runs do not move its progress bar
/// sample by sample).
struct SampleObserver<'a>(&'a dyn Observer);

impl Observer for SampleObserver<'_> {
    fn stop_requested(&self) -> bool {
        self.0.stop_requested()
    }
}

/// Runs the study's samples (all of them, or `shard`'s block) on rayon's pool and
/// writes the study's files (or the shard's) as one set into the base plan's output
/// folder, or into its `.partial` sibling when samples failed or were not run.
///
/// # Errors
///
/// [`RunError`] when a file cannot be written.
pub fn run_study(
    entry: &Entry,
    plan: &StudyPlan,
    shard: Option<Shard>,
    observer: &dyn Observer,
) -> Result<StudyOutcome, RunError> {
    let indices: Range<usize> = shard.map_or(0..plan.samples, |s| s.range(plan.samples));
    let folder = RunFolder::begin(&plan.base.out_dir)?;
    observer.sweep_started(indices.len());
    let started = Instant::now();
    let columns: Vec<Column> = plan.columns.iter().map(|(_, c)| *c).collect();
    let distributions = plan.distributions();
    let results: Vec<(SampleRow, Option<String>)> = indices
        .clone()
        .into_par_iter()
        .map(|index| {
            let drawn = draw(plan.seed, index, &distributions);
            let result = if observer.stop_requested() {
                Err(RunError::NotRun)
            } else {
                entry
                    .model
                    .trajectory(&plan.plan_at(index), &columns, &SampleObserver(observer))
            };
            observer.point_done();
            let (trajectory, error) = match result {
                Ok(t) => (Some(t), None),
                Err(e) => (None, Some(e.to_string())),
            };
            (
                SampleRow {
                    index,
                    drawn,
                    trajectory,
                },
                error,
            )
        })
        .collect();
    let wall = started.elapsed();
    let failures: Vec<(usize, String)> = results
        .iter()
        .filter_map(|(row, e)| e.clone().map(|e| (row.index, e)))
        .collect();
    let mut failure = (!failures.is_empty()).then(|| {
        format!(
            "{} of {} samples failed or were not run",
            failures.len(),
            indices.len()
        )
    });
    let rows: Vec<SampleRow> = results.into_iter().map(|(row, _)| row).collect();
    let shape = StudyShape {
        title: plan.base.title.clone(),
        model: entry.name.to_owned(),
        parameters: plan
            .parameters
            .iter()
            .map(|p| (p.name.clone(), p.unit.clone()))
            .collect(),
        columns: plan
            .columns
            .iter()
            .map(|(n, _)| {
                let unit = super::columns::column_unit(&*entry.model, n).0;
                (n.clone(), unit.to_owned())
            })
            .collect(),
        plots: plan.base.plots != Plots::None,
        only: match &plan.base.plots {
            Plots::Only(ids) => Some(ids.clone()),
            _ => None,
        },
    };
    let dir = folder.path().to_path_buf();
    let mut head = String::new();
    let _ = writeln!(
        head,
        "monte carlo    {}: {} of {} samples (seed {}) on {} threads in {:.2} s",
        entry.name,
        indices.len(),
        plan.samples,
        plan.seed,
        rayon::current_num_threads(),
        wall.as_secs_f64()
    );
    for (i, message) in failures.iter().take(10) {
        let _ = writeln!(head, "  sample {i}: {message}");
    }
    let written = match shard {
        Some(shard) => {
            let manifest = Manifest {
                program: program(&plan.base),
                study: study_hash(&program(&plan.base), &plan.canonical(entry)),
                kind: "monte_carlo".to_owned(),
                shard: shard.index,
                shards: shard.count,
                items: plan.samples,
                first: indices.start,
                end: indices.end,
                complete: failure.is_none(),
                details: serde_yaml::to_value(&shape).unwrap_or_default(),
            };
            write_shard(&dir, &shape, &plan.base.times, &rows, &manifest, &head)
        }
        None => write_study(&dir, &shape, &plan.base.times, &rows, &head, observer),
    };
    let (mut files, drawn, text) = written?;
    let (_, figures_error) = settle_drawing(drawn, &mut failure, observer)?;
    let mut record = RunRecord::build(
        entry,
        &plan.base,
        &plan
            .parameters
            .iter()
            .map(|p| p.name.as_str())
            .collect::<Vec<_>>(),
        &files
            .iter()
            .filter(|f| f.ends_with(".csv"))
            .map(PathBuf::from)
            .collect::<Vec<_>>(),
        failure.as_deref(),
    )?;
    // The drawn parameters are in `monte_carlo`; as `parameters` too, the record would
    // not read back as a scenario (a drawn parameter cannot also be set).
    for p in &plan.parameters {
        record.parameters.remove(p.name.as_str());
    }
    // Likewise the initial state: each sample's follows from its drawn parameters, so
    // only the states the scenario set are recorded.
    let set = record.initial_overridden.clone();
    record
        .initial
        .retain(|k, _| k.as_str().is_some_and(|k| set.iter().any(|s| s == k)));
    record.monte_carlo = Some(StudyRecord {
        samples: plan.samples,
        seed: plan.seed,
        parameters: plan
            .parameters
            .iter()
            .map(|p| (Value::from(p.name.as_str()), as_scenario(&p.distribution)))
            .collect(),
    });
    record.shard = shard.map(|s| s.to_string());
    provenance::write(&dir, &record)?;
    files.push(provenance::FILE_NAME.to_owned());
    let partial = failure.is_some();
    let target = folder.commit(partial)?;
    let mut summary = String::new();
    if let Some(failure) = &failure {
        let _ = writeln!(summary, "PARTIAL STUDY {failure}");
    }
    summary.push_str(&text);
    let _ = writeln!(summary, "results        {}", target.display());
    Ok(StudyOutcome {
        summary,
        files: files.iter().map(|f| target.join(f)).collect(),
        failure,
        figures_error,
        wall,
    })
}
