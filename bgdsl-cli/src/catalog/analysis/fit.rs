//! `models fit`: least-squares estimation of parameter values of a catalogue model from
//! measured signals ([`bgdsl_analysis::fit`]: Levenberg–Marquardt on exact
//! sensitivities, a noise variance per column, bounds, 95 % intervals), the model's
//! values at the measured times before and after, and its results set (`fit.json`, `fit.yaml`, `fitted.csv`,
//! `fitted.yaml`, figures, `index.html`, `run.yaml`).

use bgdsl_analysis::fit::{
    fit, FitError, FitOptions, FitParameter, FitReport, Measurements, NoiseModel,
};
use bgdsl_analysis::sensitivity::parameter_index;
use bgdsl_runtime::{FromParams, Model, Simulation, Solver};
use serde::de::DeserializeOwned;

use super::{html, with_unit, AnalysisFailure, AnalysisSet, DataFile, Figure};
use crate::catalog::{column_unit, initial_state, params_from, Entry, RunPlan};
use crate::plot::{ChartOptions, LineChart, Series, SeriesStyle};

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

/// A failed fit as the program reports it: what the user gave wrong is a usage error.
fn failure(e: FitError) -> AnalysisFailure {
    match e {
        FitError::Analysis(e) => e.into(),
        e @ (FitError::Data { .. }
        | FitError::UnknownColumn { .. }
        | FitError::TooFewData { .. }
        | FitError::BadParameter { .. }
        | FitError::BadNoise { .. }) => AnalysisFailure::Usage(e.to_string()),
        e => AnalysisFailure::Failed(format!("the fit failed: {e}")),
    }
}

