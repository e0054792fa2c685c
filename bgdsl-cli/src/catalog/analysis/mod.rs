//! The generic side of the analysis commands (`steady`, `linearize`, `bode`,
//! `periodic`, `fit`): how a command reaches `bgdsl-analysis` for the model behind an
//! [`Entry`], and the one writer of their results sets.
//!
//! Each analysis is a method of [`CatalogModel`](super::CatalogModel) (e.g.
//! [`CatalogModel::steady`](super::CatalogModel::steady)), implemented once for every
//! model by calling a generic function of a submodule here with the model's type.
//! What it returns is plain data; the submodule also turns that data into an
//! [`AnalysisSet`] (files, summary, figures, `run.yaml`'s `analysis:` record), which
//! [`write_set`] writes the way a run writes its folder:
//!
//! - into a staging folder begun with [`begin`] *before* the analysis runs (so that an
//!   output folder with foreign content is refused first), swapped in whole when every
//!   file is written ([`RunFolder`]): a failed or interrupted analysis leaves the
//!   destination as it was, and writes no `.partial` folder (it has no partial result);
//! - `run.yaml` is the record of a run ([`provenance`]) with the parameters, the
//!   initial state and the solver the analysis used, plus `analysis:`, what was asked
//!   and the headline numbers;
//! - figures through [`crate::plot`], `index.html` through [`crate::report`].

pub mod bode;
pub mod fit;
pub mod linear;
pub mod periodic;
pub mod steady;

use core::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use bgdsl_analysis::AnalysisError;
use bgdsl_runtime::{Model, Recorder, Simulation};
use serde_yaml::{Mapping, Value};

use super::folder::RunFolder;
use super::run::{initial_state, Plots};
use super::{figures, Entry, Outcome, RunError, RunPlan};
use crate::plot::{draw_line_chart_with, ChartOptions, ImageFormat, LineChart};
use crate::provenance;
use crate::report::{DrawnFigure, INDEX_FILE};

/// Where an analysis takes the model's state: the operating point of a linear model or
/// a frequency response, the start of a periodic orbit's search.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum OperatingPoint {
    /// The initial state (the model's, with the scenario's `initial:`), at the plan's
    /// start time.
    #[default]
    Initial,
    /// The equilibrium found from the initial state ([`steady`]).
    Steady,
    /// The state a run from the initial state reaches at this time, s.
    Time(f64),
}

impl FromStr for OperatingPoint {
    type Err = String;

    /// `initial`, `steady`, or a time in seconds.
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "initial" => Ok(OperatingPoint::Initial),
            "steady" => Ok(OperatingPoint::Steady),
            other => match other.parse::<f64>() {
                Ok(t) if t.is_finite() => Ok(OperatingPoint::Time(t)),
                _ => Err(format!(
                    "`{other}` is not an operating point: give `initial`, `steady` or a time \
                     in seconds (e.g. 2.5)"
                )),
            },
        }
    }
}

impl OperatingPoint {
    /// The point for a summary, with the time it was taken at:
    /// `the initial state (t = 0 s)`, `the equilibrium (t = 0 s)`,
    /// `the state of a run at t = 0.5 s`.
    pub fn describe(self, t: f64) -> String {
        match self {
            OperatingPoint::Initial => format!("the initial state (t = {t} s)"),
            OperatingPoint::Steady => format!("the equilibrium (f evaluated at t = {t} s)"),
            OperatingPoint::Time(_) => format!("the state of a run at t = {t} s"),
        }
    }
}

impl fmt::Display for OperatingPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OperatingPoint::Initial => f.write_str("initial"),
            OperatingPoint::Steady => f.write_str("steady"),
            OperatingPoint::Time(t) => write!(f, "{t}"),
        }
    }
}

/// A state at a time: where an analysis was done.
#[derive(Clone, Debug, PartialEq)]
pub struct StateAt {
    /// The time, s.
    pub t: f64,
    /// The state, in the order of the state vector.
    pub x: Vec<f64>,
}

/// Why an analysis command produced no results (nothing was written).
#[derive(Debug)]
#[non_exhaustive]
pub enum AnalysisFailure {
    /// What the command was given does not fit the model (an unknown state, input or
    /// output, an operating point before the start); a usage error.
    Usage(String),
    /// The analysis itself failed: a singular Jacobian, Newton without convergence, a
    /// failed run to the operating point.
    Analysis(AnalysisError),
    /// The results could not be written, or the folder is not the program's.
    Run(RunError),
    /// The analysis found no result, for the reason given (a periodic orbit's
    /// shooting without convergence, a fit whose data do not determine a parameter).
    Failed(String),
    /// A signal arrived before the results were committed.
    Interrupted,
}

