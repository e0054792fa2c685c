//! Exact Jacobians ∂(dx/dt)/∂x by forward-mode automatic differentiation, compressed
//! by column colouring.
//!
//! One evaluation of [`Model::derivatives`] on [`Dual`] numbers seeded with a direction
//! `v` gives the Jacobian-vector product `J v` ([`JacobianEvaluator::jvp`]). Seeding
//! the unit vector `e_j` gives column `j`, so a dense Jacobian costs `n` dual
//! evaluations. When the model declares its sparsity
//! ([`Model::JACOBIAN_SPARSITY`], emitted exactly by `bond_graph!`), columns that share
//! no row are *structurally orthogonal*: seeding their sum gives, in each row, the one
//! entry of the one column of the group that the row depends on. The columns are
//! partitioned into such groups once, at set-up ([`Colouring::greedy`]), and a Jacobian
//! then costs one dual evaluation per group (colour) instead of one per column.
//!
//! ```
//! use bgdsl_runtime::{JacobianEvaluator, Model, Scalar};
//!
//! /// ẋ₀ = −x₀², ẋ₁ = sin x₁: a diagonal Jacobian, one colour.
//! struct Decay;
//! impl Model for Decay {
//!     type Params = ();
//!     const NAME: &'static str = "decay";
//!     const STATE_NAMES: &'static [&'static str] = &["a", "b"];
//!     const OUTPUT_NAMES: &'static [&'static str] = &[];
//!     const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&[&[0], &[1]]);
//!     fn params(&self) -> &() { &() }
//!     fn initial_state(&self, x0: &mut [f64]) { x0.fill(1.0) }
//!     fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
//!         dx[0] = -(x[0] * x[0]);
//!         dx[1] = x[1].sin();
//!     }
//!     fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
//! }
//!
//! let mut evaluator = JacobianEvaluator::new(&Decay);
//! assert_eq!(evaluator.n_colours(), 1);
//! let mut jac = [f64::NAN; 4];
//! let evaluations = evaluator.evaluate(&Decay, 0.0, &[3.0, 0.0], &mut jac);
//! assert_eq!(evaluations, 1);
//! assert_eq!(jac, [-6.0, 0.0, 0.0, 1.0]);
//! ```

use core::fmt;

use crate::dual::Dual;
use crate::model::Model;

/// Why a sparsity pattern was rejected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SparsityError {
    /// The pattern does not have one row per state.
    WrongRowCount {
        /// The number of states.
        expected: usize,
        /// The number of rows given.
        found: usize,
    },
    /// A row names a column that is not a state.
    ColumnOutOfRange {
        /// The row.
        row: usize,
        /// The column it names.
        column: usize,
        /// The number of states.
        n: usize,
    },
    /// A row's columns are not strictly increasing (unsorted or repeated).
    NotIncreasing {
        /// The row.
        row: usize,
        /// The position in the row of the first column not greater than the one
        /// before it.
        position: usize,
    },
}

impl fmt::Display for SparsityError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            SparsityError::WrongRowCount { expected, found } => write!(
                f,
                "Jacobian sparsity pattern: expected one row per state ({expected}), found {found} rows"
            ),
            SparsityError::ColumnOutOfRange { row, column, n } => write!(
                f,
                "Jacobian sparsity pattern: row {row} names column {column}, but there are only {n} states"
            ),
            SparsityError::NotIncreasing { row, position } => write!(
                f,
                "Jacobian sparsity pattern: row {row} is not strictly increasing at position {position} \
                 (columns must be sorted and distinct)"
            ),
        }
    }
}

impl std::error::Error for SparsityError {}

/// The structure of an `n × n` Jacobian: for each row, the columns that may be non-zero,
/// in increasing order (compressed-row storage). Entries outside it are zero.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SparsityPattern {
    n: usize,
    dense: bool,
    /// Where each row starts in `columns` (`n + 1` entries; empty when dense).
    row_start: Vec<usize>,
    /// The rows' columns, one row after the other; when dense, `0..n` once, shared by
    /// every row.
    columns: Vec<usize>,
}

