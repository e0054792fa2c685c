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
//! analysis works on bit sets, in storage allocated once.
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

/// An `n × n` boolean matrix, each row a bit set of `words` words.
#[derive(Clone, Debug)]
pub(crate) struct BitMatrix {
    words: usize,
    bits: Vec<u64>,
}

impl BitMatrix {
    /// The empty `n × n` matrix.
    pub fn new(n: usize) -> Self {
        let words = n.div_ceil(64).max(1);
        BitMatrix {
            words,
            bits: vec![0; n * words],
        }
    }

    fn row(&self, i: usize) -> &[u64] {
        &self.bits[i * self.words..][..self.words]
    }

    fn row_mut(&mut self, i: usize) -> &mut [u64] {
        &mut self.bits[i * self.words..][..self.words]
    }

    /// Sets entry `(i, j)`; returns whether it was clear.
    pub fn set(&mut self, i: usize, j: usize) -> bool {
        let w = &mut self.bits[i * self.words + j / 64];
        let bit = 1u64 << (j % 64);
        let was_clear = *w & bit == 0;
        *w |= bit;
        was_clear
    }

    fn clear(&mut self) {
        self.bits.fill(0);
    }
}

/// The members of a bit set, increasing.
fn members(set: &[u64]) -> impl Iterator<Item = usize> + '_ {
    set.iter().enumerate().flat_map(|(k, &word)| {
        let mut w = word;
        core::iter::from_fn(move || {
            (w != 0).then(|| {
                let i = 64 * k + w.trailing_zeros() as usize;
                w &= w - 1;
                i
            })
        })
    })
}

fn count(set: &[u64]) -> usize {
    set.iter().map(|w| w.count_ones() as usize).sum()
}

/// The elimination order of an `n × n` pattern (with its diagonal) and the structure
/// of its LU factors.
#[derive(Clone, Debug)]
pub(crate) struct Symbolic {
    n: usize,
    /// `perm[k]`: the state (row and column of `A`) eliminated at step `k`.
    perm: Vec<usize>,
    /// Row `k` of the factors (of state `perm[k]`) is held in positions
    /// `row_start[k]..row_start[k + 1]`: first `L` (columns eliminated earlier, in
    /// elimination order), then the diagonal at `diag[k]`, then `U`.
    row_start: Vec<usize>,
    diag: Vec<usize>,
    /// Each entry's column, as an elimination step (`nnz` used, the rest capacity).
    step: Vec<u32>,
    /// Each entry's column, as a state.
    col: Vec<u32>,
    /// Each entry's index in the dense row-major `n × n` Jacobian.
    src: Vec<usize>,
    nnz: usize,
    /// Multiply-adds of one real factorization.
    flops: usize,
}

impl Symbolic {
    /// Storage for the structure of `n × n` factors with up to `capacity` entries.
    fn with_capacity(n: usize, capacity: usize) -> Self {
        Symbolic {
            n,
            perm: vec![0; n],
            row_start: vec![0; n + 1],
            diag: vec![0; n],
            step: vec![0; capacity],
            col: vec![0; capacity],
            src: vec![0; capacity],
            nnz: 0,
            flops: 0,
        }
    }

    /// Multiply-adds of one real factorization.
    #[cfg(test)]
    pub fn flops(&self) -> usize {
        self.flops
    }

    /// Entries of the factors `L` and `U` together (fill-in and diagonal included).
    #[cfg(test)]
    pub fn nnz(&self) -> usize {
        self.nnz
    }

    /// The elimination order: `order()[k]` is the state eliminated at step `k`.
    #[cfg(test)]
    pub fn order(&self) -> &[usize] {
        &self.perm
    }
}

/// The factors would need more entries than the storage holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct TooLarge;

/// The work space of the symbolic analysis, allocated once for `n` states.
#[derive(Clone, Debug)]
pub(crate) struct Analyser {
    /// The pattern still to be factored, by rows and by columns.
    rows: BitMatrix,
    cols: BitMatrix,
    /// Each state's `U` row (columns eliminated after it, as states) and `L` row
    /// (columns eliminated before it, as elimination steps).
    u: BitMatrix,
    l: BitMatrix,
    row_count: Vec<usize>,
    col_count: Vec<usize>,
    alive: Vec<bool>,
    position: Vec<usize>,
    pivot_row: Vec<u64>,
    pivot_col: Vec<u64>,
}

