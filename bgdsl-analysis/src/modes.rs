//! The modes of a linear model: eigenvalues of `A` with natural frequency, damping
//! ratio and the states that take part in each.
//!
//! nalgebra gives the eigenvalues of a general real matrix (Schur form) but not its
//! eigenvectors; each right and left eigenvector here comes from two steps of inverse
//! iteration on `A − λI` (complex LU), shifted off `λ` by a relative `1e-10` so the
//! matrix stays invertible. The participation factor of state `i` in mode `k` is
//! `|wᵢ vᵢ| / Σⱼ |wⱼ vⱼ|` (Pérez-Arriaga, Verghese and Schweppe, 1982): it does not
//! depend on the states' units, which a plain eigenvector component does.

use nalgebra::{Complex, DMatrix, DVector};

/// One mode: an eigenvalue of `A` (for a complex pair, the one with positive
/// imaginary part stands for both).
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// The eigenvalue, 1/s.
    pub eigenvalue: Complex<f64>,
    /// The natural frequency `|λ|`, rad/s.
    pub natural_frequency: f64,
    /// The damping ratio `−Re λ / |λ|` (1 for a stable real eigenvalue, negative for
    /// an unstable mode; NaN for `λ = 0`).
    pub damping_ratio: f64,
    /// Participation factor of each state (summing to 1).
    pub participation: Vec<f64>,
    /// The states with the largest participation, largest first, down to a tenth of
    /// the largest (at most five).
    pub dominant: Vec<usize>,
}

impl Mode {
    /// The damped frequency `|Im λ|`, rad/s (0 for a real eigenvalue).
    pub fn damped_frequency(&self) -> f64 {
        self.eigenvalue.im.abs()
    }
}

/// The modes of `a`, sorted by natural frequency (complex pairs once, with positive
/// imaginary part).
pub fn modes(a: &DMatrix<f64>) -> Vec<Mode> {
    let n = a.nrows();
    if n == 0 {
        return Vec::new();
    }
    let eigenvalues = a.complex_eigenvalues();
    let scale = a.amax().max(f64::MIN_POSITIVE);
    let mut modes: Vec<Mode> = eigenvalues
        .iter()
        .filter(|l| l.im >= 0.0)
        .map(|&l| {
            let v = inverse_iteration(a, l, scale, false);
            let w = inverse_iteration(a, l, scale, true);
            let products: Vec<f64> = v
                .iter()
                .zip(w.iter())
                .map(|(v, w)| (v * w).norm())
                .collect();
            let total: f64 = products.iter().sum();
            let participation: Vec<f64> = if total > 0.0 {
                products.iter().map(|p| p / total).collect()
            } else {
                // A defective eigenvalue (a Jordan block: wᵀv = 0): the eigenvector's
                // own components stand in.
                let big = v
                    .iter()
                    .map(|c| c.norm())
                    .sum::<f64>()
                    .max(f64::MIN_POSITIVE);
                v.iter().map(|c| c.norm() / big).collect()
            };
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&i, &j| participation[j].total_cmp(&participation[i]));
            let top = participation[order[0]];
            let dominant = order
                .into_iter()
                .take(5)
                .take_while(|&i| participation[i] >= 0.1 * top)
                .collect();
            let natural_frequency = l.norm();
            Mode {
                eigenvalue: l,
                natural_frequency,
                damping_ratio: -l.re / natural_frequency,
                participation,
                dominant,
            }
        })
        .collect();
    modes.sort_by(|a, b| a.natural_frequency.total_cmp(&b.natural_frequency));
    modes
}

/// An eigenvector of `a` (of `aᵀ` when `left`) for the eigenvalue `lambda`, unit norm.
fn inverse_iteration(
    a: &DMatrix<f64>,
    lambda: Complex<f64>,
    scale: f64,
    left: bool,
) -> DVector<Complex<f64>> {
    let n = a.nrows();
    let shift = lambda + Complex::new(1e-10 * scale, 1e-10 * scale);
    let m = DMatrix::from_fn(n, n, |i, j| {
        let entry = if left { a[(j, i)] } else { a[(i, j)] };
        Complex::new(entry, 0.0)
            - if i == j {
                shift
            } else {
                Complex::new(0.0, 0.0)
            }
    });
    let lu = m.lu();
    // A start with every component non-zero and no special direction.
    let mut v = DVector::from_fn(n, |i, _| {
        Complex::new(1.0 + (i as f64 * 0.7).sin() * 0.5, 0.3)
    });
    for _ in 0..3 {
        let Some(next) = lu.solve(&v) else {
            break;
        };
        let norm = next.norm();
        if !(norm.is_finite() && norm > 0.0) {
            break;
        }
        v = next.unscale(norm);
    }
    v
}
