//! What produced a results set: the record `run.yaml` that every run and sweep writes
//! beside its results, and the `overrides` line of its summary.
//!
//! A [`RunRecord`] is built from the validated plan ([`RunPlan`] or [`SweepPlan`]) and
//! the [`Context`] the plan carries (the command line, the scenario file, how the
//! samples were asked for, where each parameter was set); [`write_run`] and
//! [`write_sweep`] write it. `run.yaml` holds:
//!
//! - `program`: the program's name (`models` here), its version, the git commit it was
//!   built from (see [`Catalogue::commit`](crate::Catalogue::commit)) and whether
//!   the working tree had uncommitted changes to tracked files (`unknown`/`null` when
//!   it was not built from a git checkout);
//! - `started` (UTC, RFC 3339), the `command_line` and the `outcome`: `complete`, or
//!   `partial` with the reason;
//! - `model` (its name in the catalogue and its Rust type) and the `scenario` file
//!   (its path and its whole text), if any;
//! - `overrides`: every parameter whose value differs from the model's default, with
//!   the default and where it was set (`--set g=1.5`, or `file:line:column`);
//! - `parameters` (every one), `initial` (every state by name) and
//!   `initial_overridden` (the states the scenario set), `time`, `output` (the
//!   sampling, and `record`), `samples`, `plots`, `solver` (method, tolerances, step
//!   limits) and `solver_options` (every setting of the solver, as Rust prints it);
//! - `results`: the results files, by name;
//! - for a sweep, `sweep`: the swept parameters with every value, the peaks and the
//!   window;
//! - for an analysis, `analysis`: the command, what was asked and the headline
//!   results.
//!
//! The keys `parameters`, `initial`, `time`, `output`, `plots`, `solver` and `sweep` are
//! written as the keys of the same name of a [scenario file](crate::scenario), so that
//! they and `model: <model.name>` make a scenario that runs the same run again (the
//! same numbers, bit for bit, from the same program).

pub mod folder;
mod overrides;

pub use overrides::{overrides, summary_lines};

use std::collections::BTreeMap;
use std::io::{self, Write as _};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use bgdsl_runtime::record::write_atomically;
use bgdsl_runtime::Solver;
use serde::{Deserialize, Serialize};
use serde_yaml::{Mapping, Value};

use crate::catalog::{Catalogue, Entry, Plots, RunError, RunPlan, SweepPlan};
use crate::scenario::{Origin, Source};
use overrides::initial_states;

/// The name of the record in a results folder.
pub const FILE_NAME: &str = "run.yaml";

/// How the sample times were asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sampling {
    /// Every `interval` seconds from the start (and the end).
    Interval(f64),
    /// This many samples, evenly spaced, both ends included.
    Count(usize),
}

/// What a plan was made from, beyond the values it holds: the record needs it.
#[derive(Clone, Debug)]
pub struct Context {
    /// The program's arguments, the program first.
    pub command_line: Vec<String>,
    /// The scenario file, when the run came from one.
    pub scenario: Option<Source>,
    /// How the sample times were asked for (`None`: not known).
    pub sampling: Option<Sampling>,
    /// Where each parameter that the scenario or the command line set was set.
    pub parameter_origins: BTreeMap<String, Origin>,
    /// When the plan was made, just before the run.
    pub started: SystemTime,
    /// The program that runs the plan.
    pub program: Program,
}

impl Default for Context {
    fn default() -> Self {
        Context {
            command_line: Vec::new(),
            scenario: None,
            sampling: None,
            parameter_origins: BTreeMap::new(),
            started: SystemTime::now(),
            program: Program::unknown(),
        }
    }
}

/// The program that wrote a record.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Program {
    /// Its name, e.g. `models`.
    pub name: String,
    /// The crate's version.
    pub version: String,
    /// The git commit it was built from, or `unknown`.
    pub commit: String,
    /// Whether tracked files differed from that commit when it was built (`None`:
    /// unknown).
    pub dirty: Option<bool>,
}

impl Program {
    /// The program of `catalogue`: its name, version and commit.
    pub fn of(catalogue: &Catalogue) -> Self {
        Program {
            name: catalogue.program.clone(),
            version: catalogue.version.clone(),
            commit: catalogue.commit.0.clone(),
            dirty: catalogue.commit.1,
        }
    }

    /// A program not known: `bgdsl`, this library's version, commit `unknown`.
    pub fn unknown() -> Self {
        Program {
            name: "bgdsl".to_owned(),
            version: env!("CARGO_PKG_VERSION").to_owned(),
            commit: "unknown".to_owned(),
            dirty: None,
        }
    }
}