impl SparsityPattern {
    /// The dense pattern: every entry may be non-zero.
    pub fn dense(n: usize) -> Self {
        SparsityPattern {
            n,
            dense: true,
            row_start: Vec::new(),
            columns: (0..n).collect(),
        }
    }

    /// The pattern with the given rows (the number of rows is `n`), each strictly
    /// increasing and within `0..n`.
    ///
    /// # Errors
    /// [`SparsityError::ColumnOutOfRange`] or [`SparsityError::NotIncreasing`] for the
    /// first row that breaks the rules.
    pub fn from_rows<R: AsRef<[usize]>>(rows: &[R]) -> Result<Self, SparsityError> {
        let n = rows.len();
        let mut row_start = Vec::with_capacity(n + 1);
        let mut columns = Vec::new();
        row_start.push(0);
        for (row, cols) in rows.iter().enumerate() {
            let cols = cols.as_ref();
            for (position, &column) in cols.iter().enumerate() {
                if column >= n {
                    return Err(SparsityError::ColumnOutOfRange { row, column, n });
                }
                if position > 0 && column <= cols[position - 1] {
                    return Err(SparsityError::NotIncreasing { row, position });
                }
            }
            columns.extend_from_slice(cols);
            row_start.push(columns.len());
        }
        Ok(SparsityPattern {
            n,
            dense: false,
            row_start,
            columns,
        })
    }

    /// The pattern model `M` declares ([`Model::JACOBIAN_SPARSITY`]; dense when it
    /// declares none).
    ///
    /// # Errors
    /// [`SparsityError::WrongRowCount`] when the pattern does not have
    /// [`Model::N_STATES`] rows, and the errors of [`SparsityPattern::from_rows`].
    pub fn for_model<M: Model>() -> Result<Self, SparsityError> {
        match M::JACOBIAN_SPARSITY {
            None => Ok(SparsityPattern::dense(M::N_STATES)),
            Some(rows) if rows.len() != M::N_STATES => Err(SparsityError::WrongRowCount {
                expected: M::N_STATES,
                found: rows.len(),
            }),
            Some(rows) => SparsityPattern::from_rows(rows),
        }
    }

    /// The number of rows (and of columns).
    pub fn n(&self) -> usize {
        self.n
    }

    /// Whether the pattern is the dense one ([`SparsityPattern::dense`]); a pattern
    /// built from rows is never reported dense, even when every row is full.
    pub fn is_dense(&self) -> bool {
        self.dense
    }

    /// The number of entries that may be non-zero.
    pub fn nnz(&self) -> usize {
        if self.dense {
            self.n * self.n
        } else {
            self.columns.len()
        }
    }

    /// The columns of row `i` that may be non-zero, in increasing order.
    ///
    /// # Panics
    /// If `i >= n`.
    pub fn row(&self, i: usize) -> &[usize] {
        assert!(i < self.n, "row {i} out of range for {} rows", self.n);
        if self.dense {
            &self.columns
        } else {
            &self.columns[self.row_start[i]..self.row_start[i + 1]]
        }
    }

    /// Whether entry `(i, j)` may be non-zero.
    ///
    /// # Panics
    /// If `i >= n`.
    pub fn contains(&self, i: usize, j: usize) -> bool {
        self.row(i).binary_search(&j).is_ok()
    }

    /// Whether every entry `other` allows is also allowed here.
    pub fn includes(&self, other: &SparsityPattern) -> bool {
        self.n == other.n
            && (self.dense
                || (!other.dense
                    && (0..self.n).all(|i| other.row(i).iter().all(|&j| self.contains(i, j)))))
    }

