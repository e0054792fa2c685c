//! `models periodic`: the periodic steady state of a periodically driven catalogue
//! model by shooting, with its Floquet multipliers ([`bgdsl_analysis::periodic`]),
//! one period of it sampled into the columns of a run, and its results set
//! (`orbit.csv`, `floquet.json`, figures, `index.html`, `run.yaml`).

use bgdsl_analysis::periodic::{
    periodic_orbit, PeriodicError, PeriodicOptions, PeriodicOrbit, Shift,
};
use bgdsl_runtime::{FromParams, Simulation, Solver};
use serde::de::DeserializeOwned;
use serde_yaml::{Mapping, Value};

use super::{html, with_unit, AnalysisFailure, AnalysisSet, DataFile, Figure};
use crate::catalog::{column_unit, initial_state, params_from, Column, Entry, RunPlan};
use crate::plot::{ChartOptions, LineChart, Series};

/// The one period of the orbit, the columns of a run's CSV.
pub const ORBIT_FILE: &str = "orbit.csv";
/// The period, the multipliers and the shooting's record.
pub const FLOQUET_FILE: &str = "floquet.json";
/// Charts of at most this many columns are drawn (outputs first, then states).
pub const CHART_LIMIT: usize = 16;

/// What `models periodic` asks of a model, beside the plan (parameters, initial state,
/// start time = the orbit's phase `t0`).
#[derive(Clone, Debug)]
pub struct PeriodicRequest {
    /// The period, s.
    pub period: f64,
    /// Periods simulated from the initial state before Newton's method starts.
    pub warmup_periods: usize,
    /// Samples of `orbit.csv` per period (the period's end is one more row).
    pub points: usize,
    /// The shooting's convergence tolerance ([`PeriodicOptions::tolerance`]).
    pub tolerance: f64,
    /// Newton iterations at most.
    pub max_iterations: usize,
    /// The solver of the period map and of the samples (`None`: the library's,
    /// Radau5 at rtol 1e-9, atol 1e-11).
    pub solver: Option<Solver>,
    /// The states periodic up to an advance per period: (state index, advance).
    pub shifts: Vec<(usize, f64)>,
    /// SDIRK steps per period of the monodromy matrix ([`PeriodicOptions::steps`]).
    pub steps: usize,
}

impl PeriodicRequest {
    /// The library's defaults for `period`, 200 samples per period.
    pub fn new(period: f64) -> Self {
        let options = PeriodicOptions::new(period);
        PeriodicRequest {
            period,
            warmup_periods: options.warmup_periods,
            points: 200,
            tolerance: options.tolerance,
            max_iterations: options.max_iterations,
            solver: None,
            shifts: Vec::new(),
            steps: options.steps,
        }
    }

    /// The library's options for an orbit starting at `t0`.
    pub fn options(&self, t0: f64) -> PeriodicOptions {
        let defaults = PeriodicOptions::new(self.period);
        PeriodicOptions {
            t0,
            warmup_periods: self.warmup_periods,
            tolerance: self.tolerance,
            max_iterations: self.max_iterations,
            solver: self.solver.unwrap_or(defaults.solver),
            steps: self.steps,
            ..defaults
        }
    }
}

/// A periodic orbit with one period of it sampled.
#[derive(Clone, Debug)]
pub struct PeriodicFound {
    /// The orbit, its monodromy matrix and multipliers.
    pub orbit: PeriodicOrbit,
    /// The sample times `t0 + k T / points`, `k = 0..=points`.
    pub times: Vec<f64>,
    /// One row per time: the asked columns' values.
    pub rows: Vec<Vec<f64>>,
}

/// A failed shooting as the program reports it.
fn failure(e: PeriodicError) -> AnalysisFailure {
    match e {
        PeriodicError::Analysis(e) => e.into(),
        PeriodicError::BadPeriod(_) => AnalysisFailure::Usage(e.to_string()),
        e => AnalysisFailure::Failed(e.to_string()),
    }
}

