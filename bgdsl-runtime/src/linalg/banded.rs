//! Banded LU factorization with partial pivoting, real and complex, for the iteration
//! matrices `σ I - J` of the implicit solvers.
//!
//! Both factorizations work in place in storage allocated once by `new`; assembling,
//! factoring and solving allocate nothing. Matrices are square, `n × n`, with the band
//! declared at set-up: `kl` diagonals below the main one and `ku` above (from the
//! Jacobian's sparsity pattern, see [`Band::of_pattern`]; a dense matrix has
//! `kl = ku = n - 1`). Only the band is stored: row `i` holds the `w = min(2 kl + ku + 1,
//! n)` columns from `lo(i) = max(i - kl, 0)` on (the band and the fill-in of partial
//! pivoting), so storage is `n w` numbers, `n²` only for a dense matrix (where it is
//! plain row-major). Elimination is Gaussian with partial pivoting in the form of
//! LINPACK's `dgbfa`: at step `k` the largest entry of column `k` (in modulus; for
//! complex entries `|re| + |im|`) among the `kl` rows below is swapped up (only the
//! columns from `k` on: the multipliers stay where they were computed), and the rows
//! below are updated by contiguous row operations. The factor `U` then has upper
//! bandwidth `kl + ku`, so each factorization costs `O(n kl (kl + ku))` and each solve
//! `O(n (2 kl + ku))`, instead of `O(n^3)` and `O(n^2)`.
//!
//! The complex factorization stores real and imaginary parts in two separate arrays
//! ("split" storage), so that its row updates are real vector operations too.

use super::Singular;
use crate::jacobian::Jacobian;

/// The band of an `n × n` matrix: entry `(i, j)` may be non-zero only if
/// `i - kl <= j <= i + ku`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Band {
    n: usize,
    /// Lower bandwidth.
    pub kl: usize,
    /// Upper bandwidth.
    pub ku: usize,
}

impl Band {
    /// The full band of a dense `n × n` matrix.
    #[cfg(test)]
    pub fn dense(n: usize) -> Self {
        let w = n.saturating_sub(1);
        Band { n, kl: w, ku: w }
    }

    /// The smallest band holding the diagonal and every entry of the rows `rows(i)`
    /// (the columns that may be non-zero in row `i`), for `i` in `0..n`.
    pub fn of_pattern<'a>(n: usize, rows: impl Fn(usize) -> &'a [usize]) -> Self {
        let (mut kl, mut ku) = (0, 0);
        for i in 0..n {
            for &j in rows(i) {
                if j < i {
                    kl = kl.max(i - j);
                } else {
                    ku = ku.max(j - i);
                }
            }
        }
        Band { n, kl, ku }
    }

    /// Multiply-adds of one real factorization (at most: partial pivoting may need
    /// fewer).
    pub fn flops(&self) -> usize {
        let Band { n, kl, ku } = *self;
        (0..n)
            .map(|k| {
                let below = kl.min(n - 1 - k);
                below * ((kl + ku).min(n - 1 - k) + 1)
            })
            .sum()
    }

    /// The number of rows (and columns).
    pub fn n(&self) -> usize {
        self.n
    }

    /// The width of a stored row: `min(2 kl + ku + 1, n)`.
    #[inline]
    pub fn width(&self) -> usize {
        (2 * self.kl + self.ku + 1).min(self.n)
    }

    /// The numbers one matrix of this band stores: `n` rows of [`Band::width`].
    pub fn storage(&self) -> usize {
        self.n * self.width()
    }

    /// The first column stored for row `i`.
    #[inline]
    fn lo(&self, i: usize) -> usize {
        i.saturating_sub(self.kl).min(self.n - self.width())
    }

    /// The columns row `i` may hold during and after factorization: `[i - kl,
    /// i + kl + ku]`, clipped to the matrix.
    #[inline]
    fn window(&self, i: usize) -> (usize, usize) {
        (
            i.saturating_sub(self.kl),
            (i + self.kl + self.ku + 1).min(self.n),
        )
    }

    /// Where entry `(i, j)` (within row `i`'s window) is stored.
    #[inline]
    fn index(&self, i: usize, j: usize) -> usize {
        i * self.width() + j - self.lo(i)
    }
}

