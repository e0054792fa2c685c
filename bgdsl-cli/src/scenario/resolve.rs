//! From a scenario (or a bare model name) and the command line's overrides to a
//! validated [`Plan`], or every [`Diagnostic`](super::Diagnostic) found on the way.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::SystemTime;

use bgdsl_runtime::Solver;
use serde_yaml::Mapping;

use super::locate::KeyPath;
use super::solver::{per_state, pick, solver};
use super::study::study;
use super::sweep::sweep;
use super::{plot_names, Diagnostics, Origin, Scenario, Source};
use crate::catalog::{
    self, format_number, format_value, parse_value, resolve_columns, set_parameter, Catalogue,
    Column, Entry, Plots, RunPlan, StudyPlan, SweepPlan,
};
use crate::provenance::{folder, Context, Program, Sampling};

/// The smallest and largest relative tolerance a scenario may ask for.
pub const RTOL_RANGE: [f64; 2] = [1e-14, 1e-1];

/// The most samples a run may record.
pub const MAX_SAMPLES: usize = 10_000_001;

/// What the command line changes in a scenario (or in a model's defaults).
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// `NAME=VALUE` settings of parameters, in order (later ones win).
    pub set: Vec<String>,
    /// The solver's name.
    pub solver: Option<String>,
    /// Relative tolerance.
    pub rtol: Option<f64>,
    /// Absolute tolerance.
    pub atol: Option<f64>,
    /// The start of the time span, s.
    pub t_start: Option<f64>,
    /// The end of the time span, s.
    pub t_end: Option<f64>,
    /// The step of a fixed-step solver, s.
    pub step: Option<f64>,
    /// The solver's step budget.
    pub max_steps: Option<usize>,
    /// The sampling interval, s.
    pub interval: Option<f64>,
    /// Draw no figures.
    pub no_plots: bool,
    /// Phase portraits, each `X,Y` (`--phase`, repeatable).
    pub phase: Vec<String>,
    /// The output directory (default: the rule of
    /// [`provenance::folder`](crate::provenance::folder)).
    pub out: Option<PathBuf>,
    /// The program's arguments, the program first, for the run's record (`run.yaml`).
    pub command_line: Vec<String>,
}

/// What to do: one run, or a sweep.
#[derive(Clone, Debug)]
pub enum Job {
    /// One run.
    Run(RunPlan),
    /// A sweep of runs.
    Sweep(SweepPlan),
    /// A Monte Carlo study.
    Study(StudyPlan),
}

/// A validated scenario: the model and the job.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The model.
    pub entry: &'static Entry,
    /// The run or the sweep.
    pub job: Job,
}

/// Where a setting came from, for pointing at it.
pub(super) struct Places<'a> {
    pub(super) source: Option<&'a Source>,
}

impl Places<'_> {
    pub(super) fn file(&self, path: &KeyPath) -> Origin {
        match self.source {
            Some(s) => s.at(path),
            None => Origin::Nowhere,
        }
    }

    pub(super) fn keys(&self, keys: &[&str]) -> Origin {
        self.file(&KeyPath::keys(keys))
    }
}

/// Validates `scenario` (read from `source`, or made from a model name when `source` is
/// `None`) with the command line's `overrides`, into a plan whose run writes to
/// `overrides.out` or else `out/<name>`.
///
/// # Errors
///
/// Every problem found (see the [module documentation](super)); nothing has been
/// written.
pub fn resolve(
    catalogue: &'static Catalogue,
    source: Option<&Source>,
    scenario: &Scenario,
    overrides: &Overrides,
    name: &str,
) -> Result<Plan, Diagnostics> {
    let mut d = scenario.read_errors.clone();
    let plan = resolve_into(catalogue, source, scenario, overrides, name, &mut d);
    match plan {
        Some(plan) if d.is_empty() => Ok(plan),
        _ => {
            d.sort();
            Err(d)
        }
    }
}

