//! Running a model of the catalogue into files: what to run ([`RunPlan`]), who watches
//! ([`Observer`]), what came of it ([`Outcome`]) and what can stop it ([`RunError`]).
//! The files a run writes, and the results-folder rule, are described in the
//! [catalogue's documentation](crate::catalog).

use core::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use bgdsl_runtime::{CsvError, Model, Recorder, Simulation, Solver, SolverError, Stats};
use serde::de::DeserializeOwned;
use serde_yaml::{Mapping, Value};

use bgdsl_runtime::FromParams;

use super::columns::{all_columns, resolve_columns, write_units, Table};
use super::events::{self, EventCollector};
use super::extras::{ExtraRun, Finished, RunContext};
use super::folder::RunFolder;
use super::params::format_significant;
use super::{addons, figures};
use super::{Column, Entry};
use crate::provenance::{self, Context};
use crate::report::{DrawnFigure, INDEX_FILE};

/// Which figures a run draws.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Plots {
    /// None.
    None,
    /// All of them (the default).
    #[default]
    All,
    /// Those with these ids (output names, or the ids of the entry's
    /// [`Extras::figure_ids`](super::Extras::figure_ids)).
    Only(Vec<String>),
}

/// A validated run: everything a model of the catalogue needs to run once.
#[derive(Clone, Debug)]
pub struct RunPlan {
    /// Every parameter of the model, checked.
    pub params: Mapping,
    /// Initial conditions that replace the model's: (state index, value).
    pub initial: Vec<(usize, f64)>,
    /// The sample times, increasing, at least one; the run starts at the first.
    pub times: Vec<f64>,
    /// The solver and its settings.
    pub solver: Solver,
    /// One absolute tolerance per state, replacing the solver's scalar `atol`
    /// ([`Simulation::set_atol`]); `None`: the scalar for every state.
    pub atol: Option<Vec<f64>>,
    /// The states held at or above zero, by index ([`Simulation::set_non_negative`]).
    pub non_negative: Vec<usize>,
    /// The states and outputs to record into the table `<name>.csv` (`None`: the
    /// entry's [`Entry::record`], by default every state and output).
    pub record: Option<Vec<(String, Column)>>,
    /// Which figures to draw.
    pub plots: Plots,
    /// The phase portraits to draw (recorded whatever `record` says).
    pub phase: Vec<super::PhasePair>,
    /// Where the files go.
    pub out_dir: PathBuf,
    /// The title of `index.html`.
    pub title: String,
    /// What the plan was made from (command line, scenario file), for `run.yaml`.
    pub context: Arc<Context>,
}

impl RunPlan {
    /// The first and the last sample time.
    pub fn span(&self) -> [f64; 2] {
        [
            self.times.first().copied().unwrap_or(0.0),
            self.times.last().copied().unwrap_or(0.0),
        ]
    }
}

/// Watches a run: told of its progress, asked whether to stop. Every method has a
/// default that does nothing (or never stops); [`Silent`] is that observer.
pub trait Observer: Sync {
    /// A run from `t0` to `t_end` starts.
    fn run_started(&self, t0: f64, t_end: f64) {
        let _ = (t0, t_end);
    }
    /// A sample at time `t` was recorded.
    fn sample(&self, t: f64) {
        let _ = t;
    }
    /// The run ended (completely or not).
    fn run_finished(&self) {}
    /// A sweep of `points` runs starts.
    fn sweep_started(&self, points: usize) {
        let _ = points;
    }
    /// One more point of the sweep is done.
    fn point_done(&self) {}
    /// Whether the run should stop now (an interrupt); asked after every sample.
    fn stop_requested(&self) -> bool {
        false
    }
}

/// An observer that watches nothing and never stops a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The summary table, as printed and as shown in `index.html`.
    pub summary: String,
    /// Every file written, results first.
    pub files: Vec<PathBuf>,
    /// Why the run stopped early, when it did (the results are then partial).
    pub failure: Option<String>,
    /// Why the figures could not be drawn, when they could not (the results and
    /// `index.html` are written all the same).
    pub figures_error: Option<String>,
    /// Wall time of the integration (with the recording).
    pub integration: Duration,
    /// Wall time spent drawing figures and writing `index.html`.
    pub plotting: Duration,
}