/// Writes `shift I - jac` into band storage `a` (row `i`'s window zeroed first, which
/// also clears the fill-in of an earlier factorization).
fn set_shifted(band: &Band, a: &mut [f64], shift: f64, jac: &Jacobian) {
    for i in 0..band.n {
        let (lo, hi) = band.window(i);
        a[band.index(i, lo)..band.index(i, hi - 1) + 1].fill(0.0);
        let (cols, values) = jac.row(i);
        for (&j, &v) in cols.iter().zip(values) {
            a[band.index(i, j)] = -v;
        }
        a[band.index(i, i)] += shift;
    }
}

/// `A = P L U` of a real banded `n × n` matrix, computed in place.
#[derive(Clone, Debug)]
pub(crate) struct Lu {
    band: Band,
    /// The matrix before [`Lu::factor`]; the multipliers of `L` (strictly below the
    /// diagonal, where they were computed) and `U` after; band storage.
    a: Vec<f64>,
    /// At step `k`, row `k` was swapped with row `piv[k]`.
    piv: Vec<usize>,
    /// The multipliers of step `k`, contiguous: `mult[k * kl + r]` for row `k + 1 + r`.
    mult: Vec<f64>,
    /// `1 / U_kk`: the back substitution multiplies (division would make its chain of
    /// dependent operations several times longer).
    inv_diag: Vec<f64>,
}

impl Lu {
    /// Storage for `n × n` matrices with band `band`.
    pub fn new(band: Band) -> Self {
        let n = band.n;
        Lu {
            band,
            a: vec![0.0; band.storage()],
            piv: vec![0; n],
            mult: vec![0.0; n * band.kl],
            inv_diag: vec![0.0; n],
        }
    }

    /// Sets the matrix to `shift I - jac`; `jac` must be zero outside the band.
    pub fn set_shifted(&mut self, shift: f64, jac: &Jacobian) {
        set_shifted(&self.band, &mut self.a, shift, jac);
    }

    /// The matrix to be factored, dense row-major, for tests (only for a dense band);
    /// entries outside the band must stay zero.
    #[cfg(test)]
    pub fn matrix_mut(&mut self) -> &mut [f64] {
        assert_eq!(self.band.width(), self.band.n);
        &mut self.a
    }

