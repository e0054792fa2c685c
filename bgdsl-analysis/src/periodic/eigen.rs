//! The eigenvalues of a small dense real matrix: balancing, Hessenberg reduction
//! (nalgebra's), then the implicit double-shift (Francis) QR iteration with deflation
//! and exceptional shifts (Golub & Van Loan, *Matrix Computations*, 4th ed., §7.5;
//! balancing: Parlett & Reinsch, Numer. Math. 13 (1969)).
//!
//! Why not nalgebra's `Schur`: it has no exceptional shifts, and on the quick return's
//! monodromy matrix (a cluster of multipliers at exactly 1, entries over ten orders of
//! magnitude) it cycles without converging.

use nalgebra::{Complex, DMatrix};

/// QR sweeps allowed per eigenvalue found (LAPACK's `dlahqr` allows 30).
const SWEEPS_PER_EIGENVALUE: usize = 30;

/// Sweeps without a deflation after which a window is split at its smallest
/// subdiagonal entry if that is below [`STALLED_SPLIT`] (relative to its diagonal
/// neighbours).
const STALL: usize = 30;

/// The backward error accepted to split a stalled window: a cluster of (nearly)
/// defective eigenvalues — the quick return's multipliers at exactly 1 — makes the
/// subdiagonal converge only linearly. A perturbation of `1e-11` relative is far below
/// the error of a monodromy matrix integrated at `rtol` 1e-9.
const STALLED_SPLIT: f64 = 1e-11;

/// Zeroes the window's smallest subdiagonal entry (relative to its diagonal
/// neighbours) if it is below [`STALLED_SPLIT`]; whether it did.
fn split_stalled_window(h: &mut DMatrix<f64>, (lo, hi): (usize, usize)) -> bool {
    let relative = |h: &DMatrix<f64>, k: usize| {
        let scale = h[(k - 1, k - 1)].abs() + h[(k, k)].abs();
        if scale > 0.0 {
            h[(k, k - 1)].abs() / scale
        } else {
            f64::INFINITY
        }
    };
    let Some(k) = (lo + 1..=hi).min_by(|&a, &b| relative(h, a).total_cmp(&relative(h, b))) else {
        return false;
    };
    if relative(h, k) <= STALLED_SPLIT {
        h[(k, k - 1)] = 0.0;
        true
    } else {
        false
    }
}

/// `D⁻¹ A D` with `D` diagonal, powers of 2, making each row's and column's off-diagonal
/// norms comparable: the same eigenvalues, computed more accurately.
fn balance(a: &mut DMatrix<f64>) {
    let n = a.nrows();
    for _ in 0..100 {
        let mut changed = false;
        for i in 0..n {
            let c: f64 = (0..n).filter(|&j| j != i).map(|j| a[(j, i)].abs()).sum();
            let r: f64 = (0..n).filter(|&j| j != i).map(|j| a[(i, j)].abs()).sum();
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let (mut f, mut c2, mut r2) = (1.0, c, r);
            while c2 < r2 / 2.0 {
                (c2, r2, f) = (c2 * 2.0, r2 / 2.0, f * 2.0);
            }
            while c2 >= r2 * 2.0 {
                (c2, r2, f) = (c2 / 2.0, r2 * 2.0, f / 2.0);
            }
            if c2 + r2 < 0.95 * (c + r) {
                changed = true;
                for j in 0..n {
                    a[(i, j)] /= f;
                    a[(j, i)] *= f;
                }
            }
        }
        if !changed {
            break;
        }
    }
}

