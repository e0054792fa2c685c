//! The derivatives of a model's right-hand side, outputs and initial state with respect
//! to chosen parameter values: `∂f/∂p`, `∂g/∂p`, `∂x₀/∂p`.
//!
//! `∂f/∂p` and `∂g/∂p` are exact (dual numbers, [`crate::partials::PartialsWorkspace`],
//! allocation-free once set up)
//! for a model that keeps parameter tangents (`Model::EXACT_PARAMETER_DERIVATIVES`: every
//! generated model whose parameter expressions are generic); otherwise, and always for
//! `∂x₀/∂p` (the initial state is computed in `f64` only), by central differences on
//! copies of the model whose parameter values are moved by `±h` (`h = 1e-6 · max(|p|,
//! 1e-3)`: truncation error of order `h²`, rounding of order `ε/h`, both below 1e-9
//! relative for the models of the catalogue). [`ParameterDerivatives::exact`] says
//! which way `∂f/∂p` was computed, and every result that uses it carries it.

use bgdsl_runtime::{FromParams, Model};
use nalgebra::DMatrix;

use crate::error::AnalysisError;
use crate::partials::PartialsWorkspace;

/// The index among a model's parameter values ([`Model::parameter_values`]) of the
/// parameter named `name` (a scalar), or of `name[k]` (component `k` of a vector or
/// matrix parameter, its numbers laid out as `parameter_values` lays them).
pub fn parameter_index<M: Model>(name: &str) -> Option<usize> {
    let (base, component) = match name.strip_suffix(']').and_then(|s| s.split_once('[')) {
        Some((base, k)) => (base, Some(k.parse::<usize>().ok()?)),
        None => (name, None),
    };
    let mut start = 0;
    for info in M::PARAMETERS {
        if info.name == base {
            return match component {
                None if info.len == 1 => Some(start),
                Some(k) if k < info.len => Some(start + k),
                _ => None,
            };
        }
        start += info.len;
    }
    None
}

/// The name of parameter value `index`: `m1`, or `K3C[1]` for a component.
pub fn parameter_name<M: Model>(index: usize) -> Option<String> {
    let mut start = 0;
    for info in M::PARAMETERS {
        if index < start + info.len {
            return Some(if info.len == 1 {
                info.name.to_string()
            } else {
                format!("{}[{}]", info.name, index - start)
            });
        }
        start += info.len;
    }
    None
}

/// What exact `∂f/∂p` and `∂g/∂p` need: the model, the indices, the buffers.
struct Exact<M> {
    model: M,
    which: Vec<usize>,
    work: PartialsWorkspace<M>,
}

/// `∂f/∂p`, `∂g/∂p` and `∂x₀/∂p` for the parameter values `which` of a model.
pub struct ParameterDerivatives<M> {
    /// The model itself, the indices and the partials' buffers, for exact derivatives
    /// (`None`: central differences).
    exact: Option<Exact<M>>,
    /// The model moved up and down in each parameter, in the order of `which`.
    plus: Vec<M>,
    minus: Vec<M>,
    /// The steps `2h`.
    width: Vec<f64>,
    f_plus: Vec<f64>,
    f_minus: Vec<f64>,
}