/// [`resolve`], with the diagnostics pushed into `d` as found.
fn resolve_into(
    catalogue: &'static Catalogue,
    source: Option<&Source>,
    scenario: &Scenario,
    overrides: &Overrides,
    name: &str,
    d: &mut Diagnostics,
) -> Option<Plan> {
    let places = Places { source };
    let entry = match catalogue.find(&scenario.model) {
        Ok(entry) => entry,
        Err(e) => {
            let origin = match source {
                Some(_) => places.keys(&["model"]),
                None => Origin::Nowhere,
            };
            d.push(origin, e.to_string());
            return None;
        }
    };
    let (params, origins) = parameters(entry, scenario, overrides, &places, d);
    let initial = initial_conditions(entry, scenario, &places, d);
    let span = time_span(entry, scenario, overrides, &places, d);
    let times = span.and_then(|span| sample_times(entry, scenario, overrides, span, &places, d));
    let solver = solver(entry, scenario, overrides, &places, d);
    let per_state = per_state(entry, scenario, solver.as_ref(), &places, d);
    let record = record(entry, scenario, &places, d);
    let plots = plots(entry, scenario, overrides, &places, d);
    let phase = super::phase::phase_pairs(entry, scenario, &overrides.phase, &places, d);
    let is_study = scenario.sweep.is_some() || scenario.monte_carlo.is_some();
    if is_study {
        super::phase::refuse_in_study(scenario, &overrides.phase, &places, d);
    } else {
        figures_draw_something(entry, scenario, &record, &plots, &places, d);
    }
    if scenario.sweep.is_some() && scenario.monte_carlo.is_some() {
        d.push(
            places.keys(&["monte_carlo"]),
            "a scenario is a sweep or a Monte Carlo study, not both; split it into two files",
        );
    }
    // `figures: none` beside phase portraits: those only (an empty choice of figures).
    let plots = match plots {
        Plots::None if !phase.is_empty() && !overrides.no_plots => Plots::Only(Vec::new()),
        plots => plots,
    };
    let title = scenario
        .description
        .clone()
        .unwrap_or_else(|| format!("{name}: {}", entry.description));
    let out_dir = overrides.out.clone().unwrap_or_else(|| {
        folder::default_out_dir(name, &folder::command_line_settings(overrides, &params))
    });
    let context = Arc::new(Context {
        command_line: overrides.command_line.clone(),
        scenario: source.cloned(),
        sampling: sampling(entry, scenario, overrides),
        parameter_origins: origins.clone(),
        started: SystemTime::now(),
        program: Program::of(catalogue),
    });
    let base = |times: Vec<f64>, solver: Solver| RunPlan {
        params: params.clone(),
        initial: initial.clone(),
        times,
        solver,
        atol: per_state.atol.clone(),
        non_negative: per_state.non_negative.clone(),
        record: record.clone(),
        plots: plots.clone(),
        phase: phase.clone(),
        out_dir: out_dir.clone(),
        title: title.clone(),
        context: context.clone(),
    };
    if let (Some(spec), Some(times)) = (&scenario.monte_carlo, &times) {
        let plan = base(times.clone(), solver.unwrap_or(entry.solver));
        return match study(entry, spec, plan, &origins, &places, d) {
            Some(study) if d.is_empty() => Some(Plan {
                entry,
                job: Job::Study(study),
            }),
            _ => None,
        };
    }
    let job = match (&scenario.sweep, times, solver) {
        (None, Some(times), Some(solver)) if d.is_empty() => Job::Run(base(times, solver)),
        (Some(spec), Some(times), solver) => {
            // A rejected solver is reported already; the sweep is checked all the same.
            let plan = base(times, solver.unwrap_or(entry.solver));
            match sweep(entry, spec, plan, &origins, &places, d) {
                Some(sweep) if d.is_empty() => Job::Sweep(sweep),
                _ => return None,
            }
        }
        _ => return None,
    };
    Some(Plan { entry, job })
}

