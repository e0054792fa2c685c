//! The modes of a linear model: eigenvalues of `A` with natural frequency, damping
//! ratio and the states that take part in each.
//!
//! nalgebra gives the eigenvalues of a general real matrix (Schur form) but not its
//! eigenvectors; each right and left eigenvector here comes from three steps of inverse
//! iteration on `A − λI`, shifted off `λ` by a relative `1e-10` so the matrix stays
//! invertible. The iteration runs on the real Schur form `A = Q T Qᵀ` computed once
//! for the eigenvalues: `T − λI` is upper Hessenberg, so each mode costs `O(n²)`
//! (a pivoted elimination between adjacent rows) instead of a dense complex LU,
//! `O(n³)`, and the iterates are `Qᵀ` times those on `A − λI`. The participation factor of state `i` in mode `k` is
//! `|wᵢ vᵢ| / Σⱼ |wⱼ vⱼ|` (Pérez-Arriaga, Verghese and Schweppe, 1982): it does not
//! depend on the states' units, which a plain eigenvector component does.

use nalgebra::{Complex, DMatrix, DVector, Schur};

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
    let schur = Schur::new(a.clone());
    let eigenvalues = schur.complex_eigenvalues();
    let (q, t) = schur.unpack();
    let q = q.map(|v| Complex::new(v, 0.0));
    let start = DVector::from_fn(n, |i, _| {
        Complex::new(1.0 + (i as f64 * 0.7).sin() * 0.5, 0.3)
    });
    let schur = SchurForm {
        start: q.tr_mul(&start),
        t: t.map(|v| Complex::new(v, 0.0)),
        q,
    };
    let scale = a.amax().max(f64::MIN_POSITIVE);
    let mut modes: Vec<Mode> = eigenvalues
        .iter()
        .filter(|l| l.im >= 0.0)
        .map(|&l| {
            let v = inverse_iteration(&schur, l, scale, false);
            let w = inverse_iteration(&schur, l, scale, true);
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

/// An eigenvector of `a = Q T Qᵀ` (of `aᵀ` when `left`) for the eigenvalue `lambda`,
/// unit norm: inverse iteration on the quasi-triangular `T − σI` (`Tᵀ − σI`), whose
/// iterates are `Qᵀ` times those on `a − σI` from the start `Qᵀ s`.
fn inverse_iteration(
    schur: &SchurForm,
    lambda: Complex<f64>,
    scale: f64,
    left: bool,
) -> DVector<Complex<f64>> {
    let shift = lambda + Complex::new(1e-10 * scale, 1e-10 * scale);
    let lu = HessenbergLu::new(&schur.t, shift);
    let mut y = schur.start.clone();
    for _ in 0..3 {
        let mut next = y.clone();
        if !lu.solve(&mut next, left) {
            break;
        }
        let norm = next.norm();
        if !(norm.is_finite() && norm > 0.0) {
            break;
        }
        y = next.unscale(norm);
    }
    &schur.q * y
}

/// The real Schur form `a = Q T Qᵀ` (`T` quasi-upper-triangular, so upper Hessenberg),
/// complex, with the inverse iterations' start in its coordinates.
struct SchurForm {
    q: DMatrix<Complex<f64>>,
    t: DMatrix<Complex<f64>>,
    /// `Qᵀ s`, `s` a start with every component non-zero and no special direction.
    start: DVector<Complex<f64>>,
}

/// `H − σI = P L U` for an upper Hessenberg `H` by Gaussian elimination with partial
/// pivoting: each step pivots between two adjacent rows, so a factorization and a
/// solve cost `O(n²)`.
struct HessenbergLu {
    /// `U`, upper triangular.
    u: DMatrix<Complex<f64>>,
    /// Step `k`'s multiplier of row `k` subtracted from row `k + 1`, and whether the two
    /// rows were swapped first.
    steps: Vec<(Complex<f64>, bool)>,
}

impl HessenbergLu {
    /// Factors `h − shift I` (`h` upper Hessenberg; entries below its subdiagonal are
    /// taken as zero).
    fn new(h: &DMatrix<Complex<f64>>, shift: Complex<f64>) -> Self {
        let n = h.nrows();
        let zero = Complex::new(0.0, 0.0);
        let mut u = DMatrix::from_fn(n, n, |i, j| {
            if i > j + 1 {
                zero
            } else if i == j {
                h[(i, j)] - shift
            } else {
                h[(i, j)]
            }
        });
        let mut steps = Vec::with_capacity(n.saturating_sub(1));
        for k in 0..n.saturating_sub(1) {
            // Rows k and k + 1 are zero left of column k: swapping whole rows is exact.
            let swap = u[(k + 1, k)].norm() > u[(k, k)].norm();
            if swap {
                u.swap_rows(k, k + 1);
            }
            let pivot = u[(k, k)];
            let l = if pivot == zero {
                zero
            } else {
                u[(k + 1, k)] / pivot
            };
            u[(k + 1, k)] = zero;
            for j in k + 1..n {
                let ukj = u[(k, j)];
                u[(k + 1, j)] -= l * ukj;
            }
            steps.push((l, swap));
        }
        HessenbergLu { u, steps }
    }

    /// Solves `(H − σI) x = b` (`(H − σI)ᵀ x = b` when `transposed`; no conjugation),
    /// overwriting `b`; `false` if a pivot is zero.
    fn solve(&self, b: &mut DVector<Complex<f64>>, transposed: bool) -> bool {
        let (u, n) = (&self.u, self.u.nrows());
        if (0..n).any(|i| u[(i, i)] == Complex::new(0.0, 0.0)) {
            return false;
        }
        if transposed {
            // Uᵀ z = b, then the steps' transposes in reverse order.
            for i in 0..n {
                let mut s = b[i];
                for j in 0..i {
                    s -= u[(j, i)] * b[j];
                }
                b[i] = s / u[(i, i)];
            }
            for (k, &(l, swap)) in self.steps.iter().enumerate().rev() {
                let next = b[k + 1];
                b[k] -= l * next;
                if swap {
                    b.swap_rows(k, k + 1);
                }
            }
        } else {
            for (k, &(l, swap)) in self.steps.iter().enumerate() {
                if swap {
                    b.swap_rows(k, k + 1);
                }
                let here = b[k];
                b[k + 1] -= l * here;
            }
            for i in (0..n).rev() {
                let mut s = b[i];
                for j in i + 1..n {
                    s -= u[(i, j)] * b[j];
                }
                b[i] = s / u[(i, i)];
            }
        }
        true
    }
}
