//! Floquet multipliers and the neutral directions of a periodic orbit's monodromy
//! matrix.

use bgdsl_runtime::Model;
use nalgebra::{Complex, DMatrix};

use super::PeriodicOptions;

/// The directions in which the orbit neither attracts nor repels: the singular vectors
/// of the scaled `Φ − I` whose singular values are below
/// [`PeriodicOptions::neutral_tolerance`].
#[derive(Clone, Debug, PartialEq)]
pub struct NeutralDirections {
    /// The dimension of the neutral subspace.
    pub dimension: usize,
    /// The singular values of the scaled `Φ − I` (smallest first), all of them.
    pub singular_values: Vec<f64>,
    /// The part of the unit velocity `f(t₀, x*)/‖f‖` (scaled) in the neutral subspace,
    /// 0 to 1: 1 for an autonomous model (moving along the orbit is neutral), NaN when
    /// the velocity is zero.
    pub along_flow: f64,
    /// `‖Φ f − f‖ / ‖f‖` (scaled) for the velocity `f = f(t₀, x*)`: 0 in exact arithmetic
    /// for an autonomous model, whose multiplier along the orbit is exactly 1.
    pub flow_invariance: f64,
    /// The states the neutral subspace is made of, heaviest first (at most 12), with
    /// their weights (squared components summed over an orthonormal basis of the
    /// subspace, in scaled variables; the weights of all states sum to `dimension`).
    pub states: Vec<(&'static str, f64)>,
}

/// `D⁻¹ (Φ − I) D`.
pub(super) fn scaled_defect(phi: &DMatrix<f64>, d: &[f64]) -> DMatrix<f64> {
    let n = d.len();
    DMatrix::from_fn(n, n, |i, j| {
        let identity = if i == j { 1.0 } else { 0.0 };
        (phi[(i, j)] - identity) * d[j] / d[i]
    })
}

/// The eigenvalues of `phi`, largest modulus first; empty when the Schur iteration does
/// not converge in 100,000 sweeps (nalgebra's own default would iterate forever).
pub(super) fn multipliers(phi: &DMatrix<f64>) -> Vec<Complex<f64>> {
    let Some(schur) = nalgebra::linalg::Schur::try_new(phi.clone(), f64::EPSILON, 100_000) else {
        return Vec::new();
    };
    let mut mu: Vec<Complex<f64>> = schur.complex_eigenvalues().iter().copied().collect();
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.im.total_cmp(&a.im)));
    mu
}

/// The neutral directions of `phi` at the orbit point `x` (scales `d`).
pub(super) fn neutral_directions<M: Model>(
    model: &M,
    options: &PeriodicOptions,
    x: &[f64],
    phi: &DMatrix<f64>,
    d: &[f64],
) -> NeutralDirections {
    let n = x.len();
    let svd = scaled_defect(phi, d).svd(false, true);
    let mut singular_values: Vec<f64> = svd.singular_values.iter().copied().collect();
    let mut weights = vec![0.0; n];
    let mut basis = Vec::new();
    if let Some(v_t) = &svd.v_t {
        for (k, &sigma) in svd.singular_values.iter().enumerate() {
            if sigma <= options.neutral_tolerance {
                let v: Vec<f64> = (0..n).map(|j| v_t[(k, j)]).collect();
                for (w, vj) in weights.iter_mut().zip(&v) {
                    *w += vj * vj;
                }
                basis.push(v);
            }
        }
    }
    singular_values.sort_by(f64::total_cmp);
    let mut f = vec![0.0; n];
    model.derivatives::<f64>(options.t0, x, &mut f);
    let fs: Vec<f64> = f.iter().zip(d).map(|(fi, di)| fi / di).collect();
    let norm = fs.iter().map(|v| v * v).sum::<f64>().sqrt();
    let along_flow = if norm > 0.0 {
        basis
            .iter()
            .map(|v| {
                let c: f64 = v.iter().zip(&fs).map(|(a, b)| a * b).sum::<f64>() / norm;
                c * c
            })
            .sum::<f64>()
            .sqrt()
    } else {
        f64::NAN
    };
    let flow_invariance = if norm > 0.0 {
        let a = scaled_defect(phi, d);
        let defect = &a * nalgebra::DVector::from_vec(fs.clone());
        defect.norm() / norm
    } else {
        f64::NAN
    };
    let mut order: Vec<usize> = (0..n).filter(|&i| weights[i] > 1e-3).collect();
    order.sort_by(|&a, &b| weights[b].total_cmp(&weights[a]));
    order.truncate(12);
    NeutralDirections {
        dimension: basis.len(),
        singular_values,
        along_flow,
        flow_invariance,
        states: order
            .into_iter()
            .map(|i| (M::STATE_NAMES.get(i).copied().unwrap_or("?"), weights[i]))
            .collect(),
    }
}