    /// The transpose: for each column, the rows that may depend on it (compressed-row
    /// storage of the transpose).
    fn transpose(&self) -> (Vec<usize>, Vec<usize>) {
        let mut count = vec![0usize; self.n + 1];
        for i in 0..self.n {
            for &j in self.row(i) {
                count[j + 1] += 1;
            }
        }
        for j in 0..self.n {
            count[j + 1] += count[j];
        }
        let col_start = count.clone();
        let mut rows = vec![0usize; self.nnz()];
        let mut next = count;
        // Rows in increasing order, so each column's rows are sorted.
        for i in 0..self.n {
            for &j in self.row(i) {
                rows[next[j]] = i;
                next[j] += 1;
            }
        }
        (col_start, rows)
    }
}

/// A partition of the Jacobian's columns into groups (colours) of structurally
/// orthogonal columns: no two columns of a colour have a non-zero in the same row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Colouring {
    /// The colour of each column.
    colour_of: Vec<usize>,
    /// Where each colour starts in `columns` (`n_colours + 1` entries).
    colour_start: Vec<usize>,
    /// The columns, grouped by colour, increasing within each colour.
    columns: Vec<usize>,
}

impl Colouring {
    /// Greedy sequential colouring in natural column order (Curtis, Powell & Reid 1974;
    /// Coleman & Moré 1983), deterministic.
    ///
    /// Columns are taken in order `0, 1, …, n − 1`; each gets the smallest colour not
    /// already held by an earlier column it shares a row with. So a column that shares
    /// no row with any earlier column gets colour 0 (a diagonal pattern has one colour,
    /// a dense one `n`), and the number of colours is at least the longest row and at
    /// most one more than the largest number of other columns any column shares a row
    /// with. For a banded pattern of half-bandwidth `w` it is the optimal `2w + 1` (or
    /// `n` if smaller). The dense pattern is coloured directly (column `j`, colour `j`).
    ///
    /// Cost: the sum over rows of the square of the row's length.
    pub fn greedy(pattern: &SparsityPattern) -> Self {
        let n = pattern.n();
        let colour_of: Vec<usize> = if pattern.is_dense() {
            (0..n).collect()
        } else {
            let (col_start, col_rows) = pattern.transpose();
            let mut colour_of = vec![0usize; n];
            // `forbidden[c] == j`: colour `c` is taken by a neighbour of column `j`.
            let mut forbidden = vec![usize::MAX; n];
            for j in 0..n {
                for &i in &col_rows[col_start[j]..col_start[j + 1]] {
                    for &k in pattern.row(i) {
                        if k >= j {
                            break;
                        }
                        forbidden[colour_of[k]] = j;
                    }
                }
                colour_of[j] = (0..n).find(|&c| forbidden[c] != j).unwrap_or(0);
            }
            colour_of
        };
        let n_colours = colour_of.iter().map(|&c| c + 1).max().unwrap_or(0);
        let mut colour_start = vec![0usize; n_colours + 1];
        for &c in &colour_of {
            colour_start[c + 1] += 1;
        }
        for c in 0..n_colours {
            colour_start[c + 1] += colour_start[c];
        }
        let mut next = colour_start.clone();
        let mut columns = vec![0usize; n];
        for (j, &c) in colour_of.iter().enumerate() {
            columns[next[c]] = j;
            next[c] += 1;
        }
        Colouring {
            colour_of,
            colour_start,
            columns,
        }
    }

    /// The number of colours (dual evaluations per Jacobian).
    pub fn n_colours(&self) -> usize {
        self.colour_start.len() - 1
    }

    /// The colour of column `j`.
    ///
    /// # Panics
    /// If `j` is not a column.
    pub fn colour_of(&self, j: usize) -> usize {
        self.colour_of[j]
    }

    /// The columns of colour `c`, in increasing order.
    ///
    /// # Panics
    /// If `c >= n_colours()`.
    pub fn columns(&self, c: usize) -> &[usize] {
        &self.columns[self.colour_start[c]..self.colour_start[c + 1]]
    }
}

