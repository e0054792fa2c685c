//! `models fit`, the model's side: the least-squares fit of parameter values of the
//! model behind an [`Entry`](crate::catalog::Entry) to measurements, with the model's
//! values at the measured times before and after.

use bgdsl_analysis::fit::{fit, FitError, FitOptions, FitParameter, FitReport, Measurements};
use bgdsl_analysis::sensitivity::parameter_index;
use bgdsl_runtime::{FromParams, Model, Simulation, Solver};
use serde::de::DeserializeOwned;

use crate::catalog::{initial_state, params_from, RunPlan};

/// A parameter value to fit, by name (`resistance`, `l1[0]`), with its bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct FitBound {
    /// Its name, a vector's component as `name[i]`.
    pub name: String,
    /// The lowest value allowed (`-inf` for none).
    pub lower: f64,
    /// The highest value allowed (`inf` for none).
    pub upper: f64,
}

/// What a fit found, without the model's type.
#[derive(Clone, Debug)]
pub struct FitFound {
    /// The estimates, their uncertainty, the iterations.
    pub report: FitReport,
    /// Per measured column (in the data's order), the model's value at every measured
    /// time with the starting parameter values.
    pub before: Vec<Vec<f64>>,
    /// The same with the estimates.
    pub after: Vec<Vec<f64>>,
    /// A fine time grid over the measured span (for the fitted curves).
    pub curve_times: Vec<f64>,
    /// Per measured column, the fitted model on `curve_times`.
    pub curve: Vec<Vec<f64>>,
}

/// Samples of the fitted curves drawn over the measured span.
const CURVE_POINTS: usize = 600;

/// Why a fit failed.
#[derive(Debug)]
pub enum FitFailure {
    /// The plan's parameters do not fit the model (a bug: plans are validated).
    Params(String),
    /// A name of `--fit` is no parameter value of the model.
    UnknownParameter(String),
    /// The fit, or a run of the model, failed.
    Fit(FitError),
}

impl core::fmt::Display for FitFailure {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FitFailure::Params(m) => write!(f, "invalid parameters: {m}"),
            FitFailure::UnknownParameter(name) => {
                write!(f, "`{name}` is not a parameter value of the model")
            }
            FitFailure::Fit(e) => write!(f, "the fit failed: {e}"),
        }
    }
}

impl std::error::Error for FitFailure {}

/// Fits `parameters` of `M`, starting from `plan`'s parameter values, to `data` (whose
/// columns name outputs of `M`); the runs start at the first measured time from the
/// declared initial state (recomputed for every trial: it may depend on the fitted
/// parameters) or, when the plan replaces initial values, from the plan's initial state.
///
/// # Errors
///
/// [`FitFailure`].
pub fn fit_of<M>(
    plan: &RunPlan,
    data: &Measurements,
    parameters: &[FitBound],
    options: &FitOptions,
) -> Result<FitFound, FitFailure>
where
    M: FromParams + Clone,
    M::Params: DeserializeOwned,
{
    let params =
        params_from::<M::Params>(&plan.params).map_err(|e| FitFailure::Params(e.to_string()))?;
    let model = M::from_params(params);
    let fixed_start = (!plan.initial.is_empty()).then(|| initial_state(&model, &plan.initial));
    let mut asked = Vec::with_capacity(parameters.len());
    for bound in parameters {
        let index = parameter_index::<M>(&bound.name)
            .ok_or_else(|| FitFailure::UnknownParameter(bound.name.clone()))?;
        asked.push(FitParameter {
            index,
            lower: bound.lower,
            upper: bound.upper,
        });
    }
    let (report, fitted) = fit(&model, fixed_start.as_deref(), data, &asked, options)
        .map_err(FitFailure::Fit)?;
    let outputs: Vec<usize> = data
        .names
        .iter()
        .map(|n| M::OUTPUT_NAMES.iter().position(|o| o == n).unwrap_or(0))
        .collect();
    let solver = options.sensitivity.solver;
    let run = |m: &M, times: &[f64]| {
        let x0 = fixed_start.clone().unwrap_or_else(|| initial_state(m, &[]));
        sample_outputs(m, solver, &x0, times, &outputs).map_err(FitFailure::Fit)
    };
    let before = run(&model, &data.times)?;
    let after = run(&fitted, &data.times)?;
    let (t0, t1) = (data.times[0], data.times[data.times.len() - 1]);
    let curve_times: Vec<f64> = (0..=CURVE_POINTS)
        .map(|k| t0 + (t1 - t0) * k as f64 / CURVE_POINTS as f64)
        .collect();
    let curve = run(&fitted, &curve_times)?;
    Ok(FitFound {
        report,
        before,
        after,
        curve_times,
        curve,
    })
}