/// The parameters: defaults, then the scenario's, then `--set`; each checked by name
/// and shape, then all of them physically. Also where each was set.
fn parameters(
    entry: &Entry,
    scenario: &Scenario,
    overrides: &Overrides,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> (Mapping, BTreeMap<String, Origin>) {
    let mut params = entry.model.default_parameters();
    let mut origins = BTreeMap::new();
    // Parameters whose setting was rejected (they keep their defaults).
    let mut rejected: Vec<String> = Vec::new();
    for (key, value) in scenario.parameters.iter().flatten() {
        let Some(name) = key.as_str() else {
            d.push(
                places.keys(&["parameters"]),
                format!(
                    "a parameter name must be a string, found {}",
                    format_value(key)
                ),
            );
            continue;
        };
        let origin = places.keys(&["parameters", name]);
        match set_parameter(entry, &mut params, name, value.clone()) {
            Ok(()) => {
                origins.insert(name.to_owned(), origin);
            }
            Err(problem) => {
                rejected.push(name.to_owned());
                d.push(origin, problem.message);
            }
        }
    }
    for setting in &overrides.set {
        let origin = Origin::Flag(format!("--set {setting}"));
        let Some((name, text)) = setting.split_once('=') else {
            d.push(
                origin,
                "expected NAME=VALUE, e.g. `--set m1=0.5` or `--set l1=[0.2,0.01,0.01]`",
            );
            continue;
        };
        let name = name.trim();
        match parse_value(text) {
            Err(e) => {
                rejected.push(name.to_owned());
                d.push(origin, format!("the value is not YAML: {e}"));
            }
            Ok(value) => match set_parameter(entry, &mut params, name, value) {
                Ok(()) => {
                    origins.insert(name.to_owned(), origin);
                }
                Err(problem) => {
                    rejected.push(name.to_owned());
                    d.push(origin, problem.message);
                }
            },
        }
    }
    // The physical checks run on what was accepted; a problem that involves a rejected
    // parameter (now at its default) would be about a value nobody asked for.
    for problem in entry.model.check(&params) {
        if problem.keys.iter().any(|k| rejected.contains(k)) {
            continue;
        }
        let origin = problem
            .keys
            .iter()
            .find_map(|k| origins.get(k).cloned())
            .unwrap_or(Origin::Nowhere);
        d.push(origin, problem.message);
    }
    (params, origins)
}

/// A list of names for a message: all of them when few, else a count and where to look.
pub(super) fn name_list(kind: &str, model: &str, names: &[&str], flag: &str) -> String {
    if names.len() <= 20 {
        format!("the {kind} of {model} are: {}", names.join(", "))
    } else {
        format!(
            "{model} has {} {kind}; `models params {model} {flag}` lists them",
            names.len()
        )
    }
}

/// The initial conditions, by state index.
fn initial_conditions(
    entry: &Entry,
    scenario: &Scenario,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Vec<(usize, f64)> {
    let states = entry.model.state_names();
    let mut initial = Vec::new();
    for (key, value) in scenario.initial.iter().flatten() {
        let Some(name) = key.as_str() else {
            d.push(
                places.keys(&["initial"]),
                format!("a state name must be a string, found {}", format_value(key)),
            );
            continue;
        };
        let origin = places.keys(&["initial", name]);
        let Some(index) = states.iter().position(|s| *s == name) else {
            d.push(
                origin,
                format!(
                    "unknown state `{name}`; {}",
                    name_list("states", &entry.name, states, "--states")
                ),
            );
            continue;
        };
        match value.as_f64() {
            Some(v) if v.is_finite() => initial.push((index, v)),
            _ => d.push(
                origin,
                format!(
                    "the initial value of `{name}` must be a finite number, found {}",
                    catalog::describe_value(value)
                ),
            ),
        }
    }
    initial
}

/// The time span `[start, end]`, checked.
fn time_span(
    entry: &Entry,
    scenario: &Scenario,
    overrides: &Overrides,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<[f64; 2]> {
    let time = scenario.time.clone().unwrap_or_default();
    let (start, start_origin) = pick(overrides.t_start, time.start, "t-start", || {
        places.keys(&["time", "start"])
    })
    .unwrap_or((0.0, Origin::Nowhere));
    let (end, end_origin) = pick(overrides.t_end, time.end, "t-end", || {
        places.keys(&["time", "end"])
    })
    .unwrap_or((entry.t_end, Origin::Nowhere));
    if !start.is_finite() {
        d.push(
            start_origin,
            format!(
                "the start time must be a finite number of seconds, found {}",
                format_number(start)
            ),
        );
        return None;
    }
    if !(end.is_finite() && end > start) {
        d.push(
            end_origin,
            format!(
                "the time span must be positive: the end time must be a finite number of \
                 seconds > the start time ({} s), found {}",
                format_number(start),
                format_number(end)
            ),
        );
        return None;
    }
    Some([start, end])
}

/// How the scenario asks for the sample times (`count` wins: giving both is an error).
fn sampling(entry: &Entry, scenario: &Scenario, overrides: &Overrides) -> Option<Sampling> {
    let output = scenario.output.clone().unwrap_or_default();
    // `--interval` replaces the file's `count` as well as its `interval`.
    Some(match (overrides.interval, output.count) {
        (Some(interval), _) => Sampling::Interval(interval),
        (None, Some(count)) => Sampling::Count(count),
        (None, None) => Sampling::Interval(output.interval.unwrap_or(entry.interval)),
    })
}

/// The sample times: every `interval` from the start (exactly `start + k / rate` when
/// the interval is `1 / rate` for a whole `rate`, so 1 ms gives `k / 1000`), plus the
/// end if it is not on that grid; or `count` evenly spaced.
fn sample_times(
    entry: &Entry,
    scenario: &Scenario,
    overrides: &Overrides,
    [start, end]: [f64; 2],
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<Vec<f64>> {
    let output = scenario.output.clone().unwrap_or_default();
    let span = end - start;
    let interval = pick(overrides.interval, output.interval, "interval", || {
        places.keys(&["output", "interval"])
    });
    // `--interval` replaces the file's `count` as well as its `interval`.
    let count = output.count.filter(|_| overrides.interval.is_none());
    match (interval, count) {
        (Some(_), Some(_)) => {
            d.push(
                places.keys(&["output", "count"]),
                "give either `interval` or `count`, not both",
            );
            None
        }
        (_, Some(count)) => {
            if !(2..=MAX_SAMPLES).contains(&count) {
                d.push(
                    places.keys(&["output", "count"]),
                    format!("the number of samples must be in [2, {MAX_SAMPLES}], found {count}"),
                );
                return None;
            }
            Some(bgdsl_runtime::sample_times_uniform(start, end, count))
        }
        (interval, None) => {
            let (interval, origin) = interval.unwrap_or((entry.interval, Origin::Nowhere));
            if !(interval.is_finite() && interval > 0.0) {
                d.push(
                    origin,
                    format!(
                        "the sampling interval must be a number of seconds > 0, found {}",
                        format_number(interval)
                    ),
                );
                return None;
            }
            let steps = (span / interval * (1.0 + 1e-12)).floor();
            if steps + 2.0 > MAX_SAMPLES as f64 {
                d.push(
                    origin,
                    format!(
                        "a sampling interval of {} s over {} s gives more than \
                         {MAX_SAMPLES} samples; choose a larger interval",
                        format_number(interval),
                        format_number(span)
                    ),
                );
                return None;
            }
            let rate = 1.0 / interval;
            let whole_rate = (rate.round() - rate).abs() <= 1e-9 * rate && rate.round() >= 1.0;
            let at = |k: usize| {
                if whole_rate {
                    start + k as f64 / rate.round()
                } else {
                    start + k as f64 * interval
                }
            };
            let mut times: Vec<f64> = (0..=steps as usize).map(at).filter(|&t| t <= end).collect();
            if times.last().is_some_and(|&t| end - t > 1e-9 * interval) {
                times.push(end);
            }
            Some(times)
        }
    }
}

/// The names a model's outputs can be asked for by: each output, with the components
/// of a vector collapsed to its name (`Tc` for `Tc_x`, `Tc_y`, `Tc_z`).
fn output_groups(entry: &Entry) -> Vec<String> {
    let mut groups: Vec<String> = Vec::new();
    for name in entry.model.output_names() {
        let group = match name.rsplit_once('_') {
            Some((g, c))
                if matches!(c, "x" | "y" | "z")
                    || (c.len() == 2 && c.chars().all(|ch| ch.is_ascii_digit())) =>
            {
                g
            }
            _ => name,
        };
        if groups.last().map(String::as_str) != Some(group) {
            groups.push(group.to_owned());
        }
    }
    groups
}

/// A state or output by name, or a diagnostic listing the outputs.
pub(super) fn column(
    entry: &Entry,
    name: &str,
    origin: Origin,
    d: &mut Diagnostics,
) -> Option<Vec<(String, Column)>> {
    let found = resolve_columns(&*entry.model, name);
    if found.is_none() {
        let groups = output_groups(entry);
        d.push(
            origin,
            format!(
                "unknown state or output `{name}`; the outputs of {} are: {} (a vector's \
                 name stands for its components; `models params {} --states` lists the \
                 states)",
                entry.name,
                groups.join(", "),
                entry.name
            ),
        );
    }
    found
}

/// `output.record`, resolved.
fn record(
    entry: &Entry,
    scenario: &Scenario,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<Vec<(String, Column)>> {
    let names = scenario.output.as_ref()?.record.as_ref()?;
    let path = KeyPath::keys(&["output", "record"]);
    if names.is_empty() {
        d.push(places.file(&path), "`record` lists no state or output");
        return None;
    }
    let mut columns = Vec::new();
    for (i, name) in names.iter().enumerate() {
        if let Some(found) = column(entry, name, places.file(&path.index(i)), d) {
            columns.extend(found);
        }
    }
    Some(columns)
}

/// `plots`, checked against the figure ids of the entry's extras, or the outputs.
fn plots(
    entry: &Entry,
    scenario: &Scenario,
    overrides: &Overrides,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Plots {
    if overrides.no_plots {
        return Plots::None;
    }
    let (value, path) = super::phase::figures_value(scenario);
    let Some(value) = value else {
        return Plots::All;
    };
    let origin = places.file(&path);
    match value.as_str() {
        Some("all") => return Plots::All,
        Some("none") => return Plots::None,
        _ => {}
    }
    let valid: Vec<String> = match entry.extras.figure_ids() {
        Some(ids) => ids.iter().map(|s| (*s).to_owned()).collect(),
        None => generic_figure_ids(entry),
    };
    let Some(names) = plot_names(value) else {
        d.push(
            origin,
            format!(
                "`plots` must be `all`, `none` or a list of figure ids, found {}",
                catalog::describe_value(value)
            ),
        );
        return Plots::None;
    };
    for (i, name) in &names {
        if !valid.contains(name) {
            d.push(
                places.file(&path.index(*i)),
                format!(
                    "unknown figure `{name}`; the figures of {} are: {}",
                    entry.name,
                    valid.join(", ")
                ),
            );
        }
    }
    Plots::Only(names.into_values().collect())
}

/// The ids `plots` may name for an entry with the generic figures: each output, each
/// state chart (a vector's name for its components, or a scalar state's), each state
/// by name, and `energy_balance`.
fn generic_figure_ids(entry: &Entry) -> Vec<String> {
    let states = entry.model.state_names();
    let groups = catalog::state_groups(states);
    let mut ids: Vec<String> = entry
        .model
        .output_names()
        .iter()
        .map(|s| (*s).to_owned())
        .collect();
    for group in groups {
        if group.members.len() > 1 {
            ids.push(group.id);
        }
    }
    ids.extend(states.iter().map(|s| (*s).to_owned()));
    ids.push(catalog::ENERGY_FIGURE_ID.to_owned());
    ids
}

/// Every figure asked for has something to draw: for a model whose extras draw no
/// figures of their own, a chart is of a recorded output, so one of an output `record`
/// leaves out, or `plots: all` when `record` names no output, would draw nothing.
fn figures_draw_something(
    entry: &Entry,
    scenario: &Scenario,
    record: &Option<Vec<(String, Column)>>,
    plots: &Plots,
    places: &Places<'_>,
    d: &mut Diagnostics,
) {
    let path = super::phase::figures_value(scenario).1;
    if plots == &Plots::Only(Vec::new()) {
        d.push(
            places.file(&path),
            "`plots` lists no figure; write `plots: none` to draw none",
        );
    }
    let (None, Some(record)) = (entry.extras.figure_ids(), record) else {
        return;
    };
    let recorded = |name: &str| record.iter().any(|(n, _)| n == name);
    let outputs = entry.model.output_names();
    match plots {
        Plots::None => {}
        Plots::All => {
            if !outputs.iter().any(|o| recorded(o)) {
                d.push(
                    places.keys(&["output", "record"]),
                    format!(
                        "`record` names no output, so `plots: all` would draw nothing; record \
                         an output of {} ({}) or set `plots: none`",
                        entry.name,
                        outputs.join(", ")
                    ),
                );
            }
        }
        Plots::Only(ids) => {
            let states = entry.model.state_names();
            let groups = catalog::state_groups(states);
            for (i, id) in ids.iter().enumerate() {
                // A state chart draws the recorded states of its group.
                let group = groups
                    .iter()
                    .find(|g| g.id == *id || g.members.iter().any(|&m| states[m] == id));
                let state_missing = !outputs.contains(&id.as_str())
                    && group.is_some_and(|g| !g.members.iter().any(|&m| recorded(states[m])));
                if (outputs.contains(&id.as_str()) && !recorded(id)) || state_missing {
                    d.push(
                        places.file(&path.index(i)),
                        format!(
                            "figure `{id}` would draw nothing: `{id}` is not recorded; add \
                             it to `output.record`"
                        ),
                    );
                }
            }
        }
    }
}
