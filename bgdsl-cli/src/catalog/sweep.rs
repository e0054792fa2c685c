//! Sweeps: the same run at every point of a grid over one or two parameters, spread over
//! the cores (rayon); see the [catalogue's documentation](crate::catalog).

use core::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use bgdsl_runtime::record::{write_atomically, write_number};
use bgdsl_runtime::Recorder;
use rayon::prelude::*;
use serde_yaml::Value;

use crate::study::manifest::{self, study_hash, Manifest};
use crate::study::shard::Shard;

use super::folder::RunFolder;
use super::params::{format_number, format_significant};
use super::run::{settle_drawing, Observer};
use super::study::StudyOutcome;
use super::{figures, Column, Entry, RunError, RunPlan};
use crate::provenance;
use crate::report::INDEX_FILE;

/// One swept parameter and its values.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Axis {
    /// The parameter's name (a scalar parameter).
    pub name: String,
    /// Its unit, possibly empty.
    pub unit: String,
    /// The values, in order.
    pub values: Vec<f64>,
}

/// A quantity a sweep reports: the peak over the window of the magnitude (Euclidean
/// norm) of some columns, e.g. `|Tc| = |(Tc_x, Tc_y, Tc_z)|`.
#[derive(Clone, Debug, PartialEq)]
pub struct Metric {
    /// The name as given, e.g. `Tc`.
    pub name: String,
    /// The columns whose norm is taken.
    pub columns: Vec<Column>,
    /// The unit, when known.
    pub unit: Option<&'static str>,
}

impl Metric {
    /// The column name in `sweep.csv`: `peak_<name>`.
    pub fn column_name(&self) -> String {
        format!("peak_{}", self.name)
    }

    /// `peak |Tc| (N·m)`.
    pub fn label(&self) -> String {
        match self.unit {
            Some(unit) => format!("peak |{}| ({unit})", self.name),
            None => format!("peak |{}|", self.name),
        }
    }
}

/// A validated sweep.
#[derive(Clone, Debug)]
pub struct SweepPlan {
    /// The run every point starts from (its `record` is ignored; its `plots` decide
    /// whether the sweep's charts are drawn).
    pub base: RunPlan,
    /// One or two axes; the points are every combination, the first axis outermost.
    pub axes: Vec<Axis>,
    /// What each point reports.
    pub metrics: Vec<Metric>,
    /// The window the peaks are taken over, s (both ends included).
    pub window: [f64; 2],
}

impl SweepPlan {
    /// Every point of the grid: one value per axis.
    pub fn points(&self) -> Vec<Vec<f64>> {
        let mut points = vec![Vec::new()];
        for axis in &self.axes {
            points = points
                .into_iter()
                .flat_map(|p| {
                    axis.values.iter().map(move |&v| {
                        let mut q = p.clone();
                        q.push(v);
                        q
                    })
                })
                .collect();
        }
        points
    }

    /// The run at `point`.
    pub fn plan_at(&self, point: &[f64]) -> RunPlan {
        let mut plan = self.base.clone();
        for (axis, &v) in self.axes.iter().zip(point) {
            plan.params
                .insert(Value::String(axis.name.clone()), Value::from(v));
        }
        plan
    }
}

/// What a sweep's table and charts need besides the numbers: kept in a shard's
/// manifest so that `merge` draws what the one-process run draws.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweepShape {
    /// The axes.
    pub axes: Vec<Axis>,
    /// Each metric's name and label (`peak |Tc| (N·m)`).
    pub metrics: Vec<(String, String)>,
    /// The window of the peaks, s.
    pub window: [f64; 2],
    /// The title of `index.html`.
    pub title: String,
    /// The model's name.
    pub model: String,
    /// Whether charts are drawn.
    pub plots: bool,
}

impl SweepPlan {
    /// The shape of its files.
    pub fn shape(&self, entry: &Entry) -> SweepShape {
        SweepShape {
            axes: self.axes.clone(),
            metrics: self
                .metrics
                .iter()
                .map(|m| (m.name.clone(), m.label()))
                .collect(),
            window: self.window,
            title: self.base.title.clone(),
            model: entry.name.to_owned(),
            plots: self.base.plots != super::Plots::None,
        }
    }