/// The periodic orbit of `M` with `plan`'s parameters through a state near the plan's
/// initial state, starting at the plan's first time, and `columns` over one period.
///
/// # Errors
///
/// [`AnalysisFailure`]: a bad period (usage), a failed run, no convergence.
pub fn periodic_of<M>(
    plan: &RunPlan,
    columns: &[Column],
    request: &PeriodicRequest,
) -> Result<PeriodicFound, AnalysisFailure>
where
    M: FromParams,
    M::Params: DeserializeOwned,
{
    let model = M::from_params(params_from::<M::Params>(&plan.params)?);
    let guess = initial_state(&model, &plan.initial);
    let t0 = plan.span()[0];
    let options = request.options(t0);
    let shifts: Vec<Shift> = request
        .shifts
        .iter()
        .map(|&(state, per_period)| Shift { state, per_period })
        .collect();
    let orbit = periodic_orbit(&model, &guess, &shifts, &options).map_err(failure)?;
    let points = request.points.max(2);
    let times: Vec<f64> = (0..=points)
        .map(|k| t0 + request.period * k as f64 / points as f64)
        .collect();
    let mut rows = Vec::with_capacity(times.len());
    let mut sim =
        Simulation::new(&model, options.solver).map_err(|e| failure(PeriodicError::from(e)))?;
    sim.run(
        t0,
        &orbit.x0,
        &times,
        &mut |_t: f64, x: &[f64], y: &[f64]| {
            rows.push(columns.iter().map(|c| c.value(x, y)).collect())
        },
    )
    .map_err(|e| failure(PeriodicError::from(e)))?;
    Ok(PeriodicFound { orbit, times, rows })
}

/// How far a multiplier's modulus may be from 1 and still count as on the unit circle:
/// the monodromy matrix comes from an SDIRK integration of the variational equations
/// ([`PeriodicOptions::steps`] steps per period), whose determinant misses Liouville's
/// exact value by 6e-6 relative on the catalogue's Duffing oscillator.
pub const NEUTRAL_MODULUS: f64 = 1e-4;

/// One Floquet multiplier as the stability verdict reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// Its real part.
    pub re: f64,
    /// Its imaginary part.
    pub im: f64,
    /// Its error estimate ([`PeriodicOrbit::multiplier_errors`]).
    pub error: f64,
    /// Whether it is resolved ([`PeriodicOrbit::resolved`]).
    pub resolved: bool,
}

impl Reading {
    /// The orbit's multipliers with their error estimates.
    pub fn of_orbit(orbit: &PeriodicOrbit) -> Vec<Reading> {
        orbit
            .multipliers
            .iter()
            .enumerate()
            .map(|(k, m)| Reading {
                re: m.re,
                im: m.im,
                error: orbit
                    .multiplier_errors
                    .get(k)
                    .copied()
                    .unwrap_or(f64::INFINITY),
                resolved: orbit.resolved.get(k).copied().unwrap_or(false),
            })
            .collect()
    }

    fn modulus(&self) -> f64 {
        self.re.hypot(self.im)
    }
}

/// The orbit's stability read from its Floquet multipliers and their error estimates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stability {
    /// Every multiplier inside the unit circle: nearby motions return to the orbit.
    Attracting,
    /// None outside, some on the unit circle (within [`NEUTRAL_MODULUS`] or their error
    /// estimate): nearby motions neither return nor depart along those directions.
    Neutral {
        /// Multipliers on the unit circle.
        on_circle: usize,
    },
    /// A resolved multiplier outside the unit circle by more than its error estimate:
    /// nearby motions depart.
    Unstable {
        /// The largest such modulus.
        largest: f64,
    },
    /// None surely outside, but a multiplier that is not resolved may be: its modulus
    /// plus its error estimate exceeds 1.
    NotResolved {
        /// The largest modulus among those.
        largest: f64,
        /// Its error estimate.
        error: f64,
        /// The SDIRK steps per period suggested to resolve it (four times those used).
        suggested_steps: usize,
    },
}

