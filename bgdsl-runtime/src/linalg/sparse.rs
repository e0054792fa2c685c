//! Sparse LU factorization with fill-reducing orders, real and complex, for iteration
//! matrices `σ I - J` whose Jacobian has a known sparsity pattern.
//!
//! **Order and structure ([`Analyser`]).** The pattern of `σ I - J` is the Jacobian's
//! plus the diagonal. Its rows and columns are ordered by Markowitz's criterion
//! restricted to the diagonal (Markowitz 1957; Duff, Erisman & Reid, *Direct Methods
//! for Sparse Matrices*, Sect. 7.2): at each step the remaining state `v` with the
//! smallest `(r_v - 1)(c_v - 1)`, where `r_v` and `c_v` count the entries of its row
//! and column in the matrix still to be factored (fill-in included), is eliminated
//! next (ties: the smaller `r_v + c_v`, then the lower index). The order is a symmetric
//! permutation, so the model's state order is unchanged outside this module. The same
//! pass computes the exact structure of the factors, fill-in included ([`Symbolic`]),
//! and the cost of one factorization in multiply-adds ([`Symbolic::flops`]). The
//! analysis ([`super::symbolic`]) is linear in the entries of the pattern and of the
//! factors, in storage allocated once.
//!
//! **Numerical pattern ([`Pattern`]).** A Jacobian often has many fewer non-zeros than
//! its structural pattern: a planar mechanism written with 3-D multibonds has every
//! out-of-plane entry exactly zero (the flagship quick return model: 653 of 2187). The
//! factors are therefore built for the *numerical* pattern: the union of the non-zeros
//! of the Jacobians met so far in the run (plus the diagonal), analysed again, within
//! the run, whenever a new Jacobian has a non-zero outside it. Dropping exact zeros
//! changes nothing in the matrix, so the factorization is exact; each run starts from
//! an empty pattern, so a run does not depend on the runs before it. The structure's
//! storage is bounded by that of the structural pattern in its own order: if a new
//! order would need more, that order is used instead (a subpattern eliminated in the
//! same order has a subset of the fill-in).
//!
//! **Factorization.** Row by row in the elimination order (the "up-looking"
//! Doolittle form, Gustavson's algorithm): row `k` of `A` is scattered into a dense
//! work vector, the rows of `U` of the earlier pivots it depends on are subtracted
//! (in elimination order, each through the column indices of its entries; skipped
//! when the multiplier is zero), and the row is gathered back. Only the entries of the
//! factors' structure are ever touched, so a factorization costs at most
//! [`Symbolic::flops`] multiply-adds, and a solve one multiply-add per stored entry.
//!
//! **Pivoting.** The pivots are the diagonal entries, in the order chosen from the
//! structure alone ("static pivoting"): for `σ I - J` with the shift `σ = γ / h` of an
//! implicit method this is usually stable, but not always (a long step, a Jacobian
//! entry that dominates its diagonal). The factorization therefore bounds its own
//! backward error: for each row `k` it accumulates `g_k = sum_j |l_kj| ‖U_j‖₁ +
//! ‖U_k‖₁` (`U_j` the row `j` of `U`), which is the 1-norm of row `k` of `|L| |U|`;
//! by the classical analysis of Gaussian elimination (Higham, *Accuracy and Stability
//! of Numerical Algorithms*, 2nd ed., Thm. 9.3: `L U = A + ΔA`, `|ΔA| <= γ_n |L| |U|`)
//! the backward error of row `k` is at most `γ_n g_k` in the 1-norm. If some `g_k`
//! exceeds [`MAX_GROWTH`] times the 1-norm of row `k` of the matrix, or a pivot is zero
//! or not finite (NaN propagates through the sums), the factorization reports
//! [`Unstable`] and the caller factors the matrix with partial pivoting instead.
//! (Complex moduli are `|re| + |im|` throughout.)

use std::sync::Arc;

use super::symbolic::{Analyser, Rows, Symbolic};
use crate::jacobian::Jacobian;

/// The largest accepted growth `g_k / ‖A_k‖₁` of a row (see the module documentation):
/// with `γ_n ≈ n ε`, the rows of a matrix of a few hundred states keep a backward error
/// below about `1e-6` of their norm, far below what a Newton iteration with a reused
/// Jacobian, or an error estimate, can notice.
pub(crate) const MAX_GROWTH: f64 = 1e8;

/// The static pivots of a factorization were not accurate enough (or one was zero or
/// not finite) at elimination step `step`: factor with partial pivoting instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Unstable {
    /// The elimination step whose row failed the test.
    pub step: usize,
}

