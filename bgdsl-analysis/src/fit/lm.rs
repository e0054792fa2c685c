//! Levenberg–Marquardt on weighted residuals: the model's outputs at the measured times
//! less the measurements, each divided by its column's noise standard deviation.

use bgdsl_runtime::{FromParams, Model, Simulation};
use nalgebra::{DMatrix, DVector};

use super::{FitError, FitOptions, FitParameter, Measurements};
use crate::sensitivity::forward_sensitivities;

/// The measured columns matched to output indices, each column's scale, and the column
/// of every residual (samples in time order, the measured columns of each in the data's
/// order; cells not measured left out).
pub(super) struct Layout {
    /// The output index of each column.
    pub outputs: Vec<usize>,
    /// Each column's root mean square (1 when it is 0).
    pub scales: Vec<f64>,
    /// The column of each residual.
    pub row_columns: Vec<usize>,
}

impl Layout {
    pub fn new<M: Model>(data: &Measurements) -> Result<Self, FitError> {
        let mut outputs = Vec::new();
        let mut scales = Vec::new();
        for (name, column) in data.names.iter().zip(&data.values) {
            let index = M::OUTPUT_NAMES
                .iter()
                .position(|o| o == name)
                .ok_or_else(|| FitError::UnknownColumn {
                    name: name.clone(),
                    outputs: M::OUTPUT_NAMES,
                })?;
            let measured: Vec<f64> = column.iter().copied().filter(|v| v.is_finite()).collect();
            let rms =
                (measured.iter().map(|v| v * v).sum::<f64>() / measured.len().max(1) as f64).sqrt();
            outputs.push(index);
            scales.push(if rms > 0.0 { rms } else { 1.0 });
        }
        let mut row_columns = Vec::new();
        for k in 0..data.times.len() {
            for (c, column) in data.values.iter().enumerate() {
                if column[k].is_finite() {
                    row_columns.push(c);
                }
            }
        }
        Ok(Layout {
            outputs,
            scales,
            row_columns,
        })
    }

    /// The number of residuals.
    pub fn rows(&self) -> usize {
        self.row_columns.len()
    }

    /// `Σ (rᵢ/σ_c(i))²` of raw residuals `raw`.
    pub fn weighted_cost(&self, raw: &[f64], sigma: &[f64]) -> f64 {
        raw.iter()
            .zip(&self.row_columns)
            .map(|(r, &c)| (r / sigma[c]).powi(2))
            .sum()
    }

    /// The raw Jacobian with each row divided by its column's σ.
    pub fn whiten(&self, jac: &DMatrix<f64>, sigma: &[f64]) -> DMatrix<f64> {
        let mut w = jac.clone();
        for (i, &c) in self.row_columns.iter().enumerate() {
            w.row_mut(i).scale_mut(1.0 / sigma[c]);
        }
        w
    }
}

/// What is being fitted: the model with the starting values, where its runs start, the
/// data and the parameters.
pub(super) struct Problem<'a, M> {
    pub model: &'a M,
    pub x0: Option<&'a [f64]>,
    pub data: &'a Measurements,
    pub layout: &'a Layout,
    pub parameters: &'a [FitParameter],
    pub options: &'a FitOptions,
}

/// A point of the parameter space with the model there, its raw residuals (model −
/// measured) and their Jacobian in the fitted parameters.
pub(super) struct Point<M> {
    pub p: Vec<f64>,
    pub model: M,
    pub raw: Vec<f64>,
    pub jac: DMatrix<f64>,
    pub exact: bool,
}

