//! Parameter estimation: least squares of chosen parameter values to measured signals,
//! by Levenberg–Marquardt on the exact forward sensitivities
//! ([`crate::sensitivity`]).
//!
//! - **Residuals**: for every measured column (named like a model output) and sample,
//!   `(y_model − y_measured) / s`, with `s` the column's root mean square (so columns
//!   in different units weigh alike; one scale per column leaves the estimates of a
//!   one-column fit unchanged).
//! - **Steps**: `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr` (Marquardt's scaling, so parameters of
//!   different magnitudes are treated alike), `λ` divided by 3 after a step that lowers
//!   the cost, multiplied by 4 and retried after one that does not.
//! - **Bounds** by projection: every trial point is clamped into `[lower, upper]`; a
//!   parameter that ends on a bound is reported as such (its interval, from the local
//!   linearisation, then ignores the bound).
//! - **Uncertainty**: covariance `σ² (JᵀJ)⁻¹` at the estimate, `σ²` = the residual sum
//!   of squares over `m − p` degrees of freedom; 95 % intervals `± t(0.975, m − p) ·
//!   standard error`, the Student quantile by the Cornish–Fisher expansion of
//!   Abramowitz & Stegun 26.7.5 (error below 1e-4 for 3 or more degrees of freedom).
//!   The intervals assume independent, equal-variance noise per column and a model that
//!   is nearly linear in the parameters over the interval.

mod data;

pub use data::Measurements;

use core::fmt;

use bgdsl_runtime::{FromParams, Model, Simulation};
use nalgebra::{DMatrix, DVector};

use crate::error::AnalysisError;
use crate::sensitivity::{forward_sensitivities, parameter_name, SensitivityOptions};

/// A parameter value to fit, with its bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitParameter {
    /// Its index among the model's parameter values
    /// ([`parameter_index`](crate::sensitivity::parameter_index)).
    pub index: usize,
    /// The lowest value allowed (`-inf` for none).
    pub lower: f64,
    /// The highest value allowed (`inf` for none).
    pub upper: f64,
}

/// How the fit proceeds.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Levenberg–Marquardt iterations at most (default 50).
    pub max_iterations: usize,
    /// Converged when a step changes the cost by less than this fraction of it, or
    /// every parameter by less than this fraction of its value (default 1e-8).
    pub tolerance: f64,
    /// How the model and its sensitivities are integrated.
    pub sensitivity: SensitivityOptions,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            max_iterations: 50,
            tolerance: 1e-8,
            sensitivity: SensitivityOptions::default(),
        }
    }
}

/// One fitted parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedParameter {
    /// Its name (`resistance`, `K3C[1]`).
    pub name: String,
    /// Its unit as declared.
    pub unit: &'static str,
    /// The value the fit started from.
    pub initial: f64,
    /// The estimate.
    pub value: f64,
    /// Its standard error.
    pub standard_error: f64,
    /// The 95 % confidence interval.
    pub interval: (f64, f64),
    /// Whether the estimate lies on one of its bounds.
    pub at_bound: bool,
}

/// What a fit found.
#[derive(Clone, Debug, PartialEq)]
pub struct FitReport {
    /// The parameters, in the order asked.
    pub parameters: Vec<FittedParameter>,
    /// The correlation matrix of the estimates.
    pub correlation: DMatrix<f64>,
    /// The root mean square of the residuals of each measured column, in its unit
    /// (name, RMS).
    pub residual_rms: Vec<(String, f64)>,
    /// The number of residuals (measured samples).
    pub n_residuals: usize,
    /// Residuals less parameters.
    pub degrees_of_freedom: usize,
    /// The Student quantile the intervals use.
    pub t_quantile: f64,
    /// Iterations done.
    pub iterations: usize,
    /// Whether the convergence test was met (else the iteration limit was reached).
    pub converged: bool,
    /// Whether `∂f/∂p` was exact or central differences
    /// ([`ParameterDerivatives`](crate::sensitivity::ParameterDerivatives)).
    pub exact_parameter_derivatives: bool,
}

