//! `models fit`: least-squares estimation of parameters from measured signals (a CSV
//! whose first column is the time and whose others are named like the model's
//! outputs), with a noise variance per column (given with `--sigma`, else estimated),
//! bounds, 95 % intervals and correlations (`fit.json`, `fit.yaml`, `fitted.csv`,
//! `fitted.yaml`, figures, `index.html`, `run.yaml`).
//!
//! Everything given is checked before any work (the parameters' names and bounds, the
//! data file's shape, its columns against the model's outputs, the σ given), and a
//! failure leaves the output folder as it was.

use std::path::PathBuf;

use bgdsl_analysis::fit::{FitOptions, Measurements};
use clap::Args;

use super::{execute, names, plan, ModelArgs};
use crate::catalog::analysis::fit::{results_set, FitBound, FitInput};
use crate::catalog::{Catalogue, Entry};
use crate::cli::Failure;

/// The arguments of `models fit`.
#[derive(Clone, Debug, Args)]
pub struct FitArgs {
    /// The model and its settings: the parameters are the fit's starting values; the
    /// runs start at the first measured time from the initial state.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The measurements: a CSV file whose header names the time (`t` or `time`, first)
    /// and then outputs of the model; an empty cell or `nan` is a sample not measured.
    #[arg(long, value_name = "FILE.csv")]
    pub data: PathBuf,
    /// The parameters to fit, e.g. `--fit resistance,rotor_friction` (repeatable; a
    /// list parameter's component as `l1[0]`).
    #[arg(long, value_name = "P1,P2")]
    pub fit: Vec<String>,
    /// Bounds of a fitted parameter, e.g. `--bound resistance=0:10`; an empty side is
    /// unbounded (`--bound k=0:`) (repeatable) [default: none].
    #[arg(long, value_name = "P=LO:HI", allow_hyphen_values = true)]
    pub bound: Vec<String>,
    /// Fit only these columns of the data (comma-separated, repeatable) [default: all].
    #[arg(long, value_name = "C1,C2")]
    pub columns: Vec<String>,
    /// A column's known noise standard deviation, in the column's unit, e.g. `--sigma
    /// current=0.05` (comma-separated, repeatable): the column is weighted by 1/σ² as
    /// given and the residuals are checked against it (χ²) [default: each column's σ
    /// estimated from its residuals].
    #[arg(long, value_name = "C=SIGMA")]
    pub sigma: Vec<String>,
    /// Levenberg–Marquardt iterations allowed.
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub max_iterations: usize,
    /// Converged when a step changes the cost, or every parameter, by less than this
    /// fraction.
    #[arg(long, value_name = "X", default_value_t = 1e-8)]
    pub tolerance: f64,
}

impl Default for FitArgs {
    /// The command line's defaults (and no data file).
    fn default() -> Self {
        let options = FitOptions::default();
        FitArgs {
            model: ModelArgs::default(),
            data: PathBuf::new(),
            fit: Vec::new(),
            bound: Vec::new(),
            columns: Vec::new(),
            sigma: Vec::new(),
            max_iterations: options.max_iterations,
            tolerance: options.tolerance,
        }
    }
}

/// The parameters to fit, each checked against the model: a scalar by its name, a
/// list's component as `name[k]`; no name twice.
fn parameters(entry: &Entry, fit: &[String]) -> Result<Vec<FitBound>, Failure> {
    let asked = names(fit);
    if asked.is_empty() {
        return Err(Failure::Usage(
            "fit needs the parameters to fit: give --fit P1,P2 (see `models params MODEL`)"
                .to_owned(),
        ));
    }
    let infos = entry.model.parameters();
    let mut bounds: Vec<FitBound> = Vec::new();
    for name in asked {
        let (base, component) = match name.strip_suffix(']').and_then(|s| s.split_once('[')) {
            Some((base, k)) => (base, Some(k.trim())),
            None => (name.as_str(), None),
        };
        let Some(info) = infos.iter().find(|p| p.name == base) else {
            let known: Vec<&str> = infos.iter().map(|p| p.name).collect();
            return Err(Failure::Usage(format!(
                "--fit {name}: the model {} has no parameter `{base}`; its parameters: {}",
                entry.name,
                known.join(", ")
            )));
        };
        match component {
            None if info.len != 1 => {
                let parts: Vec<String> = (0..info.len).map(|k| format!("{base}[{k}]")).collect();
                return Err(Failure::Usage(format!(
                    "--fit {name}: `{base}` is a list of {} numbers, not one: fit its \
                     components, e.g. {}",
                    info.len,
                    parts.join(",")
                )));
            }
            Some(k) if k.parse::<usize>().map_or(true, |k| k >= info.len) => {
                return Err(Failure::Usage(format!(
                    "--fit {name}: `{base}` has {} component(s), numbered from 0",
                    info.len
                )));
            }
            _ => {}
        }
        if bounds.iter().any(|b| b.name == name) {
            return Err(Failure::Usage(format!("--fit {name}: given twice")));
        }
        bounds.push(FitBound {
            name,
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
        });
    }
    Ok(bounds)
}

