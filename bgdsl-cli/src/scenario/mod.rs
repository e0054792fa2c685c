//! Scenario files: a run (or a sweep of runs) of a model of the [catalogue](crate::catalog),
//! written in YAML.
//!
//! ```yaml
//! model: quick_return            # required: a name from `models list`
//! description: g = 0             # optional: the title of index.html
//! parameters:                    # optional: by name, see `models params <model>`
//!   g: 0.0
//!   l1: [0.2, 0.01, 0.01]        # a vector parameter: a list of its numbers
//! initial:                       # optional: initial conditions by state name
//!   output_slider.translation.p_x: 0.0   #   (`models params <model> --states`)
//! time:                          # optional: s; default 0 to the model's end
//!   start: 0.0
//!   end: 5.0
//! solver:                        # optional: default the model's (radau5)
//!   method: radau5               #   rk4 | dopri5 | dopri5-fixed | radau5 | rodas4 | rodas5p
//!   rtol: 1.0e-6                 #   adaptive methods: in [1e-14, 0.1]
//!   atol: 1.0e-10                #   adaptive methods: > 0; or per state:
//!   # atol: {default: 1.0e-9, output_slider.translation.p_x: 1.0e-12}
//!   non_negative: []             #   adaptive methods: states held >= 0, by name
//!   step: 1.0e-4                 #   fixed-step methods only: s, > 0
//!   max_step: 0.01               #   adaptive methods only: s, > 0
//!   max_steps: 100000            #   > 0
//!   max_wall_time: 60            #   the stiff solvers only: s, > 0
//! output:                        # optional
//!   interval: 0.001              #   s between samples (default: the model's), or
//!   # count: 5001                #   a number of samples (>= 2), ends included
//!   record: [crank_angle, j01.spring.q]   # states and outputs to record
//! plots: all                     # optional: all (default) | none | [fig05, fig07, ...]
//! # plots:                       #   or a mapping:
//! #   figures: [x, energy_balance]  # all | none | [ids], as above
//! #   phase: [[x, speed]]        #   phase portraits: pairs of state or output names
//! sweep:                         # optional: run a grid of points instead of one run
//!   parameters:                  #   one or two scalar parameters
//!     - name: w_drive
//!       from: 2.0                #   `from` <= `to`, `steps` >= 1 values, ends
//!       to: 10.0                 #   included (one step: `to` = `from`),
//!       steps: 17
//!     # - name: R_C
//!     #   values: [50, 100, 200] #   or a list of distinct finite `values`
//!   peaks: [Tc, F_O1]            #   outputs whose peak magnitude each run reports
//!   window: {from: 4.0, to: 8.0} #   optional: s; default the second half of the span
//! monte_carlo:                   # optional: a Monte Carlo study instead of one run
//!   samples: 200                 #   the number of runs, >= 2
//!   seed: 42                     #   any whole number >= 0; the same seed, the same draws
//!   parameters:                  #   scalar parameters, each from one distribution:
//!     m_s: {uniform: [200, 300]} #     uniform on [lo, hi), lo < hi
//!     k_s: {normal: {mean: 2.0e4, sd: 2.0e3}}   # sd >= 0
//!     c_s: {lognormal: {mu: 7.0, sigma: 0.2}}   # ln x is normal(mu, sigma)
//!     # m_u: {csv: {file: masses.csv, column: m_u}}  # row i for sample i; the file
//!                                #     is relative to the scenario, a header row first
//!     # g: {values: [9.78, 9.81, 9.83]}            # or listed: sample i takes the i-th
//! ```
//!
//! # Meaning
//!
//! - **`parameters`** replace the model's defaults; a vector parameter takes a list of
//!   as many numbers. Each value is checked physically (masses > 0, stiffnesses >= 0,
//!   a positive definite inertia, ...: the entry's
//!   [`checks`](crate::catalog::EntryOf::checks)).
//! - **`initial`** replaces entries of the model's initial state, by state name.
//! - **`solver.atol`** is one absolute tolerance for every state, or a mapping from
//!   state names to theirs; its `default` (else `--atol`, else the method's) applies
//!   to the states it does not name, and `--atol` replaces only that default. Each
//!   per-state value must be a finite number > 0. **`solver.non_negative`** lists
//!   states that must stay >= 0 (concentrations, amounts): a step that takes one below
//!   its tolerance is rejected and retried shorter, a smaller excursion is set to 0.
//!   Both are what [`Simulation::set_atol`](bgdsl_runtime::Simulation::set_atol) and
//!   [`Simulation::set_non_negative`](bgdsl_runtime::Simulation::set_non_negative) do,
//!   for the adaptive methods only; `docs/tolerances.md` says what atol means.
//! - **`output.record`** names states and outputs; a vector output's name stands for its
//!   components (`Tc` for `Tc_x`, `Tc_y`, `Tc_z`). It chooses the columns of
//!   `<model>.csv` (default: the entry's [`record`](crate::catalog::EntryOf::record),
//!   by default every state and output). A model's [extras](crate::catalog::Extras)
//!   may write files of their own beside it, whatever `record` says (in `models`, the
//!   quick return's spec file `quick_return.csv` with its 56 columns, the table then
//!   named `quick_return_extra.csv`).
//! - **`plots`** chooses figures by id: the ids of the extras' own figures
//!   ([`Extras::figure_ids`](crate::catalog::Extras::figure_ids); in `models`, the quick
//!   return's paper figures), or for other models the names of recorded outputs (one
//!   chart each, against time), of states or vectors of states (one chart each, drawn
//!   by default only for models of at most
//!   [`STATE_CHART_LIMIT`](crate::catalog::STATE_CHART_LIMIT) states), and
//!   `energy_balance`. In its mapping form, `figures` chooses them so and `phase`
//!   lists phase portraits, each a pair `[x, y]` of state or output names (one
//!   component, not a vector), drawn as `phase_<x>_<y>.png` for any model; a name's
//!   error points at its pair (a flow list is not looked into, see [`locate`]).
//!   `--phase X,Y` (repeatable) adds one; `--no-plots` draws none. A sweep draws
//!   no phase portraits.
//! - **`sweep`** runs every combination of the values of one or two parameters (the
//!   runs spread over the cores), and writes `sweep.csv`: the parameters' values and,
//!   for each of `peaks`, `peak_<name>`, the largest magnitude (Euclidean norm of its
//!   components) over the window; plus one chart per peak (unless `plots: none`). A
//!   sweep writes no per-run results. A swept parameter cannot also be set (in
//!   `parameters` or by `--set`): that value would be ignored, so it is an error.
//!
//! - **`monte_carlo`** runs `samples` runs with the listed parameters drawn (sample
//!   `i` from its own random stream, fixed by `seed` and `i`:
//!   [`study::distribution`](crate::study::distribution)), the others as set, and
//!   writes `samples.csv` (`index`, the drawn values, then for each banded column
//!   `peak_<c>` (the largest magnitude over the span) and `final_<c>` (the value at
//!   the end)), `trajectories.csv` (`index`, `t`, the banded columns: every sample at
//!   every time), `bands.csv` (`t`, then for each banded column its 5, 25, 50, 75 and
//!   95 % quantiles over the samples, type 7: [`study::bands`](crate::study::bands))
//!   and one band chart per column. The banded columns are those `output.record`
//!   names, by default the model's outputs. A drawn parameter cannot also be set or
//!   swept; every sample's parameters are checked physically before anything runs.
//!   `run --shard K/N` (sweeps too) runs only the K-th of N blocks of samples (or sweep
//!   points) into a shard folder, and `merge` joins the N folders into the files of the
//!   one-process run, bit for bit (see `docs/shards.md`).
//!
//! Command-line flags override the file: `--set NAME=VALUE` a parameter, `--solver`,
//! `--rtol`, `--atol`, `--step`, `--max-steps`, `--t-start`, `--t-end`, `--interval`
//! (replacing `interval` or `count`), and `--no-plots` (`plots: none`); each is checked
//! as its key is. Without `--out`,
//! the results go to `out/<file name>`, with the command line's overrides added to the
//! name ([`provenance::folder`](crate::provenance::folder)).
//!
//! # Errors
//!
//! Everything is checked before anything is written, and every error found is reported
//! in one go, one per line as `file:line:column: message`, sorted by line and column
//! (then the flags' errors): a syntax error (which stops the reading), every unknown key
//! (with the valid ones listed) and every value of the wrong type (the entry is then
//! left out and the rest still checked), unknown parameter, state, output or figure
//! names (with the valid ones), numbers too large for an `f64` (`1e400` overflows), and
//! values out of range, each independently of the others (a NaN does not hide a
//! negative mass). Errors are placed at their key by [`locate`] (see its limits).