    /// Every setting that changes a result, as text, for the study's hash.
    fn canonical(&self, entry: &Entry) -> String {
        let metrics: Vec<(&str, Vec<Column>)> = self
            .metrics
            .iter()
            .map(|m| (m.name.as_str(), m.columns.clone()))
            .collect();
        format!(
            "sweep\n{}\n{}{:?}\n{metrics:?}\n{:?}\n",
            entry.name,
            super::study::canonical_run(&self.base),
            self.axes,
            self.window
        )
    }
}

/// Writes `sweep.csv`: the axes' names and `peak_<metric>`, then one row per point.
fn write_table(
    dir: &Path,
    shape: &SweepShape,
    points: &[Vec<f64>],
    rows: &[Vec<f64>],
) -> Result<PathBuf, RunError> {
    let path = dir.join(TABLE);
    let header: Vec<String> = shape
        .axes
        .iter()
        .map(|a| a.name.clone())
        .chain(shape.metrics.iter().map(|(n, _)| format!("peak_{n}")))
        .collect();
    write_atomically(&path, |out| {
        writeln!(out, "{}", header.join(","))?;
        for (point, values) in points.iter().zip(rows) {
            for (i, v) in point.iter().chain(values).enumerate() {
                if i > 0 {
                    out.write_all(b",")?;
                }
                write_number(out, *v)?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    })?;
    Ok(path)
}

/// The sweep's table.
const TABLE: &str = "sweep.csv";

/// Joins the shard folders of a sweep (checked by [`manifest::check`]) into `out`:
/// `sweep.csv` as the one-process run writes it, its charts and `index.html`.
pub(super) fn merge_sweep(
    shards: &[(PathBuf, Manifest)],
    out: &Path,
    observer: &dyn Observer,
) -> Result<Result<StudyOutcome, RunError>, Vec<String>> {
    let shape: SweepShape = serde_yaml::from_value(shards[0].1.details.clone()).map_err(|e| {
        vec![format!(
            "{}: {}: {e}",
            shards[0].0.display(),
            manifest::FILE_NAME
        )]
    })?;
    let axes = shape.axes.len();
    let mut points = Vec::new();
    let mut rows = Vec::new();
    for (dir, m) in shards {
        let (_, table) = super::study::read_table(&dir.join(TABLE)).map_err(|e| vec![e])?;
        if table.len() != m.end - m.first {
            return Err(vec![format!(
                "{}: {TABLE} has {} rows, the manifest says {} points",
                dir.display(),
                table.len(),
                m.end - m.first
            )]);
        }
        for row in table {
            points.push(row[..axes].to_vec());
            rows.push(row[axes..].to_vec());
        }
    }
    let started = Instant::now();
    let result = (|| {
        let folder = RunFolder::begin(out)?;
        let dir = folder.path();
        let path = write_table(dir, &shape, &points, &rows)?;
        let drawing = if !shape.plots || observer.stop_requested() {
            Ok(Vec::new())
        } else {
            figures::sweep(&shape, &points, &rows, dir)
        };
        let mut failure = None;
        let (drawn, figures_error) = settle_drawing(drawing, &mut failure, observer)?;
        let summary = format!(
            "sweep          {}: {} points merged from {} shards\n",
            shape.model,
            points.len(),
            shards.len()
        );
        figures::index(dir, &shape.title, &summary, &drawn, &[])?;
        super::study::merged_record(shards, dir, &[TABLE.to_owned()])?;
        let name = path.file_name().unwrap_or_default().to_owned();
        let target = folder.commit(failure.is_some())?;
        Ok(StudyOutcome {
            summary: format!("{summary}results        {}\n", target.display()),
            files: vec![target.join(name), target.join(INDEX_FILE)],
            failure,
            figures_error,
            wall: started.elapsed(),
        })
    })();
    Ok(result)
}

/// What a sweep produced.
#[derive(Clone, Debug)]
pub struct SweepOutcome {
    /// The summary: the table and any failures.
    pub summary: String,
    /// Every file written, the table first.
    pub files: Vec<PathBuf>,
    /// Why some points have no values, when some have none.
    pub failure: Option<String>,
    /// Why the charts could not be drawn, when they could not (the table and
    /// `index.html` are written all the same).
    pub figures_error: Option<String>,
    /// Wall time of all the runs.
    pub wall: Duration,
}

/// Records the peak magnitude of each metric over a window.
pub(super) struct Peaks<'a> {
    metrics: &'a [Metric],
    window: [f64; 2],
    values: Vec<f64>,
}

impl<'a> Peaks<'a> {
    pub(super) fn new(metrics: &'a [Metric], window: [f64; 2]) -> Self {
        Peaks {
            metrics,
            window,
            values: vec![f64::NAN; metrics.len()],
        }
    }

    pub(super) fn into_values(self) -> Vec<f64> {
        self.values
    }
}

impl Recorder for Peaks<'_> {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        if t < self.window[0] || t > self.window[1] {
            return;
        }
        for (metric, peak) in self.metrics.iter().zip(&mut self.values) {
            let magnitude = metric
                .columns
                .iter()
                .map(|c| c.value(x, y).powi(2))
                .sum::<f64>()
                .sqrt();
            if peak.is_nan() || magnitude > *peak {
                *peak = magnitude;
            }
        }
    }
}