/// Why a run wrote nothing, or not everything it should have.
#[derive(Debug)]
#[non_exhaustive]
pub enum RunError {
    /// The parameters did not fit the model (a bug: plans are validated).
    Params(String),
    /// The solver could not be set up, or (for a sweep point) the run failed.
    Solver {
        /// The solver's name.
        solver: &'static str,
        /// What it reported.
        source: SolverError,
    },
    /// A file or directory could not be written or removed.
    Io {
        /// The path.
        path: PathBuf,
        /// What was being done, e.g. "creating the output directory".
        action: &'static str,
        /// The underlying error.
        source: io::Error,
    },
    /// A CSV file could not be written.
    Csv(CsvError),
    /// An entry's extras could not record or write their results.
    Results(Box<dyn std::error::Error + Send + Sync>),
    /// The results were written but drawing the figures or the index failed.
    Figures(String),
    /// A point of a sweep was not run: the sweep was interrupted first.
    NotRun,
    /// The output folder is not the program's to replace (see
    /// [`RunFolder`](super::folder::RunFolder)); nothing was written.
    NotOurs {
        /// The folder.
        path: PathBuf,
        /// Why not, and what to do.
        reason: String,
    },
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Params(message) => write!(f, "invalid parameters: {message}"),
            RunError::Solver { solver, source } => write!(f, "the {solver} run failed: {source}"),
            RunError::Io {
                path,
                action,
                source,
            } => write!(f, "{action} `{}` failed: {source}", path.display()),
            RunError::Csv(e) => write!(f, "{e}"),
            RunError::Results(e) => write!(f, "{e}"),
            RunError::Figures(message) => write!(f, "drawing the figures failed: {message}"),
            RunError::NotRun => f.write_str("not run: the sweep was interrupted"),
            RunError::NotOurs { path, reason } => {
                write!(f, "the output folder `{}` {reason}", path.display())
            }
        }
    }
}

impl std::error::Error for RunError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RunError::Solver { source, .. } => Some(source),
            RunError::Io { source, .. } => Some(source),
            RunError::Csv(e) => Some(e),
            RunError::Results(e) => Some(&**e),
            RunError::Params(_)
            | RunError::Figures(_)
            | RunError::NotRun
            | RunError::NotOurs { .. } => None,
        }
    }
}

impl From<CsvError> for RunError {
    fn from(e: CsvError) -> Self {
        RunError::Csv(e)
    }
}

/// The model's parameter struct from the mapping of every parameter.
///
/// # Errors
///
/// [`RunError::Params`] when the mapping does not fit the struct.
pub fn params_from<P: DeserializeOwned>(params: &Mapping) -> Result<P, RunError> {
    serde_yaml::from_value(Value::Mapping(params.clone()))
        .map_err(|e| RunError::Params(e.to_string()))
}

/// The model's initial state with the plan's replacements `(state index, value)`.
pub fn initial_state<M: Model>(model: &M, initial: &[(usize, f64)]) -> Vec<f64> {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    for &(i, v) in initial {
        x0[i] = v;
    }
    x0
}

/// Forwards every sample to some recorders and tells the observer; asks the observer
/// whether to stop.
pub(super) struct Monitor<'a> {
    pub(super) recorders: Vec<&'a mut dyn Recorder>,
    pub(super) observer: &'a dyn Observer,
}

impl Recorder for Monitor<'_> {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        for r in &mut self.recorders {
            r.record(t, x, y);
        }
        self.observer.sample(t);
    }

    fn event(&mut self, record: &bgdsl_runtime::EventRecord<'_>) {
        for r in &mut self.recorders {
            r.event(record);
        }
    }

    fn stop_requested(&self) -> bool {
        self.observer.stop_requested()
    }
}