impl Analyser {
    /// The work space for `n` states.
    pub fn new(n: usize) -> Self {
        let words = n.div_ceil(64).max(1);
        Analyser {
            rows: BitMatrix::new(n),
            cols: BitMatrix::new(n),
            u: BitMatrix::new(n),
            l: BitMatrix::new(n),
            row_count: vec![0; n],
            col_count: vec![0; n],
            alive: vec![true; n],
            position: vec![0; n],
            pivot_row: vec![0; words],
            pivot_col: vec![0; words],
        }
    }

    /// Analyses `pattern` (the diagonal is added) into `out`, in Markowitz order or,
    /// when given, in `order`; fails, leaving `out` to be analysed again, if the factors
    /// do not fit its storage. Allocates nothing.
    fn analyse(
        &mut self,
        pattern: &BitMatrix,
        order: Option<&[usize]>,
        out: &mut Symbolic,
    ) -> Result<(), TooLarge> {
        let (nnz, flops) = self.eliminate(pattern, order, &mut out.perm);
        if nnz > out.step.len() {
            return Err(TooLarge);
        }
        self.build(out);
        out.nnz = nnz;
        out.flops = flops;
        Ok(())
    }

    /// The symbolic elimination of `pattern` (plus the diagonal) in Markowitz order or
    /// in `order`, writing the order into `perm` and keeping the factors' rows; returns
    /// the factors' entries and the multiply-adds of a real factorization.
    fn eliminate(
        &mut self,
        pattern: &BitMatrix,
        order: Option<&[usize]>,
        perm: &mut [usize],
    ) -> (usize, usize) {
        let n = perm.len();
        self.rows.clear();
        self.cols.clear();
        self.u.clear();
        self.l.clear();
        for i in 0..n {
            self.rows.row_mut(i).copy_from_slice(pattern.row(i));
            self.rows.set(i, i);
        }
        for i in 0..n {
            for j in members(self.rows.row(i)) {
                self.cols.set(j, i);
            }
        }
        for i in 0..n {
            self.row_count[i] = count(self.rows.row(i));
            self.col_count[i] = count(self.cols.row(i));
        }
        self.alive.fill(true);
        let (mut nnz, mut flops) = (n, 0);
        for k in 0..n {
            let v = match order {
                Some(order) => order[k],
                None => {
                    let (rc, cc, alive) = (&self.row_count, &self.col_count, &self.alive);
                    (0..n)
                        .filter(|&v| alive[v])
                        .min_by_key(|&v| ((rc[v] - 1) * (cc[v] - 1), rc[v] + cc[v], v))
                        .expect("a state is left")
                }
            };
            self.alive[v] = false;
            perm[k] = v;
            self.position[v] = k;
            self.pivot_row.copy_from_slice(self.rows.row(v));
            self.pivot_col.copy_from_slice(self.cols.row(v));
            let clear = !(1u64 << (v % 64));
            self.pivot_row[v / 64] &= clear;
            self.pivot_col[v / 64] &= clear;
            self.u.row_mut(v).copy_from_slice(&self.pivot_row);
            let (below, right) = (count(&self.pivot_col), count(&self.pivot_row));
            nnz += below + right;
            flops += below * (right + 1);
            // Rows with an entry in column v receive row v's pattern (fill-in).
            for i in members(&self.pivot_col) {
                self.l.set(i, k);
                let row = self.rows.row_mut(i);
                for (a, b) in row.iter_mut().zip(&self.pivot_row) {
                    *a |= b;
                }
                row[v / 64] &= clear;
                self.row_count[i] = count(row);
            }
            for j in members(&self.pivot_row) {
                let col = self.cols.row_mut(j);
                for (a, b) in col.iter_mut().zip(&self.pivot_col) {
                    *a |= b;
                }
                col[v / 64] &= clear;
                self.col_count[j] = count(col);
            }
        }
        (nnz, flops)
    }