/// Passes only the stop request on to the sweep's observer (the runs of a sweep do not
/// move its progress bar sample by sample).
struct PointObserver<'a>(&'a dyn Observer);

impl Observer for PointObserver<'_> {
    fn stop_requested(&self) -> bool {
        self.0.stop_requested()
    }
}

/// Runs the sweep on rayon's pool and writes `sweep.csv`, its charts and `index.html`
/// as one set into the base plan's output folder (or, when points failed or were not
/// run, into its `.partial` sibling; see the [catalogue's
/// documentation](crate::catalog#results-folders)).
///
/// # Errors
///
/// [`RunError`] when a file cannot be written; failed points are not errors (see the
/// [catalogue's documentation](crate::catalog)).
pub fn run_sweep(
    entry: &Entry,
    plan: &SweepPlan,
    shard: Option<Shard>,
    observer: &dyn Observer,
) -> Result<SweepOutcome, RunError> {
    let all = plan.points();
    let range = shard.map_or(0..all.len(), |s| s.range(all.len()));
    let points = all[range.clone()].to_vec();
    let folder = RunFolder::begin(&plan.base.out_dir)?;
    observer.sweep_started(points.len());
    let started = Instant::now();
    let results: Vec<Result<Vec<f64>, RunError>> = points
        .par_iter()
        .map(|point| {
            let watcher = PointObserver(observer);
            let result = if observer.stop_requested() {
                Err(RunError::NotRun)
            } else {
                entry
                    .model
                    .sweep_point(&plan.plan_at(point), &plan.metrics, plan.window, &watcher)
            };
            observer.point_done();
            result
        })
        .collect();
    let wall = started.elapsed();

    let failures: Vec<(usize, String)> = results
        .iter()
        .enumerate()
        .filter_map(|(i, r)| r.as_ref().err().map(|e| (i, e.to_string())))
        .collect();
    let mut failure = (!failures.is_empty()).then(|| {
        format!(
            "{} of {} points failed or were not run",
            failures.len(),
            points.len()
        )
    });
    let rows: Vec<Vec<f64>> = results
        .iter()
        .map(|r| match r {
            Ok(values) => values.clone(),
            Err(_) => vec![f64::NAN; plan.metrics.len()],
        })
        .collect();

    let dir = folder.path();
    let shape = plan.shape(entry);
    let table_name = TABLE;
    write_table(dir, &shape, &points, &rows)?;
    if let Some(shard) = shard {
        let manifest = Manifest {
            program: super::study::program(&plan.base),
            study: study_hash(&super::study::program(&plan.base), &plan.canonical(entry)),
            kind: "sweep".to_owned(),
            shard: shard.index,
            shards: shard.count,
            items: all.len(),
            first: range.start,
            end: range.end,
            complete: failures.is_empty(),
            details: serde_yaml::to_value(&shape).unwrap_or_default(),
        };
        let path = dir.join(manifest::FILE_NAME);
        write_atomically(&path, |out| out.write_all(manifest.to_yaml().as_bytes()))?;
    }

    let drawing = if !shape.plots || shard.is_some() || observer.stop_requested() {
        Ok(Vec::new())
    } else {
        figures::sweep(&shape, &points, &rows, dir)
    };
    let (drawn, figures_error) = settle_drawing(drawing, &mut failure, observer)?;
    let partial = failure.is_some();
    let target = folder.target(partial);
    let path = target.join(table_name);

    let mut summary = String::new();
    if let Some(failure) = &failure {
        let _ = writeln!(summary, "PARTIAL SWEEP {failure}");
    }
    let axes: Vec<&str> = plan.axes.iter().map(|a| a.name.as_str()).collect();
    let _ = writeln!(
        summary,
        "sweep          {} over {}: {} runs on {} threads in {:.2} s",
        entry.name,
        axes.join(" × "),
        points.len(),
        rayon::current_num_threads(),
        wall.as_secs_f64()
    );
    summary.push_str(&provenance::summary_lines(entry, &plan.base, &axes));
    let _ = writeln!(
        summary,
        "peaks over     {} to {} s of each run",
        plan.window[0], plan.window[1]
    );
    let _ = writeln!(
        summary,
        "results        {} ({} rows)",
        path.display(),
        points.len()
    );
    let _ = writeln!(summary);
    let labels: Vec<String> = plan
        .axes
        .iter()
        .map(|a| {
            if a.unit.is_empty() {
                a.name.clone()
            } else {
                format!("{} ({})", a.name, a.unit)
            }
        })
        .chain(plan.metrics.iter().map(Metric::label))
        .collect();
    let widths: Vec<usize> = labels.iter().map(|l| l.chars().count().max(10)).collect();
    let mut line = String::from(" ");
    for (label, w) in labels.iter().zip(&widths) {
        let _ = write!(line, " {label:>w$}");
    }
    let _ = writeln!(summary, "{}", line.trim_end());
    for (point, values) in points.iter().zip(&rows) {
        let mut line = String::from(" ");
        for (v, w) in point.iter().chain(values).zip(&widths) {
            let text = if v.is_nan() {
                "failed".to_owned()
            } else {
                format_significant(*v)
            };
            let _ = write!(line, " {text:>w$}");
        }
        let _ = writeln!(summary, "{line}");
    }
    for (i, message) in &failures {
        let coordinates: Vec<String> = plan
            .axes
            .iter()
            .zip(&points[*i])
            .map(|(a, v)| format!("{} = {}", a.name, format_number(*v)))
            .collect();
        let _ = writeln!(summary, "  at {}: {message}", coordinates.join(", "));
    }

    summary.push_str(&super::report_line(&target.join(INDEX_FILE)));
    let mut record = provenance::RunRecord::of_sweep(
        entry,
        plan,
        std::slice::from_ref(&path),
        failure.as_deref(),
    )?;
    record.shard = shard.map(|s| s.to_string());
    provenance::write(dir, &record)?;
    figures::index(dir, &plan.base.title, &summary, &drawn, &[])?;
    let target = folder.commit(partial)?;
    let mut files = vec![path, target.join(provenance::FILE_NAME)];
    files.extend(drawn.iter().flat_map(|f| {
        f.files
            .iter()
            .map(|p| target.join(p.file_name().unwrap_or_default()))
    }));
    files.push(target.join(INDEX_FILE));
    Ok(SweepOutcome {
        summary,
        files,
        failure,
        figures_error,
        wall,
    })
}

/// The unit of a metric over the columns `names` of `model` (the norm of a vector
/// output's components): the unit the model declares for them, when they share one.
pub fn metric_unit(model: &dyn super::CatalogModel, names: &[&str]) -> Option<&'static str> {
    let units: Vec<&'static str> = names
        .iter()
        .map(|name| super::columns::column_unit(model, name).0)
        .collect();
    let first = *units.first()?;
    (!first.is_empty() && units.iter().all(|u| *u == first)).then_some(first)
}