/// Fits `parameters` of `M`, starting from `plan`'s parameter values, to `data` (whose
/// columns name outputs of `M`), with `plan`'s solver; the runs start at the first
/// measured time from the declared initial state (recomputed for every trial: it may
/// depend on the fitted parameters) or, when the plan replaces initial values, from the
/// plan's initial state.
///
/// # Errors
///
/// [`AnalysisFailure`]: an unknown parameter or column (usage), a failed run, a
/// parameter the data do not determine.
pub fn fit_of<M>(
    plan: &RunPlan,
    data: &Measurements,
    parameters: &[FitBound],
    options: &FitOptions,
) -> Result<FitFound, AnalysisFailure>
where
    M: FromParams + Clone,
    M::Params: DeserializeOwned,
{
    let model = M::from_params(params_from::<M::Params>(&plan.params)?);
    let fixed_start = (!plan.initial.is_empty()).then(|| initial_state(&model, &plan.initial));
    let mut asked = Vec::with_capacity(parameters.len());
    for bound in parameters {
        let index = parameter_index::<M>(&bound.name).ok_or_else(|| {
            AnalysisFailure::Usage(format!(
                "`{}` is not a parameter value of the model",
                bound.name
            ))
        })?;
        asked.push(FitParameter {
            index,
            lower: bound.lower,
            upper: bound.upper,
        });
    }
    let (report, fitted) =
        fit(&model, fixed_start.as_deref(), data, &asked, options).map_err(failure)?;
    let outputs: Vec<usize> = data
        .names
        .iter()
        .map(|n| M::OUTPUT_NAMES.iter().position(|o| o == n).unwrap_or(0))
        .collect();
    let solver = options.sensitivity.solver;
    let run = |m: &M, times: &[f64]| {
        let x0 = fixed_start.clone().unwrap_or_else(|| initial_state(m, &[]));
        sample_outputs(m, solver, &x0, times, &outputs).map_err(failure)
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
/// `((model − measured) / σ)²`, `σ` the column's noise standard deviation (`sigma`, as
/// the fit used it; measured samples only, empty cells left out).
pub fn cost(data: &Measurements, model: &[Vec<f64>], sigma: &[f64]) -> f64 {
    let mut total = 0.0;
    for ((measured, modelled), s) in data.values.iter().zip(model).zip(sigma) {
        total += measured
            .iter()
            .zip(modelled)
            .filter(|(m, _)| m.is_finite())
            .map(|(m, y)| ((y - m) / s).powi(2))
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
    /// The cost ([`cost`], with the final σ) with the starting values.
    pub cost_before: f64,
    /// The cost with the estimates.
    pub cost_after: f64,
    /// How the noise was modelled: `per column` (the default) or `pooled`.
    pub noise: String,
    /// Each measured column: its noise σ (given or estimated), weight, residual RMS.
    pub columns: Vec<ColumnSummary>,
    /// The residuals against the σ given (when some are given).
    pub chi_square: Option<ChiSquareSummary>,
    /// The residuals' root mean square per measured column, in its unit (also in
    /// `columns`).
    pub residual_rms: Vec<ColumnRms>,
    /// Measured samples used.
    pub residuals: usize,
    /// Residuals less parameters.
    pub degrees_of_freedom: usize,
    /// Refits with new weights after the first fit (estimating the columns' σ).
    pub reweightings: usize,
    /// Whether the estimated σ settled.
    pub weights_settled: bool,
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
    /// The effective degrees of freedom of its variance (Welch–Satterthwaite over the
    /// columns whose σ is estimated; `null`, infinite, when every σ is given).
    pub degrees_of_freedom: Option<f64>,
    /// The Student quantile `t(0.975, degrees_of_freedom)` of its interval.
    pub t_quantile: f64,
    /// The 95 % confidence interval `[low, high]`.
    pub interval_95: [f64; 2],
    /// The bounds it was held in.
    pub bounds: [f64; 2],
    /// Whether the estimate lies on a bound (its interval then ignores the bound).
    pub at_bound: bool,
}

/// One column of [`FitSummary::columns`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct ColumnSummary {
    /// The measured column.
    pub column: String,
    /// Its unit.
    pub unit: String,
    /// Its measured samples.
    pub samples: usize,
    /// The noise's standard deviation the fit used, in the column's unit.
    pub sigma: f64,
    /// Whether `sigma` was given (`--sigma`), else estimated from the residuals.
    pub sigma_given: bool,
    /// The residuals' weight `1/σ²`.
    pub weight: f64,
    /// The residuals' root mean square, in the column's unit.
    pub rms: f64,
    /// The column's share of the residual degrees of freedom.
    pub degrees_of_freedom: f64,
    /// Its residual sum of squares over `σ²` and its degrees of freedom (1 when σ is
    /// estimated; about 1 when the σ given is right).
    pub reduced_chi_square: f64,
}

/// [`FitSummary::chi_square`]: the residuals of the columns whose σ was given.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ChiSquareSummary {
    /// `Σ RSSₖ/σₖ²` over those columns.
    pub chi_square: f64,
    /// Its degrees of freedom.
    pub degrees_of_freedom: f64,
    /// χ² over its degrees of freedom.
    pub reduced: f64,
    /// The probability of a χ² at least this large if the σ given are right.
    pub p_value: f64,
    /// What it says: `consistent`, or the residuals `larger` or `smaller` than the σ
    /// given (p below 0.01 or above 0.99).
    pub verdict: String,
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
    pub fn new(entry: &Entry, data: &Measurements, bounds: &[FitBound], found: &FitFound) -> Self {
        let report = &found.report;
        let sigma: Vec<f64> = report.columns.iter().map(|c| c.sigma).collect();
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
            model: entry.name.clone(),
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
                    degrees_of_freedom: Some(p.degrees_of_freedom).filter(|d| d.is_finite()),
                    t_quantile: p.t_quantile,
                    interval_95: [p.interval.0, p.interval.1],
                    bounds: [b.lower, b.upper],
                    at_bound: p.at_bound,
                })
                .collect(),
            correlation_names: report.parameters.iter().map(|p| p.name.clone()).collect(),
            correlation: (0..n)
                .map(|i| (0..n).map(|j| report.correlation[(i, j)]).collect())
                .collect(),
            cost_before: cost(data, &found.before, &sigma),
            cost_after: cost(data, &found.after, &sigma),
            noise: match report.noise {
                NoiseModel::Pooled => "pooled",
                _ => "per column",
            }
            .to_owned(),
            columns: report
                .columns
                .iter()
                .map(|c| ColumnSummary {
                    column: c.name.clone(),
                    unit: column_unit(&*entry.model, &c.name).0.to_owned(),
                    samples: c.samples,
                    sigma: c.sigma,
                    sigma_given: c.sigma_given,
                    weight: c.weight,
                    rms: c.residual_rms,
                    degrees_of_freedom: c.degrees_of_freedom,
                    reduced_chi_square: c.reduced_chi_square,
                })
                .collect(),
            chi_square: report.chi_square.map(|c| ChiSquareSummary {
                chi_square: c.chi_square,
                degrees_of_freedom: c.degrees_of_freedom,
                reduced: c.reduced,
                p_value: c.p_value,
                verdict: if c.p_value < 0.01 {
                    "larger: the residuals are larger than the σ given (σ too small, or the \
                     model misses something)"
                } else if c.p_value > 0.99 {
                    "smaller: the residuals are smaller than the σ given (σ too large)"
                } else {
                    "consistent: the residuals agree with the σ given"
                }
                .to_owned(),
            }),
            residual_rms: report
                .columns
                .iter()
                .map(|c| ColumnRms {
                    column: c.name.clone(),
                    rms: c.residual_rms,
                })
                .collect(),
            residuals: report.n_residuals,
            degrees_of_freedom: report.degrees_of_freedom,
            reweightings: report.reweightings,
            weights_settled: report.weights_settled,
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

/// The text of `fitted.yaml`: a scenario `models run` accepts, of `entry`'s model with
/// `params` (every parameter; those that differ from the defaults are written, and the
/// fitted ones always), the plan's replaced initial values `initial` (state index,
/// value) and the measured time span.
pub fn fitted_scenario(
    entry: &crate::catalog::Entry,
    params: &serde_yaml::Mapping,
    fitted: &[String],
    initial: &[(usize, f64)],
    span: [f64; 2],
) -> String {
    use serde_yaml::{Mapping, Value};
    let defaults = entry.model.default_parameters();
    let fitted_bases: Vec<&str> = fitted
        .iter()
        .map(|n| n.split_once('[').map_or(n.as_str(), |(b, _)| b))
        .collect();
    let mut written = Mapping::new();
    for (key, value) in params {
        let name = key.as_str().unwrap_or_default();
        if fitted_bases.contains(&name) || defaults.get(key) != Some(value) {
            written.insert(key.clone(), value.clone());
        }
    }
    let mut scenario = Mapping::new();
    scenario.insert("model".into(), entry.name.clone().into());
    scenario.insert(
        "description".into(),
        format!("{} with the parameters fitted by `models fit`", entry.name).into(),
    );
    scenario.insert("parameters".into(), Value::Mapping(written));
    if !initial.is_empty() {
        let names = entry.model.state_names();
        let mut init = Mapping::new();
        for &(i, v) in initial {
            if let Some(name) = names.get(i) {
                init.insert((*name).into(), v.into());
            }
        }
        scenario.insert("initial".into(), Value::Mapping(init));
    }
    let mut time = Mapping::new();
    time.insert("start".into(), span[0].into());
    time.insert("end".into(), span[1].into());
    scenario.insert("time".into(), Value::Mapping(time));
    let body = serde_yaml::to_string(&Value::Mapping(scenario)).unwrap_or_default();
    format!(
        "# Written by `models fit`: the model with the estimates in place of the \
         starting values,\n# over the measured time span. Run it with `models run \
         fitted.yaml`.\n{body}"
    )
}

/// What `models fit` was given, for the results set.
#[derive(Clone, Debug)]
pub struct FitInput<'a> {
    /// The measurements file as given.
    pub data_file: &'a str,
    /// The measurements (the columns used).
    pub data: &'a Measurements,
    /// The fitted parameters with their bounds.
    pub bounds: &'a [FitBound],
}