/// The Householder vector `v` (with `v₀ = 1`) and `β = 2/vᵀv` that map `x` onto a
/// multiple of the first unit vector; `None` when `x` is zero already below its top.
fn householder<const K: usize>(x: [f64; K]) -> Option<([f64; K], f64)> {
    let tail: f64 = x[1..].iter().map(|v| v * v).sum();
    if tail == 0.0 {
        return None;
    }
    let norm = (x[0] * x[0] + tail).sqrt();
    let v0 = if x[0] <= 0.0 {
        x[0] - norm
    } else {
        -tail / (x[0] + norm)
    };
    let mut v = x;
    v[0] = 1.0;
    for vi in &mut v[1..] {
        *vi /= v0;
    }
    let vtv: f64 = v.iter().map(|vi| vi * vi).sum();
    Some((v, 2.0 / vtv))
}

/// `H ← P H P` for the reflector `P = I − β v vᵀ` acting on rows and columns
/// `k..k + K`, within the active window `lo..=hi`.
fn reflect<const K: usize>(
    h: &mut DMatrix<f64>,
    (v, beta): ([f64; K], f64),
    k: usize,
    (lo, hi): (usize, usize),
) {
    for j in k.saturating_sub(1).max(lo)..=hi {
        let s: f64 = (0..K).map(|i| v[i] * h[(k + i, j)]).sum::<f64>() * beta;
        for i in 0..K {
            h[(k + i, j)] -= s * v[i];
        }
    }
    for i in lo..=(k + K).min(hi) {
        let s: f64 = (0..K).map(|j| h[(i, k + j)] * v[j]).sum::<f64>() * beta;
        for j in 0..K {
            h[(i, k + j)] -= s * v[j];
        }
    }
}

/// One Francis double-shift sweep on the Hessenberg window `lo..=hi` (at least 3 × 3)
/// with shifts the roots of `λ² − s λ + t`.
fn francis_sweep(h: &mut DMatrix<f64>, (lo, hi): (usize, usize), s: f64, t: f64) {
    let mut x = h[(lo, lo)] * h[(lo, lo)] + h[(lo, lo + 1)] * h[(lo + 1, lo)] - s * h[(lo, lo)] + t;
    let mut y = h[(lo + 1, lo)] * (h[(lo, lo)] + h[(lo + 1, lo + 1)] - s);
    let mut z = h[(lo + 1, lo)] * h[(lo + 2, lo + 1)];
    for k in lo..hi - 1 {
        if let Some(p) = householder([x, y, z]) {
            reflect(h, p, k, (lo, hi));
        }
        x = h[(k + 1, k)];
        y = h[(k + 2, k)];
        if k + 3 <= hi {
            z = h[(k + 3, k)];
        }
    }
    if let Some(p) = householder([x, y]) {
        reflect(h, p, hi - 1, (lo, hi));
    }
}

/// The eigenvalues of the 2 × 2 block at `k`.
fn pair(h: &DMatrix<f64>, k: usize) -> [Complex<f64>; 2] {
    let (a, b, c, d) = (h[(k, k)], h[(k, k + 1)], h[(k + 1, k)], h[(k + 1, k + 1)]);
    let mean = 0.5 * (a + d);
    let half = 0.5 * (a - d);
    let disc = half * half + b * c;
    if disc >= 0.0 {
        let root = disc.sqrt();
        // The larger root first, the other from the determinant (no cancellation).
        let big = if mean >= 0.0 {
            mean + root
        } else {
            mean - root
        };
        let small = if big != 0.0 {
            (a * d - b * c) / big
        } else {
            0.0
        };
        [Complex::new(big, 0.0), Complex::new(small, 0.0)]
    } else {
        let im = (-disc).sqrt();
        [Complex::new(mean, im), Complex::new(mean, -im)]
    }
}