/// `outputs` of `model` run from `x0` at `times[0]`, one list per output.
fn sample_outputs<M: Model>(
    model: &M,
    solver: Solver,
    x0: &[f64],
    times: &[f64],
    outputs: &[usize],
) -> Result<Vec<Vec<f64>>, FitError> {
    let mut columns = vec![Vec::with_capacity(times.len()); outputs.len()];
    let mut sim = Simulation::new(model, solver)?;
    sim.run(
        times[0],
        x0,
        times,
        &mut |_t: f64, _x: &[f64], y: &[f64]| {
            for (column, &o) in columns.iter_mut().zip(outputs) {
                column.push(y[o]);
            }
        },
    )?;
    Ok(columns)
}

/// The fit's cost as the library minimises it: over every measured column, the sum of
/// `((model − measured) / s)²`, `s` the column's root mean square (measured samples
/// only; empty cells are left out).
pub fn cost(data: &Measurements, model: &[Vec<f64>]) -> f64 {
    let mut total = 0.0;
    for (measured, modelled) in data.values.iter().zip(model) {
        let finite: Vec<f64> = measured.iter().copied().filter(|v| v.is_finite()).collect();
        let rms = (finite.iter().map(|v| v * v).sum::<f64>() / finite.len().max(1) as f64).sqrt();
        let scale = if rms > 0.0 { rms } else { 1.0 };
        total += measured
            .iter()
            .zip(modelled)
            .filter(|(m, _)| m.is_finite())
            .map(|(m, y)| ((y - m) / scale).powi(2))
            .sum::<f64>();
    }
    total
}

/// `fit.json` and `fit.yaml`: what the fit found.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FitSummary {
    /// The model's catalogue name.
    pub model: String,
    /// The fitted parameters.
    pub parameters: Vec<ParameterSummary>,
    /// The fitted parameters' names, the rows and columns of `correlation`.
    pub correlation_names: Vec<String>,
    /// The correlation matrix of the estimates, as rows.
    pub correlation: Vec<Vec<f64>>,
    /// The cost ([`cost`]) with the starting values.
    pub cost_before: f64,
    /// The cost with the estimates.
    pub cost_after: f64,
    /// The residuals' root mean square per measured column, in its unit.
    pub residual_rms: Vec<ColumnRms>,
    /// Measured samples used.
    pub residuals: usize,
    /// Residuals less parameters.
    pub degrees_of_freedom: usize,
    /// The Student quantile `t(0.975, dof)` of the intervals.
    pub t_quantile: f64,
    /// Levenberg–Marquardt iterations done.
    pub iterations: usize,
    /// Whether the convergence test was met.
    pub converged: bool,
    /// Why the iteration stopped.
    pub stopping_reason: String,
    /// Whether `∂f/∂p` was exact (dual numbers) or central differences.
    pub exact_parameter_derivatives: bool,
}

/// One parameter of [`FitSummary`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct ParameterSummary {
    /// Its name.
    pub name: String,
    /// Its declared unit.
    pub unit: String,
    /// The starting value.
    pub initial: f64,
    /// The estimate.
    pub estimate: f64,
    /// Its standard error.
    pub standard_error: f64,
    /// The 95 % confidence interval `[low, high]`.
    pub interval_95: [f64; 2],
    /// The bounds it was held in.
    pub bounds: [f64; 2],
    /// Whether the estimate lies on a bound (its interval then ignores the bound).
    pub at_bound: bool,
}