mod diagnostic;
pub mod locate;
mod phase;
mod resolve;
mod schema;
mod solver;
mod study;
mod sweep;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde_yaml::Value;

pub use diagnostic::{yaml_message, Diagnostic, Diagnostics, Origin, Source};
pub use resolve::{resolve, Job, Overrides, Plan};

/// A scenario file as written (see the [module documentation](self)).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The model's name in the catalogue.
    pub model: String,
    /// What the scenario is; the title of `index.html`.
    #[serde(default)]
    pub description: Option<String>,
    /// Parameter values by name (kept in the file's order); empty (`parameters:` with
    /// nothing under it) is the same as absent.
    #[serde(default)]
    pub parameters: Option<serde_yaml::Mapping>,
    /// Initial conditions by state name.
    #[serde(default)]
    pub initial: Option<serde_yaml::Mapping>,
    /// The time span.
    #[serde(default)]
    pub time: Option<TimeSpec>,
    /// The solver and its settings.
    #[serde(default)]
    pub solver: Option<SolverSpec>,
    /// Sampling and recording.
    #[serde(default)]
    pub output: Option<OutputSpec>,
    /// `all`, `none`, or a list of figure ids.
    #[serde(default)]
    pub plots: Option<Value>,
    /// A sweep over one or two parameters.
    #[serde(default)]
    pub sweep: Option<SweepSpec>,
    /// A Monte Carlo study.
    #[serde(default)]
    pub monte_carlo: Option<MonteCarloSpec>,
    /// What was wrong with the file's shape (unknown keys, wrong types), found while
    /// reading it; the entries at fault were left out. [`resolve`] reports these with
    /// its own.
    #[serde(skip)]
    pub read_errors: Diagnostics,
}