/// Whether the results are the whole run.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunOutcome {
    /// `complete` or `partial`.
    pub status: String,
    /// Why the run stopped early (partial runs only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

impl RunOutcome {
    /// `complete` without a failure, else `partial` and why.
    pub fn of(failure: Option<&str>) -> Self {
        RunOutcome {
            status: if failure.is_some() {
                "partial"
            } else {
                "complete"
            }
            .to_owned(),
            reason: failure.map(str::to_owned),
        }
    }
}

/// The model that ran.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ModelId {
    /// Its name in the catalogue, e.g. `quick_return`.
    pub name: String,
    /// Its Rust type, e.g. `QuickReturn`.
    #[serde(rename = "type")]
    pub type_name: String,
}

/// The scenario file a run came from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ScenarioFile {
    /// The path as given on the command line.
    pub path: String,
    /// Its whole text.
    pub text: String,
}

/// A parameter whose value differs from the model's default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Override {
    /// The parameter.
    pub name: String,
    /// The value the run used.
    pub value: Value,
    /// The model's default.
    pub default: Value,
    /// Where it was set: `--set NAME=VALUE` or `file:line:column` (empty: not known).
    pub from: String,
}

/// The time span, as a scenario's `time:`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeSpan {
    /// The first sample time, s.
    pub start: f64,
    /// The last sample time, s.
    pub end: f64,
}

/// The sampling and recording, as a scenario's `output:`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Output {
    /// Seconds between samples.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interval: Option<f64>,
    /// Number of samples, both ends included.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<usize>,
    /// The states and outputs recorded (absent: the model's default columns).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<Vec<String>>,
}

/// The solver and the settings a scenario can give, as a scenario's `solver:`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverRecord {
    /// `rk4`, `dopri5`, `dopri5-fixed`, `radau5`, `rodas4` or `rodas5p`.
    pub method: String,
    /// Relative tolerance (adaptive methods).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rtol: Option<f64>,
    /// Absolute tolerance (adaptive methods).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atol: Option<f64>,
    /// The step, s (fixed-step methods).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    /// The largest step, s (adaptive methods; absent: unlimited).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_step: Option<f64>,
    /// The step budget.
    pub max_steps: usize,
    /// The wall-time limit, s (stiff methods; absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_wall_time: Option<f64>,
    /// Absolute tolerances by state name, for the states whose atol is not `atol`
    /// (a scenario's per-state `solver.atol`; absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atol_by_state: Option<Mapping>,
    /// The states held at or above zero (a scenario's `solver.non_negative`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub non_negative: Vec<String>,
}

impl SolverRecord {
    /// The settings of `solver` a scenario can give.
    pub fn of(solver: &Solver) -> Self {
        let finite = |v: f64| v.is_finite().then_some(v);
        let mut record = SolverRecord {
            method: solver.name().to_owned(),
            rtol: None,
            atol: None,
            step: None,
            max_step: None,
            max_steps: 0,
            max_wall_time: None,
            atol_by_state: None,
            non_negative: Vec::new(),
        };
        match solver {
            Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => {
                record.step = Some(o.step);
                record.max_steps = o.max_steps;
            }
            Solver::DormandPrince(o) => {
                (record.rtol, record.atol) = (Some(o.rtol), Some(o.atol));
                record.max_step = finite(o.max_step);
                record.max_steps = o.max_steps;
            }
            Solver::Radau5(o) => {
                (record.rtol, record.atol) = (Some(o.rtol), Some(o.atol));
                record.max_step = finite(o.max_step);
                record.max_steps = o.max_steps;
                record.max_wall_time = o.max_wall_time.map(|d| d.as_secs_f64());
            }
            Solver::Rodas4(o) | Solver::Rodas5P(o) => {
                (record.rtol, record.atol) = (Some(o.rtol), Some(o.atol));
                record.max_step = finite(o.max_step);
                record.max_steps = o.max_steps;
                record.max_wall_time = o.max_wall_time.map(|d| d.as_secs_f64());
            }
            // A method added later: its name, and its settings in `solver_options`.
            _ => {}
        }
        record
    }
}

/// One swept parameter, as an entry of a scenario's `sweep.parameters`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweptParameter {
    /// The parameter.
    pub name: String,
    /// Every value, in order.
    pub values: Vec<f64>,
}

/// The window of a sweep, as a scenario's `sweep.window`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// Start, s.
    pub from: f64,
    /// End, s.
    pub to: f64,
}

