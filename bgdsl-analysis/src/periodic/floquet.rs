//! Floquet multipliers and the neutral directions of a periodic orbit's monodromy
//! matrix, in the shooting's unknowns.

use bgdsl_runtime::Model;
use nalgebra::{Complex, DMatrix, DVector};

use super::coordinates::Coordinates;
use super::eigen;
use super::newton::Defect;
use super::PeriodicOptions;

/// The directions in which the orbit neither attracts nor repels: the right singular
/// vectors of the scaled `Φ_z − I` (in the unknowns) whose singular values are below
/// [`PeriodicOptions::neutral_tolerance`].
#[derive(Clone, Debug, PartialEq)]
pub struct NeutralDirections {
    /// The dimension of the neutral subspace.
    pub dimension: usize,
    /// The singular values of the scaled `Φ_z − I` (smallest first), all of them.
    pub singular_values: Vec<f64>,
    /// The part of the unit velocity `f(t₀, x*)/‖f‖` (scaled, in the unknowns) in the
    /// neutral subspace, 0 to 1: 1 for an autonomous model (moving along the orbit is
    /// neutral), NaN when the velocity is zero.
    pub along_flow: f64,
    /// `‖Φ f − f‖ / ‖f‖` (scaled, in the unknowns) for the velocity `f = f(t₀, x*)`:
    /// 0 in exact arithmetic for an autonomous model, whose multiplier along the orbit
    /// is exactly 1.
    pub flow_invariance: f64,
    /// The unknowns the neutral subspace is made of, heaviest first (at most 12), with
    /// their weights (squared components summed over an orthonormal basis of the
    /// subspace, in scaled unknowns; the weights of all unknowns sum to `dimension`):
    /// a state by its name, a rigid body's rotation (its three angles together) by the
    /// body's name.
    pub states: Vec<(&'static str, f64)>,
}

/// The eigenvalues of `a + I`, largest modulus first (`a` the scaled `Φ_z − I`, so
/// these are the multipliers: a similarity does not move eigenvalues). Empty when the QR
/// iteration does not converge ([`eigen::eigenvalues`]).
pub(super) fn multipliers(a: &DMatrix<f64>) -> Vec<Complex<f64>> {
    let n = a.nrows();
    let phi = a + DMatrix::<f64>::identity(n, n);
    let Some(mut mu) = eigen::eigenvalues(&phi) else {
        return Vec::new();
    };
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.im.total_cmp(&a.im)));
    mu
}

/// The neutral directions at the orbit point `x`, from the decomposition of the scaled
/// defect in the unknowns (scales `s`).
pub(super) fn neutral_directions<M: Model>(
    model: &M,
    options: &PeriodicOptions,
    x: &[f64],
    coordinates: &Coordinates,
    defect: &Defect,
    s: &[f64],
) -> NeutralDirections {
    let basis = &defect.right_neutral;
    let mut weights: Vec<(&'static str, f64)> = Vec::new();
    for k in 0..coordinates.len() {
        let w = basis.row(k).norm_squared();
        let name = coordinates.name::<M>(k);
        match weights.iter_mut().find(|(n, _)| *n == name) {
            Some((_, total)) => *total += w,
            None => weights.push((name, w)),
        }
    }
    let mut singular_values = defect.singular_values.clone();
    singular_values.sort_by(f64::total_cmp);
    let mut f = vec![0.0; x.len()];
    model.derivatives::<f64>(options.t0, x, &mut f);
    let fz = coordinates.tangent(x, &DMatrix::from_column_slice(f.len(), 1, &f));
    let fs = DVector::from_fn(s.len(), |k, _| fz[(k, 0)] / s[k]);
    let norm = fs.norm();
    let (along_flow, flow_invariance) = if norm > 0.0 {
        (
            (basis.transpose() * &fs).norm() / norm,
            (&defect.a * &fs).norm() / norm,
        )
    } else {
        (f64::NAN, f64::NAN)
    };
    weights.retain(|(_, w)| *w > 1e-3);
    weights.sort_by(|a, b| b.1.total_cmp(&a.1));
    weights.truncate(12);
    NeutralDirections {
        dimension: basis.ncols(),
        singular_values,
        along_flow,
        flow_invariance,
        states: weights,
    }
}