/// The structural pattern of the Jacobians of a model and its analysis, computed once
/// at set-up and shared by the factorizations.
#[derive(Debug)]
pub(crate) struct Structural {
    n: usize,
    /// The pattern, by rows (without the diagonal unless the Jacobian has it): the
    /// Jacobian's own, so an entry's position here is its value's position in the
    /// [`Jacobian`].
    row_start: Vec<usize>,
    cols: Vec<usize>,
    /// Its analysis, in Markowitz order: the bound of the storage, and the order used
    /// when another would not fit.
    sym: Symbolic,
}

impl Structural {
    /// Analyses the `n × n` pattern whose row `i` holds the columns `rows(i)`.
    pub fn analyse<'a>(n: usize, rows: impl Fn(usize) -> &'a [usize]) -> Self {
        let (mut row_start, mut cols) = (Vec::with_capacity(n + 1), Vec::new());
        row_start.push(0);
        for i in 0..n {
            cols.extend_from_slice(rows(i));
            row_start.push(cols.len());
        }
        let pattern = Rows {
            row_start: &row_start,
            cols: &cols,
            active: None,
        };
        let mut analyser = Analyser::new(n, cols.len() + n, true);
        let mut perm = vec![0; n];
        let (nnz, _) = analyser.count(pattern, &mut perm);
        let mut sym = Symbolic::with_capacity(n, nnz);
        analyser
            .analyse(pattern, Some(&perm), &mut sym)
            .expect("sized to fit");
        Structural {
            n,
            row_start,
            cols,
            sym,
        }
    }

    /// Multiply-adds of one real factorization of the structural pattern.
    pub fn flops(&self) -> usize {
        self.sym.flops
    }

    /// Entries of the factors of the structural pattern.
    pub fn nnz(&self) -> usize {
        self.sym.nnz
    }
}

/// The numerical pattern of the Jacobians of a run and the structure of its factors
/// (see the module documentation).
#[derive(Clone, Debug)]
pub(crate) struct Pattern {
    structural: Arc<Structural>,
    /// The union of the non-zeros of the Jacobians seen since [`Pattern::restart`],
    /// one flag per entry of the structural pattern.
    active: Vec<bool>,
    analyser: Analyser,
    sym: Symbolic,
    /// `sym` describes `active` (false after a restart).
    analysed: bool,
    /// `-J` at the entries of the factors' structure, in their order (zero at the
    /// fill-in).
    minus_jac: Vec<f64>,
}

impl Pattern {
    /// The pattern of `structural`'s model, with all its storage.
    pub fn new(structural: Arc<Structural>) -> Self {
        let n = structural.n;
        let capacity = structural.sym.nnz;
        Pattern {
            active: vec![false; structural.cols.len()],
            analyser: Analyser::new(n, capacity, false),
            sym: Symbolic::with_capacity(n, capacity),
            structural,
            analysed: false,
            minus_jac: vec![0.0; capacity],
        }
    }

    /// Forgets the Jacobians seen: a new run starts.
    pub fn restart(&mut self) {
        self.active.fill(false);
        self.analysed = false;
    }

    /// Takes in a new Jacobian `jac` (stored over the structural pattern): its
    /// non-zeros, analysing the pattern again if it grew, and its values.
    pub fn update(&mut self, jac: &Jacobian) {
        let st = &*self.structural;
        let values = jac.values();
        debug_assert_eq!(values.len(), st.cols.len(), "a Jacobian of another pattern");
        let mut grew = !self.analysed;
        for (a, &v) in self.active.iter_mut().zip(values) {
            // NaN counts as non-zero.
            if v != 0.0 && !*a {
                *a = true;
                grew = true;
            }
        }
        if grew {
            let pattern = Rows {
                row_start: &st.row_start,
                cols: &st.cols,
                active: Some(&self.active),
            };
            let fresh = self.analyser.analyse(pattern, None, &mut self.sym);
            if fresh.is_err() {
                self.analyser
                    .analyse(pattern, Some(st.sym.order()), &mut self.sym)
                    .expect("a subpattern in the structural order fits");
            }
            self.analysed = true;
        }
        let nnz = self.sym.nnz;
        for (a, &src) in self.minus_jac[..nnz].iter_mut().zip(&self.sym.src[..nnz]) {
            *a = if src == Symbolic::NONE {
                0.0
            } else {
                -values[src]
            };
        }
    }

    /// The structure of the factors of the current pattern.
    fn sym(&self) -> &Symbolic {
        &self.sym
    }

    /// `-J` at the entries of the factors' structure.
    fn minus_jac(&self) -> &[f64] {
        &self.minus_jac
    }
}