/// One sentence on why a run stopped early.
pub(super) fn failure_text(solver: &Solver, error: &SolverError) -> String {
    match error {
        SolverError::Stopped { t } => format!("interrupted after the sample at t = {t} s"),
        other => format!("the {} run failed: {other}", solver.name()),
    }
}

/// Settles a run's (or a sweep's) outcome once its figures are drawn: `failure`
/// becomes the interruption if a signal came while writing or drawing, and the
/// figures drawn come back with why drawing failed, if it did, to report beside the
/// results (a partial run's drawing failure is not reported: the run's is).
///
/// # Errors
///
/// [`RunError::Io`] from drawing: a file that cannot be written (a full disk), for
/// which the whole set is abandoned.
pub(super) fn settle_drawing(
    drawing: Result<Vec<DrawnFigure>, RunError>,
    failure: &mut Option<String>,
    observer: &dyn Observer,
) -> Result<(Vec<DrawnFigure>, Option<String>), RunError> {
    if failure.is_none() && observer.stop_requested() {
        *failure = Some("interrupted while writing the results and drawing the figures".to_owned());
    }
    match drawing {
        Ok(drawn) => Ok((drawn, None)),
        Err(e @ RunError::Io { .. }) => Err(e),
        Err(_) if failure.is_some() => Ok((Vec::new(), None)),
        Err(RunError::Figures(message)) => Ok((Vec::new(), Some(message))),
        Err(other) => Ok((Vec::new(), Some(other.to_string()))),
    }
}

/// Creates the output directory `dir` with any missing folders above it: the one rule
/// for every `--out` (a run, a sweep, and the folder of `models fmu`'s file).
///
/// # Errors
///
/// [`RunError::Io`] naming `dir`.
pub fn create_dir(dir: &Path) -> Result<(), RunError> {
    std::fs::create_dir_all(dir).map_err(|source| RunError::Io {
        path: dir.to_path_buf(),
        action: "creating the output directory",
        source,
    })
}

/// What the integration produced.
struct Integrated {
    stats: Stats,
    wall: Duration,
    error: Option<SolverError>,
}

/// Integrates `model` through the plan's sample times into `recorders`.
fn integrate<'a, M: Model>(
    model: &M,
    plan: &RunPlan,
    recorders: Vec<&'a mut dyn Recorder>,
    observer: &'a dyn Observer,
) -> Result<Integrated, RunError> {
    let x0 = initial_state(model, &plan.initial);
    let mut sim = Simulation::new(model, plan.solver).map_err(|source| RunError::Solver {
        solver: plan.solver.name(),
        source,
    })?;
    let solver_error = |source| RunError::Solver {
        solver: plan.solver.name(),
        source,
    };
    if let Some(atol) = &plan.atol {
        sim.set_atol(atol).map_err(solver_error)?;
    }
    if !plan.non_negative.is_empty() {
        sim.set_non_negative(&plan.non_negative)
            .map_err(solver_error)?;
    }
    let [t0, t_end] = plan.span();
    let mut monitor = Monitor {
        recorders,
        observer,
    };
    observer.run_started(t0, t_end);
    let started = Instant::now();
    let result = sim.run(t0, &x0, &plan.times, &mut monitor);
    let wall = started.elapsed();
    observer.run_finished();
    Ok(Integrated {
        stats: sim.stats(),
        wall,
        error: result.err(),
    })
}