/// `time:` of a scenario.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// The start, s (default 0).
    pub start: Option<f64>,
    /// The end, s (default: the model's).
    pub end: Option<f64>,
}

/// `solver:` of a scenario.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// The method's name.
    pub method: Option<String>,
    /// Relative tolerance (adaptive methods).
    pub rtol: Option<f64>,
    /// Absolute tolerance (adaptive methods): one number, or per state.
    pub atol: Option<AtolSpec>,
    /// States held at or above zero (adaptive methods), by name.
    pub non_negative: Option<Vec<String>>,
    /// The step, s (fixed-step methods).
    pub step: Option<f64>,
    /// The largest step, s (adaptive methods).
    pub max_step: Option<f64>,
    /// The step budget.
    pub max_steps: Option<usize>,
    /// The wall-time limit, s (stiff methods).
    pub max_wall_time: Option<f64>,
}

/// `solver.atol` of a scenario: one number for every state, or a mapping of state names
/// to numbers, with an optional `default` for the states it does not name.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum AtolSpec {
    /// The same absolute tolerance for every state.
    All(f64),
    /// By state name (`default`: the others'; else the method's atol).
    PerState(serde_yaml::Mapping),
}

/// `output:` of a scenario.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Seconds between samples.
    pub interval: Option<f64>,
    /// Number of samples, both ends included.
    pub count: Option<usize>,
    /// States and outputs to record.
    pub record: Option<Vec<String>>,
}

/// `sweep:` of a scenario.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// The swept parameters (one or two).
    pub parameters: Vec<AxisSpec>,
    /// The outputs whose peaks are reported.
    pub peaks: Vec<String>,
    /// The window of each run the peaks are taken over.
    #[serde(default)]
    pub window: Option<WindowSpec>,
}

/// One swept parameter.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisSpec {
    /// The parameter's name.
    pub name: String,
    /// Its values, or:
    pub values: Option<Vec<f64>>,
    /// the first value,
    pub from: Option<f64>,
    /// the last value,
    pub to: Option<f64>,
    /// and the number of values, evenly spaced.
    pub steps: Option<usize>,
}

/// `monte_carlo:` of a scenario.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MonteCarloSpec {
    /// The number of samples (runs).
    pub samples: usize,
    /// The seed of every sample's random stream.
    pub seed: u64,
    /// Each drawn parameter's distribution, by name (checked by the resolver).
    pub parameters: serde_yaml::Mapping,
}

/// `sweep.window:`.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindowSpec {
    /// Start, s (default: the middle of the time span).
    pub from: Option<f64>,
    /// End, s (default: the end of the time span).
    pub to: Option<f64>,
}

/// A scenario file, read and parsed, with its text kept for pointing at errors.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The file's text and path.
    pub source: Source,
    /// What it says.
    pub scenario: Scenario,
}

/// Reads and parses the scenario file at `path`.
///
/// # Errors
///
/// The file cannot be read or is not YAML (one [`Diagnostic`]), or its `model` is
/// missing or unusable (with every other shape error of the file). Other shape errors
/// (unknown keys, wrong types) do not stop the reading: they are kept in
/// [`Scenario::read_errors`] for [`resolve`] to report with its own.
pub fn load(path: &Path) -> Result<Loaded, Diagnostics> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        let mut d = Diagnostics::default();
        d.push(
            Origin::File {
                path: path.to_path_buf(),
                position: None,
            },
            format!("cannot read the scenario file: {e}"),
        );
        d
    })?;
    parse(path.to_path_buf(), text)
}

/// Parses `text` as the scenario file `path`.
///
/// # Errors
///
/// As [`load`].
pub fn parse(path: PathBuf, text: String) -> Result<Loaded, Diagnostics> {
    let source = Source { path, text };
    let mut d = Diagnostics::default();
    let mut value = match serde_yaml::from_str::<Value>(&source.text) {
        Ok(value) => value,
        Err(e) => {
            d.push(source.at_error(&e), yaml_message(&e));
            return Err(d);
        }
    };
    if !schema::check(&mut value, &source, &mut d) {
        d.sort();
        return Err(d);
    }
    match serde_yaml::from_value::<Scenario>(value) {
        Ok(mut scenario) => {
            scenario.read_errors = d;
            Ok(Loaded { source, scenario })
        }
        Err(e) => {
            d.push(source.at_error(&e), yaml_message(&e));
            d.sort();
            Err(d)
        }
    }
}

/// The figure ids of a plots list, by the position where each occurs (for messages).
pub(crate) fn plot_names(value: &Value) -> Option<BTreeMap<usize, String>> {
    match value {
        Value::Sequence(items) => items
            .iter()
            .enumerate()
            .map(|(i, v)| v.as_str().map(|s| (i, s.to_owned())))
            .collect(),
        _ => None,
    }
}