/// Why a fit could not be done.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FitError {
    /// A simulation or evaluation failed.
    Analysis(AnalysisError),
    /// The measurements file is malformed.
    Data {
        /// The line (1-based).
        line: usize,
        /// What is wrong there.
        message: String,
    },
    /// A measured column names no output of the model.
    UnknownColumn {
        /// The column's name.
        name: String,
        /// The model's outputs.
        outputs: &'static [&'static str],
    },
    /// Fewer measured samples than parameters plus one.
    TooFewData {
        /// Residuals available.
        residuals: usize,
        /// Parameters fitted.
        parameters: usize,
    },
    /// A parameter's bounds are empty, or the parameter is not one of the model's.
    BadParameter {
        /// Its index.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// `JᵀJ` is singular at the estimate: some parameter (combination) does not
    /// affect the measured signals.
    Unidentifiable {
        /// The parameters.
        parameters: Vec<String>,
    },
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitError::Analysis(e) => write!(f, "{e}"),
            FitError::Data { line, message } => {
                write!(f, "the measurements, line {line}: {message}")
            }
            FitError::UnknownColumn { name, outputs } => write!(
                f,
                "the measured column `{name}` is not an output of the model (its outputs: {})",
                outputs.join(", ")
            ),
            FitError::TooFewData {
                residuals,
                parameters,
            } => write!(
                f,
                "{residuals} measured samples cannot determine {parameters} parameters \
                 with an uncertainty: at least {} are needed",
                parameters + 1
            ),
            FitError::BadParameter { index, message } => {
                write!(f, "parameter value #{index}: {message}")
            }
            FitError::Unidentifiable { parameters } => write!(
                f,
                "the measurements do not determine {}: JᵀJ is singular at the estimate \
                 (a parameter, or a combination, has no effect on the measured signals)",
                parameters.join(", ")
            ),
        }
    }
}

impl std::error::Error for FitError {}

impl From<AnalysisError> for FitError {
    fn from(e: AnalysisError) -> Self {
        FitError::Analysis(e)
    }
}

impl From<bgdsl_runtime::SolverError> for FitError {
    fn from(e: bgdsl_runtime::SolverError) -> Self {
        FitError::Analysis(e.into())
    }
}

/// The Student-t quantile `t(0.975, ν)`: Abramowitz & Stegun 26.7.5 around the normal
/// quantile 1.959964.
pub fn t_quantile_975(dof: usize) -> f64 {
    let z: f64 = 1.959_963_984_540_054;
    let v = dof.max(1) as f64;
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    z + (z3 + z) / (4.0 * v)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * v * v)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * v * v * v)
}

/// The measured columns matched to output indices, and each column's scale.
struct Layout {
    outputs: Vec<usize>,
    scales: Vec<f64>,
    n_residuals: usize,
}

impl Layout {
    fn new<M: Model>(data: &Measurements) -> Result<Self, FitError> {
        let mut outputs = Vec::new();
        let mut scales = Vec::new();
        let mut n_residuals = 0;
        for (name, column) in data.names.iter().zip(&data.values) {
            let index = M::OUTPUT_NAMES
                .iter()
                .position(|o| o == name)
                .ok_or_else(|| FitError::UnknownColumn {
                    name: name.clone(),
                    outputs: M::OUTPUT_NAMES,
                })?;
            let measured: Vec<f64> = column.iter().copied().filter(|v| v.is_finite()).collect();
            n_residuals += measured.len();
            let rms =
                (measured.iter().map(|v| v * v).sum::<f64>() / measured.len().max(1) as f64).sqrt();
            outputs.push(index);
            scales.push(if rms > 0.0 { rms } else { 1.0 });
        }
        Ok(Layout {
            outputs,
            scales,
            n_residuals,
        })
    }
}

/// The model with parameter values `values` at the fitted indices.
fn with_values<M: Model + FromParams + Clone>(
    model: &M,
    parameters: &[FitParameter],
    p: &[f64],
) -> M {
    let mut all = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut all);
    for (fp, v) in parameters.iter().zip(p) {
        all[fp.index] = *v;
    }
    let mut moved = M::from_params(model.params().clone());
    moved.set_parameter_values(&all);
    moved
}