impl<M: Model + FromParams + Clone> ParameterDerivatives<M> {
    /// The derivatives of `model` in its parameter values `which` (indices into
    /// [`Model::parameter_values`]).
    ///
    /// # Errors
    /// [`AnalysisError::Dimension`] for an index past the last parameter value.
    pub fn new(model: &M, which: &[usize]) -> Result<Self, AnalysisError> {
        let mut values = vec![0.0; M::N_PARAMETER_VALUES];
        model.parameter_values(&mut values);
        let (mut plus, mut minus, mut width) = (Vec::new(), Vec::new(), Vec::new());
        for &j in which {
            if j >= values.len() {
                return Err(AnalysisError::Dimension {
                    what: "parameter index",
                    expected: values.len(),
                    found: j,
                });
            }
            let h = 1e-6 * values[j].abs().max(1e-3);
            for (sign, list) in [(1.0, &mut plus), (-1.0, &mut minus)] {
                let mut moved = values.clone();
                moved[j] += sign * h;
                let mut copy = M::from_params(model.params().clone());
                copy.set_parameter_values(&moved);
                list.push(copy);
            }
            width.push(2.0 * h);
        }
        Ok(ParameterDerivatives {
            exact: M::EXACT_PARAMETER_DERIVATIVES.then(|| Exact {
                model: model.clone(),
                which: which.to_vec(),
                work: PartialsWorkspace::new(model),
            }),
            plus,
            minus,
            width,
            f_plus: vec![0.0; M::N_STATES.max(M::N_OUTPUTS)],
            f_minus: vec![0.0; M::N_STATES.max(M::N_OUTPUTS)],
        })
    }

    /// Whether `∂f/∂p` and `∂g/∂p` are exact (dual numbers) rather than central
    /// differences.
    pub fn exact(&self) -> bool {
        self.exact.is_some()
    }

    /// The exact `∂f/∂p` (`rhs`) or `∂g/∂p` into `out`; NaN where the evaluation
    /// failed (the integration then reports a non-finite value). `false` when the model
    /// keeps no parameter tangents.
    fn exact_into(&mut self, t: f64, x: &[f64], out: &mut DMatrix<f64>, rhs: bool) -> bool {
        let Some(Exact { model, which, work }) = &mut self.exact else {
            return false;
        };
        let partials = if rhs {
            work.parameter_rhs_partials(model, t, x, which)
        } else {
            work.parameter_output_partials(model, t, x, which)
        };
        match partials {
            Ok(p) => out.copy_from(p),
            Err(_) => out.fill(f64::NAN),
        }
        true
    }

    /// The number of parameters.
    pub fn len(&self) -> usize {
        self.width.len()
    }

    /// Whether no parameter was chosen.
    pub fn is_empty(&self) -> bool {
        self.width.is_empty()
    }

    /// `∂f/∂p` at `(t, x)` into `out` (`N_STATES × len`).
    pub fn df_dp(&mut self, t: f64, x: &[f64], out: &mut DMatrix<f64>) {
        if self.exact_into(t, x, out, true) {
            return;
        }
        let n = M::N_STATES;
        for j in 0..self.len() {
            self.plus[j].derivatives::<f64>(t, x, &mut self.f_plus[..n]);
            self.minus[j].derivatives::<f64>(t, x, &mut self.f_minus[..n]);
            for i in 0..n {
                out[(i, j)] = (self.f_plus[i] - self.f_minus[i]) / self.width[j];
            }
        }
    }

    /// `∂g/∂p` at `(t, x)` into `out` (`N_OUTPUTS × len`).
    pub fn dg_dp(&mut self, t: f64, x: &[f64], out: &mut DMatrix<f64>) {
        if self.exact_into(t, x, out, false) {
            return;
        }
        let n = M::N_OUTPUTS;
        for j in 0..self.len() {
            self.plus[j].outputs::<f64>(t, x, &mut self.f_plus[..n]);
            self.minus[j].outputs::<f64>(t, x, &mut self.f_minus[..n]);
            for i in 0..n {
                out[(i, j)] = (self.f_plus[i] - self.f_minus[i]) / self.width[j];
            }
        }
    }

    /// `∂x₀/∂p` of the declared initial state into `out` (`N_STATES × len`).
    pub fn dx0_dp(&mut self, out: &mut DMatrix<f64>) {
        let n = M::N_STATES;
        for j in 0..self.len() {
            self.plus[j].initial_state(&mut self.f_plus[..n]);
            self.minus[j].initial_state(&mut self.f_minus[..n]);
            for i in 0..n {
                out[(i, j)] = (self.f_plus[i] - self.f_minus[i]) / self.width[j];
            }
        }
    }
}