/// The results set of `models fit`: `fit.json` and `fit.yaml` ([`FitSummary`]),
/// `fitted.csv`, `fitted.yaml` (a scenario with the estimates), one figure per measured
/// column (the measurements, the model at the start and fitted), the summary and the
/// record.
pub fn results_set(
    entry: &Entry,
    plan: &RunPlan,
    input: &FitInput<'_>,
    found: &FitFound,
) -> AnalysisSet {
    let data = input.data;
    let report = &found.report;
    let summary_file = FitSummary::new(entry, data, input.bounds, found);
    let json = serde_json::to_string_pretty(&summary_file).unwrap_or_default() + "\n";
    let yaml = serde_yaml::to_string(&summary_file).unwrap_or_default();
    let fitted_names: Vec<String> = report.parameters.iter().map(|p| p.name.clone()).collect();
    let span = [data.times[0], data.times[data.times.len() - 1]];
    let params = with_estimates(&plan.params, found);
    let files = vec![
        DataFile::new("fit.json", json),
        DataFile::new("fit.yaml", yaml),
        DataFile::new(
            "fitted.csv",
            String::from_utf8(fitted_csv(data, found)).unwrap_or_default(),
        ),
        DataFile::new(
            "fitted.yaml",
            fitted_scenario(entry, &params, &fitted_names, &plan.initial, span),
        ),
    ];

    let mut summary = format!(
        "model          {} ({})\n\
         data           {}: {} samples of {} (t {} … {} s)\n\
         fit            {} in {} iteration(s), {}; cost {} → {}\n",
        entry.name,
        entry.model.type_name(),
        input.data_file,
        data.times.len(),
        data.names.join(", "),
        span[0],
        span[1],
        fitted_names.join(", "),
        report.iterations,
        if report.converged {
            "converged"
        } else {
            "NOT converged (iteration limit)"
        },
        crate::catalog::format_significant(summary_file.cost_before),
        crate::catalog::format_significant(summary_file.cost_after),
    );
    for p in &report.parameters {
        summary.push_str(&format!(
            "{:<14} {} ± {} (95 %: {} … {}), from {}{}\n",
            p.name,
            with_unit(p.value, p.unit),
            crate::catalog::format_significant(p.standard_error),
            crate::catalog::format_significant(p.interval.0),
            crate::catalog::format_significant(p.interval.1),
            crate::catalog::format_significant(p.initial),
            if p.at_bound { ", AT A BOUND" } else { "" }
        ));
    }
    for c in &summary_file.columns {
        summary.push_str(&format!(
            "{:<14} σ {} ({}), residual RMS {}\n",
            c.column,
            with_unit(c.sigma, &c.unit),
            if c.sigma_given { "given" } else { "estimated" },
            with_unit(c.rms, &c.unit),
        ));
    }
    if let Some(chi) = &summary_file.chi_square {
        summary.push_str(&format!(
            "χ² check       χ²/dof = {} ({} dof), p = {}: {}\n",
            crate::catalog::format_significant(chi.reduced),
            crate::catalog::format_significant(chi.degrees_of_freedom),
            crate::catalog::format_significant(chi.p_value),
            chi.verdict
        ));
    }
    let n = report.parameters.len();
    let mut pairs = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            pairs.push(format!(
                "{}–{} {:.3}",
                fitted_names[i],
                fitted_names[j],
                report.correlation[(i, j)]
            ));
        }
    }
    if !pairs.is_empty() {
        summary.push_str(&format!("correlation    {}\n", pairs.join(", ")));
    }
    summary.push_str(
        "files          fit.json, fit.yaml, fitted.csv, fitted.yaml (run it with `run`)\n",
    );

    let figures = data
        .names
        .iter()
        .enumerate()
        .map(|(c, name)| column_figure(entry, data, found, c, name))
        .collect();

    let mut table = String::from(
        "<h2>Estimates</h2><table><tr><th>parameter</th><th>start</th><th>estimate</th>\
         <th>standard error</th><th>95 % interval</th><th>unit</th></tr>",
    );
    for p in &report.parameters {
        table.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} … {}</td><td>{}</td></tr>",
            html(&p.name),
            p.initial,
            p.value,
            p.standard_error,
            p.interval.0,
            p.interval.1,
            html(p.unit)
        ));
    }
    table.push_str(&format!(
        "</table><p>{}. Intervals: ± t(0.975, ν) standard errors (ν, the effective \
         degrees of freedom of each estimate's variance: {}), from the covariance \
         (JᵀWJ)⁻¹ at the estimate, W = diag(1/σ²) with each column's σ below.</p>",
        html(&summary_file.stopping_reason),
        report
            .parameters
            .iter()
            .map(|p| format!(
                "{} {:.1}, t = {:.4}",
                html(&p.name),
                p.degrees_of_freedom,
                p.t_quantile
            ))
            .collect::<Vec<_>>()
            .join("; ")
    ));
    table.push_str(
        "<h2>Noise</h2><table><tr><th>column</th><th>σ</th><th></th><th>weight 1/σ²</th>\
         <th>residual RMS</th><th>samples</th><th>degrees of freedom</th><th>unit</th></tr>",
    );
    for c in &summary_file.columns {
        table.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{:.2}</td><td>{}</td></tr>",
            html(&c.column),
            c.sigma,
            if c.sigma_given { "given" } else { "estimated" },
            c.weight,
            c.rms,
            c.samples,
            c.degrees_of_freedom,
            html(&c.unit)
        ));
    }
    table.push_str("</table>");
    if let Some(chi) = &summary_file.chi_square {
        table.push_str(&format!(
            "<p>χ² against the σ given: {} over {:.1} degrees of freedom (χ²/dof {:.4}), \
             p = {:.4}: {}.</p>",
            chi.chi_square,
            chi.degrees_of_freedom,
            chi.reduced,
            chi.p_value,
            html(&chi.verdict)
        ));
    }

    let mut record = serde_yaml::Mapping::new();
    record.insert("data".into(), input.data_file.into());
    record.insert(
        "columns".into(),
        serde_yaml::to_value(&data.names).unwrap_or_default(),
    );
    let mut sigma = serde_yaml::Mapping::new();
    for c in &summary_file.columns {
        let mut entry = serde_yaml::Mapping::new();
        entry.insert("sigma".into(), c.sigma.into());
        entry.insert("given".into(), c.sigma_given.into());
        sigma.insert(c.column.clone().into(), entry.into());
    }
    record.insert("noise".into(), sigma.into());
    let mut estimates = serde_yaml::Mapping::new();
    for (p, b) in report.parameters.iter().zip(input.bounds) {
        let mut entry = serde_yaml::Mapping::new();
        entry.insert("estimate".into(), p.value.into());
        entry.insert("standard_error".into(), p.standard_error.into());
        entry.insert(
            "bounds".into(),
            serde_yaml::to_value([b.lower, b.upper]).unwrap_or_default(),
        );
        estimates.insert(p.name.clone().into(), entry.into());
    }
    record.insert("parameters".into(), estimates.into());
    record.insert("iterations".into(), report.iterations.into());
    record.insert("converged".into(), report.converged.into());
    record.insert("cost_before".into(), summary_file.cost_before.into());
    record.insert("cost_after".into(), summary_file.cost_after.into());
    AnalysisSet {
        command: "fit",
        summary,
        files,
        figures,
        sections: vec![table],
        record,
    }
}