/// Runs a model of the catalogue (see the [module documentation](self)).
pub(super) fn run_model<M>(
    entry: &Entry,
    plan: &RunPlan,
    observer: &dyn Observer,
) -> Result<Outcome, RunError>
where
    M: FromParams + bgdsl_runtime::Model + 'static,
    M::Params: DeserializeOwned,
{
    let model = M::from_params(params_from(&plan.params)?);
    // Room for the samples up front, up to a million (beyond, the columns grow).
    let n = plan.times.len().min(1 << 20);
    let context = RunContext {
        entry,
        plan,
        capacity: n,
    };
    let mut extra_runs: Vec<Box<dyn ExtraRun + '_>> = Vec::new();
    if let Some(extra) = entry.extras.start(&context)? {
        extra_runs.push(extra);
    }
    extra_runs.extend(addons::start(&model, &context)?);
    let selection = match &plan.record {
        Some(chosen) => chosen.clone(),
        None => default_columns(entry),
    };
    let mut table = (!selection.is_empty()).then(|| Table::new(&selection, n));
    let mut recorders: Vec<&mut dyn Recorder> = Vec::new();
    for extra in &mut extra_runs {
        recorders.push(&mut **extra);
    }
    if let Some(t) = table.as_mut() {
        recorders.push(t);
    }
    // The log grows as events come (a run here need not be allocation-free): room for
    // four per sample interval up front would be 39 MB for the friction quick return's
    // 121 states and 5001 samples, for the 36 events of its run.
    let mut collector = (!M::EVENTS.is_empty()).then(|| EventCollector::new::<M>(64));
    if let Some(c) = collector.as_mut() {
        recorders.push(c);
    }
    let folder = RunFolder::begin(&plan.out_dir)?;
    let run = integrate(&model, plan, recorders, observer)?;
    let mut failure = run.error.as_ref().map(|e| failure_text(&plan.solver, e));
    let event_energies = collector
        .as_ref()
        .map(|c| events::energies(&model, &c.log))
        .unwrap_or_default();
    if let Some(c) = &collector {
        let energies: Vec<(f64, f64)> = c
            .log
            .iter()
            .zip(&event_energies)
            .map(|(e, change)| (e.t, change.unwrap_or(0.0)))
            .collect();
        for extra in &mut extra_runs {
            extra.events(&energies);
        }
    }

    let dir = folder.path();
    // The results files' names, written into the staging folder, and their units
    // side files (see `columns::write_units`).
    let mut results_files = Vec::new();
    let mut unit_files = Vec::new();
    let writing = Instant::now();
    for extra in &mut extra_runs {
        let written = extra.write(dir)?;
        results_files.extend(written.results);
        unit_files.extend(written.others);
    }
    if let Some(table) = &table {
        let name = format!("{}.csv", entry.extras.table_stem(entry));
        let path = dir.join(&name);
        table.write_csv(&path)?;
        unit_files.push(write_units(&*entry.model, &path, &table.names())?);
        results_files.push(name);
    }
    if let Some(c) = &collector {
        events::write_csv(
            &dir.join(events::FILE_NAME),
            &c.log,
            &event_energies,
            M::STATE_NAMES,
        )?;
        results_files.push(events::FILE_NAME.to_owned());
    }
    let write_time = writing.elapsed();

    let plotting = Instant::now();
    let drawing = if failure.is_none() && observer.stop_requested() {
        Ok(Vec::new())
    } else {
        draw(entry, plan, &extra_runs, table.as_ref(), dir)
    };
    // The page's sections (the causal graph runs `dot`) belong to the drawing: an
    // interrupt while they are made marks the run partial like one while drawing.
    let sections: Vec<String> = extra_runs.iter().flat_map(|x| x.sections()).collect();
    let (drawn, figures_error) = settle_drawing(drawing, &mut failure, observer)?;
    let partial = failure.is_some();
    let plotting = plotting.elapsed();

    // The summary names the files where they will be once committed.
    let target = folder.target(partial);
    let results_paths: Vec<PathBuf> = results_files.iter().map(|n| target.join(n)).collect();
    let finished = Finished {
        entry,
        plan,
        stats: run.stats,
        wall: run.wall,
        write_time,
        failure: failure.as_deref(),
        results: &results_paths,
    };
    let mut summary = match extra_runs.iter().find_map(|x| x.summary(&finished)) {
        Some(summary) => summary,
        None => trajectory_summary(
            entry,
            plan,
            &run,
            table.as_ref(),
            &results_paths,
            write_time,
            &failure,
        ),
    };
    if let Some(c) = &collector {
        summary.push_str(&events::summary_lines(
            &M::EVENTS.iter().map(|e| e.name).collect::<Vec<_>>(),
            &c.log,
            &event_energies,
        ));
    }
    for extra in &extra_runs {
        summary.push_str(&extra.summary_tail(&finished));
    }
    let figure_files = drawn.iter().map(|f| f.files.len()).sum::<usize>();
    if !drawn.is_empty() {
        summary.push_str(&format!(
            "figures        {} figures ({figure_files} files) in {:.0} ms\n",
            drawn.len(),
            plotting.as_secs_f64() * 1e3
        ));
    }
    summary.push_str(&super::report_line(&target.join(INDEX_FILE)));
    provenance::write_run(dir, entry, plan, &results_paths, failure.as_deref())?;
    figures::index(dir, &plan.title, &summary, &drawn, &sections)?;
    let target = folder.commit(partial)?;
    let in_target = |path: &PathBuf| target.join(path.file_name().unwrap_or_default());
    let mut files = results_paths;
    files.extend(unit_files.iter().map(in_target));
    files.extend(drawn.iter().flat_map(|f| f.files.iter().map(in_target)));
    files.push(target.join(provenance::FILE_NAME));
    files.push(target.join(INDEX_FILE));
    Ok(Outcome {
        summary,
        files,
        failure,
        figures_error,
        integration: run.wall,
        plotting,
    })
}