/// Evaluates Jacobians ∂(dx/dt)/∂x and Jacobian-vector products of one model, with the
/// buffers and colouring it needs allocated once, at set-up: [`evaluate`] and [`jvp`]
/// do not allocate.
///
/// [`evaluate`]: JacobianEvaluator::evaluate
/// [`jvp`]: JacobianEvaluator::jvp
#[derive(Clone, Debug)]
pub struct JacobianEvaluator {
    pattern: SparsityPattern,
    colouring: Colouring,
    /// For each column, where its rows start in `col_rows` (`n + 1` entries; empty when
    /// the pattern is dense).
    col_start: Vec<usize>,
    /// The rows of each column, one column after the other.
    col_rows: Vec<usize>,
    /// The dual state.
    x: Vec<Dual>,
    /// The dual state derivative.
    dx: Vec<Dual>,
}

impl JacobianEvaluator {
    /// The evaluator for models of type `M`, compressed by the pattern it declares
    /// ([`Model::JACOBIAN_SPARSITY`]; dense when it declares none). The model itself is
    /// not read: the argument only names its type.
    ///
    /// # Panics
    /// If `M`'s declared pattern is malformed (see [`SparsityPattern::for_model`]), a
    /// bug in the model's implementation of [`Model`].
    pub fn new<M: Model>(model: &M) -> Self {
        let _ = model;
        match SparsityPattern::for_model::<M>() {
            Ok(pattern) => JacobianEvaluator::with_pattern(pattern),
            Err(e) => panic!("model `{}`: {e}", M::NAME),
        }
    }

    /// The evaluator compressed by `pattern`, which must include every entry of the
    /// Jacobian that can be non-zero (a larger pattern is correct, only slower).
    /// [`SparsityPattern::dense`] gives the uncompressed evaluator: one evaluation per
    /// column.
    pub fn with_pattern(pattern: SparsityPattern) -> Self {
        let n = pattern.n();
        let colouring = Colouring::greedy(&pattern);
        let (col_start, col_rows) = if pattern.is_dense() {
            (Vec::new(), Vec::new())
        } else {
            pattern.transpose()
        };
        JacobianEvaluator {
            pattern,
            colouring,
            col_start,
            col_rows,
            x: vec![Dual::default(); n],
            dx: vec![Dual::default(); n],
        }
    }

    /// The number of states `n` (the Jacobian is `n × n`).
    pub fn n_states(&self) -> usize {
        self.pattern.n()
    }

    /// The number of colours: dual evaluations per automatically differentiated
    /// Jacobian.
    pub fn n_colours(&self) -> usize {
        self.colouring.n_colours()
    }

    /// The sparsity pattern the evaluator compresses by.
    pub fn pattern(&self) -> &SparsityPattern {
        &self.pattern
    }

    /// The column colouring.
    pub fn colouring(&self) -> &Colouring {
        &self.colouring
    }

    /// Writes the Jacobian ∂(dx/dt)/∂x of `model` at `(t, x)` into `jac`, dense and
    /// row-major (`jac[i * n + j]` = ∂ẋᵢ/∂xⱼ, zero outside the pattern), and returns the
    /// number of derivative evaluations it took: 0 when the model supplies its own
    /// Jacobian ([`Model::jacobian`] returns `true`), else one dual evaluation per
    /// colour ([`JacobianEvaluator::evaluate_ad`]).
    ///
    /// # Panics
    /// If `M::N_STATES`, `x.len()` or `jac.len()` do not match `n` and `n²`.
    pub fn evaluate<M: Model>(&mut self, model: &M, t: f64, x: &[f64], jac: &mut [f64]) -> usize {
        let n = self.n_states();
        self.check_sizes::<M>(x.len(), jac.len(), "jac", n * n);
        if model.jacobian(t, x, jac) {
            return 0;
        }
        self.differentiate(model, t, x, jac)
    }