/// Applies `--bound P=LO:HI` flags to the fitted parameters.
fn apply_bounds(bounds: &mut [FitBound], flags: &[String]) -> Result<(), Failure> {
    for flag in flags {
        let usage = |why: &str| Failure::Usage(format!("--bound {flag}: {why}"));
        let (name, range) = flag
            .split_once('=')
            .ok_or_else(|| usage("give P=LO:HI, e.g. resistance=0:10"))?;
        let (lo, hi) = range
            .split_once(':')
            .ok_or_else(|| usage("give the range as LO:HI, e.g. 0:10, or 0: for no upper bound"))?;
        let side = |text: &str, none: f64| -> Result<f64, Failure> {
            let text = text.trim();
            if text.is_empty() {
                return Ok(none);
            }
            text.parse::<f64>()
                .ok()
                .filter(|v| !v.is_nan())
                .ok_or_else(|| usage(&format!("`{text}` is not a number")))
        };
        let (lower, upper) = (side(lo, f64::NEG_INFINITY)?, side(hi, f64::INFINITY)?);
        if lower > upper {
            return Err(usage(&format!("the range [{lower}, {upper}] is empty")));
        }
        let bound = bounds
            .iter_mut()
            .find(|b| b.name == name.trim())
            .ok_or_else(|| {
                usage(&format!(
                    "`{}` is not fitted (add it to --fit)",
                    name.trim()
                ))
            })?;
        bound.lower = lower;
        bound.upper = upper;
    }
    Ok(())
}

/// The measurements from `--data`, restricted to `--columns`, each column an output
/// of the model with at least one measured value, every value finite or empty.
fn measurements(args: &FitArgs, entry: &Entry) -> Result<Measurements, Failure> {
    let file = args.data.display();
    if args.data.as_os_str().is_empty() {
        return Err(Failure::Usage(
            "fit needs the measurements: give --data FILE.csv".to_owned(),
        ));
    }
    let text = std::fs::read_to_string(&args.data)
        .map_err(|e| Failure::Usage(format!("--data {file}: cannot read it: {e}")))?;
    let mut data = Measurements::parse_csv(&text)
        .map_err(|e| Failure::Usage(format!("--data {file}: {e}")))?;
    let chosen = names(&args.columns);
    if !chosen.is_empty() {
        let mut names = Vec::new();
        let mut values = Vec::new();
        for name in chosen {
            let Some(c) = data.names.iter().position(|n| *n == name) else {
                return Err(Failure::Usage(format!(
                    "--columns: the data have no column `{name}`; its columns: {}",
                    data.names.join(", ")
                )));
            };
            names.push(name);
            values.push(data.values[c].clone());
        }
        data.sigma = vec![None; names.len()];
        data.names = names;
        data.values = values;
    }
    let outputs = entry.model.output_names();
    for (name, column) in data.names.iter().zip(&data.values) {
        if !outputs.contains(&name.as_str()) {
            let state = if entry.model.state_names().contains(&name.as_str()) {
                " (it is a state; the fit compares outputs: measure an output, or add one \
                 equal to the state)"
            } else {
                ""
            };
            return Err(Failure::Usage(format!(
                "--data {file}: the column `{name}` is not an output of the model {}{state}; \
                 its outputs: {} (or choose columns with --columns)",
                entry.name,
                outputs.join(", ")
            )));
        }
        if let Some(k) = column.iter().position(|v| v.is_infinite()) {
            return Err(Failure::Usage(format!(
                "--data {file}: `{name}` at t = {} s is {}, not a finite number",
                data.times[k], column[k]
            )));
        }
        if !column.iter().any(|v| v.is_finite()) {
            return Err(Failure::Usage(format!(
                "--data {file}: the column `{name}` has no measured value"
            )));
        }
    }
    apply_sigma(&mut data, &args.sigma)?;
    Ok(data)
}

/// Applies `--sigma C=SIGMA` flags to the measured columns.
fn apply_sigma(data: &mut Measurements, flags: &[String]) -> Result<(), Failure> {
    for flag in names(flags) {
        let usage = |why: &str| Failure::Usage(format!("--sigma {flag}: {why}"));
        let (name, value) = flag
            .split_once('=')
            .ok_or_else(|| usage("give C=SIGMA, e.g. current=0.05"))?;
        let name = name.trim();
        let Some(c) = data.names.iter().position(|n| n == name) else {
            return Err(usage(&format!(
                "the data fitted have no column `{name}`; its columns: {}",
                data.names.join(", ")
            )));
        };
        if data.sigma_of(c).is_some() {
            return Err(usage(&format!("`{name}` is given twice")));
        }
        let sigma = value
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|s| s.is_finite() && *s > 0.0)
            .ok_or_else(|| {
                usage(&format!(
                    "`{}` is not a positive number (the noise's standard deviation, in \
                     the column's unit)",
                    value.trim()
                ))
            })?;
        data.set_sigma(name, sigma)
            .map_err(|e| usage(&e.to_string()))?;
    }
    Ok(())
}

/// `models fit ...`.
pub(crate) fn fit(args: &FitArgs, catalogue: &'static Catalogue) -> Result<(), Failure> {
    let fitted = names(&args.fit);
    let options = vec![("fit".to_owned(), fitted.join("+"))];
    let (entry, plan) = plan(&args.model, catalogue, "fit", &options)?;
    let mut bounds = parameters(entry, &args.fit)?;
    apply_bounds(&mut bounds, &args.bound)?;
    let data = measurements(args, entry)?;
    if !(args.tolerance.is_finite() && args.tolerance > 0.0) {
        return Err(Failure::Usage(format!(
            "--tolerance {}: give a positive number (e.g. 1e-8)",
            args.tolerance
        )));
    }
    let mut options = FitOptions {
        max_iterations: args.max_iterations,
        tolerance: args.tolerance,
        ..FitOptions::default()
    };
    if args.model.solver.is_some() || args.model.rtol.is_some() || args.model.atol.is_some() {
        options.sensitivity.solver = plan.solver;
    }
    let data_file = args.data.display().to_string();
    execute(entry, &plan, || {
        let found = entry.model.fit(&plan, &data, &bounds, &options)?;
        let input = FitInput {
            data_file: &data_file,
            data: &data,
            bounds: &bounds,
        };
        Ok(results_set(entry, &plan, &input, &found))
    })
}