/// Draws a run's figures: the extras' first, then the table's charts (of the outputs,
/// or those `plots` names; for an entry whose extras have figures of their own, of
/// the columns it records by default only).
fn draw(
    entry: &Entry,
    plan: &RunPlan,
    extra_runs: &[Box<dyn ExtraRun + '_>],
    table: Option<&Table>,
    dir: &Path,
) -> Result<Vec<DrawnFigure>, RunError> {
    if plan.plots == Plots::None {
        return Ok(Vec::new());
    }
    let mut drawn = Vec::new();
    for extra in extra_runs {
        drawn.extend(extra.figures(dir, &plan.plots)?);
    }
    if let Some(table) = table {
        if entry.extras.generic_figures() {
            drawn.extend(figures::trajectory(entry, table, dir, &plan.plots)?);
            drawn.extend(figures::states::draw(entry, table, dir, &plan.plots)?);
        } else if plan.record.is_none() {
            drawn.extend(figures::trajectory(entry, table, dir, &Plots::All)?);
        }
    }
    Ok(drawn)
}

/// The columns an entry records when the plan names none: its [`Entry::record`], or
/// every state and output.
fn default_columns(entry: &Entry) -> Vec<(String, Column)> {
    match entry.record {
        Some(names) => names
            .iter()
            .filter_map(|name| resolve_columns(&*entry.model, name))
            .flatten()
            .collect(),
        None => all_columns(&*entry.model),
    }
}

/// The generic summary of a run: the run, then each recorded column's minimum, maximum
/// and last value.
fn trajectory_summary(
    entry: &Entry,
    plan: &RunPlan,
    run: &Integrated,
    table: Option<&Table>,
    files: &[PathBuf],
    write_time: Duration,
    failure: &Option<String>,
) -> String {
    use core::fmt::Write as _;
    let mut s = String::new();
    let [t0, t_end] = plan.span();
    let st = &run.stats;
    if let Some(failure) = failure {
        let _ = writeln!(s, "PARTIAL RUN   {failure}");
    }
    let _ = writeln!(
        s,
        "model          {} ({}), {t0} to {t_end} s",
        entry.model.type_name(),
        entry.name
    );
    s.push_str(&provenance::summary_lines(entry, plan, &[]));
    let _ = writeln!(s, "solver         {}", SolverSettings(&plan.solver));
    let _ = writeln!(
        s,
        "steps          {} ({} accepted, {} rejected), {} derivative evaluations",
        st.steps(),
        st.accepted,
        st.rejected,
        st.n_rhs
    );
    let _ = writeln!(
        s,
        "wall time      {:.1} ms integrating, {:.1} ms writing",
        run.wall.as_secs_f64() * 1e3,
        write_time.as_secs_f64() * 1e3
    );
    if let (Some(table), Some(path)) = (table, files.first()) {
        let _ = writeln!(
            s,
            "results        {} ({} rows, {} columns{})",
            path.display(),
            table.len(),
            table.width(),
            if failure.is_some() { ", partial" } else { "" }
        );
        let _ = writeln!(s);
        let width = table
            .columns()
            .map(|(n, _)| n.len())
            .max()
            .unwrap_or(6)
            .max(6);
        let _ = writeln!(
            s,
            "  {:<width$}  {:>14} {:>14} {:>14}  unit",
            "column", "min", "max", "last"
        );
        for (name, values) in table.columns() {
            let (lo, hi) = values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            let last = values.last().copied().unwrap_or(f64::NAN);
            let [lo, hi, last] = [lo, hi, last].map(format_significant);
            let unit = super::columns::column_unit(&*entry.model, name).0;
            let line = format!("  {name:<width$}  {lo:>14} {hi:>14} {last:>14}  {unit}");
            let _ = writeln!(s, "{}", line.trim_end());
        }
    }
    s
}

/// Runs one point of a sweep: the metrics' peaks over `window`.
pub(super) fn sweep_point<M: FromParams>(
    plan: &RunPlan,
    metrics: &[super::Metric],
    window: [f64; 2],
    observer: &dyn Observer,
) -> Result<Vec<f64>, RunError>
where
    M::Params: DeserializeOwned,
{
    let model = M::from_params(params_from(&plan.params)?);
    let mut peaks = super::sweep::Peaks::new(metrics, window);
    let run = integrate(&model, plan, vec![&mut peaks], observer)?;
    match run.error {
        Some(source) => Err(RunError::Solver {
            solver: plan.solver.name(),
            source,
        }),
        None => Ok(peaks.into_values()),
    }
}

/// The solver's name and its main settings, e.g. `radau5 (rtol 1e-6, atol 1e-10)`.
#[derive(Clone, Copy, Debug)]
pub struct SolverSettings<'a>(pub &'a Solver);