    /// Writes the rows of the factors kept by the last [`Analyser::eliminate`] into
    /// `out` (whose `perm` holds its order and whose storage is large enough).
    fn build(&self, out: &mut Symbolic) {
        let n = out.n;
        let mut next = 0;
        out.row_start[0] = 0;
        for k in 0..n {
            let s = out.perm[k];
            let lower = members(self.l.row(s)).map(|kk| (kk, out.perm[kk]));
            let diagonal = core::iter::once((k, s));
            let upper = members(self.u.row(s)).map(|j| (self.position[j], j));
            for (step, j) in lower.chain(diagonal).chain(upper) {
                if j == s {
                    out.diag[k] = next;
                }
                out.step[next] = step as u32;
                out.col[next] = j as u32;
                out.src[next] = s * n + j;
                next += 1;
            }
            out.row_start[k + 1] = next;
        }
    }
}

/// The structural pattern of the Jacobians of a model and its analysis, computed once
/// at set-up and shared by the factorizations.
#[derive(Debug)]
pub(crate) struct Structural {
    n: usize,
    /// The pattern, by rows (without the diagonal unless the Jacobian has it).
    row_start: Vec<usize>,
    cols: Vec<usize>,
    /// Its analysis, in Markowitz order: the bound of the storage, and the order used
    /// when another would not fit.
    sym: Symbolic,
}

impl Structural {
    /// Analyses the `n × n` pattern whose row `i` holds the columns `rows(i)`.
    pub fn analyse<'a>(n: usize, rows: impl Fn(usize) -> &'a [usize]) -> Self {
        let mut pattern = BitMatrix::new(n);
        let (mut row_start, mut cols) = (vec![0], Vec::new());
        for i in 0..n {
            for &j in rows(i) {
                pattern.set(i, j);
                cols.push(j);
            }
            row_start.push(cols.len());
        }
        let mut analyser = Analyser::new(n);
        let mut perm = vec![0; n];
        let (nnz, _) = analyser.eliminate(&pattern, None, &mut perm);
        let mut sym = Symbolic::with_capacity(n, nnz);
        analyser
            .analyse(&pattern, Some(&perm), &mut sym)
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
}