impl Stability {
    /// The stability of `multipliers`, computed at `steps` SDIRK steps per period.
    pub fn of(multipliers: impl IntoIterator<Item = Reading>, steps: usize) -> Self {
        let mut on_circle = 0;
        let mut unstable = None::<f64>;
        let mut unresolved = None::<(f64, f64)>;
        for m in multipliers {
            let modulus = m.modulus();
            if modulus.is_nan() {
                return Stability::Unstable { largest: f64::NAN };
            }
            let band = NEUTRAL_MODULUS.max(m.error);
            if m.resolved && modulus - band > 1.0 {
                unstable = Some(unstable.map_or(modulus, |u| u.max(modulus)));
            } else if !m.resolved && modulus + m.error > 1.0 + NEUTRAL_MODULUS {
                if unresolved.is_none_or(|(u, _)| modulus > u) {
                    unresolved = Some((modulus, m.error));
                }
            } else if (modulus - 1.0).abs() <= band {
                on_circle += 1;
            }
        }
        match (unstable, unresolved) {
            (Some(largest), _) => Stability::Unstable { largest },
            (None, Some((largest, error))) => Stability::NotResolved {
                largest,
                error,
                suggested_steps: 4 * steps.max(1),
            },
            (None, None) if on_circle > 0 => Stability::Neutral { on_circle },
            (None, None) => Stability::Attracting,
        }
    }

    /// One line for a person.
    pub fn describe(self) -> String {
        match self {
            Stability::Attracting => {
                "stable: every Floquet multiplier is inside the unit circle".to_owned()
            }
            Stability::Neutral { on_circle } => format!(
                "stable but not attracting in every direction: {on_circle} multiplier(s) on \
                 the unit circle (|μ| = 1 within {NEUTRAL_MODULUS:e} or their error \
                 estimate), the rest inside"
            ),
            Stability::Unstable { largest } => format!(
                "unstable: a Floquet multiplier of modulus {largest:.6} lies outside the unit \
                 circle by more than its error estimate"
            ),
            Stability::NotResolved {
                largest,
                error,
                suggested_steps,
            } => format!(
                "not resolved: a Floquet multiplier of modulus {largest:.6} has an error \
                 estimate of {error:.2e} and may lie outside the unit circle (or be a \
                 neutral multiplier split by the monodromy matrix's integration error); run \
                 with --steps {suggested_steps}"
            ),
        }
    }

    /// A short keyword: `attracting`, `neutral`, `unstable` or `not_resolved`.
    pub fn keyword(self) -> &'static str {
        match self {
            Stability::Attracting => "attracting",
            Stability::Neutral { .. } => "neutral",
            Stability::Unstable { .. } => "unstable",
            Stability::NotResolved { .. } => "not_resolved",
        }
    }
}