impl fmt::Display for SolverSettings<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = self.0.name();
        match self.0 {
            Solver::Radau5(o) => write!(f, "{name} (rtol {:e}, atol {:e})", o.rtol, o.atol),
            Solver::Rodas4(o) | Solver::Rodas5P(o) => {
                write!(f, "{name} (rtol {:e}, atol {:e})", o.rtol, o.atol)
            }
            Solver::DormandPrince(o) => {
                write!(f, "{name} (rtol {:e}, atol {:e})", o.rtol, o.atol)
            }
            Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => {
                write!(f, "{name} (step {:e} s)", o.step)
            }
            _ => f.write_str(name),
        }
    }
}

/// Records the values of some columns at every sample: row-major, times then columns.
struct Samples<'a> {
    columns: &'a [Column],
    values: Vec<f64>,
}

impl Recorder for Samples<'_> {
    fn record(&mut self, _t: f64, x: &[f64], y: &[f64]) {
        self.values
            .extend(self.columns.iter().map(|c| c.value(x, y)));
    }
}

/// Runs one sample of a study and returns `columns` at every sample time (row-major:
/// times, then columns).
pub(super) fn trajectory<M: FromParams>(
    plan: &RunPlan,
    columns: &[Column],
    observer: &dyn Observer,
) -> Result<Vec<f64>, RunError>
where
    M::Params: DeserializeOwned,
{
    let model = M::from_params(params_from(&plan.params)?);
    let mut samples = Samples {
        columns,
        values: Vec::with_capacity(plan.times.len() * columns.len()),
    };
    let run = integrate(&model, plan, vec![&mut samples], observer)?;
    match run.error {
        Some(source) => Err(RunError::Solver {
            solver: plan.solver.name(),
            source,
        }),
        None if observer.stop_requested() => Err(RunError::NotRun),
        None => Ok(samples.values),
    }
}