    /// As [`JacobianEvaluator::evaluate`], but always by automatic differentiation,
    /// ignoring a hand-written [`Model::jacobian`] (to check one, for instance). Returns
    /// the number of dual evaluations: the number of colours.
    ///
    /// # Panics
    /// If `M::N_STATES`, `x.len()` or `jac.len()` do not match `n` and `n²`.
    pub fn evaluate_ad<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        jac: &mut [f64],
    ) -> usize {
        let n = self.n_states();
        self.check_sizes::<M>(x.len(), jac.len(), "jac", n * n);
        self.differentiate(model, t, x, jac)
    }

    /// The Jacobian by one dual evaluation per colour: the columns of a colour are
    /// seeded together, and each row's tangent is the entry of the one column of the
    /// colour that the row depends on (for a dense pattern: every row, one column per
    /// colour).
    fn differentiate<M: Model>(&mut self, model: &M, t: f64, x: &[f64], jac: &mut [f64]) -> usize {
        let n = self.n_states();
        let dense = self.pattern.is_dense();
        for (d, &v) in self.x.iter_mut().zip(x) {
            *d = Dual::constant(v);
        }
        if !dense {
            // Entries outside the pattern are never written below.
            jac.fill(0.0);
        }
        for c in 0..self.colouring.n_colours() {
            let columns = self.colouring.columns(c);
            for &j in columns {
                self.x[j].eps = 1.0;
            }
            model.derivatives(t, &self.x, &mut self.dx);
            for &j in columns {
                self.x[j].eps = 0.0;
                if dense {
                    for (i, d) in self.dx.iter().enumerate() {
                        jac[i * n + j] = d.eps;
                    }
                } else {
                    for &i in &self.col_rows[self.col_start[j]..self.col_start[j + 1]] {
                        jac[i * n + j] = self.dx[i].eps;
                    }
                }
            }
        }
        self.colouring.n_colours()
    }

    /// Writes the Jacobian-vector product `J v` of `model` at `(t, x)` into `out`, with
    /// one dual evaluation of [`Model::derivatives`] (never the hand-written Jacobian).
    ///
    /// # Panics
    /// If `M::N_STATES`, `x.len()`, `v.len()` or `out.len()` are not `n`.
    pub fn jvp<M: Model>(&mut self, model: &M, t: f64, x: &[f64], v: &[f64], out: &mut [f64]) {
        let n = self.n_states();
        self.check_sizes::<M>(x.len(), out.len(), "out", n);
        assert_eq!(v.len(), n, "direction length");
        for ((d, &xi), &vi) in self.x.iter_mut().zip(x).zip(v) {
            *d = Dual::new(xi, vi);
        }
        model.derivatives(t, &self.x, &mut self.dx);
        for (o, d) in out.iter_mut().zip(&self.dx) {
            *o = d.eps;
        }
    }

    /// The size checks shared by the evaluation methods (and, with debug assertions,
    /// that `M`'s declared pattern lies inside the evaluator's).
    #[inline]
    fn check_sizes<M: Model>(&self, x_len: usize, out_len: usize, out_name: &str, expected: usize) {
        let n = self.n_states();
        assert_eq!(
            M::N_STATES,
            n,
            "model `{}` has {} states, the Jacobian evaluator was built for {n}",
            M::NAME,
            M::N_STATES
        );
        assert_eq!(x_len, n, "state vector length");
        assert_eq!(out_len, expected, "`{out_name}` length");
        debug_assert!(
            self.accepts::<M>(),
            "model `{}` declares a Jacobian sparsity pattern that the evaluator's does not include \
             (was the evaluator built for another model?)",
            M::NAME
        );
    }

    /// Whether every entry `M` declares possibly non-zero is inside the evaluator's
    /// pattern (a model that declares none is accepted: it may have been given one).
    fn accepts<M: Model>(&self) -> bool {
        let Some(rows) = M::JACOBIAN_SPARSITY else {
            return true;
        };
        self.pattern.is_dense()
            || (rows.len() == self.n_states()
                && rows
                    .iter()
                    .enumerate()
                    .all(|(i, row)| row.iter().all(|&j| self.pattern.contains(i, j))))
    }
}