/// The scaled residuals of `model` against `data` (outputs at the sample times).
fn residuals<M: Model>(
    model: &M,
    x0: &[f64],
    data: &Measurements,
    layout: &Layout,
    options: &FitOptions,
) -> Result<Vec<f64>, FitError> {
    let mut sim = Simulation::new(model, options.sensitivity.solver)?;
    let mut r = Vec::with_capacity(layout.n_residuals);
    let mut k = 0;
    sim.run(
        data.times[0],
        x0,
        &data.times,
        &mut |_t: f64, _x: &[f64], y: &[f64]| {
            push_residuals(&mut r, y, data, layout, k);
            k += 1;
        },
    )?;
    Ok(r)
}

fn push_residuals(r: &mut Vec<f64>, y: &[f64], data: &Measurements, layout: &Layout, k: usize) {
    for (c, (&o, s)) in layout.outputs.iter().zip(&layout.scales).enumerate() {
        let measured = data.values[c][k];
        if measured.is_finite() {
            r.push((y[o] - measured) / s);
        }
    }
}

/// The start state of the model at `p`: `x0`, or its declared initial state.
fn start<M: Model>(model: &M, x0: Option<&[f64]>) -> Vec<f64> {
    x0.map(<[f64]>::to_vec).unwrap_or_else(|| {
        let mut x = vec![0.0; M::N_STATES];
        model.initial_state(&mut x);
        x
    })
}

/// Residuals and their Jacobian in the fitted parameters.
fn residuals_and_jacobian<M: Model + FromParams + Clone>(
    model: &M,
    x0: Option<&[f64]>,
    data: &Measurements,
    layout: &Layout,
    parameters: &[FitParameter],
    options: &FitOptions,
) -> Result<(Vec<f64>, DMatrix<f64>, bool), FitError> {
    let which: Vec<usize> = parameters.iter().map(|p| p.index).collect();
    let s = forward_sensitivities(model, x0, &which, &data.times, &options.sensitivity)?;
    let mut r = Vec::with_capacity(layout.n_residuals);
    let mut jac = DMatrix::<f64>::zeros(layout.n_residuals, which.len());
    let mut row = 0;
    for (k, y) in s.outputs.iter().enumerate() {
        for (c, (&o, scale)) in layout.outputs.iter().zip(&layout.scales).enumerate() {
            if data.values[c][k].is_finite() {
                for j in 0..which.len() {
                    jac[(row, j)] = s.output_sensitivities[k][(o, j)] / scale;
                }
                row += 1;
            }
        }
        push_residuals(&mut r, y, data, layout, k);
    }
    Ok((r, jac, s.exact_parameter_derivatives))
}