impl fmt::Display for AnalysisFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AnalysisFailure::Usage(message) | AnalysisFailure::Failed(message) => {
                f.write_str(message)
            }
            AnalysisFailure::Analysis(e) => write!(f, "{e}"),
            AnalysisFailure::Run(e) => write!(f, "{e}"),
            AnalysisFailure::Interrupted => {
                f.write_str("interrupted before the results were written; nothing was changed")
            }
        }
    }
}

impl std::error::Error for AnalysisFailure {}

impl From<AnalysisError> for AnalysisFailure {
    /// An unknown name is the user's to fix (a usage error); the rest are failures.
    fn from(e: AnalysisError) -> Self {
        match e {
            AnalysisError::UnknownName { .. } => AnalysisFailure::Usage(e.to_string()),
            e => AnalysisFailure::Analysis(e),
        }
    }
}

impl From<RunError> for AnalysisFailure {
    fn from(e: RunError) -> Self {
        AnalysisFailure::Run(e)
    }
}

/// The state index of `name`.
///
/// # Errors
///
/// [`AnalysisFailure::Usage`] listing the states.
pub fn state_index(entry: &Entry, name: &str) -> Result<usize, AnalysisFailure> {
    let names = entry.model.state_names();
    names.iter().position(|n| *n == name).ok_or_else(|| {
        AnalysisFailure::Usage(format!(
            "the model {} has no state `{name}`; its states: {}",
            entry.name,
            names.join(", ")
        ))
    })
}

/// The plan's initial state of `model` (its own, with the plan's `initial:`
/// replacements) at the plan's start time.
pub fn initial<M: Model>(model: &M, plan: &RunPlan) -> StateAt {
    StateAt {
        t: plan.span()[0],
        x: initial_state(model, &plan.initial),
    }
}

/// The state a run of `model` by `plan`'s solver from its initial state reaches at
/// time `t` (at least the start time).
///
/// # Errors
///
/// [`AnalysisFailure::Usage`] for a time before the start;
/// [`AnalysisFailure::Analysis`] when the run fails.
pub fn state_at_time<M: Model>(
    model: &M,
    plan: &RunPlan,
    t: f64,
) -> Result<StateAt, AnalysisFailure> {
    let start = initial(model, plan);
    if t < start.t {
        return Err(AnalysisFailure::Usage(format!(
            "the operating point's time {t} s is before the run's start, {} s",
            start.t
        )));
    }
    if t == start.t {
        return Ok(start);
    }
    /// Keeps the last state recorded.
    struct Last(Vec<f64>);
    impl Recorder for Last {
        fn record(&mut self, _t: f64, x: &[f64], _y: &[f64]) {
            self.0.clear();
            self.0.extend_from_slice(x);
        }
        fn stop_requested(&self) -> bool {
            crate::interrupt::requested()
        }
    }
    let mut sim = Simulation::new(model, plan.solver)
        .map_err(|e| AnalysisFailure::Analysis(AnalysisError::Solver(e)))?;
    if let Some(atol) = &plan.atol {
        sim.set_atol(atol)
            .map_err(|e| AnalysisFailure::Analysis(AnalysisError::Solver(e)))?;
    }
    let mut last = Last(start.x.clone());
    sim.run(start.t, &start.x, &[start.t, t], &mut last)
        .map_err(|e| AnalysisFailure::Analysis(AnalysisError::Solver(e)))?;
    Ok(StateAt { t, x: last.0 })
}

/// One data file of a results set.
#[derive(Clone, Debug, PartialEq)]
pub struct DataFile {
    /// Its name in the folder, e.g. `steady.yaml`.
    pub name: String,
    /// Its contents.
    pub text: String,
}

impl DataFile {
    /// The file `name` holding `text`.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        DataFile {
            name: name.into(),
            text: text.into(),
        }
    }
}

/// A figure of a results set, drawn by [`write_set`] as PNG and SVG.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Its id: the file name without extension, e.g. `bode_magnitude`.
    pub id: String,
    /// Its title in `index.html`.
    pub title: String,
    /// What it shows.
    pub caption: String,
    /// The chart.
    pub chart: LineChart,
    /// How it is drawn (fixed ticks, ranges).
    pub options: ChartOptions,
}

/// An analysis's results, ready to write ([`write_set`]).
#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisSet {
    /// The command, e.g. `steady`: the `command` of `run.yaml`'s `analysis:`.
    pub command: &'static str,
    /// The summary, printed and shown at the top of `index.html` (without the report
    /// line, which [`write_set`] adds).
    pub summary: String,
    /// The data files, the main one first.
    pub files: Vec<DataFile>,
    /// The figures (not drawn when the plan's plots are off).
    pub figures: Vec<Figure>,
    /// HTML fragments for `index.html` (tables), after the summary.
    pub sections: Vec<String>,
    /// What was asked and the headline results: `run.yaml`'s `analysis:` mapping
    /// (`command` is added).
    pub record: Mapping,
}

