//! Parameter estimation: weighted least squares of chosen parameter values to measured
//! signals, by Levenberg–Marquardt on the exact forward sensitivities
//! ([`crate::sensitivity`]).
//!
//! - **Residuals**: for every measured column `k` (named like a model output) and
//!   sample, `(y_model − y_measured) / σₖ`, with `σₖ` the column's noise standard
//!   deviation: given ([`Measurements::set_sigma`]) or estimated (below).
//! - **Steps**: `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr` (Marquardt's scaling, so parameters of
//!   different magnitudes are treated alike), `λ` divided by 3 after a step that lowers
//!   the cost, multiplied by 4 and retried after one that does not.
//! - **Bounds** by projection: every trial point is clamped into `[lower, upper]`; a
//!   parameter that ends on a bound is reported as such (its interval, from the local
//!   linearisation, then ignores the bound).
//! - **Noise, per column** ([`NoiseModel::PerColumn`], the default): a `σₖ` given is
//!   taken as it is (absolute, like SciPy's `curve_fit(..., absolute_sigma=True)`);
//!   the others are estimated by iteratively reweighted least squares, the multiresponse
//!   scheme of Bard (*Nonlinear Parameter Estimation*, 1974, §4-9) and Seber & Wild
//!   (*Nonlinear Regression*, 1989, §11.3) for independent responses: fit with each
//!   column weighted by its RMS, set `σₖ² = RSSₖ / (nₖ − hₖ)` (the column's residual sum
//!   of squares over its share of the degrees of freedom, `hₖ` its rows' leverages,
//!   which makes the estimate unbiased for a linear model), refit with weights `1/σₖ²`,
//!   and repeat until no `σₖ` moves by more than [`FitOptions::reweight_tolerance`].
//!   The leverage share rather than the maximum-likelihood `RSSₖ/nₖ` keeps a column
//!   with few samples from looking quieter than it is.
//! - **Uncertainty**: covariance `(JᵀWJ)⁻¹` at the estimate, `W = diag(1/σₖ²)`; 95 %
//!   intervals `± t(0.975, ν_j) · standard error`, where `ν_j` is the Welch–Satterthwaite
//!   effective degrees of freedom of the parameter's variance (each estimated `σₖ²` has
//!   `nₖ − hₖ`; a given one is exact), and infinite (the normal quantile) when every
//!   `σₖ` is given. A χ² check of the residuals against the `σₖ` given
//!   ([`ChiSquareCheck`]) says whether they are consistent.
//! - **Pooled** ([`NoiseModel::Pooled`]): one variance factor for all columns, each
//!   weighted by its `σₖ` given or else its RMS (SciPy's `absolute_sigma=False`): right
//!   only when the noise is the same fraction of every column's weight; with unequal
//!   noise its intervals are too narrow for the parameters the noisier column
//!   determines.
//!
//! The intervals assume independent Gaussian noise, of one variance within a column,
//! and a model nearly linear in the parameters over the interval.

mod data;
mod lm;
mod noise;
mod stats;

pub use data::Measurements;
pub use stats::{chi_square_upper_tail, t_quantile_975};

use core::fmt;

use bgdsl_runtime::{FromParams, Model};
use nalgebra::DMatrix;

use crate::error::AnalysisError;
use crate::sensitivity::{parameter_name, SensitivityOptions};
use lm::{Layout, Problem};
use noise::{effective_dof, ColumnSums};

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

/// How the measurement noise's variance is modelled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NoiseModel {
    /// A variance per measured column: the `σ` given, the others estimated by
    /// iteratively reweighted least squares (the default; see the module's doc).
    #[default]
    PerColumn,
    /// One variance factor pooled over all columns, each column weighted by its `σ`
    /// given or else its RMS: right only when the noise is the same fraction of every
    /// column's weight.
    Pooled,
}