/// Column `c`'s figure: the measurements (+), the model with the starting values
/// (dashed) and fitted (solid).
fn column_figure(
    entry: &Entry,
    data: &Measurements,
    found: &FitFound,
    c: usize,
    name: &str,
) -> Figure {
    let (unit, _) = column_unit(&*entry.model, name);
    let measured: Vec<(f64, f64)> = data
        .times
        .iter()
        .zip(&data.values[c])
        .filter(|(_, v)| v.is_finite())
        .map(|(t, v)| (*t, *v))
        .collect();
    let (lo, hi) = measured
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(_, v)| {
            (lo.min(v), hi.max(v))
        });
    let dy = 0.012 * (hi - lo).abs().max(1e-300);
    let span = data.times[data.times.len() - 1] - data.times[0];
    let dx = 0.004 * span;
    let mut marks = Vec::with_capacity(measured.len() * 6);
    for &(t, v) in &measured {
        marks.extend([
            (t - dx, v),
            (t + dx, v),
            (f64::NAN, f64::NAN),
            (t, v - dy),
            (t, v + dy),
            (f64::NAN, f64::NAN),
        ]);
    }
    let start: Vec<(f64, f64)> = data
        .times
        .iter()
        .copied()
        .zip(found.before[c].iter().copied())
        .collect();
    let fitted: Vec<(f64, f64)> = found
        .curve_times
        .iter()
        .copied()
        .zip(found.curve[c].iter().copied())
        .collect();
    let y_label = if unit.is_empty() {
        name.to_owned()
    } else {
        format!("{name} ({unit})")
    };
    Figure {
        id: format!("fit_{name}"),
        title: format!("{name}: measured and fitted"),
        caption: format!(
            "{name} as measured (+, {} samples), the model with the starting parameter \
             values (dashed) and with the estimates (solid); the residuals are in \
             fitted.csv.",
            measured.len()
        ),
        chart: LineChart {
            title: format!("{name}: measured and fitted ({})", entry.name),
            x_label: "time t (s)".to_owned(),
            y_label,
            series: vec![
                Series::new("measured", marks),
                Series::new("start", start),
                Series::new("fitted", fitted),
            ],
        },
        options: ChartOptions {
            styles: vec![
                SeriesStyle {
                    color: (90, 90, 90),
                    width: 1,
                    dashed: false,
                },
                SeriesStyle::dashed((31, 119, 180)),
                SeriesStyle::solid((214, 39, 40)),
            ],
            ..ChartOptions::default()
        },
    }
}