/// Begins the results folder of `plan` (see [`RunFolder::begin`]): call it before the
/// analysis, so that a folder with foreign content is refused before any work, and a
/// failed analysis leaves nothing behind (the staging folder is removed when dropped).
///
/// # Errors
///
/// [`RunError::NotOurs`] or [`RunError::Io`], as [`RunFolder::begin`].
pub fn begin(plan: &RunPlan) -> Result<RunFolder, RunError> {
    RunFolder::begin(&plan.out_dir)
}

/// Writes `set` into `folder` (begun by [`begin`] for `plan`) and commits it whole:
/// the data files, the figures (unless the plan's plots are off), `run.yaml` (the
/// run's record with the set's `analysis:`) and `index.html`. The outcome's summary
/// ends with the report's line.
///
/// # Errors
///
/// [`AnalysisFailure::Run`] when a file cannot be written (the destination is then
/// untouched), [`AnalysisFailure::Interrupted`] when a signal came first.
pub fn write_set(
    folder: RunFolder,
    entry: &Entry,
    plan: &RunPlan,
    set: AnalysisSet,
) -> Result<Outcome, AnalysisFailure> {
    let started = std::time::Instant::now();
    let dir = folder.path().to_path_buf();
    let target = folder.target(false);
    let mut results = Vec::new();
    for file in &set.files {
        let path = dir.join(&file.name);
        bgdsl_runtime::record::write_atomically(&path, |out| {
            std::io::Write::write_all(out, file.text.as_bytes())
        })
        .map_err(|e| AnalysisFailure::Run(RunError::Csv(e)))?;
        results.push(target.join(&file.name));
    }
    let drawn = draw(&set.figures, plan, &dir)?;
    if crate::interrupt::requested() {
        return Err(AnalysisFailure::Interrupted);
    }
    let mut summary = set.summary.clone();
    let figure_files: usize = drawn.iter().map(|f| f.files.len()).sum();
    if !drawn.is_empty() {
        summary.push_str(&format!(
            "figures        {} figures ({figure_files} files) in {:.0} ms\n",
            drawn.len(),
            started.elapsed().as_secs_f64() * 1e3
        ));
    }
    summary.push_str(&super::report_line(&target.join(INDEX_FILE)));
    let mut record = provenance::RunRecord::of_run(entry, plan, &results, None)?;
    let mut analysis = Mapping::new();
    analysis.insert(Value::from("command"), Value::from(set.command));
    analysis.extend(set.record.clone());
    record.analysis = Some(analysis);
    provenance::write(&dir, &record)?;
    figures::index(&dir, &plan.title, &summary, &drawn, &set.sections)?;
    if crate::interrupt::requested() {
        return Err(AnalysisFailure::Interrupted);
    }
    let target = folder.commit(false)?;
    let in_target = |path: &PathBuf| target.join(path.file_name().unwrap_or_default());
    let mut files = results;
    files.extend(drawn.iter().flat_map(|f| f.files.iter().map(in_target)));
    files.push(target.join(provenance::FILE_NAME));
    files.push(target.join(INDEX_FILE));
    Ok(Outcome {
        summary,
        files,
        failure: None,
        figures_error: None,
        integration: std::time::Duration::ZERO,
        plotting: started.elapsed(),
    })
}

/// Draws `figures` into `dir` (none when the plan's plots are off; only those named
/// when it names some).
fn draw(figures: &[Figure], plan: &RunPlan, dir: &Path) -> Result<Vec<DrawnFigure>, RunError> {
    let mut drawn = Vec::new();
    for figure in figures {
        let wanted = match &plan.plots {
            Plots::None => false,
            Plots::All => true,
            Plots::Only(ids) => ids.contains(&figure.id),
        };
        if !wanted {
            continue;
        }
        if crate::interrupt::requested() {
            break;
        }
        let files = draw_line_chart_with(
            &figure.chart,
            &figure.options,
            &dir.join(&figure.id),
            &ImageFormat::ALL,
        )
        .map_err(figures::plot_error)?;
        drawn.push(DrawnFigure {
            id: figure.id.clone(),
            title: figure.title.clone(),
            caption: figure.caption.clone(),
            files,
        });
    }
    Ok(drawn)
}

/// `value` with its unit, for summaries: `1.5 rad/s`, or the number alone.
pub fn with_unit(value: f64, unit: &str) -> String {
    let number = super::format_significant(value);
    if unit.is_empty() {
        number
    } else {
        format!("{number} {unit}")
    }
}

/// `text` escaped for HTML.
pub(crate) fn html(text: &str) -> String {
    crate::report::escape(text)
}