/// The numerical pattern of the Jacobians of a run and the structure of its factors
/// (see the module documentation).
#[derive(Clone, Debug)]
pub(crate) struct Pattern {
    structural: Arc<Structural>,
    /// The union of the non-zeros of the Jacobians seen since [`Pattern::restart`].
    active: BitMatrix,
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
            active: BitMatrix::new(n),
            analyser: Analyser::new(n),
            sym: Symbolic::with_capacity(n, capacity),
            structural,
            analysed: false,
            minus_jac: vec![0.0; capacity],
        }
    }

    /// Forgets the Jacobians seen: a new run starts.
    pub fn restart(&mut self) {
        self.active.clear();
        self.analysed = false;
    }

    /// Takes in a new Jacobian `jac` (dense row-major; entries outside the structural
    /// pattern are ignored): its non-zeros, analysing the pattern again if it grew, and
    /// its values.
    pub fn update(&mut self, jac: &[f64]) {
        let st = &*self.structural;
        let n = st.n;
        let mut grew = !self.analysed;
        for i in 0..n {
            for &j in &st.cols[st.row_start[i]..st.row_start[i + 1]] {
                // NaN counts as non-zero.
                if jac[i * n + j] != 0.0 && self.active.set(i, j) {
                    grew = true;
                }
            }
        }
        if grew {
            let fresh = self.analyser.analyse(&self.active, None, &mut self.sym);
            if fresh.is_err() {
                self.analyser
                    .analyse(&self.active, Some(&st.sym.perm), &mut self.sym)
                    .expect("a subpattern in the structural order fits");
            }
            self.analysed = true;
        }
        let nnz = self.sym.nnz;
        for (a, &src) in self.minus_jac[..nnz].iter_mut().zip(&self.sym.src[..nnz]) {
            *a = -jac[src];
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

    /// Factors `shift I - jac` (`jac` dense row-major, zero outside the structural
    /// pattern). `new_jacobian` says that `jac` may differ from the last call's.
    pub fn factor(&mut self, shift: f64, jac: &[f64], new_jacobian: bool) -> Result<(), Unstable> {
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

    /// Factors `E1 = gamma I - jac` and `E2 = (alpha + i beta) I - jac` (`jac` dense
    /// row-major, zero outside the structural pattern); `new_jacobian` says that `jac`
    /// may differ from the last call's. Fails if either matrix fails the stability
    /// test.
    pub fn factor(
        &mut self,
        [gamma, alpha, beta]: [f64; 3],
        jac: &[f64],
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
        // The right-hand sides in elimination order.
        let [y1, yr, yi] = &mut self.work;
        for (k, &i) in s.perm.iter().enumerate() {
            (y1[k], yr[k], yi[k]) = (b[i], c_re[i], c_im[i]);
        }
        for k in 0..s.n {
            let (start, d) = (s.row_start[k], s.diag[k]);
            let (mut a1, mut ar, mut ai) = (y1[k], yr[k], yi[k]);
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
        }
        for (k, &i) in s.perm.iter().enumerate() {
            (b[i], c_re[i], c_im[i]) = (y1[k], yr[k], yi[k]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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

    /// A Jacobian with random values on `rows`, zero elsewhere (dense row-major).
    fn random_jacobian(rows: &[Vec<usize>], seed: &mut u64) -> Vec<f64> {
        let n = rows.len();
        let mut jac = vec![0.0; n * n];
        for (i, row) in rows.iter().enumerate() {
            for &j in row {
                jac[i * n + j] = rand(seed);
            }
        }
        jac
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
        assert_eq!(st.sym.nnz(), 3 * n - 2);
        assert_eq!(st.sym.flops(), 2 * (n - 1));
        // The hub goes last (with the last leaf: their order does not matter).
        assert!(!st.sym.order()[..n - 2].contains(&0));
        // The natural order fills the whole matrix.
        let mut pattern = BitMatrix::new(n);
        for (i, row) in rows.iter().enumerate() {
            for &j in row {
                pattern.set(i, j);
            }
        }
        let natural: Vec<usize> = (0..n).collect();
        let mut sym = Symbolic::with_capacity(n, n * n);
        let mut analyser = Analyser::new(n);
        analyser
            .analyse(&pattern, Some(&natural), &mut sym)
            .unwrap();
        assert_eq!(sym.nnz(), n * n);
        // Too little storage is reported.
        let mut small = Symbolic::with_capacity(n, 3 * n - 3);
        assert_eq!(analyser.analyse(&pattern, None, &mut small), Err(TooLarge));
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
        for (k, v) in half.iter_mut().enumerate() {
            if k % 2 == 0 {
                *v = 0.0;
            }
        }
        let mut lu = SparseLu::new(st.clone());
        let mut dense = Lu::new(Band::dense(n));
        let mut sizes = Vec::new();
        for (jac, new) in [(&half, true), (&half, false), (&full, true), (&half, true)] {
            lu.factor(3.0, jac, new).unwrap();
            sizes.push(lu.pattern.sym().nnz());
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
        assert!(sizes[2] <= st.sym.nnz());
        lu.restart();
        lu.factor(3.0, &half, false).unwrap();
        assert_eq!(lu.pattern.sym().nnz(), sizes[0]);
    }

    /// A subpattern eliminated in the order of the whole pattern fits the whole
    /// pattern's storage (the guarantee `Pattern::update` relies on).
    #[test]
    fn subpatterns_fit_in_the_structural_order() {
        let mut seed = 5;
        for n in [8, 30, 90] {
            let rows = random_pattern(n, 4, &mut seed);
            let st = structural(&rows);
            let mut analyser = Analyser::new(n);
            let mut sym = Symbolic::with_capacity(n, st.sym.nnz());
            for _ in 0..5 {
                let mut sub = BitMatrix::new(n);
                for (i, row) in rows.iter().enumerate() {
                    for &j in row {
                        if rand(&mut seed) > 0.0 {
                            sub.set(i, j);
                        }
                    }
                }
                analyser
                    .analyse(&sub, Some(st.sym.order()), &mut sym)
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
        for (w, stable) in [(1e3, true), (1e12, false)] {
            let jac = [0.0, w, -w, 0.0];
            assert_eq!(lu.factor(1.0, &jac, true).is_ok(), stable, "w = {w}");
            assert_eq!(pair.factor([1.0, 1.0, 0.5], &jac, true).is_ok(), stable);
        }
        // A zero pivot.
        assert_eq!(
            lu.factor(0.0, &[0.0, 1.0, 1.0, 0.0], true),
            Err(Unstable { step: 0 })
        );
    }
}
