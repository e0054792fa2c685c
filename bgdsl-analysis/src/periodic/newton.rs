//! The shooting Newton step in scaled unknowns, `A y = −r` with `A = S⁻¹ (Φ_z − I) S`,
//! taken inside the range of `A`.
//!
//! Why inside the range: where `Φ_z` has the multiplier 1 (a first integral of the
//! model, or the autonomous model's motion along its orbit), `P(x) = x` has a whole
//! family of solutions, and a run from `x` settles on one of them: the one with `x`'s
//! values of the first integrals and `x`'s asymptotic phase. The error of `x` relative
//! to that point lies in the decaying invariant subspace, which (the multiplier 1 being
//! semisimple) is the range of `Φ_z − I`: the orthogonal complement of its left null
//! vectors, the gradients of the first integrals and of the asymptotic phase. A step
//! inside it changes neither, to first order; a minimum-norm step of the whole least
//! squares problem would, and lands on another member of the family (on the quick
//! return: the slider's lever point on the rocker, `slider.r − rocker.r`, a first
//! integral of its joint springs and positions, moved by 1e-4 m).

use nalgebra::{DMatrix, DVector, Dyn, SVD};

/// The scaled defect `A`'s decomposition, split at the neutral tolerance.
pub(super) struct Defect {
    /// `A = S⁻¹ (Φ_z − I) S`.
    pub a: DMatrix<f64>,
    /// Its singular values, in the SVD's order.
    pub singular_values: Vec<f64>,
    /// The left singular vectors of the singular values at most the tolerance: the
    /// left null space (first integrals, asymptotic phase), orthonormal columns.
    pub left_neutral: DMatrix<f64>,
    /// The other left singular vectors: an orthonormal basis of the range of `A`.
    pub range: DMatrix<f64>,
    /// The right singular vectors of the neutral singular values: the null space
    /// (directions the period map returns unchanged).
    pub right_neutral: DMatrix<f64>,
    /// The SVD of `A` restricted to its range (`A · range`), for the step.
    restricted: SVD<f64, Dyn, Dyn>,
    /// The neutral tolerance.
    neutral: f64,
}

/// The columns of `m` whose flag is set, as a matrix.
fn columns(m: &DMatrix<f64>, keep: &[bool]) -> DMatrix<f64> {
    let chosen: Vec<usize> = (0..m.ncols()).filter(|&k| keep[k]).collect();
    DMatrix::from_fn(m.nrows(), chosen.len(), |i, j| m[(i, chosen[j])])
}

impl Defect {
    /// Decomposes `a` (square), singular values at most `neutral` being neutral.
    pub(super) fn new(a: DMatrix<f64>, neutral: f64) -> Self {
        let svd = a.clone().svd(true, true);
        let singular_values: Vec<f64> = svd.singular_values.iter().copied().collect();
        let is_neutral: Vec<bool> = singular_values.iter().map(|&s| s <= neutral).collect();
        let not_neutral: Vec<bool> = is_neutral.iter().map(|&b| !b).collect();
        // Both are computed when asked for; the identity only keeps this total.
        let n = a.nrows();
        let u = svd.u.unwrap_or_else(|| DMatrix::identity(n, n));
        let v = svd
            .v_t
            .map_or_else(|| DMatrix::identity(n, n), |v_t| v_t.transpose());
        let left_neutral = columns(&u, &is_neutral);
        let range = columns(&u, &not_neutral);
        let right_neutral = columns(&v, &is_neutral);
        let restricted = (&a * &range).svd(true, true);
        Defect {
            a,
            singular_values,
            left_neutral,
            range,
            right_neutral,
            restricted,
            neutral,
        }
    }

    /// The scaled residual `r` split into its part outside the left null space (largest
    /// entry, and where) and inside it (largest entry): Newton can remove only the first.
    pub(super) fn split(&self, r: &[f64]) -> (f64, usize, f64) {
        let r = DVector::from_column_slice(r);
        let inside = &self.left_neutral * (self.left_neutral.transpose() * &r);
        let outside = &r - &inside;
        let (mut worst, mut at) = (0.0, 0);
        for (i, v) in outside.iter().enumerate() {
            if v.abs() > worst || v.is_nan() {
                worst = v.abs();
                at = i;
            }
        }
        (worst, at, inside.amax())
    }

    /// The damped Newton correction `y` in the range of `A` for `A y = −r`:
    /// `−Σ σ/(σ² + μ²) (uᵀr) v` over the SVD of `A` restricted to its range, singular
    /// values at most the neutral tolerance left out (`μ = 0`: Newton's step).
    pub(super) fn step(&self, r: &[f64], mu: f64) -> Vec<f64> {
        let svd = &self.restricted;
        let (Some(u), Some(v_t)) = (&svd.u, &svd.v_t) else {
            return vec![0.0; r.len()];
        };
        let r = DVector::from_column_slice(r);
        let mut w = DVector::<f64>::zeros(self.range.ncols());
        for (k, &sigma) in svd.singular_values.iter().enumerate() {
            if sigma <= self.neutral {
                continue;
            }
            let projection = u.column(k).dot(&r);
            let coefficient = projection * sigma / (sigma * sigma + mu * mu);
            w.axpy(-coefficient, &v_t.row(k).transpose(), 1.0);
        }
        (&self.range * w).iter().copied().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map with a first integral: `Φ = [[0.5, 0.2], [0, 1]]` keeps `x₂` (left null
    /// vector `(0, 1)` of `Φ − I`) and contracts `x₁` towards `0.4 x₂`. From
    /// `(1, 1)` the iteration `x ← Φx` settles at `(0.4, 1)`; the step in the range
    /// lands there in one go, where the minimum-norm step would move `x₂` too.
    #[test]
    fn the_step_keeps_the_first_integral() {
        let phi = DMatrix::from_row_slice(2, 2, &[0.5, 0.2, 0.0, 1.0]);
        let a = &phi - DMatrix::<f64>::identity(2, 2);
        let defect = Defect::new(a.clone(), 1e-12);
        assert_eq!(defect.left_neutral.ncols(), 1);
        let x = DVector::from_column_slice(&[1.0, 1.0]);
        let r = &a * &x;
        let y = defect.step(r.as_slice(), 0.0);
        let next = &x + DVector::from_column_slice(&y);
        assert!((next[0] - 0.4).abs() < 1e-15, "{next}");
        assert!((next[1] - 1.0).abs() < 1e-15, "{next}");
        let (outside, _, inside) = defect.split((&a * &next).as_slice());
        assert!(outside < 1e-15 && inside < 1e-15);
    }
}