/// The grid and the metrics of a sweep, as a scenario's `sweep:`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepRecord {
    /// The swept parameters, the first outermost.
    pub parameters: Vec<SweptParameter>,
    /// The outputs whose peak magnitude each run reports.
    pub peaks: Vec<String>,
    /// The window the peaks are taken over.
    pub window: Window,
}

/// What produced a results set: the content of `run.yaml` (see the
/// [module documentation](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// The program.
    pub program: Program,
    /// When the run started, UTC, RFC 3339.
    pub started: String,
    /// The program's arguments, the program first.
    pub command_line: Vec<String>,
    /// Complete or partial.
    pub outcome: RunOutcome,
    /// The model.
    pub model: ModelId,
    /// The scenario file, if the run came from one.
    pub scenario: Option<ScenarioFile>,
    /// The parameters that differ from the model's defaults (for a sweep, other than
    /// the swept ones).
    pub overrides: Vec<Override>,
    /// Every parameter (for a sweep, the swept ones at the value they have outside it;
    /// for a study, all but the drawn ones).
    pub parameters: Mapping,
    /// The initial state, every state by name (for a study, only those the scenario
    /// set: the others follow from each sample's drawn parameters).
    pub initial: Mapping,
    /// The states whose initial value the scenario set.
    pub initial_overridden: Vec<String>,
    /// The time span.
    pub time: TimeSpan,
    /// The sampling and recording.
    pub output: Output,
    /// The number of sample times.
    pub samples: usize,
    /// `all`, `none` or the figures drawn; with phase portraits, the mapping
    /// `{figures: .., phase: [[x, y], ..]}`.
    pub plots: Value,
    /// The solver.
    pub solver: SolverRecord,
    /// Every setting of the solver, as Rust's `Debug` prints it.
    pub solver_options: String,
    /// The results files, by name, in the results folder.
    pub results: Vec<String>,
    /// The sweep, for a sweep.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepRecord>,
    /// The Monte Carlo study, for a study.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<StudyRecord>,
    /// `K/N` for a shard (`run --shard K/N`) of a sweep or study.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    /// The shard folders a `merge` joined into this one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged_from: Vec<String>,
    /// For an analysis (`models steady`, `linearize`, `bode`, `periodic`, `fit`): its
    /// `command`, what was asked and the headline results
    /// ([`catalog::analysis`](crate::catalog::analysis)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub analysis: Option<Mapping>,
}

/// A Monte Carlo study, as a scenario's `monte_carlo:` (a `csv` column written as the
/// `values` it gave).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyRecord {
    /// The number of samples.
    pub samples: usize,
    /// The seed.
    pub seed: u64,
    /// Each drawn parameter's distribution.
    pub parameters: Mapping,
}

impl RunRecord {
    /// The record of a run of `entry`'s model by `plan` that wrote `results` (paths;
    /// recorded by file name) and stopped early for `failure`, if it did.
    ///
    /// # Errors
    ///
    /// [`RunError::Params`] when the plan's parameters do not fit the model (plans are
    /// validated: a bug).
    pub fn of_run(
        entry: &Entry,
        plan: &RunPlan,
        results: &[PathBuf],
        failure: Option<&str>,
    ) -> Result<Self, RunError> {
        Self::build(entry, plan, &[], results, failure)
    }

    /// The record of a sweep (see [`RunRecord::of_run`]).
    ///
    /// # Errors
    ///
    /// As [`RunRecord::of_run`].
    pub fn of_sweep(
        entry: &Entry,
        plan: &SweepPlan,
        results: &[PathBuf],
        failure: Option<&str>,
    ) -> Result<Self, RunError> {
        let axes: Vec<&str> = plan.axes.iter().map(|a| a.name.as_str()).collect();
        let mut record = Self::build(entry, &plan.base, &axes, results, failure)?;
        record.sweep = Some(SweepRecord {
            parameters: plan
                .axes
                .iter()
                .map(|a| SweptParameter {
                    name: a.name.clone(),
                    values: a.values.clone(),
                })
                .collect(),
            peaks: plan.metrics.iter().map(|m| m.name.clone()).collect(),
            window: Window {
                from: plan.window[0],
                to: plan.window[1],
            },
        });
        Ok(record)
    }

