//! Forward parameter sensitivities along a trajectory: `S(t) = ∂x(t)/∂p` from the
//! variational equations `dS/dt = ∂f/∂x S + ∂f/∂p`, `S(t₀) = ∂x₀/∂p`, and the outputs'
//! `dy/dp = ∂g/∂x S + ∂g/∂p`.
//!
//! `∂f/∂x` and `∂g/∂x S` are exact (dual numbers); `∂f/∂p`, `∂g/∂p` (exact for a
//! generated model) and `∂x₀/∂p` come from [`ParameterDerivatives`] (see there how, and
//! [`Sensitivities::exact_parameter_derivatives`]). The state is integrated by the
//! runtime's solver, the sensitivities staggered on the same trajectory by an
//! L-stable SDIRK method of order 3 ([`variational`]): the accuracy of `S` is set by
//! [`SensitivityOptions::substeps`], that of `x` by the solver's tolerances.

mod parameters;
pub(crate) mod variational;

pub use parameters::{parameter_index, parameter_name, ParameterDerivatives};

use bgdsl_runtime::{Dual, FromParams, Model, Radau5Options, Solver};
use nalgebra::DMatrix;

use crate::error::AnalysisError;
use variational::{propagate, Forcing};

/// How sensitivities are integrated.
#[derive(Clone, Copy, Debug)]
pub struct SensitivityOptions {
    /// The solver of the state (default: Radau5 at `rtol` 1e-8, `atol` 1e-10).
    pub solver: Solver,
    /// SDIRK steps per interval between two requested times (default 10).
    pub substeps: usize,
}

impl Default for SensitivityOptions {
    fn default() -> Self {
        SensitivityOptions {
            solver: Solver::Radau5(Radau5Options {
                rtol: 1e-8,
                atol: 1e-10,
                ..Default::default()
            }),
            substeps: 10,
        }
    }
}

/// A trajectory with its sensitivities to chosen parameters, at the requested times.
#[derive(Clone, Debug)]
pub struct Sensitivities {
    /// The requested times.
    pub times: Vec<f64>,
    /// The parameters, by name (`m1`, `K3C[1]`).
    pub parameters: Vec<String>,
    /// Whether `∂f/∂p` and `∂g/∂p` were exact (dual numbers) or central differences
    /// (`∂x₀/∂p` always is: [`ParameterDerivatives`]).
    pub exact_parameter_derivatives: bool,
    /// The state at each time.
    pub states: Vec<Vec<f64>>,
    /// The outputs at each time.
    pub outputs: Vec<Vec<f64>>,
    /// `∂x/∂p` at each time (`N_STATES × parameters`).
    pub state_sensitivities: Vec<DMatrix<f64>>,
    /// `∂y/∂p` at each time (`N_OUTPUTS × parameters`).
    pub output_sensitivities: Vec<DMatrix<f64>>,
    /// Steps the runtime's solver accepted for the state.
    pub accepted_steps: usize,
}

impl Sensitivities {
    /// `∂y/∂p_j` of output `output` along the times.
    pub fn output_column(&self, output: usize, parameter: usize) -> Vec<f64> {
        self.output_sensitivities
            .iter()
            .map(|s| s[(output, parameter)])
            .collect()
    }
}

/// The forcing `∂f/∂p` of the variational equations.
struct ParameterForcing<'a, M>(&'a mut ParameterDerivatives<M>);

impl<M: Model + FromParams + Clone> Forcing for ParameterForcing<'_, M> {
    fn forcing(&mut self, t: f64, x: &[f64], out: &mut DMatrix<f64>) {
        self.0.df_dp(t, x, out);
    }
}

/// `∂g/∂x v` for every column `v` of `s`, exactly, plus `dg_dp`: one evaluation of the
/// outputs on dual numbers per column.
fn output_sensitivity<M: Model>(
    model: &M,
    t: f64,
    x: &[f64],
    s: &DMatrix<f64>,
    dg_dp: &DMatrix<f64>,
) -> DMatrix<f64> {
    let (n, q) = (M::N_STATES, M::N_OUTPUTS);
    let mut out = dg_dp.clone();
    let mut xd = vec![Dual::default(); n];
    let mut yd = vec![Dual::default(); q];
    for j in 0..s.ncols() {
        for i in 0..n {
            xd[i] = Dual::new(x[i], s[(i, j)]);
        }
        model.outputs::<Dual>(t, &xd, &mut yd);
        for i in 0..q {
            out[(i, j)] += yd[i].eps;
        }
    }
    out
}

/// The sensitivities of `model`'s trajectory from `x0` (its declared initial state
/// when `None`, whose own dependence on the parameters is then included) to its
/// parameter values `which` (indices into [`Model::parameter_values`]; see
/// [`parameter_index`]), at `times` (increasing, the first the start).
///
/// # Errors
/// [`AnalysisError::Dimension`] for a wrong `x0` length, a parameter index out of
/// range or fewer than two times; [`AnalysisError::Solver`] when the run fails.
pub fn forward_sensitivities<M: Model + FromParams + Clone>(
    model: &M,
    x0: Option<&[f64]>,
    which: &[usize],
    times: &[f64],
    options: &SensitivityOptions,
) -> Result<Sensitivities, AnalysisError> {
    let (n, q) = (M::N_STATES, M::N_OUTPUTS);
    let mut derivatives = ParameterDerivatives::new(model, which)?;
    let p = which.len();
    let mut s = DMatrix::<f64>::zeros(n, p);
    let start = match x0 {
        Some(x0) if x0.len() != n => {
            return Err(AnalysisError::Dimension {
                what: "state vector",
                expected: n,
                found: x0.len(),
            })
        }
        Some(x0) => x0.to_vec(),
        None => {
            derivatives.dx0_dp(&mut s);
            let mut x0 = vec![0.0; n];
            model.initial_state(&mut x0);
            x0
        }
    };
    let mut result = Sensitivities {
        times: times.to_vec(),
        parameters: which
            .iter()
            .map(|&j| parameter_name::<M>(j).unwrap_or_else(|| format!("#{j}")))
            .collect(),
        exact_parameter_derivatives: derivatives.exact(),
        states: Vec::with_capacity(times.len()),
        outputs: Vec::with_capacity(times.len()),
        state_sensitivities: Vec::with_capacity(times.len()),
        output_sensitivities: Vec::with_capacity(times.len()),
        accepted_steps: 0,
    };
    let mut nodes: Vec<(Vec<f64>, DMatrix<f64>)> = Vec::with_capacity(times.len());
    let run = propagate(
        model,
        (options.solver, options.substeps),
        &start,
        times,
        &mut s,
        &mut ParameterForcing(&mut derivatives),
        |_k, x, s| nodes.push((x.to_vec(), s.clone())),
    )?;
    result.accepted_steps = run.accepted;
    let mut dg_dp = DMatrix::<f64>::zeros(q, p);
    for (k, (x, s)) in nodes.into_iter().enumerate() {
        let t = times[k];
        derivatives.dg_dp(t, &x, &mut dg_dp);
        let mut y = vec![0.0; q];
        model.outputs::<f64>(t, &x, &mut y);
        result
            .output_sensitivities
            .push(output_sensitivity(model, t, &x, &s, &dg_dp));
        result.outputs.push(y);
        result.states.push(x);
        result.state_sensitivities.push(s);
    }
    Ok(result)
}