/// `floquet.json`.
#[derive(serde::Serialize)]
struct FloquetFile<'a> {
    model: &'a str,
    period: f64,
    t0: f64,
    multipliers: Vec<[f64; 2]>,
    moduli: Vec<f64>,
    multiplier_errors: Vec<Option<f64>>,
    resolved: Vec<bool>,
    check_steps: usize,
    resolution: &'static str,
    stability: &'static str,
    stability_text: String,
    iterations: usize,
    residual: f64,
    neutral_residual: f64,
    periods_integrated: usize,
    initial_state: Vec<(&'a str, f64)>,
    shifts: Vec<(&'a str, f64)>,
    neutral: NeutralFile,
    free_states: Vec<FreeFile>,
}

/// `floquet.json`'s `neutral`.
#[derive(serde::Serialize)]
struct NeutralFile {
    dimension: usize,
    singular_values: Vec<f64>,
    along_flow: f64,
    flow_invariance: f64,
    states: Vec<(&'static str, f64)>,
    explanation: &'static str,
}

/// One of `floquet.json`'s `free_states`.
#[derive(serde::Serialize)]
struct FreeFile {
    name: &'static str,
    drift: f64,
    reason: &'static str,
}

/// The text of `floquet.json` for the orbit of `model` (its type name) with
/// `state_names`: `period` and `multipliers` as `[re, im]` pairs (the keys issue 16
/// fixes), then their moduli, the stability, the shooting's iterations and residuals,
/// the orbit's initial state, the neutral directions and the free states.
pub fn floquet_json(
    model: &str,
    state_names: &[&str],
    orbit: &PeriodicOrbit,
    steps: usize,
) -> String {
    let pairs: Vec<(f64, f64)> = orbit.multipliers.iter().map(|m| (m.re, m.im)).collect();
    let stability = Stability::of(Reading::of_orbit(orbit), steps);
    let file = FloquetFile {
        model,
        period: orbit.period,
        t0: orbit.t0,
        multipliers: pairs.iter().map(|&(re, im)| [re, im]).collect(),
        moduli: pairs.iter().map(|&(re, im)| re.hypot(im)).collect(),
        // JSON has no infinity: an unchecked multiplier's error is null.
        multiplier_errors: orbit
            .multiplier_errors
            .iter()
            .map(|e| e.is_finite().then_some(*e))
            .collect(),
        resolved: orbit.resolved.clone(),
        check_steps: orbit.check_steps,
        resolution: "each multiplier's error estimate is its distance to its partner among \
            the multipliers of the monodromy matrix at check_steps SDIRK steps per period \
            (matched one to one, least total distance); resolved: at most the tolerance. A \
            neutral multiplier split by the integration error is not resolved",
        stability: stability.keyword(),
        stability_text: stability.describe(),
        iterations: orbit.iterations,
        residual: orbit.residual,
        neutral_residual: orbit.neutral_residual,
        periods_integrated: orbit.periods_integrated,
        shifts: orbit
            .shifts
            .iter()
            .map(|s| {
                (
                    state_names.get(s.state).copied().unwrap_or("?"),
                    s.per_period,
                )
            })
            .collect(),
        initial_state: state_names
            .iter()
            .copied()
            .zip(orbit.x0.iter().copied())
            .collect(),
        neutral: NeutralFile {
            dimension: orbit.neutral.dimension,
            singular_values: orbit.neutral.singular_values.clone(),
            along_flow: orbit.neutral.along_flow,
            flow_invariance: orbit.neutral.flow_invariance,
            states: orbit.neutral.states.clone(),
            explanation: "directions in which the period map neither attracts nor repels \
                (singular values of the scaled Φ − I below the neutral tolerance): along the \
                orbit for an autonomous model (along_flow near 1), a first integral, or a \
                free coordinate; Newton's method does not move the state along them",
        },
        free_states: orbit
            .free_states
            .iter()
            .map(|f| FreeFile {
                name: f.name,
                drift: f.drift,
                reason: "nothing depends on this state (its column of Φ is the unit \
                    vector), so it is not required to return; drift is its advance over \
                    one period",
            })
            .collect(),
    };
    let mut text = serde_json::to_string_pretty(&file).unwrap_or_default();
    text.push('\n');
    text
}

/// The text of `orbit.csv`: the header `t,<names>`, then one row per sample of `found`,
/// numbers as a run's CSV writes them.
pub fn orbit_csv(names: &[String], found: &PeriodicFound) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(b"t");
    for name in names {
        out.push(b',');
        out.extend_from_slice(name.as_bytes());
    }
    out.push(b'\n');
    let mut writer = bgdsl_runtime::record::RowWriter::new();
    for (t, row) in found.times.iter().zip(&found.rows) {
        // Writing to a Vec cannot fail.
        let _ = writer.write_row(&mut out, core::iter::once(*t).chain(row.iter().copied()));
    }
    out
}

/// The columns of `orbit.csv`, those of the run's CSV: the plan's `record`, else the
/// entry's [`Entry::record`], else every state and output.
pub fn orbit_columns(entry: &Entry, plan: &RunPlan) -> Vec<(String, Column)> {
    if let Some(chosen) = &plan.record {
        return chosen.clone();
    }
    match entry.record {
        Some(names) => names
            .iter()
            .filter_map(|name| crate::catalog::resolve_columns(&*entry.model, name))
            .flatten()
            .collect(),
        None => crate::catalog::columns::all_columns(&*entry.model),
    }
}

/// The text of `orbit.units.csv`: `column,unit,description`, one row per column of
/// `orbit.csv`, as beside a run's CSV.
fn units_csv(entry: &Entry, names: &[String]) -> String {
    let field = |text: &str| {
        if text.contains([',', '"', '\n']) {
            format!("\"{}\"", text.replace('"', "\"\""))
        } else {
            text.to_owned()
        }
    };
    let mut text = String::from("column,unit,description\n");
    for name in core::iter::once("t").chain(names.iter().map(String::as_str)) {
        let (unit, doc) = column_unit(&*entry.model, name);
        let doc = doc.split_whitespace().collect::<Vec<_>>().join(" ");
        text.push_str(&format!(
            "{},{},{}\n",
            field(name),
            field(unit),
            field(&doc)
        ));
    }
    text
}

/// A figure id from a column name: letters, digits and `_` only.
fn figure_id(name: &str) -> String {
    let cleaned: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    format!("orbit_{cleaned}")
}

/// The results set of `models periodic`: `orbit.csv` (+ units), `floquet.json`, one
/// chart per column over the period (outputs first, at most [`CHART_LIMIT`]), the
/// multipliers against the unit circle, the summary and the record.
pub fn results_set(
    entry: &Entry,
    request: &PeriodicRequest,
    period_source: &str,
    columns: &[(String, Column)],
    found: &PeriodicFound,
) -> AnalysisSet {
    let orbit = &found.orbit;
    let names: Vec<String> = columns.iter().map(|(n, _)| n.clone()).collect();
    let pairs: Vec<(f64, f64)> = orbit.multipliers.iter().map(|m| (m.re, m.im)).collect();
    let readings = Reading::of_orbit(orbit);
    let stability = Stability::of(readings.iter().copied(), request.steps);
    let files = vec![
        DataFile::new(
            ORBIT_FILE,
            String::from_utf8(orbit_csv(&names, found)).unwrap_or_default(),
        ),
        DataFile::new("orbit.units.csv", units_csv(entry, &names)),
        DataFile::new(
            FLOQUET_FILE,
            floquet_json(
                entry.model.type_name(),
                entry.model.state_names(),
                orbit,
                request.steps,
            ),
        ),
    ];

    // An unresolved multiplier's modulus is marked `?`.
    let moduli: Vec<String> = readings
        .iter()
        .map(|m| format!("{:.6}{}", m.modulus(), if m.resolved { "" } else { "?" }))
        .collect();
    let unresolved = readings.iter().filter(|m| !m.resolved).count();
    let mut summary = format!(
        "model          {} ({})\n\
         periodic orbit period {} ({period_source}), from t0 = {} s\n\
         shooting       {} Newton iteration(s), {} period(s) integrated, residual {:.2e} \
         of the tolerance {:e}\n\
         multipliers    |μ| = {}\n\
         resolution     {}\n\
         stability      {}\n",
        entry.name,
        entry.model.type_name(),
        with_unit(orbit.period, "s"),
        orbit.t0,
        orbit.iterations,
        orbit.periods_integrated,
        orbit.residual,
        request.tolerance,
        moduli.join(", "),
        resolution_line(orbit, unresolved),
        stability.describe(),
    );
    if orbit.neutral.dimension > 0 {
        let states: Vec<&str> = orbit.neutral.states.iter().map(|(n, _)| *n).collect();
        summary.push_str(&format!(
            "neutral        {} direction(s), mostly {} (along the flow: {:.3})\n",
            orbit.neutral.dimension,
            states.join(", "),
            orbit.neutral.along_flow
        ));
    }
    for free in &orbit.free_states {
        summary.push_str(&format!(
            "free state     {}: nothing depends on it, not required to return (drift {} per \
             period)\n",
            free.name,
            crate::catalog::format_significant(free.drift)
        ));
    }
    summary.push_str(&format!(
        "files          {ORBIT_FILE} ({} samples over one period), {FLOQUET_FILE}\n",
        found.times.len()
    ));

    let mut figures = Vec::new();
    let outputs_first = columns
        .iter()
        .enumerate()
        .filter(|(_, (_, c))| matches!(c, Column::Output(_)))
        .chain(
            columns
                .iter()
                .enumerate()
                .filter(|(_, (_, c))| matches!(c, Column::State(_))),
        );
    for (k, (name, _)) in outputs_first.take(CHART_LIMIT) {
        let (unit, doc) = column_unit(&*entry.model, name);
        let points: Vec<(f64, f64)> = found
            .times
            .iter()
            .zip(&found.rows)
            .map(|(t, row)| (*t, row[k]))
            .collect();
        let y_label = if unit.is_empty() {
            name.clone()
        } else {
            format!("{name} ({unit})")
        };
        figures.push(Figure {
            id: figure_id(name),
            title: format!("{name} over one period"),
            caption: format!(
                "{name}{}{} on the periodic orbit, from t0 = {} s over one period T = {} s \
                 ({} samples; {ORBIT_FILE}).",
                if doc.is_empty() { "" } else { ": " },
                doc.trim_end_matches('.'),
                orbit.t0,
                orbit.period,
                found.times.len()
            ),
            chart: LineChart {
                title: format!("{name} on the periodic orbit ({})", entry.name),
                x_label: "time t (s)".to_owned(),
                y_label,
                series: vec![Series::new(name.clone(), points)],
            },
            options: ChartOptions::default(),
        });
    }
    figures.push(multiplier_figure(entry, &pairs));

    let mut table = String::from(
        "<h2>Floquet multipliers</h2><table><tr><th>#</th><th>Re μ</th><th>Im μ</th>\
         <th>|μ|</th><th>error estimate</th><th>resolved</th></tr>",
    );
    for (i, m) in readings.iter().enumerate() {
        table.push_str(&format!(
            "<tr><td>{}</td><td>{:.9}</td><td>{:.9}</td><td>{:.9}</td><td>{:.2e}</td>\
             <td>{}</td></tr>",
            i + 1,
            m.re,
            m.im,
            m.modulus(),
            m.error,
            if m.resolved { "yes" } else { "no" }
        ));
    }
    table.push_str(&format!(
        "</table><p>{}. {}.</p>",
        html(&resolution_line(orbit, unresolved)),
        html(&stability.describe())
    ));

    let mut record = Mapping::new();
    record.insert("period".into(), orbit.period.into());
    record.insert("period_source".into(), period_source.into());
    record.insert("t0".into(), orbit.t0.into());
    record.insert("warmup_periods".into(), request.warmup_periods.into());
    record.insert("points".into(), request.points.into());
    record.insert("tolerance".into(), request.tolerance.into());
    record.insert("steps".into(), request.steps.into());
    if !request.shifts.is_empty() {
        let names = entry.model.state_names();
        let mut shifts = Mapping::new();
        for &(state, advance) in &request.shifts {
            let name = names.get(state).copied().unwrap_or("?");
            shifts.insert(name.into(), advance.into());
        }
        record.insert("shifts".into(), Value::Mapping(shifts));
    }
    record.insert("iterations".into(), orbit.iterations.into());
    record.insert("stability".into(), stability.keyword().into());
    record.insert("check_steps".into(), orbit.check_steps.into());
    record.insert("unresolved_multipliers".into(), unresolved.into());
    record.insert(
        "largest_multiplier_modulus".into(),
        pairs
            .iter()
            .map(|&(re, im)| re.hypot(im))
            .fold(0.0f64, f64::max)
            .into(),
    );
    record.insert(
        "neutral_directions".into(),
        Value::from(orbit.neutral.dimension),
    );
    AnalysisSet {
        command: "periodic",
        summary,
        files,
        figures,
        sections: vec![table],
        record,
    }
}

/// The summary's line on the multipliers' error estimates.
fn resolution_line(orbit: &PeriodicOrbit, unresolved: usize) -> String {
    if orbit.check_steps == 0 {
        return "not checked: no error estimates".to_owned();
    }
    let largest = orbit
        .multiplier_errors
        .iter()
        .zip(&orbit.resolved)
        .filter(|(_, r)| **r)
        .fold(0.0f64, |m, (e, _)| m.max(*e));
    format!(
        "{} of {} multipliers resolved (error estimate against {} SDIRK steps per period at \
         most {largest:.1e}); {unresolved} not resolved (marked ?)",
        orbit.multipliers.len() - unresolved,
        orbit.multipliers.len(),
        orbit.check_steps
    )
}

/// The multipliers (×) in the complex plane with the unit circle: inside is
/// attracting.
fn multiplier_figure(entry: &Entry, pairs: &[(f64, f64)]) -> Figure {
    let extent = pairs
        .iter()
        .map(|&(re, im)| re.abs().max(im.abs()))
        .fold(1.0f64, f64::max)
        * 1.1;
    let d = 0.03 * extent;
    let mut crosses = Vec::new();
    for &(x, y) in pairs {
        crosses.extend([
            (x - d, y - d),
            (x + d, y + d),
            (f64::NAN, f64::NAN),
            (x - d, y + d),
            (x + d, y - d),
            (f64::NAN, f64::NAN),
        ]);
    }
    let circle: Vec<(f64, f64)> = (0..=360)
        .map(|k| {
            let a = core::f64::consts::TAU * k as f64 / 360.0;
            (a.cos(), a.sin())
        })
        .collect();
    Figure {
        id: "floquet_multipliers".to_owned(),
        title: "Floquet multipliers".to_owned(),
        caption: format!(
            "The {} Floquet multipliers (eigenvalues of the monodromy matrix Φ, ×) and the \
             unit circle: a multiplier inside it is a direction in which motions near the \
             orbit return to it, by the factor |μ| per period; on it, one in which they \
             neither return nor depart; outside, one in which they depart. See \
             {FLOQUET_FILE}.",
            pairs.len()
        ),
        chart: LineChart {
            title: format!("Floquet multipliers ({})", entry.name),
            x_label: "Re μ".to_owned(),
            y_label: "Im μ".to_owned(),
            series: vec![
                Series::new("multiplier", crosses),
                Series::new("unit circle", circle),
            ],
        },
        options: ChartOptions {
            x_range: Some((-extent, extent)),
            y_range: Some((-extent, extent)),
            size: (880, 720),
            ..ChartOptions::default()
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stability_from_the_multipliers_moduli() {
        let at = |re: f64, im: f64, error: f64| Reading {
            re,
            im,
            error,
            resolved: error <= 1e-2,
        };
        assert_eq!(
            Stability::of([at(0.5, 0.5, 1e-6), at(0.5, -0.5, 1e-6)], 400),
            Stability::Attracting
        );
        // An autonomous model's multiplier along the flow, integrated to 1e-5.
        assert_eq!(
            Stability::of([at(1.0 + 1e-5, 0.0, 1e-5), at(0.3, 0.0, 1e-6)], 400),
            Stability::Neutral { on_circle: 1 }
        );
        // Off the circle by less than its error: on it.
        assert_eq!(
            Stability::of([at(1.002, 0.0, 3e-3)], 400),
            Stability::Neutral { on_circle: 1 }
        );
        assert_eq!(
            Stability::of([at(0.0, 1.2, 1e-6), at(0.0, -1.2, 1e-6)], 400),
            Stability::Unstable { largest: 1.2 }
        );
        // The quick return at 400 steps: a spurious pair of modulus 2.2 (not resolved)
        // and the genuine 1.0817 (resolved): unstable, for the genuine one.
        let pair = [at(1.965, 1.033, 1.28), at(1.965, -1.033, 17.8)];
        assert_eq!(
            Stability::of(pair.into_iter().chain([at(1.0821, 0.0, 2.5e-3)]), 400),
            Stability::Unstable { largest: 1.0821 }
        );
        // Without the genuine one, the pair alone is not resolved.
        match Stability::of(pair, 400) {
            Stability::NotResolved {
                largest,
                suggested_steps,
                ..
            } => {
                assert!((largest - 1.965f64.hypot(1.033)).abs() < 1e-12);
                assert_eq!(suggested_steps, 1600);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn figure_ids_are_file_names() {
        assert_eq!(figure_id("spring.q"), "orbit_spring_q");
        assert_eq!(figure_id("R1_21"), "orbit_R1_21");
    }
}