impl<M: Model + FromParams + Clone> Problem<'_, M> {
    /// The model with the fitted values `p`.
    pub fn with_values(&self, p: &[f64]) -> M {
        let mut all = vec![0.0; M::N_PARAMETER_VALUES];
        self.model.parameter_values(&mut all);
        for (fp, v) in self.parameters.iter().zip(p) {
            all[fp.index] = *v;
        }
        let mut moved = M::from_params(self.model.params().clone());
        moved.set_parameter_values(&all);
        moved
    }

    /// The raw residuals of `model` (its outputs at the sample times).
    fn residuals(&self, model: &M) -> Result<Vec<f64>, FitError> {
        let x0 = start(model, self.x0);
        let mut sim = Simulation::new(model, self.options.sensitivity.solver)?;
        let mut r = Vec::with_capacity(self.layout.rows());
        let mut k = 0;
        sim.run(
            self.data.times[0],
            &x0,
            &self.data.times,
            &mut |_t: f64, _x: &[f64], y: &[f64]| {
                self.push_residuals(&mut r, y, k);
                k += 1;
            },
        )?;
        Ok(r)
    }

    fn push_residuals(&self, r: &mut Vec<f64>, y: &[f64], k: usize) {
        for (column, &o) in self.data.values.iter().zip(&self.layout.outputs) {
            if column[k].is_finite() {
                r.push(y[o] - column[k]);
            }
        }
    }

    /// The point `p`: its model, residuals and Jacobian (a sensitivity run).
    pub fn point(&self, p: Vec<f64>, model: M) -> Result<Point<M>, FitError> {
        let which: Vec<usize> = self.parameters.iter().map(|fp| fp.index).collect();
        let opts = &self.options.sensitivity;
        let s = forward_sensitivities(&model, self.x0, &which, &self.data.times, opts)?;
        let mut raw = Vec::with_capacity(self.layout.rows());
        let mut jac = DMatrix::<f64>::zeros(self.layout.rows(), which.len());
        for (k, y) in s.outputs.iter().enumerate() {
            let row = raw.len();
            self.push_residuals(&mut raw, y, k);
            for (i, r) in (row..raw.len()).enumerate() {
                let o = self.layout.outputs[self.layout.row_columns[r]];
                for j in 0..which.len() {
                    jac[(row + i, j)] = s.output_sensitivities[k][(o, j)];
                }
            }
        }
        Ok(Point {
            p,
            model,
            raw,
            jac,
            exact: s.exact_parameter_derivatives,
        })
    }

    /// Minimises `Σ (rᵢ/σ_c(i))²` from `from`: `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr` on the
    /// weighted residuals, `λ` divided by 3 after a step that lowers the cost and
    /// multiplied by 4 and retried after one that does not; every trial clamped into
    /// the bounds. Returns the point reached, the iterations and whether the
    /// convergence test was met.
    pub fn minimise(
        &self,
        from: Point<M>,
        sigma: &[f64],
    ) -> Result<(Point<M>, usize, bool), FitError> {
        let np = self.parameters.len();
        let tolerance = self.options.tolerance;
        let mut point = from;
        let mut lambda = 1e-3;
        let mut converged = false;
        let mut iterations = 0;
        while iterations < self.options.max_iterations && !converged {
            iterations += 1;
            let jw = self.layout.whiten(&point.jac, sigma);
            let rw: Vec<f64> = (point.raw.iter().zip(&self.layout.row_columns))
                .map(|(r, &c)| r / sigma[c])
                .collect();
            let jt = jw.transpose();
            let h = &jt * &jw;
            let g = &jt * DVector::from_vec(rw);
            let c0 = self.layout.weighted_cost(&point.raw, sigma);
            let mut accepted = None;
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
                let p = &point.p;
                let trial: Vec<f64> = (0..np)
                    .map(|j| {
                        let fp = &self.parameters[j];
                        (p[j] + delta[j]).clamp(fp.lower, fp.upper)
                    })
                    .collect();
                let moved = self.with_values(&trial);
                let c1 = self
                    .residuals(&moved)
                    .map_or(f64::INFINITY, |r| self.layout.weighted_cost(&r, sigma));
                if c1 < c0 {
                    let small_step = (0..np)
                        .all(|j| (trial[j] - p[j]).abs() <= tolerance * p[j].abs().max(1e-300));
                    converged = (c0 - c1) <= tolerance * c0 || small_step;
                    lambda = (lambda / 3.0).max(1e-12);
                    accepted = Some((trial, moved));
                    break;
                }
                lambda *= 4.0;
            }
            let Some((trial, moved)) = accepted else {
                // No step lowers the cost: a minimum to working precision.
                converged = true;
                break;
            };
            point = self.point(trial, moved)?;
        }
        Ok((point, iterations, converged))
    }
}

/// The start state of `model`: `x0`, or its declared initial state (which may depend
/// on the fitted parameters).
fn start<M: Model>(model: &M, x0: Option<&[f64]>) -> Vec<f64> {
    x0.map(<[f64]>::to_vec).unwrap_or_else(|| {
        let mut x = vec![0.0; M::N_STATES];
        model.initial_state(&mut x);
        x
    })
}