/// The eigenvalues of `a` (square), in no particular order; `None` when the QR
/// iteration has not converged after [`SWEEPS_PER_EIGENVALUE`] sweeps per eigenvalue.
pub(super) fn eigenvalues(a: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    let n = a.nrows();
    let mut b = a.clone();
    balance(&mut b);
    let mut h = nalgebra::linalg::Hessenberg::new(b).unpack_h();
    let mut out = Vec::with_capacity(n);
    let mut sweeps = 0;
    let mut hi = n as isize - 1;
    let mut since_deflation = 0;
    while hi >= 0 {
        let end = hi as usize;
        // The window's start: below the last negligible subdiagonal entry.
        let mut lo = end;
        while lo > 0 {
            let scale = h[(lo - 1, lo - 1)].abs() + h[(lo, lo)].abs();
            if h[(lo, lo - 1)].abs() <= f64::EPSILON * scale || h[(lo, lo - 1)] == 0.0 {
                h[(lo, lo - 1)] = 0.0;
                break;
            }
            lo -= 1;
        }
        if lo == end {
            out.push(Complex::new(h[(end, end)], 0.0));
            hi -= 1;
            since_deflation = 0;
            continue;
        }
        if lo + 1 == end {
            out.extend(pair(&h, lo));
            hi -= 2;
            since_deflation = 0;
            continue;
        }
        if sweeps >= SWEEPS_PER_EIGENVALUE * n {
            return None;
        }
        if since_deflation >= STALL && split_stalled_window(&mut h, (lo, end)) {
            since_deflation = 0;
            continue;
        }
        sweeps += 1;
        since_deflation += 1;
        let (s, t) = if since_deflation % 10 == 0 {
            // An exceptional shift (a double real one near the corner) breaks the
            // cycles the standard shifts can fall into.
            let mu = h[(end, end)] + 0.75 * (h[(end, end - 1)].abs() + h[(end - 1, end - 2)].abs());
            (2.0 * mu, mu * mu)
        } else {
            let (p, q) = (end - 1, end);
            (
                h[(p, p)] + h[(q, q)],
                h[(p, p)] * h[(q, q)] - h[(p, q)] * h[(q, p)],
            )
        };
        francis_sweep(&mut h, (lo, end), s, t);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Eigenvalues placed by a similarity `V diag V⁻¹` come back to round-off: a
    /// complex pair, a cluster of three at exactly 1, entries over ten orders of
    /// magnitude (a diagonal scaling `10^±5` on top).
    #[test]
    fn eigenvalues_of_a_matrix_with_known_spectrum() {
        let n = 9;
        let mut d = DMatrix::<f64>::zeros(n, n);
        let reals = [1.0, 1.0, 1.0, 0.3, -0.2, 1e-6, 0.0];
        for (i, r) in reals.iter().enumerate() {
            d[(i, i)] = *r;
        }
        // 0.5 ± 0.4i as a real 2 × 2 block.
        d[(7, 7)] = 0.5;
        d[(8, 8)] = 0.5;
        d[(7, 8)] = 0.4;
        d[(8, 7)] = -0.4;
        let v = DMatrix::<f64>::from_fn(n, n, |i, j| {
            let x = ((i * 7 + j * 3) % 11) as f64 / 11.0 - 0.4;
            if i == j {
                2.0 + x
            } else {
                x
            }
        });
        let scale = DMatrix::<f64>::from_fn(n, n, |i, j| {
            if i == j {
                10f64.powi(5 - (i as i32 * 10) / (n as i32 - 1))
            } else {
                0.0
            }
        });
        let sv = &scale * &v;
        let a = &sv * d * sv.try_inverse().unwrap();
        let mut got = eigenvalues(&a).unwrap();
        got.sort_by(|a, b| b.re.total_cmp(&a.re).then(b.im.total_cmp(&a.im)));
        let want = [
            Complex::new(1.0, 0.0),
            Complex::new(1.0, 0.0),
            Complex::new(1.0, 0.0),
            Complex::new(0.5, 0.4),
            Complex::new(0.5, -0.4),
            Complex::new(0.3, 0.0),
            Complex::new(1e-6, 0.0),
            Complex::new(0.0, 0.0),
            Complex::new(-0.2, 0.0),
        ];
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).norm() < 1e-9, "{got:?}");
        }
    }
}