    /// The record of `plan`'s run, the parameters `except` left out of the overrides.
    pub(crate) fn build(
        entry: &Entry,
        plan: &RunPlan,
        except: &[&str],
        results: &[PathBuf],
        failure: Option<&str>,
    ) -> Result<Self, RunError> {
        let context: &Context = &plan.context;
        let names = entry.model.state_names();
        let (_, used) = initial_states(entry, plan)?;
        let [start, end] = plan.span();
        let (interval, count) = match context.sampling {
            Some(Sampling::Interval(dt)) => (Some(dt), None),
            Some(Sampling::Count(n)) => (None, Some(n)),
            None => (None, None),
        };
        let plots = match &plan.plots {
            Plots::None => Value::from("none"),
            Plots::Only(ids) if ids.is_empty() => Value::from("none"),
            Plots::All => Value::from("all"),
            Plots::Only(ids) => {
                Value::Sequence(ids.iter().map(|s| Value::from(s.as_str())).collect())
            }
        };
        // With phase portraits, the mapping form a scenario writes them in.
        let plots = if plan.phase.is_empty() {
            plots
        } else {
            let pair = |p: &crate::catalog::PhasePair| {
                Value::Sequence(vec![
                    Value::from(p.x.0.as_str()),
                    Value::from(p.y.0.as_str()),
                ])
            };
            let mut map = Mapping::new();
            map.insert(Value::from("figures"), plots);
            map.insert(
                Value::from("phase"),
                Value::Sequence(plan.phase.iter().map(pair).collect()),
            );
            Value::Mapping(map)
        };
        Ok(RunRecord {
            program: context.program.clone(),
            started: humantime::format_rfc3339_seconds(context.started).to_string(),
            command_line: context.command_line.clone(),
            outcome: RunOutcome::of(failure),
            model: ModelId {
                name: entry.name.to_owned(),
                type_name: entry.model.type_name().to_owned(),
            },
            scenario: context.scenario.as_ref().map(|s| ScenarioFile {
                path: s.path.display().to_string(),
                text: s.text.clone(),
            }),
            overrides: overrides(entry, plan, except),
            parameters: plan.params.clone(),
            initial: names
                .iter()
                .zip(&used)
                .map(|(n, v)| (Value::from(*n), Value::from(*v)))
                .collect(),
            initial_overridden: plan
                .initial
                .iter()
                .map(|&(i, _)| names[i].to_owned())
                .collect(),
            time: TimeSpan { start, end },
            output: Output {
                interval,
                count,
                record: plan
                    .record
                    .as_ref()
                    .map(|columns| columns.iter().map(|(n, _)| n.clone()).collect()),
            },
            samples: plan.times.len(),
            plots,
            solver: {
                let mut record = SolverRecord::of(&plan.solver);
                record.atol_by_state = plan.atol.as_ref().map(|atol| {
                    names
                        .iter()
                        .zip(atol)
                        .filter(|(_, a)| Some(**a) != record.atol)
                        .map(|(n, a)| (Value::from(*n), Value::from(*a)))
                        .collect()
                });
                record.non_negative = plan
                    .non_negative
                    .iter()
                    .map(|&i| names[i].to_owned())
                    .collect();
                record
            },
            solver_options: format!("{:?}", plan.solver),
            results: results
                .iter()
                .filter_map(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
                .collect(),
            sweep: None,
            monte_carlo: None,
            shard: None,
            merged_from: Vec::new(),
            analysis: None,
        })
    }
}

/// Writes `record` as `dir/run.yaml`, whole or not at all; returns its path.
///
/// # Errors
///
/// [`RunError::Csv`] (the atomic writer's error, naming the file) when it cannot be
/// written.
pub fn write(dir: &Path, record: &RunRecord) -> Result<PathBuf, RunError> {
    let path = dir.join(FILE_NAME);
    write_atomically(&path, |out| {
        out.write_all(
            b"# What produced the results in this folder: see `bgdsl_cli::provenance`.\n",
        )?;
        serde_yaml::to_writer(&mut *out, record).map_err(io::Error::other)
    })?;
    Ok(path)
}

/// Writes the record of a run into `dir` (see [`RunRecord::of_run`] and [`write()`]).
///
/// # Errors
///
/// As [`RunRecord::of_run`] and [`write()`].
pub fn write_run(
    dir: &Path,
    entry: &Entry,
    plan: &RunPlan,
    results: &[PathBuf],
    failure: Option<&str>,
) -> Result<PathBuf, RunError> {
    write(dir, &RunRecord::of_run(entry, plan, results, failure)?)
}

/// Writes the record of a sweep into `dir` (see [`RunRecord::of_sweep`] and [`write()`]).
///
/// # Errors
///
/// As [`RunRecord::of_sweep`] and [`write()`].
pub fn write_sweep(
    dir: &Path,
    entry: &Entry,
    plan: &SweepPlan,
    results: &[PathBuf],
    failure: Option<&str>,
) -> Result<PathBuf, RunError> {
    write(dir, &RunRecord::of_sweep(entry, plan, results, failure)?)
}
