//! Monte Carlo studies: every sample run like a sweep point (rayon over the cores), the
//! results written as one set (see the [catalogue's documentation](crate::catalog)):
//! `samples.csv`, `trajectories.csv`, `bands.csv`, one band chart per column and
//! `index.html`; or, with `--shard K/N`, one block of the samples into a shard folder
//! that [`merge`] joins with the others into exactly those files.

use core::fmt::Write as _;
use std::io::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::study::bands::{bands, SUFFIXES};
use crate::study::distribution::{draw, Distribution};
use crate::study::manifest::{self, study_hash, Manifest};
use crate::study::shard::Shard;
use bgdsl_runtime::record::{write_atomically, write_number};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_yaml::Value;

use super::folder::RunFolder;
use super::params::format_significant;
use super::run::{settle_drawing, Observer};
use super::{figures, CatalogModel, Column, Entry, Plots, RunError, RunPlan};
use crate::provenance::{self, RunRecord, StudyRecord};
use crate::report::INDEX_FILE;

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
/// initial state, sample times, solver.
pub(super) fn canonical_run(plan: &RunPlan) -> String {
    format!(
        "{:?}\n{:?}\n{:?}\n{:?}\n",
        plan.params, plan.initial, plan.times, plan.solver
    )
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

/// The drawing's result, for [`settle_drawing`].
type Drawn = Result<Vec<crate::report::DrawnFigure>, RunError>;

/// Writes a shard's files: its rows of `samples.csv` and `trajectories.csv`,
/// `shard.yaml` and a short `index.html`. Returns the file names.
fn write_shard(
    dir: &Path,
    shape: &StudyShape,
    times: &[f64],
    rows: &[SampleRow],
    manifest: &Manifest,
    head: &str,
) -> Result<(Vec<String>, Drawn, String), RunError> {
    write_samples(dir, shape, rows)?;
    write_trajectories(dir, shape, times, rows)?;
    let path = dir.join(manifest::FILE_NAME);
    write_atomically(&path, |out| out.write_all(manifest.to_yaml().as_bytes()))?;
    let summary = format!(
        "shard {} of a study: samples {}..{} of {} (end excluded); join the shards with \
         the `merge` command\n{head}",
        manifest.shard(),
        manifest.first,
        manifest.end,
        manifest.items
    );
    figures::index(dir, &shape.title, &summary, &[], &[])?;
    Ok((
        vec![
            SAMPLES.to_owned(),
            TRAJECTORIES.to_owned(),
            manifest::FILE_NAME.to_owned(),
            INDEX_FILE.to_owned(),
        ],
        Ok(Vec::new()),
        summary,
    ))
}

/// `samples.csv`.
pub const SAMPLES: &str = "samples.csv";
/// `trajectories.csv`.
pub const TRAJECTORIES: &str = "trajectories.csv";
/// `bands.csv`.
pub const BANDS: &str = "bands.csv";

/// Writes the study's files from its rows (all samples, in index order): the one
/// writer of both the one-process run and [`merge`], so that their files are equal.
fn write_study(
    dir: &Path,
    shape: &StudyShape,
    times: &[f64],
    rows: &[SampleRow],
    head: &str,
    observer: &dyn Observer,
) -> Result<(Vec<String>, Drawn, String), RunError> {
    write_samples(dir, shape, rows)?;
    write_trajectories(dir, shape, times, rows)?;
    let width = shape.columns.len();
    let traces: Vec<&[f64]> = rows
        .iter()
        .filter_map(|r| r.trajectory.as_deref())
        .collect();
    let bands = bands(&traces, times.len(), width);
    write_atomically(&dir.join(BANDS), |out| {
        let mut header = vec!["t".to_owned()];
        for (name, _) in &shape.columns {
            header.extend(SUFFIXES.iter().map(|s| format!("{name}_{s}")));
        }
        writeln!(out, "{}", header.join(","))?;
        for (t, row) in times.iter().zip(&bands) {
            write_number(out, *t)?;
            for q in row.iter().flatten() {
                out.write_all(b",")?;
                write_number(out, *q)?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    })?;
    let drawing = if !shape.plots || observer.stop_requested() {
        Ok(Vec::new())
    } else {
        figures::bands(shape, times, &bands, traces.len(), dir)
    };
    let mut summary = String::from(head);
    let _ = writeln!(
        summary,
        "\nat the end ({} s), over the samples:",
        super::format_number(times.last().copied().unwrap_or(0.0))
    );
    let _ = writeln!(
        summary,
        "  {:>24} {:>12} {:>12} {:>12}",
        "column", "q05", "q50", "q95"
    );
    if let Some(last) = bands.last() {
        for ((name, unit), q) in shape.columns.iter().zip(last) {
            let label = if unit.is_empty() {
                name.clone()
            } else {
                format!("{name} ({unit})")
            };
            let _ = writeln!(
                summary,
                "  {label:>24} {:>12} {:>12} {:>12}",
                format_significant(q[0]),
                format_significant(q[2]),
                format_significant(q[4])
            );
        }
    }
    let drawn_ok = match &drawing {
        Ok(d) => d.clone(),
        Err(_) => Vec::new(),
    };
    figures::index(dir, &shape.title, &summary, &drawn_ok, &[])?;
    let mut files = vec![
        SAMPLES.to_owned(),
        TRAJECTORIES.to_owned(),
        BANDS.to_owned(),
    ];
    files.extend(drawn_ok.iter().flat_map(|f| {
        f.files
            .iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
    }));
    files.push(INDEX_FILE.to_owned());
    Ok((files, drawing, summary))
}

/// The per-sample metrics of a trajectory: for each column, the peak magnitude and
/// the final value (NaN for a failed run).
fn metrics(trajectory: Option<&[f64]>, width: usize) -> Vec<f64> {
    let Some(values) = trajectory.filter(|v| !v.is_empty() && width > 0) else {
        return vec![f64::NAN; 2 * width];
    };
    let times = values.len() / width;
    let peak = (0..width).map(|c| {
        (0..times)
            .map(|t| values[t * width + c].abs())
            .fold(f64::NAN, f64::max)
    });
    let last = (0..width).map(|c| values[(times - 1) * width + c]);
    peak.chain(last).collect()
}

/// `samples.csv`: `index`, the drawn values, `peak_<c>` and `final_<c>` of each column.
fn write_samples(dir: &Path, shape: &StudyShape, rows: &[SampleRow]) -> Result<(), RunError> {
    let width = shape.columns.len();
    write_atomically(&dir.join(SAMPLES), |out| {
        let header: Vec<String> = std::iter::once("index".to_owned())
            .chain(shape.parameters.iter().map(|(n, _)| n.clone()))
            .chain(shape.columns.iter().map(|(n, _)| format!("peak_{n}")))
            .chain(shape.columns.iter().map(|(n, _)| format!("final_{n}")))
            .collect();
        writeln!(out, "{}", header.join(","))?;
        for row in rows {
            write!(out, "{}", row.index)?;
            for v in row
                .drawn
                .iter()
                .chain(&metrics(row.trajectory.as_deref(), width))
            {
                out.write_all(b",")?;
                write_number(out, *v)?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    })?;
    Ok(())
}

/// `trajectories.csv`: `index`, `t`, the banded columns; one row per sample and time
/// (failed samples left out).
fn write_trajectories(
    dir: &Path,
    shape: &StudyShape,
    times: &[f64],
    rows: &[SampleRow],
) -> Result<(), RunError> {
    let width = shape.columns.len();
    write_atomically(&dir.join(TRAJECTORIES), |out| {
        let header: Vec<&str> = ["index", "t"]
            .into_iter()
            .chain(shape.columns.iter().map(|(n, _)| n.as_str()))
            .collect();
        writeln!(out, "{}", header.join(","))?;
        for row in rows {
            let Some(values) = &row.trajectory else {
                continue;
            };
            for (k, t) in times.iter().enumerate() {
                write!(out, "{},", row.index)?;
                write_number(out, *t)?;
                for v in &values[k * width..(k + 1) * width] {
                    out.write_all(b",")?;
                    write_number(out, *v)?;
                }
                out.write_all(b"\n")?;
            }
        }
        Ok(())
    })?;
    Ok(())
}

/// The numbers of a CSV file written by this module: its header and rows.
pub(super) fn read_table(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read it: {e}", path.display()))?;
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::to_owned)
        .collect::<Vec<_>>();
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let row: Result<Vec<f64>, _> = line.split(',').map(str::parse::<f64>).collect();
        match row {
            Ok(row) if row.len() == header.len() => rows.push(row),
            _ => {
                return Err(format!(
                    "{}:{}: not a row of {} numbers; was the file edited?",
                    path.display(),
                    i + 2,
                    header.len()
                ))
            }
        }
    }
    Ok((header, rows))
}

/// The rows of one Monte Carlo shard folder, and its sample times.
fn read_shard(
    dir: &Path,
    shape: &StudyShape,
    m: &Manifest,
) -> Result<(Vec<f64>, Vec<SampleRow>), String> {
    let (_, samples) = read_table(&dir.join(SAMPLES))?;
    let (_, points) = read_table(&dir.join(TRAJECTORIES))?;
    let drawn = shape.parameters.len();
    let width = shape.columns.len();
    let count = m.end - m.first;
    if samples.len() != count {
        return Err(format!(
            "{}: {SAMPLES} has {} rows, the manifest says {count} samples",
            dir.display(),
            samples.len()
        ));
    }
    let times_len = points.len().checked_div(count).unwrap_or(0);
    if times_len * count != points.len() {
        return Err(format!("{}: {TRAJECTORIES} is incomplete", dir.display()));
    }
    let times: Vec<f64> = points.iter().take(times_len).map(|r| r[1]).collect();
    let rows = samples
        .iter()
        .zip(points.chunks(times_len.max(1)))
        .map(|(s, chunk)| SampleRow {
            index: s[0] as usize,
            drawn: s[1..1 + drawn].to_vec(),
            trajectory: Some(
                chunk
                    .iter()
                    .flat_map(|r| r[2..2 + width].iter().copied())
                    .collect(),
            ),
        })
        .collect();
    Ok((times, rows))
}

/// Joins shard folders into the one-process result at `out` (see the [module
/// documentation](self)).
///
/// # Errors
///
/// The manifests' problems (every one, naming the folders) or an unreadable shard as
/// [`RunError::Figures`]-free messages in `Err(Left)`; a failure to write as
/// [`RunError`].
pub fn merge(
    dirs: &[PathBuf],
    out: &Path,
    observer: &dyn Observer,
) -> Result<Result<StudyOutcome, RunError>, Vec<String>> {
    let mut manifests = Vec::new();
    let mut errors = Vec::new();
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    if let Some(dir) = dirs.iter().find(|d| same(d, out)) {
        return Err(vec![format!(
            "the output folder {} is one of the shards: the merge would replace it; choose \
             another --out",
            dir.display()
        )]);
    }
    for dir in dirs {
        match Manifest::read(dir) {
            Ok(m) => manifests.push((dir.clone(), m)),
            Err(e) => errors.push(e),
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let shards = manifest::check(manifests)?;
    let kind = shards[0].1.kind.clone();
    match kind.as_str() {
        "monte_carlo" => merge_study(&shards, out, observer),
        "sweep" => super::sweep::merge_sweep(&shards, out, observer),
        other => Err(vec![format!(
            "{}: unknown kind of study `{other}`",
            shards[0].0.display()
        )]),
    }
}

fn merge_study(
    shards: &[(PathBuf, Manifest)],
    out: &Path,
    observer: &dyn Observer,
) -> Result<Result<StudyOutcome, RunError>, Vec<String>> {
    let shape: StudyShape = serde_yaml::from_value(shards[0].1.details.clone()).map_err(|e| {
        vec![format!(
            "{}: {}: {e}",
            shards[0].0.display(),
            manifest::FILE_NAME
        )]
    })?;
    let mut times: Option<Vec<f64>> = None;
    let mut rows = Vec::new();
    for (dir, m) in shards {
        let (t, r) = read_shard(dir, &shape, m).map_err(|e| vec![e])?;
        if times.as_ref().is_some_and(|times| *times != t) {
            return Err(vec![format!(
                "{}: its sample times differ from the first shard's",
                dir.display()
            )]);
        }
        times = Some(t);
        rows.extend(r);
    }
    let times = times.unwrap_or_default();
    let started = Instant::now();
    let result = (|| {
        let folder = RunFolder::begin(out)?;
        let head = format!(
            "monte carlo    {}: {} samples merged from {} shards\n",
            shape.model,
            rows.len(),
            shards.len()
        );
        let (mut files, drawn, text) =
            write_study(folder.path(), &shape, &times, &rows, &head, observer)?;
        let mut failure = None;
        let (_, figures_error) = settle_drawing(drawn, &mut failure, observer)?;
        if let Some(path) = merged_record(shards, folder.path(), &files)? {
            files.push(path);
        }
        let target = folder.commit(failure.is_some())?;
        Ok(StudyOutcome {
            summary: format!("{text}results        {}\n", target.display()),
            files: files.iter().map(|f| target.join(f)).collect(),
            failure,
            figures_error,
            wall: started.elapsed(),
        })
    })();
    Ok(result)
}

/// Writes the record of a merge into `dir`: the first shard's `run.yaml` (the study's
/// settings are the same in every shard) without its shard, with the merge's command
/// line, the folders joined and the files written. `None` when the shard has no record.
pub(super) fn merged_record(
    shards: &[(PathBuf, Manifest)],
    dir: &Path,
    files: &[String],
) -> Result<Option<String>, RunError> {
    let Ok(text) = std::fs::read_to_string(shards[0].0.join(provenance::FILE_NAME)) else {
        return Ok(None);
    };
    let Ok(mut record) = serde_yaml::from_str::<RunRecord>(&text) else {
        return Ok(None);
    };
    record.shard = None;
    record.command_line = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    record.merged_from = shards
        .iter()
        .map(|(d, _)| d.display().to_string())
        .collect();
    record.results = files
        .iter()
        .filter(|f| f.ends_with(".csv"))
        .cloned()
        .collect();
    provenance::write(dir, &record)?;
    Ok(Some(provenance::FILE_NAME.to_owned()))
}
