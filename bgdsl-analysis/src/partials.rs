//! Exact partial derivatives of a model's right-hand side `f(t, x, p, u)` and outputs
//! `g(t, x, p, u)`: in the state (∂f/∂x, ∂g/∂x), in chosen parameters (∂f/∂p, ∂g/∂p)
//! and in chosen inputs (∂f/∂u, ∂g/∂u).
//!
//! States are seeded as [`DualN`] numbers; parameters and inputs as
//! [`ParamDual`] numbers (see `bgdsl_runtime::param_dual`), [`LANES`] directions per
//! evaluation. A model that does not keep parameter tangents
//! ([`Model::EXACT_PARAMETER_DERIVATIVES`] is `false`: a hand-written one, or one whose
//! parameter expression calls a user's `f64` function) is differentiated in its
//! parameters and inputs by central differences instead, and [`Partials::method`] says
//! so.
//!
//! Parameter indices are those of [`Model::parameter_values`] (declaration order,
//! vectors component by component, matrices row by row); input indices those of
//! [`WithInputs::INPUTS`].

use bgdsl_runtime::param_dual::with_seeds;
use bgdsl_runtime::{DualN, Model, ParamDual, Scalar, WithInputs};
use nalgebra::DMatrix;

use crate::AnalysisError;

/// Directions evaluated together (tangent lanes per evaluation).
pub const LANES: usize = 8;

/// How a set of partial derivatives was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// By dual numbers: exact to round-off.
    Exact,
    /// By central differences (step `6e-6·|v|` for a value `v`, `6e-6` at 0): accurate to
    /// about 1e-10 relative for smooth laws, for models that do not keep parameter
    /// tangents.
    CentralDifferences,
}

impl Method {
    /// A short description for reports: `exact (dual numbers)` or `central differences`.
    pub fn describe(self) -> &'static str {
        match self {
            Method::Exact => "exact (dual numbers)",
            Method::CentralDifferences => "central differences",
        }
    }
}

/// Partial derivatives of the right-hand side and the outputs with respect to some
/// variables (states, parameters or inputs), one column per variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Partials {
    /// ∂f/∂v: `N_STATES` rows.
    pub df: DMatrix<f64>,
    /// ∂g/∂v: `N_OUTPUTS` rows.
    pub dg: DMatrix<f64>,
    /// How they were computed.
    pub method: Method,
}

/// Checks that `x` is a state of `M`.
pub(crate) fn check_state<M: Model>(x: &[f64]) -> Result<(), AnalysisError> {
    if x.len() != M::N_STATES {
        return Err(AnalysisError::Dimension {
            what: "state vector",
            expected: M::N_STATES,
            found: x.len(),
        });
    }
    Ok(())
}

fn check_indices(which: &[usize], bound: usize, what: &'static str) -> Result<(), AnalysisError> {
    match which.iter().find(|&&i| i >= bound) {
        Some(&found) => Err(AnalysisError::Dimension {
            what,
            expected: bound,
            found,
        }),
        None => Ok(()),
    }
}

/// Fails on the first non-finite entry of `values`, named from `names`.
pub(crate) fn check_finite(
    values: impl IntoIterator<Item = f64>,
    names: &[&str],
    what: &'static str,
) -> Result<(), AnalysisError> {
    match values.into_iter().position(|v| !v.is_finite()) {
        Some(i) => Err(AnalysisError::NonFinite {
            what,
            name: names.get(i).copied().unwrap_or("?").to_string(),
        }),
        None => Ok(()),
    }
}

/// ∂f/∂x and ∂g/∂x of `model` at `(t, x)`, exact (dense; `LANES` columns per
/// evaluation of `derivatives` and `outputs`).
///
/// # Errors
/// A state vector of the wrong length; non-finite derivatives.
pub fn state_partials<M: Model>(model: &M, t: f64, x: &[f64]) -> Result<Partials, AnalysisError> {
    check_state::<M>(x)?;
    let (n, m) = (M::N_STATES, M::N_OUTPUTS);
    let mut df = DMatrix::zeros(n, n);
    let mut dg = DMatrix::zeros(m, n);
    let mut xs = vec![DualN::<LANES>::default(); n];
    let mut dx = vec![DualN::<LANES>::default(); n];
    let mut y = vec![DualN::<LANES>::default(); m];
    for first in (0..n).step_by(LANES) {
        for (j, (xj, &value)) in xs.iter_mut().zip(x).enumerate() {
            *xj = DualN::constant(value);
            if (first..first + LANES).contains(&j) {
                xj.set_tangent(j - first, 1.0);
            }
        }
        model.derivatives(t, &xs, &mut dx);
        model.outputs(t, &xs, &mut y);
        let lanes = LANES.min(n - first);
        for k in 0..lanes {
            for i in 0..n {
                df[(i, first + k)] = dx[i].tangents()[k];
            }
            for i in 0..m {
                dg[(i, first + k)] = y[i].tangents()[k];
            }
        }
    }
    check_finite(df.iter().copied(), &[], "derivatives' Jacobian")?;
    Ok(Partials {
        df,
        dg,
        method: Method::Exact,
    })
}

/// Which kind of variable [`seeded_partials`] differentiates in.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Parameters,
    Inputs,
}