/// The backward-error test of row `step`: pivot modulus, `g_k` and `‖A_k‖₁` (see the
/// module documentation).
#[inline]
fn check(step: usize, pivot: f64, growth: f64, row_norm: f64) -> Result<(), Unstable> {
    // Written so that NaN fails.
    if pivot > 0.0 && pivot.is_finite() && growth <= MAX_GROWTH * row_norm {
        Ok(())
    } else {
        Err(Unstable { step })
    }
}

/// `A = L U` of a real matrix on the numerical [`Pattern`] of its Jacobians, diagonal
/// pivots.
#[derive(Clone, Debug)]
pub(crate) struct SparseLu {
    pattern: Pattern,
    /// The factors, in the order of the structure's entries.
    val: Vec<f64>,
    /// `1 / U_kk`, by elimination step.
    inv_diag: Vec<f64>,
    /// `sum_j |U_kj|`, by elimination step (for the growth bound).
    u_norm: Vec<f64>,
    /// The row being factored, indexed by elimination step.
    work: Vec<f64>,
}

impl SparseLu {
    /// Storage for the factors of `structural`'s matrices.
    pub fn new(structural: Arc<Structural>) -> Self {
        let (n, capacity) = (structural.n, structural.sym.nnz);
        SparseLu {
            pattern: Pattern::new(structural),
            val: vec![0.0; capacity],
            inv_diag: vec![0.0; n],
            u_norm: vec![0.0; n],
            work: vec![0.0; n],
        }
    }

    /// Forgets the Jacobians seen: a new run starts.
    pub fn restart(&mut self) {
        self.pattern.restart();
    }

    /// Factors `shift I - jac` (`jac` stored over the structural pattern).
    /// `new_jacobian` says that `jac` may differ from the last call's.
    pub fn factor(
        &mut self,
        shift: f64,
        jac: &Jacobian,
        new_jacobian: bool,
    ) -> Result<(), Unstable> {
        if new_jacobian || !self.pattern.analysed {
            self.pattern.update(jac);
        }
        let (s, minus_jac) = (self.pattern.sym(), self.pattern.minus_jac());
        let w = &mut self.work[..];
        let val = &mut self.val[..];
        for k in 0..s.n {
            let (start, d, end) = (s.row_start[k], s.diag[k], s.row_start[k + 1]);
            let mut row_norm = 0.0;
            for (&t, &a) in s.step[start..end].iter().zip(&minus_jac[start..end]) {
                w[t as usize] = a;
                row_norm += a.abs();
            }
            let a = minus_jac[d];
            w[k] = shift + a;
            // The diagonal was counted as `|a|` above.
            row_norm += (shift + a).abs() - a.abs();
            let mut growth = 0.0;
            for p in start..d {
                let j = s.step[p] as usize;
                let l = w[j] * self.inv_diag[j];
                w[j] = l;
                if l != 0.0 {
                    growth += l.abs() * self.u_norm[j];
                    let (from, to) = (s.diag[j] + 1, s.row_start[j + 1]);
                    for (&t, &u) in s.step[from..to].iter().zip(&val[from..to]) {
                        w[t as usize] -= l * u;
                    }
                }
            }
            for (v, &t) in val[start..d].iter_mut().zip(&s.step[start..d]) {
                *v = w[t as usize];
            }
            let mut u_norm = 0.0;
            for (v, &t) in val[d..end].iter_mut().zip(&s.step[d..end]) {
                let a = w[t as usize];
                *v = a;
                u_norm += a.abs();
            }
            self.u_norm[k] = u_norm;
            let pivot = val[d];
            check(k, pivot.abs(), growth + u_norm, row_norm)?;
            self.inv_diag[k] = 1.0 / pivot;
        }
        Ok(())
    }

    /// Solves `A x = b` with the factors of the last successful [`SparseLu::factor`],
    /// overwriting `b` (in the model's state order) with `x`.
    pub fn solve(&self, b: &mut [f64]) {
        let s = self.pattern.sym();
        debug_assert_eq!(b.len(), s.n);
        let val = &self.val;
        for k in 0..s.n {
            let (start, d) = (s.row_start[k], s.diag[k]);
            let mut acc = b[s.perm[k]];
            for (&c, &l) in s.col[start..d].iter().zip(&val[start..d]) {
                acc -= l * b[c as usize];
            }
            b[s.perm[k]] = acc;
        }
        for k in (0..s.n).rev() {
            let (d, end) = (s.diag[k], s.row_start[k + 1]);
            let mut acc = b[s.perm[k]];
            for (&c, &u) in s.col[d + 1..end].iter().zip(&val[d + 1..end]) {
                acc -= u * b[c as usize];
            }
            b[s.perm[k]] = acc * self.inv_diag[k];
        }
    }
}