fn cost(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Fits the parameter values `parameters` of `model` (starting from its values) to
/// `data`, the run starting at the first sample time from `x0` (the declared initial
/// state, which may depend on the parameters, when `None`). Returns the report and the
/// model with the estimates.
///
/// # Errors
/// See [`FitError`].
pub fn fit<M: Model + FromParams + Clone>(
    model: &M,
    x0: Option<&[f64]>,
    data: &Measurements,
    parameters: &[FitParameter],
    options: &FitOptions,
) -> Result<(FitReport, M), FitError> {
    let layout = Layout::new::<M>(data)?;
    let np = parameters.len();
    if layout.n_residuals <= np {
        return Err(FitError::TooFewData {
            residuals: layout.n_residuals,
            parameters: np,
        });
    }
    let mut values = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    let mut initial = Vec::with_capacity(np);
    for fp in parameters {
        let ok_index = fp.index < values.len();
        if !ok_index || fp.lower.is_nan() || fp.upper.is_nan() || fp.lower > fp.upper {
            return Err(FitError::BadParameter {
                index: fp.index,
                message: if ok_index {
                    format!("empty bounds [{}, {}]", fp.lower, fp.upper)
                } else {
                    format!("the model has {} parameter values", values.len())
                },
            });
        }
        initial.push(values[fp.index].clamp(fp.lower, fp.upper));
    }
    let names: Vec<String> = parameters
        .iter()
        .map(|fp| parameter_name::<M>(fp.index).unwrap_or_else(|| format!("#{}", fp.index)))
        .collect();

    let mut p = initial.clone();
    let mut current = with_values(model, parameters, &p);
    let (mut r, mut jac, exact) =
        residuals_and_jacobian(&current, x0, data, &layout, parameters, options)?;
    let mut lambda = 1e-3;
    let mut converged = false;
    let mut iterations = 0;
    while iterations < options.max_iterations && !converged {
        iterations += 1;
        let jt = jac.transpose();
        let h = &jt * &jac;
        let g = &jt * DVector::from_column_slice(&r);
        let c0 = cost(&r);
        let mut accepted = false;
        while lambda < 1e12 {
            let mut a = h.clone();
            for d in 0..np {
                a[(d, d)] += lambda * h[(d, d)].max(1e-300);
            }
            let Some(chol) = a.cholesky() else {
                lambda *= 4.0;
                continue;
            };
            let delta = chol.solve(&(-&g));
            let trial: Vec<f64> = (0..np)
                .map(|j| (p[j] + delta[j]).clamp(parameters[j].lower, parameters[j].upper))
                .collect();
            let moved = with_values(model, parameters, &trial);
            let x_start = start(&moved, x0);
            let c1 = match residuals(&moved, &x_start, data, &layout, options) {
                Ok(r1) => cost(&r1),
                Err(_) => f64::INFINITY,
            };
            if c1 < c0 {
                let small_step = (0..np)
                    .all(|j| (trial[j] - p[j]).abs() <= options.tolerance * p[j].abs().max(1e-300));
                converged = (c0 - c1) <= options.tolerance * c0 || small_step;
                p = trial;
                current = moved;
                lambda = (lambda / 3.0).max(1e-12);
                accepted = true;
                break;
            }
            lambda *= 4.0;
        }
        if !accepted {
            // No step lowers the cost: a minimum to working precision.
            converged = true;
            break;
        }
        (r, jac, _) = residuals_and_jacobian(&current, x0, data, &layout, parameters, options)?;
    }

    let m = layout.n_residuals;
    let dof = m - np;
    let sigma2 = cost(&r) / dof as f64;
    let jt = jac.transpose();
    let inverse = (&jt * &jac)
        .try_inverse()
        .ok_or_else(|| FitError::Unidentifiable {
            parameters: names.clone(),
        })?;
    let covariance = inverse * sigma2;
    let t = t_quantile_975(dof);
    let fitted = (0..np)
        .map(|j| {
            let se = covariance[(j, j)].max(0.0).sqrt();
            let fp = &parameters[j];
            FittedParameter {
                name: names[j].clone(),
                unit: unit_of_value::<M>(fp.index),
                initial: initial[j],
                value: p[j],
                standard_error: se,
                interval: (p[j] - t * se, p[j] + t * se),
                at_bound: p[j] <= fp.lower || p[j] >= fp.upper,
            }
        })
        .collect();
    let correlation = DMatrix::from_fn(np, np, |i, j| {
        covariance[(i, j)] / (covariance[(i, i)] * covariance[(j, j)]).sqrt()
    });
    // The RMS of each column's residuals, in its own unit.
    let mut residual_rms = Vec::new();
    let per_sample = data.names.len();
    for (c, name) in data.names.iter().enumerate() {
        let mut sum = 0.0;
        let mut count = 0usize;
        let mut row = 0;
        for k in 0..data.times.len() {
            for cc in 0..per_sample {
                if data.values[cc][k].is_finite() {
                    if cc == c {
                        sum += (r[row] * layout.scales[c]).powi(2);
                        count += 1;
                    }
                    row += 1;
                }
            }
        }
        residual_rms.push((name.clone(), (sum / count.max(1) as f64).sqrt()));
    }
    Ok((
        FitReport {
            parameters: fitted,
            correlation,
            residual_rms,
            n_residuals: m,
            degrees_of_freedom: dof,
            t_quantile: t,
            iterations,
            converged,
            exact_parameter_derivatives: exact,
        },
        current,
    ))
}

/// The declared unit of parameter value `index`.
fn unit_of_value<M: Model>(index: usize) -> &'static str {
    let mut start = 0;
    for info in M::PARAMETERS {
        if index < start + info.len {
            return info.unit;
        }
        start += info.len;
    }
    ""
}