/// ∂f/∂v and ∂g/∂v for the parameters or inputs `which`, by [`ParamDual`] evaluations.
fn seeded_partials<M: Model>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
    kind: Kind,
) -> Partials {
    let (n, m) = (M::N_STATES, M::N_OUTPUTS);
    let mut df = DMatrix::zeros(n, which.len());
    let mut dg = DMatrix::zeros(m, which.len());
    let xs: Vec<ParamDual<LANES>> = x.iter().map(|&v| ParamDual::from_f64(v)).collect();
    let mut dx = vec![ParamDual::<LANES>::default(); n];
    let mut y = vec![ParamDual::<LANES>::default(); m];
    for (c, chunk) in which.chunks(LANES).enumerate() {
        let (params, inputs): (&[usize], &[usize]) = match kind {
            Kind::Parameters => (chunk, &[]),
            Kind::Inputs => (&[], chunk),
        };
        with_seeds(params, inputs, || {
            model.derivatives(t, &xs, &mut dx);
            model.outputs(t, &xs, &mut y);
        });
        for k in 0..chunk.len() {
            let col = c * LANES + k;
            for i in 0..n {
                df[(i, col)] = dx[i].tangents()[k];
            }
            for i in 0..m {
                dg[(i, col)] = y[i].tangents()[k];
            }
        }
    }
    Partials {
        df,
        dg,
        method: Method::Exact,
    }
}

/// Central differences of `f` and `g` along the values `which` of a vector that
/// `get`/`set` read and write on a copy of `model`.
fn central_partials<M: Model + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
    get: impl Fn(&M) -> Vec<f64>,
    set: impl Fn(&mut M, &[f64]),
) -> Partials {
    let (n, m) = (M::N_STATES, M::N_OUTPUTS);
    let mut df = DMatrix::zeros(n, which.len());
    let mut dg = DMatrix::zeros(m, which.len());
    let mut copy = model.clone();
    let base = get(model);
    let (mut f_plus, mut f_minus) = (vec![0.0; n], vec![0.0; n]);
    let (mut g_plus, mut g_minus) = (vec![0.0; m], vec![0.0; m]);
    for (col, &i) in which.iter().enumerate() {
        let h = 6e-6 * if base[i] == 0.0 { 1.0 } else { base[i].abs() };
        let mut values = base.clone();
        values[i] = base[i] + h;
        set(&mut copy, &values);
        copy.derivatives(t, x, &mut f_plus);
        copy.outputs(t, x, &mut g_plus);
        values[i] = base[i] - h;
        set(&mut copy, &values);
        copy.derivatives(t, x, &mut f_minus);
        copy.outputs(t, x, &mut g_minus);
        for r in 0..n {
            df[(r, col)] = (f_plus[r] - f_minus[r]) / (2.0 * h);
        }
        for r in 0..m {
            dg[(r, col)] = (g_plus[r] - g_minus[r]) / (2.0 * h);
        }
    }
    Partials {
        df,
        dg,
        method: Method::CentralDifferences,
    }
}

/// ∂f/∂p and ∂g/∂p of `model` at `(t, x)` for the parameters `which` (indices into
/// [`Model::parameter_values`]), one column each: exact when the model keeps parameter
/// tangents ([`Model::EXACT_PARAMETER_DERIVATIVES`]), else central differences.
///
/// # Errors
/// A state vector of the wrong length or an index out of range; non-finite results.
pub fn parameter_partials<M: Model + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
) -> Result<Partials, AnalysisError> {
    check_state::<M>(x)?;
    check_indices(which, M::N_PARAMETER_VALUES, "parameter index")?;
    let partials = if M::EXACT_PARAMETER_DERIVATIVES {
        seeded_partials(model, t, x, which, Kind::Parameters)
    } else {
        central_partials(
            model,
            t,
            x,
            which,
            |model| {
                let mut values = vec![0.0; M::N_PARAMETER_VALUES];
                model.parameter_values(&mut values);
                values
            },
            |model, values| model.set_parameter_values(values),
        )
    };
    check_finite(partials.df.iter().copied(), &[], "parameter derivatives")?;
    Ok(partials)
}

/// ∂f/∂u and ∂g/∂u of `model` at `(t, x)` and its current inputs, for the inputs
/// `which` (indices into [`WithInputs::INPUTS`]), one column each; exact or by central
/// differences as [`parameter_partials`].
///
/// # Errors
/// A state vector of the wrong length or an index out of range; non-finite results.
pub fn input_partials<M: WithInputs + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
) -> Result<Partials, AnalysisError> {
    check_state::<M>(x)?;
    check_indices(which, M::INPUTS.len(), "input index")?;
    let partials = if M::EXACT_PARAMETER_DERIVATIVES {
        seeded_partials(model, t, x, which, Kind::Inputs)
    } else {
        central_partials(
            model,
            t,
            x,
            which,
            |model| {
                let mut values = vec![0.0; M::INPUTS.len()];
                model.input_values(&mut values);
                values
            },
            |model, values| model.set_input_values(values),
        )
    };
    check_finite(partials.df.iter().copied(), &[], "input derivatives")?;
    Ok(partials)
}

/// ∂f/∂p for the parameters `which` written into `out` column by column
/// (`out[k * N_STATES + i]` = ∂fᵢ/∂p_which[k]), the form a sensitivity integrator
/// wants; returns how it was computed.
///
/// # Errors
/// As [`parameter_partials`]; also an `out` of the wrong length.
pub fn parameter_jacobian<M: Model + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
    out: &mut [f64],
) -> Result<Method, AnalysisError> {
    if out.len() != M::N_STATES * which.len() {
        return Err(AnalysisError::Dimension {
            what: "output slice",
            expected: M::N_STATES * which.len(),
            found: out.len(),
        });
    }
    let partials = parameter_partials(model, t, x, which)?;
    out.copy_from_slice(partials.df.as_slice());
    Ok(partials.method)
}