/// The two iteration matrices of Radau IIA, `E1 = γ I - J` (real) and
/// `E2 = (α + iβ) I - J` (complex), factored together on the numerical [`Pattern`] of
/// the Jacobians, with diagonal pivots.
///
/// The matrices share the Jacobian and the structure, so they are factored in one pass
/// (each row of `J` read once, each column index read once for the three updates of a
/// real and a complex entry), and solved in one pass when both are solved; the values
/// of an entry of the factors are stored together: `[E1, re E2, im E2]`.
#[derive(Clone, Debug)]
pub(crate) struct SparseRadauLu {
    pattern: Pattern,
    /// `[E1, re E2, im E2]` factors, in the order of the structure's entries.
    val: Vec<[f64; 3]>,
    /// `1 / U_kk` of `E1` and (real and imaginary parts) of `E2`, by elimination step.
    inv: Vec<[f64; 3]>,
    /// `sum_j |U_kj|` of `E1` and of `E2` (`|z| = |re| + |im|`), by elimination step.
    u_norm: Vec<[f64; 2]>,
    /// The row being factored (`E1`, `re E2`, `im E2`), indexed by elimination step;
    /// the right-hand sides of a solve.
    work: [Vec<f64>; 3],
}

impl SparseRadauLu {
    /// Storage for the factors of `structural`'s matrices.
    pub fn new(structural: Arc<Structural>) -> Self {
        let (n, capacity) = (structural.n, structural.sym.nnz);
        SparseRadauLu {
            pattern: Pattern::new(structural),
            val: vec![[0.0; 3]; capacity],
            inv: vec![[0.0; 3]; n],
            u_norm: vec![[0.0; 2]; n],
            work: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
        }
    }

    /// Forgets the Jacobians seen: a new run starts.
    pub fn restart(&mut self) {
        self.pattern.restart();
    }

    /// Entries of the factors of the current numerical pattern, and multiply-adds of
    /// one real factorization.
    pub fn size(&self) -> (usize, usize) {
        (self.pattern.sym.nnz, self.pattern.sym.flops)
    }

    /// Factors `E1 = gamma I - jac` and `E2 = (alpha + i beta) I - jac` (`jac` stored over
    /// the structural pattern); `new_jacobian` says that `jac`
    /// may differ from the last call's. Fails if either matrix fails the stability
    /// test.
    pub fn factor(
        &mut self,
        [gamma, alpha, beta]: [f64; 3],
        jac: &Jacobian,
        new_jacobian: bool,
    ) -> Result<(), Unstable> {
        if new_jacobian || !self.pattern.analysed {
            self.pattern.update(jac);
        }
        let (s, minus_jac) = (self.pattern.sym(), self.pattern.minus_jac());
        // The row in three arrays: each entry is stored and loaded as one `f64`.
        let [w1, wr, wi] = &mut self.work;
        let val = &mut self.val[..];
        for k in 0..s.n {
            let (start, d, end) = (s.row_start[k], s.diag[k], s.row_start[k + 1]);
            let mut row_norm = 0.0;
            for (&t, &a) in s.step[start..end].iter().zip(&minus_jac[start..end]) {
                let t = t as usize;
                w1[t] = a;
                wr[t] = a;
                wi[t] = 0.0;
                row_norm += a.abs();
            }
            let a = minus_jac[d];
            (w1[k], wr[k], wi[k]) = (gamma + a, alpha + a, beta);
            // The diagonal was counted as `|a|` above.
            let row_norm1 = row_norm - a.abs() + (gamma + a).abs();
            let row_norm2 = row_norm - a.abs() + (alpha + a).abs() + beta.abs();
            let (mut growth1, mut growth2) = (0.0, 0.0);
            for p in start..d {
                let j = s.step[p] as usize;
                let (x1, xr, xi) = (w1[j], wr[j], wi[j]);
                let [p1, pr, pi] = self.inv[j];
                let l1 = x1 * p1;
                let (lr, li) = (xr * pr - xi * pi, xr * pi + xi * pr);
                val[p] = [l1, lr, li];
                if l1 != 0.0 || lr != 0.0 || li != 0.0 {
                    let [m1, m2] = self.u_norm[j];
                    growth1 += l1.abs() * m1;
                    growth2 += (lr.abs() + li.abs()) * m2;
                    let (from, to) = (s.diag[j] + 1, s.row_start[j + 1]);
                    for (&t, &[u1, ur, ui]) in s.step[from..to].iter().zip(&val[from..to]) {
                        let t = t as usize;
                        w1[t] -= l1 * u1;
                        wr[t] -= lr * ur - li * ui;
                        wi[t] -= lr * ui + li * ur;
                    }
                }
            }
            let (mut u_norm1, mut u_norm2) = (0.0, 0.0);
            for (v, &t) in val[d..end].iter_mut().zip(&s.step[d..end]) {
                let t = t as usize;
                let (a, b, c) = (w1[t], wr[t], wi[t]);
                *v = [a, b, c];
                u_norm1 += a.abs();
                u_norm2 += b.abs() + c.abs();
            }
            self.u_norm[k] = [u_norm1, u_norm2];
            let [p1, pr, pi] = val[d];
            check(k, p1.abs(), growth1 + u_norm1, row_norm1)?;
            check(k, pr.abs() + pi.abs(), growth2 + u_norm2, row_norm2)?;
            let m = pr * pr + pi * pi;
            self.inv[k] = [1.0 / p1, pr / m, -pi / m];
        }
        Ok(())
    }