    /// Factors the matrix in place. On error the storage holds a partly factored
    /// matrix and must be set again before the next [`Lu::factor`].
    pub fn factor(&mut self) -> Result<(), Singular> {
        let band = self.band;
        let Band { n, kl, ku } = band;
        let w = band.width();
        let a = &mut self.a[..];
        for k in 0..n {
            let rows_end = (k + kl + 1).min(n);
            let cols_end = (k + kl + ku + 1).min(n);
            // The pivot: the largest entry of column k on or below the diagonal.
            let mut p = k;
            let mut best = a[band.index(k, k)].abs();
            for i in k + 1..rows_end {
                let v = a[band.index(i, k)].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            self.piv[k] = p;
            // `!(best > 0)` also catches NaN.
            if !(best > 0.0 && best.is_finite()) {
                return Err(Singular { column: k });
            }
            let len = cols_end - k;
            if p != k {
                let (upper, lower) = a.split_at_mut(p * w);
                let (from_k, from_p) = (band.index(k, k), band.index(p, k) - p * w);
                upper[from_k..from_k + len].swap_with_slice(&mut lower[from_p..from_p + len]);
            }
            let (head, tail) = a.split_at_mut((k + 1) * w);
            let from_k = band.index(k, k);
            let pivot_row = &head[from_k..from_k + len];
            let inv = 1.0 / pivot_row[0];
            self.inv_diag[k] = inv;
            let mult = &mut self.mult[k * kl..k * kl + kl];
            let rows = tail.chunks_exact_mut(w).take(rows_end - k - 1);
            for ((row, m), i) in rows.zip(mult.iter_mut()).zip(k + 1..) {
                let at = k - band.lo(i);
                let row = &mut row[at..at + len];
                let l = row[0] * inv;
                row[0] = l;
                *m = l;
                if l != 0.0 {
                    for (r, u) in row[1..].iter_mut().zip(&pivot_row[1..]) {
                        *r -= l * u;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves `A x = b` with the factors of the last successful [`Lu::factor`],
    /// overwriting `b` with `x`.
    pub fn solve(&self, b: &mut [f64]) {
        let band = self.band;
        let Band { n, kl, ku } = band;
        debug_assert_eq!(b.len(), n);
        let a = &self.a;
        // L^-1 P^T b, one elimination step at a time (as the factorization went).
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
            let (head, tail) = b.split_at_mut(k + 1);
            let bk = head[k];
            if bk != 0.0 {
                let end = kl.min(n - k - 1);
                for (bi, l) in tail[..end].iter_mut().zip(&self.mult[k * kl..]) {
                    *bi -= l * bk;
                }
            }
        }
        // Back substitution with U, of upper bandwidth kl + ku. The sum runs from the
        // far end, so that it waits for the value just computed only at its last term.
        for i in (0..n).rev() {
            let end = (i + kl + ku + 1).min(n);
            let from = band.index(i, i) + 1;
            let row = &a[from..from + (end - i - 1)];
            let s = row
                .iter()
                .zip(&b[i + 1..end])
                .rev()
                .fold(0.0, |s, (u, x)| s + u * x);
            b[i] = (b[i] - s) * self.inv_diag[i];
        }
    }
}

/// `A = P L U` of a complex banded `n × n` matrix `A = re + i im`, in split storage,
/// computed in place.
#[derive(Clone, Debug)]
pub(crate) struct ComplexLu {
    band: Band,
    re: Vec<f64>,
    im: Vec<f64>,
    piv: Vec<usize>,
    /// As in [`Lu`]: contiguous multipliers, reciprocal pivots (real and imaginary
    /// parts).
    mult_re: Vec<f64>,
    mult_im: Vec<f64>,
    inv_re: Vec<f64>,
    inv_im: Vec<f64>,
}

impl ComplexLu {
    /// Storage for `n × n` complex matrices with band `band`.
    pub fn new(band: Band) -> Self {
        let n = band.n;
        ComplexLu {
            band,
            re: vec![0.0; band.storage()],
            im: vec![0.0; band.storage()],
            piv: vec![0; n],
            mult_re: vec![0.0; n * band.kl],
            mult_im: vec![0.0; n * band.kl],
            inv_re: vec![0.0; n],
            inv_im: vec![0.0; n],
        }
    }

    /// Sets the matrix to `(shift_re + i shift_im) I - jac`, with `jac` real and zero
    /// outside the band.
    pub fn set_shifted(&mut self, shift_re: f64, shift_im: f64, jac: &Jacobian) {
        let band = self.band;
        set_shifted(&band, &mut self.re, shift_re, jac);
        for i in 0..band.n {
            let (lo, hi) = band.window(i);
            self.im[band.index(i, lo)..band.index(i, hi - 1) + 1].fill(0.0);
            self.im[band.index(i, i)] = shift_im;
        }
    }

    /// The real and imaginary parts of the matrix, dense row-major, for tests (only for
    /// a dense band); entries outside the band must stay zero.
    #[cfg(test)]
    pub fn matrix_mut(&mut self) -> (&mut [f64], &mut [f64]) {
        assert_eq!(self.band.width(), self.band.n);
        (&mut self.re, &mut self.im)
    }

    /// Factors the matrix in place; see [`Lu::factor`].
    pub fn factor(&mut self) -> Result<(), Singular> {
        let band = self.band;
        let Band { n, kl, ku } = band;
        let w = band.width();
        let (re, im) = (&mut self.re[..], &mut self.im[..]);
        for k in 0..n {
            let rows_end = (k + kl + 1).min(n);
            let cols_end = (k + kl + ku + 1).min(n);
            let mut p = k;
            let kk = band.index(k, k);
            let mut best = re[kk].abs() + im[kk].abs();
            for i in k + 1..rows_end {
                let ik = band.index(i, k);
                let v = re[ik].abs() + im[ik].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            self.piv[k] = p;
            if !(best > 0.0 && best.is_finite()) {
                return Err(Singular { column: k });
            }
            let len = cols_end - k;
            if p != k {
                let from_p = band.index(p, k) - p * w;
                let (upper, lower) = re.split_at_mut(p * w);
                upper[kk..kk + len].swap_with_slice(&mut lower[from_p..from_p + len]);
                let (upper, lower) = im.split_at_mut(p * w);
                upper[kk..kk + len].swap_with_slice(&mut lower[from_p..from_p + len]);
            }
            let (re_head, re_tail) = re.split_at_mut((k + 1) * w);
            let (im_head, im_tail) = im.split_at_mut((k + 1) * w);
            let ur = &re_head[kk..kk + len];
            let ui = &im_head[kk..kk + len];
            // 1 / pivot.
            let (pr, pi) = (ur[0], ui[0]);
            let d = pr * pr + pi * pi;
            let (inv_r, inv_i) = (pr / d, -pi / d);
            self.inv_re[k] = inv_r;
            self.inv_im[k] = inv_i;
            let rows = re_tail.chunks_exact_mut(w).zip(im_tail.chunks_exact_mut(w));
            let mults = self.mult_re[k * kl..k * kl + kl]
                .iter_mut()
                .zip(&mut self.mult_im[k * kl..k * kl + kl]);
            for (((rr, ri), (mr, mi)), i) in rows.take(rows_end - k - 1).zip(mults).zip(k + 1..) {
                let at = k - band.lo(i);
                let (rr, ri) = (&mut rr[at..at + len], &mut ri[at..at + len]);
                let (xr, xi) = (rr[0], ri[0]);
                let lr = xr * inv_r - xi * inv_i;
                let li = xr * inv_i + xi * inv_r;
                rr[0] = lr;
                ri[0] = li;
                *mr = lr;
                *mi = li;
                if lr != 0.0 || li != 0.0 {
                    let row = rr[1..].iter_mut().zip(&mut ri[1..]);
                    for ((r, i), (u_r, u_i)) in row.zip(ur[1..].iter().zip(&ui[1..])) {
                        *r -= lr * u_r - li * u_i;
                        *i -= lr * u_i + li * u_r;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves `A x = b` for `b = b_re + i b_im` with the factors of the last successful
    /// [`ComplexLu::factor`], overwriting `b` with `x`.
    pub fn solve(&self, b_re: &mut [f64], b_im: &mut [f64]) {
        let band = self.band;
        let Band { n, kl, ku } = band;
        debug_assert!(b_re.len() == n && b_im.len() == n);
        let (re, im) = (&self.re, &self.im);
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b_re.swap(k, p);
                b_im.swap(k, p);
            }
            let (br, bi) = (b_re[k], b_im[k]);
            if br != 0.0 || bi != 0.0 {
                let end = kl.min(n - k - 1);
                let (lr, li) = (
                    &self.mult_re[k * kl..k * kl + end],
                    &self.mult_im[k * kl..k * kl + end],
                );
                let (tr, ti) = (&mut b_re[k + 1..k + 1 + end], &mut b_im[k + 1..k + 1 + end]);
                for r in 0..end {
                    tr[r] -= lr[r] * br - li[r] * bi;
                    ti[r] -= lr[r] * bi + li[r] * br;
                }
            }
        }
        for i in (0..n).rev() {
            let end = (i + kl + ku + 1).min(n);
            let from = band.index(i, i) + 1;
            let len = end - i - 1;
            let (ur, ui) = (&re[from..from + len], &im[from..from + len]);
            let (xr, xi) = (&b_re[i + 1..end], &b_im[i + 1..end]);
            // From the far end, as in the real case.
            let (mut sr, mut si) = (0.0, 0.0);
            for j in (0..ur.len()).rev() {
                sr += ur[j] * xr[j] - ui[j] * xi[j];
                si += ur[j] * xi[j] + ui[j] * xr[j];
            }
            let (sr, si) = (b_re[i] - sr, b_im[i] - si);
            // (sr + i si) / U_ii.
            let (pr, pi) = (self.inv_re[i], self.inv_im[i]);
            b_re[i] = sr * pr - si * pi;
            b_im[i] = sr * pi + si * pr;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::jacobian_of;

    /// A deterministic pseudo-random number in [-1, 1) (a 64-bit LCG).
    fn rand(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    #[test]
    fn real_solve_reproduces_the_right_hand_side() {
        let mut s = 7;
        for n in [1, 2, 3, 8, 31] {
            let a: Vec<f64> = (0..n * n).map(|_| rand(&mut s)).collect();
            let x: Vec<f64> = (0..n).map(|_| rand(&mut s)).collect();
            let mut b: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum())
                .collect();
            let mut lu = Lu::new(Band::dense(n));
            lu.matrix_mut().copy_from_slice(&a);
            lu.factor().unwrap();
            lu.solve(&mut b);
            for (got, want) in b.iter().zip(&x) {
                assert!((got - want).abs() < 1e-10, "n = {n}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn pivoting_handles_a_zero_leading_entry() {
        let mut lu = Lu::new(Band::dense(2));
        lu.matrix_mut().copy_from_slice(&[0.0, 1.0, 1.0, 0.0]);
        lu.factor().unwrap();
        let mut b = [2.0, 3.0];
        lu.solve(&mut b);
        assert_eq!(b, [3.0, 2.0]);
    }

    #[test]
    fn singular_and_non_finite_matrices_are_reported() {
        let mut lu = Lu::new(Band::dense(2));
        lu.matrix_mut().copy_from_slice(&[1.0, 2.0, 2.0, 4.0]);
        assert_eq!(lu.factor(), Err(Singular { column: 1 }));
        lu.matrix_mut().copy_from_slice(&[f64::NAN, 0.0, 0.0, 1.0]);
        assert_eq!(lu.factor(), Err(Singular { column: 0 }));
        let mut c = ComplexLu::new(Band::dense(2));
        let (re, im) = c.matrix_mut();
        re.copy_from_slice(&[1.0, 1.0, 1.0, 1.0]);
        im.copy_from_slice(&[1.0, 1.0, 1.0, 1.0]);
        assert_eq!(c.factor(), Err(Singular { column: 1 }));
    }

    #[test]
    fn complex_solve_reproduces_the_right_hand_side() {
        let mut s = 11;
        for n in [1, 2, 5, 24] {
            let ar: Vec<f64> = (0..n * n).map(|_| rand(&mut s)).collect();
            let ai: Vec<f64> = (0..n * n).map(|_| rand(&mut s)).collect();
            let xr: Vec<f64> = (0..n).map(|_| rand(&mut s)).collect();
            let xi: Vec<f64> = (0..n).map(|_| rand(&mut s)).collect();
            let mut br = vec![0.0; n];
            let mut bi = vec![0.0; n];
            for i in 0..n {
                for j in 0..n {
                    let (r, m) = (ar[i * n + j], ai[i * n + j]);
                    br[i] += r * xr[j] - m * xi[j];
                    bi[i] += r * xi[j] + m * xr[j];
                }
            }
            let mut lu = ComplexLu::new(Band::dense(n));
            let (re, im) = lu.matrix_mut();
            re.copy_from_slice(&ar);
            im.copy_from_slice(&ai);
            lu.factor().unwrap();
            lu.solve(&mut br, &mut bi);
            for i in 0..n {
                assert!((br[i] - xr[i]).abs() < 1e-10, "n = {n}");
                assert!((bi[i] - xi[i]).abs() < 1e-10, "n = {n}");
            }
        }
    }

    /// `shift I - J` for a random `J` with lower bandwidth `kl` and upper `ku`, dense.
    fn banded(n: usize, kl: usize, ku: usize, seed: &mut u64) -> Vec<f64> {
        let mut j = vec![0.0; n * n];
        for i in 0..n {
            for c in i.saturating_sub(kl)..(i + ku + 1).min(n) {
                j[i * n + c] = rand(seed);
            }
        }
        j
    }

    #[test]
    fn band_of_a_pattern() {
        let rows: [&[usize]; 4] = [&[1], &[0, 3], &[], &[0]];
        let band = Band::of_pattern(4, |i| rows[i]);
        assert_eq!((band.kl, band.ku), (3, 2));
        assert_eq!(Band::dense(5), Band { n: 5, kl: 4, ku: 4 });
    }

    /// The banded factorization, pivoting included, solves like the dense one, and
    /// re-setting the matrix clears the fill-in of the previous factorization.
    #[test]
    fn banded_solves_match_dense_solves() {
        let mut s = 5;
        for (n, kl, ku) in [
            (1, 0, 0),
            (9, 2, 1),
            (12, 1, 3),
            (20, 4, 4),
            (7, 0, 2),
            (6, 3, 0),
        ] {
            let mut banded_lu = Lu::new(Band { n, kl, ku });
            let mut dense_lu = Lu::new(Band::dense(n));
            let mut banded_c = ComplexLu::new(Band { n, kl, ku });
            let mut dense_c = ComplexLu::new(Band::dense(n));
            for shift in [0.1, 2.0] {
                // A small shift forces pivoting.
                let j = banded(n, kl, ku, &mut s);
                let jac = jacobian_of(n, &j);
                banded_lu.set_shifted(shift, &jac);
                dense_lu.set_shifted(shift, &jac);
                banded_lu.factor().unwrap();
                dense_lu.factor().unwrap();
                let b: Vec<f64> = (0..n).map(|_| rand(&mut s)).collect();
                let (mut x1, mut x2) = (b.clone(), b.clone());
                banded_lu.solve(&mut x1);
                dense_lu.solve(&mut x2);
                for (p, q) in x1.iter().zip(&x2) {
                    assert!(
                        (p - q).abs() < 1e-9 * (1.0 + q.abs()),
                        "n {n} kl {kl} ku {ku}"
                    );
                }
                // Residual of the dense solve against the matrix itself.
                for i in 0..n {
                    let r: f64 = (0..n)
                        .map(|c| (if c == i { shift } else { 0.0 } - j[i * n + c]) * x2[c])
                        .sum();
                    assert!((r - b[i]).abs() < 1e-9, "residual");
                }
                banded_c.set_shifted(shift, 0.7, &jac);
                dense_c.set_shifted(shift, 0.7, &jac);
                banded_c.factor().unwrap();
                dense_c.factor().unwrap();
                let (mut r1, mut i1) = (b.clone(), b.iter().map(|v| 0.5 * v).collect::<Vec<_>>());
                let (mut r2, mut i2) = (r1.clone(), i1.clone());
                banded_c.solve(&mut r1, &mut i1);
                dense_c.solve(&mut r2, &mut i2);
                for k in 0..n {
                    assert!((r1[k] - r2[k]).abs() < 1e-9 * (1.0 + r2[k].abs()));
                    assert!((i1[k] - i2[k]).abs() < 1e-9 * (1.0 + i2[k].abs()));
                }
            }
        }
    }
}
