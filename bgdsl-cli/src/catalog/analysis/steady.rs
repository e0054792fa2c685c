//! `models steady`: the equilibrium `f(t, x*, p, u) = 0` of a catalogue model, by
//! Newton's method on the exact Jacobian ([`bgdsl_analysis::equilibrium`]) from the
//! initial state or a guess, inputs held at their values; and its results set
//! (`steady.yaml`, `index.html`, `run.yaml`).

use bgdsl_analysis::{equilibrium, SteadyOptions};
use bgdsl_runtime::{unit_of, FromParams};
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_yaml::{Mapping, Value};

use super::{html, initial, with_unit, AnalysisFailure, AnalysisSet, DataFile, StateAt};
use crate::catalog::{params_from, Entry, RunPlan};

/// The file `models steady` writes its equilibrium into.
pub const FILE_NAME: &str = "steady.yaml";

/// What `models steady` (or an operating point `steady`) asks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SteadyRequest {
    /// States whose starting value replaces the initial state's: (index, value).
    pub guess: Vec<(usize, f64)>,
    /// States held at their starting value (their own rates need not vanish).
    pub held: Vec<usize>,
    /// Newton's settings; its `t` is replaced by the plan's start time.
    pub options: SteadyOptions,
}

/// An equilibrium of a catalogue model, with where the search started.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyResult {
    /// The time at which `f` was evaluated (the plan's start), s.
    pub t: f64,
    /// The starting state.
    pub guess: Vec<f64>,
    /// The equilibrium.
    pub x: Vec<f64>,
    /// `f` there: zero but for round-off, except for held states.
    pub rates: Vec<f64>,
    /// The outputs there.
    pub outputs: Vec<f64>,
    /// The inputs' values (held).
    pub inputs: Vec<f64>,
    /// The largest `|fᵢ|` over the states not held.
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
    /// The held states, by index.
    pub held: Vec<usize>,
}

/// The model of `plan`'s parameters.
pub(crate) fn model<M>(plan: &RunPlan) -> Result<M, AnalysisFailure>
where
    M: FromParams,
    M::Params: DeserializeOwned,
{
    Ok(M::from_params(params_from(&plan.params)?))
}

/// The equilibrium of `model` from the plan's initial state with `request`'s guess.
pub(crate) fn solve<M: bgdsl_runtime::WithInputs>(
    model: &M,
    plan: &RunPlan,
    request: &SteadyRequest,
) -> Result<SteadyResult, AnalysisFailure> {
    let StateAt { t, x: mut guess } = initial(model, plan);
    for &(i, v) in &request.guess {
        guess[i] = v;
    }
    let options = SteadyOptions {
        t,
        ..request.options
    };
    let found = equilibrium(model, &guess, &request.held, options)?;
    let mut outputs = vec![0.0; M::N_OUTPUTS];
    model.outputs(t, &found.x, &mut outputs);
    let mut inputs = vec![0.0; M::INPUTS.len()];
    model.input_values(&mut inputs);
    Ok(SteadyResult {
        t,
        guess,
        x: found.x,
        rates: found.rates,
        outputs,
        inputs,
        residual: found.residual,
        iterations: found.iterations,
        held: request.held.clone(),
    })
}

/// The generic body of [`CatalogModel::steady`](crate::catalog::CatalogModel::steady).
pub(crate) fn steady<M>(
    plan: &RunPlan,
    request: &SteadyRequest,
) -> Result<SteadyResult, AnalysisFailure>
where
    M: FromParams + bgdsl_runtime::WithInputs,
    M::Params: DeserializeOwned,
{
    solve(&model::<M>(plan)?, plan, request)
}

/// One state of `steady.yaml`.
#[derive(Serialize)]
struct StateRow<'a> {
    name: &'a str,
    value: f64,
    unit: &'a str,
    rate: f64,
    guess: f64,
    held: bool,
}

/// One output or input of `steady.yaml`.
#[derive(Serialize)]
struct SignalRow<'a> {
    name: &'a str,
    value: f64,
    unit: &'a str,
}