    /// Solves `E1 x = b` with the factors of the last successful
    /// [`SparseRadauLu::factor`], overwriting `b` (in the model's state order) with `x`.
    pub fn solve_real(&self, b: &mut [f64]) {
        let s = self.pattern.sym();
        debug_assert_eq!(b.len(), s.n);
        let val = &self.val;
        for k in 0..s.n {
            let (start, d) = (s.row_start[k], s.diag[k]);
            let mut acc = b[s.perm[k]];
            for (&c, l) in s.col[start..d].iter().zip(&val[start..d]) {
                acc -= l[0] * b[c as usize];
            }
            b[s.perm[k]] = acc;
        }
        for k in (0..s.n).rev() {
            let (d, end) = (s.diag[k], s.row_start[k + 1]);
            let mut acc = b[s.perm[k]];
            for (&c, u) in s.col[d + 1..end].iter().zip(&val[d + 1..end]) {
                acc -= u[0] * b[c as usize];
            }
            b[s.perm[k]] = acc * self.inv[k][0];
        }
    }

    /// Solves `E1 x = b` and `E2 y = c` (`c = c_re + i c_im`) with the factors of the
    /// last successful [`SparseRadauLu::factor`], overwriting `b` with `x` and `c` with
    /// `y` (in the model's state order).
    pub fn solve_both(&mut self, b: &mut [f64], c_re: &mut [f64], c_im: &mut [f64]) {
        let s = self.pattern.sym();
        debug_assert!(b.len() == s.n && c_re.len() == s.n && c_im.len() == s.n);
        let val = &self.val;
        // The solutions in elimination order (each right-hand side read where its row
        // is reached, each solution written out when it is final).
        let [y1, yr, yi] = &mut self.work;
        for (k, &i) in s.perm.iter().enumerate() {
            let (start, d) = (s.row_start[k], s.diag[k]);
            let (mut a1, mut ar, mut ai) = (b[i], c_re[i], c_im[i]);
            for (&c, &[l1, lr, li]) in s.step[start..d].iter().zip(&val[start..d]) {
                let c = c as usize;
                let (x1, xr, xi) = (y1[c], yr[c], yi[c]);
                a1 -= l1 * x1;
                ar -= lr * xr - li * xi;
                ai -= lr * xi + li * xr;
            }
            (y1[k], yr[k], yi[k]) = (a1, ar, ai);
        }
        for k in (0..s.n).rev() {
            let (d, end) = (s.diag[k], s.row_start[k + 1]);
            let (mut a1, mut ar, mut ai) = (y1[k], yr[k], yi[k]);
            for (&c, &[u1, ur, ui]) in s.step[d + 1..end].iter().zip(&val[d + 1..end]) {
                let c = c as usize;
                let (x1, xr, xi) = (y1[c], yr[c], yi[c]);
                a1 -= u1 * x1;
                ar -= ur * xr - ui * xi;
                ai -= ur * xi + ui * xr;
            }
            let [p1, pr, pi] = self.inv[k];
            (y1[k], yr[k], yi[k]) = (a1 * p1, ar * pr - ai * pi, ar * pi + ai * pr);
            let i = s.perm[k];
            (b[i], c_re[i], c_im[i]) = (y1[k], yr[k], yi[k]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jacobian::SparsityPattern;
    use crate::linalg::symbolic::TooLarge;
    use crate::linalg::{Band, ComplexLu, Lu};

    /// A deterministic pseudo-random number in [-1, 1) (a 64-bit LCG).
    fn rand(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// A random pattern of `n` rows with about `per_row` off-diagonal entries each
    /// (columns anywhere: a wide band).
    fn random_pattern(n: usize, per_row: usize, seed: &mut u64) -> Vec<Vec<usize>> {
        (0..n)
            .map(|_| {
                let mut row: Vec<usize> = (0..per_row)
                    .map(|_| ((rand(seed) + 1.0) * 0.5 * n as f64) as usize % n)
                    .collect();
                row.sort_unstable();
                row.dedup();
                row
            })
            .collect()
    }

    /// A Jacobian with random values on `rows`, stored over `rows`.
    fn random_jacobian(rows: &[Vec<usize>], seed: &mut u64) -> Jacobian {
        let mut jac = Jacobian::new(SparsityPattern::from_rows(rows).unwrap().into());
        for v in jac.values_mut() {
            *v = rand(seed);
        }
        jac
    }

    /// `rows` as compressed rows.
    fn csr(rows: &[Vec<usize>]) -> (Vec<usize>, Vec<usize>) {
        let mut row_start = vec![0];
        let mut cols = Vec::new();
        for row in rows {
            cols.extend_from_slice(row);
            row_start.push(cols.len());
        }
        (row_start, cols)
    }

    fn structural(rows: &[Vec<usize>]) -> Arc<Structural> {
        Arc::new(Structural::analyse(rows.len(), |i| &rows[i]))
    }

    /// An arrow matrix (full first row and column) fills in completely in the natural
    /// order; Markowitz's order eliminates the other states first, without fill-in.
    #[test]
    fn markowitz_order_avoids_the_fill_in_of_an_arrow() {
        let n = 10;
        let rows: Vec<Vec<usize>> = (0..n)
            .map(|i| if i == 0 { (1..n).collect() } else { vec![0] })
            .collect();
        let st = structural(&rows);
        assert_eq!(st.sym.nnz, 3 * n - 2);
        assert_eq!(st.sym.flops, 2 * (n - 1));
        // The hub goes last (with the last leaf: their order does not matter).
        assert!(!st.sym.order()[..n - 2].contains(&0));
        // The natural order fills the whole matrix.
        let (row_start, cols) = csr(&rows);
        let pattern = Rows {
            row_start: &row_start,
            cols: &cols,
            active: None,
        };
        let natural: Vec<usize> = (0..n).collect();
        let mut sym = Symbolic::with_capacity(n, n * n);
        let mut analyser = Analyser::new(n, n * n, false);
        analyser.analyse(pattern, Some(&natural), &mut sym).unwrap();
        assert_eq!(sym.nnz, n * n);
        // Too little storage is reported.
        let mut small = Symbolic::with_capacity(n, 3 * n - 3);
        assert_eq!(analyser.analyse(pattern, None, &mut small), Err(TooLarge));
        // A work space without room for the natural order's fill-in says so too.
        let mut tight = Analyser::new(n, 3 * n - 2, false);
        assert_eq!(
            tight.analyse(pattern, Some(&natural), &mut sym),
            Err(TooLarge)
        );
    }

    /// The sparse factorizations solve like the dense ones with partial pivoting, for
    /// random wide-band patterns, the real one and the Radau pair.
    #[test]
    fn sparse_solves_match_dense_solves() {
        let mut seed = 3;
        for (n, per_row) in [(1, 0), (5, 2), (40, 3), (117, 6)] {
            let rows = random_pattern(n, per_row, &mut seed);
            let st = structural(&rows);
            let mut real = SparseLu::new(st.clone());
            let mut pair = SparseRadauLu::new(st);
            let mut dense = Lu::new(Band::dense(n));
            let mut dense_c = ComplexLu::new(Band::dense(n));
            for shifts in [[4.0, 3.0, 2.5], [40.0, 30.0, 25.0]] {
                let jac = random_jacobian(&rows, &mut seed);
                real.factor(shifts[0], &jac, true).unwrap();
                pair.factor(shifts, &jac, true).unwrap();
                dense.set_shifted(shifts[0], &jac);
                dense.factor().unwrap();
                dense_c.set_shifted(shifts[1], shifts[2], &jac);
                dense_c.factor().unwrap();
                let b: Vec<f64> = (0..n).map(|_| rand(&mut seed)).collect();
                let c: Vec<f64> = (0..n).map(|_| rand(&mut seed)).collect();
                let (mut x_dense, mut x_real, mut x_pair, mut x_both) =
                    (b.clone(), b.clone(), b.clone(), b.clone());
                dense.solve(&mut x_dense);
                real.solve(&mut x_real);
                pair.solve_real(&mut x_pair);
                let (mut y_re, mut y_im) = (c.clone(), b.clone());
                let (mut z_re, mut z_im) = (c.clone(), b.clone());
                dense_c.solve(&mut y_re, &mut y_im);
                pair.solve_both(&mut x_both, &mut z_re, &mut z_im);
                let close = |a: &[f64], b: &[f64]| {
                    a.iter()
                        .zip(b)
                        .all(|(p, q)| (p - q).abs() <= 1e-12 * (1.0 + q.abs()))
                };
                assert!(close(&x_real, &x_dense), "n {n}: real");
                assert!(close(&x_pair, &x_dense), "n {n}: pair, real only");
                assert!(close(&x_both, &x_dense), "n {n}: pair, real");
                assert!(
                    close(&z_re, &y_re) && close(&z_im, &y_im),
                    "n {n}: pair, complex"
                );
            }
        }
    }

    /// The normwise backward residual `‖A x - b‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)` of the sparse
    /// solves stays at rounding level (below 1e-14, 45 ε; the largest seen is 3.3 ε),
    /// for the real matrix and for both of the Radau pair, on 300 random matrices:
    /// random patterns of 1 to 150 states with 1 to 8 entries a row, some with a hub row and column (heavy
    /// fill-in), random entries in [-1, 1) and shifts from 2 to 40. The residual is
    /// computed from the matrix itself, independently of the factors (Higham,
    /// *Accuracy and Stability of Numerical Algorithms*, Sect. 7.1: a backward stable
    /// solve has a residual of order ε in this norm).
    #[test]
    fn sparse_solves_have_rounding_level_residuals() {
        let mut seed = 23;
        for case in 0..300 {
            let n = 1 + (rand(&mut seed).abs() * 150.0) as usize;
            let per_row = 1 + (rand(&mut seed).abs() * 8.0) as usize;
            let mut rows = random_pattern(n, per_row, &mut seed);
            if case % 3 == 0 {
                // A hub: row and column 0 full.
                rows[0] = (0..n).collect();
                for row in rows.iter_mut().skip(1) {
                    if !row.contains(&0) {
                        row.insert(0, 0);
                    }
                }
            }
            let jac = random_jacobian(&rows, &mut seed);
            let scale = 2.0 + 38.0 * rand(&mut seed).abs();
            let shifts = [scale, 0.8 * scale, 0.6 * scale];
            let st = structural(&rows);
            let mut real = SparseLu::new(st.clone());
            let mut pair = SparseRadauLu::new(st);
            real.factor(shifts[0], &jac, true).unwrap();
            pair.factor(shifts, &jac, true).unwrap();
            // (σ_re + i σ_im) I - J applied to x, with its ∞-norm.
            let apply = |(s_re, s_im): (f64, f64), (x_re, x_im): (&[f64], &[f64])| {
                let (mut y_re, mut y_im, mut norm) = (vec![0.0; n], vec![0.0; n], 0.0f64);
                for i in 0..n {
                    let (cols, values) = jac.row(i);
                    y_re[i] = s_re * x_re[i] - s_im * x_im[i];
                    y_im[i] = s_re * x_im[i] + s_im * x_re[i];
                    let mut row_norm = (s_re.abs() + s_im.abs()) * f64::from(!cols.contains(&i));
                    for (&j, &v) in cols.iter().zip(values) {
                        y_re[i] -= v * x_re[j];
                        y_im[i] -= v * x_im[j];
                        let a = if j == i { s_re - v } else { -v };
                        let b = if j == i { s_im } else { 0.0 };
                        row_norm += a.abs() + b.abs();
                    }
                    norm = norm.max(row_norm);
                }
                (y_re, y_im, norm)
            };
            let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let residual = |shift, x: (&[f64], &[f64]), b: (&[f64], &[f64])| {
                let (y_re, y_im, norm) = apply(shift, x);
                let r: Vec<f64> = (0..n)
                    .map(|i| (y_re[i] - b.0[i]).abs() + (y_im[i] - b.1[i]).abs())
                    .collect();
                let x_norm = inf(x.0).max(inf(x.1));
                inf(&r) / (norm * x_norm + inf(b.0).max(inf(b.1)))
            };
            let b: Vec<f64> = (0..n).map(|_| rand(&mut seed)).collect();
            let (c_re, c_im): (Vec<f64>, Vec<f64>) =
                (0..n).map(|_| (rand(&mut seed), rand(&mut seed))).unzip();
            let zero = vec![0.0; n];
            let (mut x, mut x_pair, mut x_both) = (b.clone(), b.clone(), b.clone());
            let (mut y_re, mut y_im) = (c_re.clone(), c_im.clone());
            real.solve(&mut x);
            pair.solve_real(&mut x_pair);
            pair.solve_both(&mut x_both, &mut y_re, &mut y_im);
            let real_shift = (shifts[0], 0.0);
            for (what, x) in [
                ("real", &x),
                ("pair, real", &x_pair),
                ("both, real", &x_both),
            ] {
                let r = residual(real_shift, (x, &zero), (&b, &zero));
                assert!(r < 1e-14, "case {case} (n {n}): {what}: residual {r:e}");
            }
            let r = residual((shifts[1], shifts[2]), (&y_re, &y_im), (&c_re, &c_im));
            assert!(r < 1e-14, "case {case} (n {n}): complex: residual {r:e}");
        }
    }

    /// Entries that are zero in the first Jacobians are left out of the factors until
    /// a Jacobian has them (the pattern grows and is analysed again); a restart
    /// forgets them. Every solve is right.
    #[test]
    fn the_numerical_pattern_grows_with_the_jacobians() {
        let mut seed = 11;
        let n = 60;
        let rows = random_pattern(n, 5, &mut seed);
        let st = structural(&rows);
        let full = random_jacobian(&rows, &mut seed);
        // Half the entries zero.
        let mut half = full.clone();
        for (k, v) in half.values_mut().iter_mut().enumerate() {
            if k % 2 == 0 {
                *v = 0.0;
            }
        }
        let mut lu = SparseLu::new(st.clone());
        let mut dense = Lu::new(Band::dense(n));
        let mut sizes = Vec::new();
        for (jac, new) in [(&half, true), (&half, false), (&full, true), (&half, true)] {
            lu.factor(3.0, jac, new).unwrap();
            sizes.push(lu.pattern.sym().nnz);
            dense.set_shifted(3.0, jac);
            dense.factor().unwrap();
            let b: Vec<f64> = (0..n).map(|_| rand(&mut seed)).collect();
            let (mut x, mut y) = (b.clone(), b);
            lu.solve(&mut x);
            dense.solve(&mut y);
            for (p, q) in x.iter().zip(&y) {
                assert!((p - q).abs() <= 1e-12 * (1.0 + q.abs()));
            }
        }
        assert!(sizes[0] < sizes[2], "{sizes:?}");
        assert_eq!(sizes[0], sizes[1]);
        // The union is kept: the half pattern again changes nothing.
        assert_eq!(sizes[2], sizes[3]);
        assert!(sizes[2] <= st.sym.nnz);
        lu.restart();
        lu.factor(3.0, &half, false).unwrap();
        assert_eq!(lu.pattern.sym().nnz, sizes[0]);
    }

    /// A subpattern eliminated in the order of the whole pattern fits the whole
    /// pattern's storage (the guarantee `Pattern::update` relies on).
    #[test]
    fn subpatterns_fit_in_the_structural_order() {
        let mut seed = 5;
        for n in [8, 30, 90] {
            let rows = random_pattern(n, 4, &mut seed);
            let st = structural(&rows);
            let mut analyser = Analyser::new(n, st.sym.nnz, false);
            let mut sym = Symbolic::with_capacity(n, st.sym.nnz);
            let (row_start, cols) = csr(&rows);
            for _ in 0..5 {
                let active: Vec<bool> = cols.iter().map(|_| rand(&mut seed) > 0.0).collect();
                let sub = Rows {
                    row_start: &row_start,
                    cols: &cols,
                    active: Some(&active),
                };
                analyser
                    .analyse(sub, Some(st.sym.order()), &mut sym)
                    .unwrap();
            }
        }
    }

    /// Pivots too small for what they eliminate fail the stability test; the pivots
    /// that do not are accepted even when far from the largest of their column.
    #[test]
    fn unstable_pivots_are_reported() {
        // σ I - J for J = [[0, w], [-w, 0]]: the growth of the elimination is w / σ.
        let rows = vec![vec![1], vec![0]];
        let st = structural(&rows);
        let mut lu = SparseLu::new(st.clone());
        let mut pair = SparseRadauLu::new(st);
        let mut jac = Jacobian::new(SparsityPattern::from_rows(&rows).unwrap().into());
        for (w, stable) in [(1e3, true), (1e12, false)] {
            jac.values_mut().copy_from_slice(&[w, -w]);
            assert_eq!(lu.factor(1.0, &jac, true).is_ok(), stable, "w = {w}");
            assert_eq!(pair.factor([1.0, 1.0, 0.5], &jac, true).is_ok(), stable);
        }
        // A zero pivot.
        jac.values_mut().copy_from_slice(&[1.0, 1.0]);
        assert_eq!(lu.factor(0.0, &jac, true), Err(Unstable { step: 0 }));
    }
}