/// How the fit proceeds.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Levenberg–Marquardt iterations at most, in the first fit and in each refit
    /// (default 50).
    pub max_iterations: usize,
    /// Converged when a step changes the cost by less than this fraction of it, or
    /// every parameter by less than this fraction of its value (default 1e-8).
    pub tolerance: f64,
    /// How the noise's variance is modelled (default [`NoiseModel::PerColumn`]).
    pub noise: NoiseModel,
    /// Refits with new weights at most (default 20); [`FitReport::weights_settled`]
    /// says whether they settled within it.
    pub max_reweightings: usize,
    /// The weights have settled when no estimated `σₖ²` changes by more than this
    /// fraction in a refit (relative to the others' change, when no `σ` is given: a
    /// common factor does not move the estimate) (default 1e-4).
    pub reweight_tolerance: f64,
    /// How the model and its sensitivities are integrated.
    pub sensitivity: SensitivityOptions,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            max_iterations: 50,
            tolerance: 1e-8,
            noise: NoiseModel::PerColumn,
            max_reweightings: 20,
            reweight_tolerance: 1e-4,
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
    /// The effective degrees of freedom of its variance (Welch–Satterthwaite;
    /// infinite when every column's `σ` is given).
    pub degrees_of_freedom: f64,
    /// The Student quantile `t(0.975, degrees_of_freedom)` of its interval.
    pub t_quantile: f64,
    /// The 95 % confidence interval.
    pub interval: (f64, f64),
    /// Whether the estimate lies on one of its bounds.
    pub at_bound: bool,
}

/// One measured column of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnFit {
    /// Its name (an output of the model).
    pub name: String,
    /// Its measured samples.
    pub samples: usize,
    /// The noise's standard deviation the fit used, in the column's unit: as given, or
    /// estimated.
    pub sigma: f64,
    /// Whether `sigma` was given (else estimated from the residuals).
    pub sigma_given: bool,
    /// Its residuals' weight `1/σ²`.
    pub weight: f64,
    /// The root mean square of its residuals, in its unit.
    pub residual_rms: f64,
    /// Its share of the residual degrees of freedom, `nₖ − hₖ` (`hₖ` its rows'
    /// leverages).
    pub degrees_of_freedom: f64,
    /// `RSSₖ / (σₖ² (nₖ − hₖ))`: 1 when `σ` is estimated (per column), about 1 when the
    /// `σ` given is right.
    pub reduced_chi_square: f64,
}

/// The residuals against the `σ` given: `χ² = Σ RSSₖ/σₖ²` over those columns, with
/// `Σ (nₖ − hₖ)` degrees of freedom (`m − p` when every `σ` is given).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChiSquareCheck {
    /// `Σ RSSₖ/σₖ²`.
    pub chi_square: f64,
    /// Its degrees of freedom.
    pub degrees_of_freedom: f64,
    /// `χ²` over its degrees of freedom: about 1 when the `σ` given are right.
    pub reduced: f64,
    /// The probability of a `χ²` at least this large if the `σ` given are right and the
    /// model fits: below 0.01, the residuals are larger than the `σ` say (or the model
    /// misses something); above 0.99, smaller.
    pub p_value: f64,
}