/// `steady.yaml`.
#[derive(Serialize)]
struct SteadyFile<'a> {
    model: &'a str,
    t: f64,
    iterations: usize,
    /// The largest |dx/dt| over the free states.
    residual: f64,
    jacobian: &'static str,
    states: Vec<StateRow<'a>>,
    outputs: Vec<SignalRow<'a>>,
    inputs: Vec<SignalRow<'a>>,
}

/// How the Jacobian of every equilibrium is computed.
const JACOBIAN: &str = "exact (dual numbers)";

/// The results set of `result` for `entry`'s model.
pub fn results_set(entry: &Entry, result: &SteadyResult) -> AnalysisSet {
    let model = &*entry.model;
    let states = model.state_names();
    let outputs = model.output_names();
    let inputs = model.inputs();
    let file = SteadyFile {
        model: &entry.name,
        t: result.t,
        iterations: result.iterations,
        residual: result.residual,
        jacobian: JACOBIAN,
        states: states
            .iter()
            .enumerate()
            .map(|(i, name)| StateRow {
                name,
                value: result.x[i],
                unit: unit_of(model.states(), i),
                rate: result.rates[i],
                guess: result.guess[i],
                held: result.held.contains(&i),
            })
            .collect(),
        outputs: outputs
            .iter()
            .enumerate()
            .map(|(i, name)| SignalRow {
                name,
                value: result.outputs[i],
                unit: unit_of(model.outputs(), i),
            })
            .collect(),
        inputs: inputs
            .iter()
            .zip(&result.inputs)
            .map(|(info, &value)| SignalRow {
                name: info.name,
                value,
                unit: info.unit,
            })
            .collect(),
    };
    let text = format!(
        "# The equilibrium of {} found by `steady`: dx/dt = 0 (Newton's method).\n{}",
        entry.name,
        serde_yaml::to_string(&file).unwrap_or_default()
    );

    let width = states
        .iter()
        .chain(outputs)
        .map(|n| n.len())
        .max()
        .unwrap_or(0)
        .max(6);
    let mut summary = format!(
        "model          {}: {}\nequilibrium    {} Newton iteration{}, Jacobian {JACOBIAN}, \
         largest rate {:.3e} (t = {} s)\n",
        entry.name,
        entry.description,
        result.iterations,
        if result.iterations == 1 { "" } else { "s" },
        result.residual,
        result.t
    );
    let mut rows = String::new();
    for (i, name) in states.iter().enumerate() {
        let held = if result.held.contains(&i) {
            " (held)"
        } else {
            ""
        };
        let value = with_unit(result.x[i], unit_of(model.states(), i));
        summary.push_str(&format!("state   {name:<width$}  {value}{held}\n"));
        rows.push_str(&format!(
            "<tr><td>state</td><td>{}</td><td>{}</td><td>{:.3e}</td></tr>\n",
            html(name),
            html(&format!("{value}{held}")),
            result.rates[i]
        ));
    }
    for (i, name) in outputs.iter().enumerate() {
        let value = with_unit(result.outputs[i], unit_of(model.outputs(), i));
        summary.push_str(&format!("output  {name:<width$}  {value}\n"));
        rows.push_str(&format!(
            "<tr><td>output</td><td>{}</td><td>{}</td><td></td></tr>\n",
            html(name),
            html(&value)
        ));
    }
    summary.push_str(&format!("results        {FILE_NAME}\n"));
    let section = format!(
        "<h2>Equilibrium</h2>\n<table>\n<tr><th></th><th>name</th><th>value</th>\
         <th>rate dx/dt</th></tr>\n{rows}</table>\n"
    );
    let mut record = Mapping::new();
    record.insert(
        Value::from("guess"),
        Value::Mapping(
            states
                .iter()
                .zip(&result.guess)
                .map(|(n, v)| (Value::from(*n), Value::from(*v)))
                .collect(),
        ),
    );
    record.insert(
        Value::from("held"),
        Value::Sequence(
            result
                .held
                .iter()
                .map(|&i| Value::from(states[i]))
                .collect(),
        ),
    );
    record.insert(
        Value::from("iterations"),
        Value::from(result.iterations as u64),
    );
    record.insert(Value::from("residual"), Value::from(result.residual));
    AnalysisSet {
        command: "steady",
        summary,
        files: vec![DataFile::new(FILE_NAME, text)],
        figures: Vec::new(),
        sections: vec![section],
        record,
    }
}