/// One column of [`FitSummary::residual_rms`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct ColumnRms {
    /// The measured column.
    pub column: String,
    /// The residuals' root mean square, in the column's unit.
    pub rms: f64,
}

impl FitSummary {
    /// The summary of `found` for model `model`, fitted to `data` within `bounds`.
    pub fn new(model: &str, data: &Measurements, bounds: &[FitBound], found: &FitFound) -> Self {
        let report = &found.report;
        let n = report.parameters.len();
        let stopping_reason = if report.converged {
            "converged: a step changed the cost, or every parameter, by less than the \
             tolerance (or no step lowered the cost)"
                .to_owned()
        } else {
            format!(
                "not converged: the iteration limit ({}) was reached",
                report.iterations
            )
        };
        FitSummary {
            model: model.to_owned(),
            parameters: report
                .parameters
                .iter()
                .zip(bounds)
                .map(|(p, b)| ParameterSummary {
                    name: p.name.clone(),
                    unit: p.unit.to_owned(),
                    initial: p.initial,
                    estimate: p.value,
                    standard_error: p.standard_error,
                    interval_95: [p.interval.0, p.interval.1],
                    bounds: [b.lower, b.upper],
                    at_bound: p.at_bound,
                })
                .collect(),
            correlation_names: report.parameters.iter().map(|p| p.name.clone()).collect(),
            correlation: (0..n)
                .map(|i| (0..n).map(|j| report.correlation[(i, j)]).collect())
                .collect(),
            cost_before: cost(data, &found.before),
            cost_after: cost(data, &found.after),
            residual_rms: report
                .residual_rms
                .iter()
                .map(|(column, rms)| ColumnRms {
                    column: column.clone(),
                    rms: *rms,
                })
                .collect(),
            residuals: report.n_residuals,
            degrees_of_freedom: report.degrees_of_freedom,
            t_quantile: report.t_quantile,
            iterations: report.iterations,
            converged: report.converged,
            stopping_reason,
            exact_parameter_derivatives: report.exact_parameter_derivatives,
        }
    }
}

/// The text of `fitted.csv`: `t`, then per measured column `<c>_measured`, `<c>_model`
/// (the fitted model) and `<c>_residual` (measured − model; empty where nothing was
/// measured).
pub fn fitted_csv(data: &Measurements, found: &FitFound) -> Vec<u8> {
    let mut out = String::from("t");
    for name in &data.names {
        out.push_str(&format!(",{name}_measured,{name}_model,{name}_residual"));
    }
    out.push('\n');
    let mut bytes = out.into_bytes();
    let mut writer = bgdsl_runtime::record::RowWriter::new();
    for (k, t) in data.times.iter().enumerate() {
        let mut row = vec![*t];
        for (measured, model) in data.values.iter().zip(&found.after) {
            let (m, y) = (measured[k], model[k]);
            row.extend([m, y, m - y]);
        }
        // Writing to a Vec cannot fail.
        let _ = writer.write_row(&mut bytes, row);
    }
    bytes
}

/// `params` with the estimates of `found` in place of the fitted values (`name` or
/// `name[i]`, as [`FitBound`] names them).
pub fn with_estimates(params: &serde_yaml::Mapping, found: &FitFound) -> serde_yaml::Mapping {
    use serde_yaml::Value;
    let mut params = params.clone();
    for p in &found.report.parameters {
        let (base, component) = match p.name.strip_suffix(']').and_then(|s| s.split_once('[')) {
            Some((base, k)) => (base, k.parse::<usize>().ok()),
            None => (p.name.as_str(), None),
        };
        let value = Value::from(p.value);
        let key = Value::from(base);
        match (component, params.get_mut(&key)) {
            (Some(k), Some(Value::Sequence(items))) if k < items.len() => items[k] = value,
            (None, Some(slot)) => *slot = value,
            _ => {}
        }
    }
    params
}