/// What a fit found.
#[derive(Clone, Debug, PartialEq)]
pub struct FitReport {
    /// The parameters, in the order asked.
    pub parameters: Vec<FittedParameter>,
    /// The correlation matrix of the estimates.
    pub correlation: DMatrix<f64>,
    /// The covariance matrix of the estimates.
    pub covariance: DMatrix<f64>,
    /// Each measured column: its noise, weight, residual RMS.
    pub columns: Vec<ColumnFit>,
    /// How the noise was modelled.
    pub noise: NoiseModel,
    /// The residuals against the `σ` given (per column, when some are given).
    pub chi_square: Option<ChiSquareCheck>,
    /// The final cost `Σ ((y_model − y_measured)/σₖ)²`.
    pub cost: f64,
    /// The number of residuals (measured samples).
    pub n_residuals: usize,
    /// Residuals less parameters.
    pub degrees_of_freedom: usize,
    /// Refits with new weights done after the first fit.
    pub reweightings: usize,
    /// Whether the weights settled (within [`FitOptions::reweight_tolerance`]).
    pub weights_settled: bool,
    /// Iterations done, over all reweightings.
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
    /// A column's noise is given wrongly, or cannot be estimated: too few samples
    /// beside the parameters it determines.
    BadNoise {
        /// The column.
        column: String,
        /// What is wrong.
        message: String,
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
            FitError::BadNoise { column, message } => {
                write!(f, "the noise of the column `{column}`: {message}")
            }
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
    if layout.rows() <= np {
        return Err(FitError::TooFewData {
            residuals: layout.rows(),
            parameters: np,
        });
    }
    let initial = starting_values(model, parameters)?;
    let given = given_sigma(data)?;
    let names: Vec<String> = parameters
        .iter()
        .map(|fp| parameter_name::<M>(fp.index).unwrap_or_else(|| format!("#{}", fp.index)))
        .collect();
    let unidentifiable = || FitError::Unidentifiable {
        parameters: names.clone(),
    };

    let problem = Problem {
        model,
        x0,
        data,
        layout: &layout,
        parameters,
        options,
    };
    let per_column = options.noise == NoiseModel::PerColumn;
    let all_given = given.iter().all(Option::is_some);
    // The first fit weighs each column by its σ given or else its RMS; per column, an
    // estimated σ replaces the RMS from the second on.
    let mut sigma: Vec<f64> = (given.iter().zip(&layout.scales))
        .map(|(g, s)| {
            if per_column && !all_given {
                *s
            } else {
                g.unwrap_or(*s)
            }
        })
        .collect();
    let mut point = problem.point(initial.clone(), problem.with_values(&initial))?;
    let (mut iterations, mut reweightings) = (0, 0);
    let mut converged;
    let mut settled = !per_column || all_given;
    loop {
        let (reached, done, met) = problem.minimise(point, &sigma)?;
        (point, iterations, converged) = (reached, iterations + done, met);
        if settled {
            break;
        }
        let jw = layout.whiten(&point.jac, &sigma);
        let inverse = (jw.transpose() * &jw)
            .try_inverse()
            .ok_or_else(unidentifiable)?;
        let sums = ColumnSums::new(&layout, &point.raw, &jw, &inverse);
        let estimated = estimated_sigma(data, &layout, &sums, &given)?;
        settled = weights_settled(&sigma, &estimated, given.iter().any(Option::is_some))
            <= options.reweight_tolerance;
        sigma = estimated;
        if settled || reweightings == options.max_reweightings {
            break;
        }
        reweightings += 1;
    }

    let jw = layout.whiten(&point.jac, &sigma);
    let inverse = (jw.transpose() * &jw)
        .try_inverse()
        .ok_or_else(unidentifiable)?;
    let sums = ColumnSums::new(&layout, &point.raw, &jw, &inverse);
    let m = layout.rows();
    let dof = m - np;
    let (covariance, nu) = if per_column {
        let nu: Vec<f64> = (given.iter().zip(&sums.dof))
            .map(|(g, d)| if g.is_some() { f64::INFINITY } else { *d })
            .collect();
        let dof_j = effective_dof(&layout, &jw, &inverse, &nu);
        (inverse, dof_j)
    } else {
        // One variance factor: the weighted residual sum of squares over m − p.
        let factor = layout.weighted_cost(&point.raw, &sigma) / dof as f64;
        for s in &mut sigma {
            *s *= factor.sqrt();
        }
        (inverse * factor, vec![dof as f64; np])
    };
    let fitted = (0..np)
        .map(|j| {
            let se = covariance[(j, j)].max(0.0).sqrt();
            let t = t_quantile_975(nu[j]);
            let (fp, p) = (&parameters[j], point.p[j]);
            FittedParameter {
                name: names[j].clone(),
                unit: unit_of_value::<M>(fp.index),
                initial: initial[j],
                value: p,
                standard_error: se,
                degrees_of_freedom: nu[j],
                t_quantile: t,
                interval: (p - t * se, p + t * se),
                at_bound: p <= fp.lower || p >= fp.upper,
            }
        })
        .collect();
    let correlation = DMatrix::from_fn(np, np, |i, j| {
        covariance[(i, j)] / (covariance[(i, i)] * covariance[(j, j)]).sqrt()
    });
    let columns: Vec<ColumnFit> = (0..data.names.len())
        .map(|c| ColumnFit {
            name: data.names[c].clone(),
            samples: sums.samples[c],
            sigma: sigma[c],
            sigma_given: per_column && given[c].is_some(),
            weight: sigma[c].powi(-2),
            residual_rms: (sums.rss[c] / sums.samples[c].max(1) as f64).sqrt(),
            degrees_of_freedom: sums.dof[c],
            reduced_chi_square: sums.rss[c] / (sigma[c].powi(2) * sums.dof[c]),
        })
        .collect();
    let chi_square = (per_column && given.iter().any(Option::is_some)).then(|| {
        let checked = || columns.iter().filter(|c| c.sigma_given);
        let chi_square: f64 = checked()
            .map(|c| c.reduced_chi_square * c.degrees_of_freedom)
            .sum();
        let dof: f64 = checked().map(|c| c.degrees_of_freedom).sum();
        ChiSquareCheck {
            chi_square,
            degrees_of_freedom: dof,
            reduced: chi_square / dof,
            p_value: chi_square_upper_tail(chi_square, dof),
        }
    });
    let cost = layout.weighted_cost(&point.raw, &sigma);
    Ok((
        FitReport {
            parameters: fitted,
            correlation,
            covariance,
            columns,
            noise: options.noise,
            chi_square,
            cost,
            n_residuals: m,
            degrees_of_freedom: dof,
            reweightings,
            weights_settled: settled,
            iterations,
            converged,
            exact_parameter_derivatives: point.exact,
        },
        point.model,
    ))
}

/// The fitted parameters' starting values, clamped into their bounds.
fn starting_values<M: Model>(model: &M, parameters: &[FitParameter]) -> Result<Vec<f64>, FitError> {
    let mut values = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    parameters
        .iter()
        .map(|fp| {
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
            Ok(values[fp.index].clamp(fp.lower, fp.upper))
        })
        .collect()
}

/// Each column's σ as given, checked positive and finite.
fn given_sigma(data: &Measurements) -> Result<Vec<Option<f64>>, FitError> {
    (0..data.names.len())
        .map(|c| match data.sigma_of(c) {
            Some(s) if !(s.is_finite() && s > 0.0) => Err(FitError::BadNoise {
                column: data.names[c].clone(),
                message: format!(
                    "the noise's standard deviation must be a positive number, not {s}"
                ),
            }),
            given => Ok(given),
        })
        .collect()
}

/// The columns' σ: as given, or `√(RSSₖ / (nₖ − hₖ))` (at least 1e-15 of the column's
/// RMS, so an exact fit keeps finite weights).
fn estimated_sigma(
    data: &Measurements,
    layout: &Layout,
    sums: &ColumnSums,
    given: &[Option<f64>],
) -> Result<Vec<f64>, FitError> {
    (0..given.len())
        .map(|c| {
            if let Some(s) = given[c] {
                return Ok(s);
            }
            if sums.dof[c] < 1.0 {
                return Err(FitError::BadNoise {
                    column: data.names[c].clone(),
                    message: format!(
                        "its {} sample(s) leave {:.2} degrees of freedom beside the \
                         parameters they determine, too few to estimate its variance: \
                         give its σ",
                        sums.samples[c], sums.dof[c]
                    ),
                });
            }
            Ok((sums.rss[c] / sums.dof[c])
                .sqrt()
                .max(1e-15 * layout.scales[c]))
        })
        .collect()
}

/// How far the weights moved: the largest `|ln(σ_new²/σ_old²)|`, less their common
/// part (the geometric mean) when no σ is given, since scaling every weight alike does
/// not move the estimate.
fn weights_settled(old: &[f64], new: &[f64], absolute: bool) -> f64 {
    let moves: Vec<f64> = old
        .iter()
        .zip(new)
        .map(|(o, n)| 2.0 * (n / o).ln())
        .collect();
    let common = if absolute {
        0.0
    } else {
        moves.iter().sum::<f64>() / moves.len() as f64
    };
    moves.iter().map(|m| (m - common).abs()).fold(0.0, f64::max)
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
