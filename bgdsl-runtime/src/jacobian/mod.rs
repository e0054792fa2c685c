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
//! then costs one directional derivative per group (colour) instead of one per column.
//! The directions are evaluated [`LANES`] at a time, on [`DualN`] numbers: the value,
//! the branches and the elementary functions of the model are then computed once for
//! all of them, and the tangents in short vector loops.
//!
//! The stiff solvers go one step further: a Jacobian often has many fewer non-zeros
//! than its structural pattern (a planar mechanism written with 3-D multibonds has all
//! its out-of-plane entries exactly zero: 653 of the 2187 of the quick return model,
//! whose longest row drops from 75 entries to 30), so after the first Jacobian of a
//! run they colour its *numerical* pattern instead, and check every Jacobian so
//! compressed with one more directional derivative: if the check finds a non-zero
//! outside the numerical pattern, the Jacobian is evaluated again with the structural
//! colouring and the pattern grows. [`Stats::n_jac_rhs`](crate::Stats::n_jac_rhs)
//! counts the directional derivatives.
//!
//! A row whose value the model evaluates to NaN or infinity has NaN derivatives,
//! whatever the tangents say: a model whose evaluation failed (an implicit solve that
//! did not converge writes NaN values with zero tangents) gives a Jacobian a solver
//! sees is not finite, and then asks the model why
//! ([`Model::evaluation_error`]).
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

mod matrix;

use core::fmt;

pub use matrix::Jacobian;

use crate::dual::{Dual, DualN};

/// The derivative in `lane` of a derivative the model evaluated: NaN where the value
/// itself is not finite. A model whose evaluation failed (an implicit solve that did
/// not converge) writes NaN values with zero tangents; the derivative of an undefined
/// value is undefined, and a NaN entry lets the solver see it and ask the model why
/// ([`Model::evaluation_error`]).
#[inline(always)]
fn derivative(d: &DualN<LANES>, lane: usize) -> f64 {
    if d.value().is_finite() {
        d.tangents()[lane]
    } else {
        f64::NAN
    }
}

/// The number of directional derivatives (colours) [`JacobianEvaluator`] evaluates
/// together, in one evaluation of [`Model::derivatives`] on [`DualN`]`<LANES>`.
pub const LANES: usize = 4;
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

    /// Where row `i`'s entries are in the pattern's order (row by row): the range of
    /// their positions among the pattern's [`SparsityPattern::nnz`] entries.
    ///
    /// # Panics
    /// If `i >= n`.
    pub fn row_range(&self, i: usize) -> core::ops::Range<usize> {
        assert!(i < self.n, "row {i} out of range for {} rows", self.n);
        if self.dense {
            i * self.n..(i + 1) * self.n
        } else {
            self.row_start[i]..self.row_start[i + 1]
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

    /// The number of colours (directional derivatives per Jacobian).
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
    /// The state and its derivative with [`LANES`] tangents.
    x_lanes: Vec<DualN<LANES>>,
    dx_lanes: Vec<DualN<LANES>>,
    /// The numerical pattern of a run's Jacobians, for
    /// [`JacobianEvaluator::evaluate_numerical`].
    numerical: Numerical,
}

/// How much the product `J v` of a Jacobian compressed by its numerical pattern may
/// differ from the one computed directly, relative to `sum_j |J_ij v_j| + |(J v)_i|`,
/// before the compression is taken to have missed an entry. Rounding makes them
/// differ by a few `ε` of the terms; an entry missed below this, which goes unnoticed,
/// is too small to matter to the Newton iterations the Jacobian is for.
const CHECK_TOLERANCE: f64 = 1e-8;

/// The numerical sparsity of the Jacobians of a run, for
/// [`JacobianEvaluator::evaluate_numerical`]: the union `P` of the entries found
/// non-zero so far (within the declared pattern), by rows and by columns, and a
/// greedy colouring of `P`. All storage is allocated at set-up (bounded by the declared
/// pattern).
#[derive(Clone, Debug, Default)]
struct Numerical {
    /// `P` holds the non-zeros of at least one Jacobian of this run.
    known: bool,
    /// A check failed although no entry was missing (rounding in the model's
    /// derivative larger than [`CHECK_TOLERANCE`] allows): no more compression this
    /// run.
    given_up: bool,
    /// `P` as a bit set per row (`words` words each).
    words: usize,
    member: Vec<u64>,
    /// `P` by rows and by columns (capacity: the declared pattern's entries).
    row_start: Vec<usize>,
    cols: Vec<usize>,
    col_start: Vec<usize>,
    col_rows: Vec<usize>,
    /// The colouring of `P`'s columns: colour of each column, and the columns of each
    /// colour (`columns[colour_start[c]..colour_start[c + 1]]`).
    n_colours: usize,
    colour_of: Vec<usize>,
    colour_start: Vec<usize>,
    columns: Vec<usize>,
    /// Scratch of the colouring.
    forbidden: Vec<usize>,
    /// The direction `v` of the check, and `J v` computed directly.
    direction: Vec<f64>,
    jv: Vec<f64>,
}

impl Numerical {
    /// The storage for `pattern` (empty for a dense pattern, which is never
    /// compressed).
    fn new(pattern: &SparsityPattern) -> Self {
        if pattern.is_dense() {
            return Numerical::default();
        }
        let (n, nnz) = (pattern.n(), pattern.nnz());
        let words = n.div_ceil(64).max(1);
        // A fixed direction with entries in [1, 2): no sign pattern, no zero, to make
        // an exact cancellation of a missed entry in `J v` as unlikely as possible.
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let direction = (0..n)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                1.0 + (seed >> 11) as f64 / (1u64 << 53) as f64
            })
            .collect();
        Numerical {
            known: false,
            given_up: false,
            words,
            member: vec![0; n * words],
            row_start: vec![0; n + 1],
            cols: vec![0; nnz],
            col_start: vec![0; n + 1],
            col_rows: vec![0; nnz],
            n_colours: 0,
            colour_of: vec![0; n],
            colour_start: vec![0; n + 1],
            columns: vec![0; n],
            forbidden: vec![usize::MAX; n],
            direction,
            jv: vec![0.0; n],
        }
    }

    /// Adds the non-zeros of `jac` (at the entries of `pattern`) to `P`; if it grew,
    /// rebuilds its rows, columns and colouring, and says so. Allocates nothing.
    fn include(&mut self, pattern: &SparsityPattern, jac: &[f64]) -> bool {
        let n = pattern.n();
        let mut grew = !self.known;
        for i in 0..n {
            for &j in pattern.row(i) {
                let (w, bit) = (i * self.words + j / 64, 1u64 << (j % 64));
                // NaN counts as non-zero.
                if jac[i * n + j] != 0.0 && self.member[w] & bit == 0 {
                    self.member[w] |= bit;
                    grew = true;
                }
            }
        }
        self.known = true;
        if !grew {
            return false;
        }
        let member = |i: usize, j: usize| self.member[i * self.words + j / 64] >> (j % 64) & 1 == 1;
        // By rows, then by columns (rows increasing within each column).
        let mut next = 0;
        self.col_start.fill(0);
        for i in 0..n {
            self.row_start[i] = next;
            for &j in pattern.row(i) {
                if member(i, j) {
                    self.cols[next] = j;
                    next += 1;
                    self.col_start[j + 1] += 1;
                }
            }
        }
        self.row_start[n] = next;
        for j in 0..n {
            self.col_start[j + 1] += self.col_start[j];
        }
        // `colour_of` serves as the fill pointer of each column here.
        self.colour_of.copy_from_slice(&self.col_start[..n]);
        for i in 0..n {
            for &j in &self.cols[self.row_start[i]..self.row_start[i + 1]] {
                self.col_rows[self.colour_of[j]] = i;
                self.colour_of[j] += 1;
            }
        }
        // Greedy colouring in natural column order (as `Colouring::greedy`).
        self.forbidden.fill(usize::MAX);
        let mut n_colours = 0;
        for j in 0..n {
            for &i in &self.col_rows[self.col_start[j]..self.col_start[j + 1]] {
                for &k in &self.cols[self.row_start[i]..self.row_start[i + 1]] {
                    if k >= j {
                        break;
                    }
                    self.forbidden[self.colour_of[k]] = j;
                }
            }
            let c = (0..n).find(|&c| self.forbidden[c] != j).unwrap_or(0);
            self.colour_of[j] = c;
            n_colours = n_colours.max(c + 1);
        }
        self.n_colours = n_colours;
        self.colour_start.fill(0);
        for j in 0..n {
            self.colour_start[self.colour_of[j] + 1] += 1;
        }
        for c in 0..n_colours {
            self.colour_start[c + 1] += self.colour_start[c];
        }
        // `forbidden` serves as the fill pointer of each colour here.
        self.forbidden[..n_colours].copy_from_slice(&self.colour_start[..n_colours]);
        for j in 0..n {
            let c = self.colour_of[j];
            self.columns[self.forbidden[c]] = j;
            self.forbidden[c] += 1;
        }
        true
    }

    /// The columns of colour `c`.
    fn columns(&self, c: usize) -> &[usize] {
        &self.columns[self.colour_start[c]..self.colour_start[c + 1]]
    }

    /// Whether `jac`, recovered for `P`, reproduces `J v` (see [`CHECK_TOLERANCE`]).
    fn check(&self, jac: &[f64]) -> bool {
        let n = self.jv.len();
        (0..n).all(|i| {
            let (mut sum, mut scale) = (0.0, self.jv[i].abs());
            for &j in &self.cols[self.row_start[i]..self.row_start[i + 1]] {
                let term = jac[i * n + j] * self.direction[j];
                sum += term;
                scale += term.abs();
            }
            // Written so that NaN fails.
            (self.jv[i] - sum).abs() <= CHECK_TOLERANCE * scale
        })
    }
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
            colouring,
            col_start,
            col_rows,
            x: vec![Dual::default(); n],
            dx: vec![Dual::default(); n],
            x_lanes: vec![DualN::default(); n],
            dx_lanes: vec![DualN::default(); n],
            numerical: Numerical::new(&pattern),
            pattern,
        }
    }

    /// The number of states `n` (the Jacobian is `n × n`).
    pub fn n_states(&self) -> usize {
        self.pattern.n()
    }

    /// The number of colours: directional derivatives per automatically
    /// differentiated Jacobian (evaluated [`LANES`] per evaluation of the model).
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
    /// number of directional derivatives it took: 0 when the model supplies its own
    /// Jacobian ([`Model::jacobian`] returns `true`), else one per colour
    /// ([`JacobianEvaluator::evaluate_ad`]).
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
    /// the number of directional derivatives: the number of colours (they are
    /// evaluated [`LANES`] at a time, on [`DualN`] numbers).
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

    /// The Jacobian by one directional derivative per colour, [`LANES`] colours per
    /// evaluation on [`DualN`]: the columns of colour `c` are seeded together in lane
    /// `c % LANES`, and each row's tangent in that lane is the entry of the one column
    /// of the colour that the row depends on (for a dense pattern: every row, one
    /// column per colour). Returns the number of colours.
    fn differentiate<M: Model>(&mut self, model: &M, t: f64, x: &[f64], jac: &mut [f64]) -> usize {
        let n = self.n_states();
        let dense = self.pattern.is_dense();
        for (d, &v) in self.x_lanes.iter_mut().zip(x) {
            *d = DualN::constant(v);
        }
        if !dense {
            // Entries outside the pattern are never written below.
            jac.fill(0.0);
        }
        let n_colours = self.colouring.n_colours();
        for first in (0..n_colours).step_by(LANES) {
            let colours = first..(first + LANES).min(n_colours);
            for c in colours.clone() {
                for &j in self.colouring.columns(c) {
                    self.x_lanes[j].set_tangent(c - first, 1.0);
                }
            }
            model.derivatives(t, &self.x_lanes, &mut self.dx_lanes);
            for c in colours {
                let lane = c - first;
                for &j in self.colouring.columns(c) {
                    self.x_lanes[j].set_tangent(lane, 0.0);
                    if dense {
                        for (i, d) in self.dx_lanes.iter().enumerate() {
                            jac[i * n + j] = derivative(d, lane);
                        }
                    } else {
                        for &i in &self.col_rows[self.col_start[j]..self.col_start[j + 1]] {
                            jac[i * n + j] = derivative(&self.dx_lanes[i], lane);
                        }
                    }
                }
            }
        }
        n_colours
    }

    /// Forgets the numerical pattern of [`JacobianEvaluator::evaluate_numerical`]: a
    /// new run starts.
    pub(crate) fn restart(&mut self) {
        self.numerical.known = false;
        self.numerical.given_up = false;
        self.numerical.member.fill(0);
    }

    /// As [`JacobianEvaluator::evaluate`], compressed by the *numerical* pattern of the
    /// Jacobians met since [`JacobianEvaluator::restart`] when that is smaller.
    ///
    /// A Jacobian can have many fewer non-zeros than its structural pattern (a planar
    /// mechanism written with 3-D multibonds has every out-of-plane entry exactly zero),
    /// and a colouring of the non-zeros needs fewer colours. The first Jacobian of a run
    /// is evaluated with the structural colouring; its non-zeros form the pattern `P`.
    /// The next ones are evaluated with a colouring of `P`, plus one directional
    /// derivative along a fixed direction `v`, which checks the result: if `J v` does
    /// not match the product of the recovered Jacobian with `v` (to
    /// [`CHECK_TOLERANCE`]), some entry outside `P` is not zero, and the Jacobian is
    /// evaluated again with the structural colouring and its non-zeros are added to
    /// `P`. (If that finds nothing new, the check was defeated by rounding in the
    /// model's derivative, and the run goes on with the structural colouring.) Returns
    /// the directional derivatives evaluated.
    pub(crate) fn evaluate_numerical<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        jac: &mut [f64],
    ) -> usize {
        let n = self.n_states();
        self.check_sizes::<M>(x.len(), jac.len(), "jac", n * n);
        if model.jacobian(t, x, jac) {
            return 0;
        }
        if self.pattern.is_dense() {
            return self.differentiate(model, t, x, jac);
        }
        let num = &self.numerical;
        let compress = num.known && !num.given_up && num.n_colours < self.colouring.n_colours();
        let mut count = 0;
        if compress {
            count += self.differentiate_numerical(model, t, x, jac);
            if self.numerical.check(jac) {
                return count;
            }
        }
        count += self.differentiate(model, t, x, jac);
        let grew = self.numerical.include(&self.pattern, jac);
        if compress && !grew {
            // The check failed with no entry missing: the model's rounding defeats it.
            self.numerical.given_up = true;
        }
        count
    }

    /// The Jacobian compressed by the numerical pattern's colouring, and `J v` into
    /// `numerical.jv`: `n_colours + 1` directional derivatives, [`LANES`] at a time.
    fn differentiate_numerical<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        jac: &mut [f64],
    ) -> usize {
        let n = self.n_states();
        let num = &mut self.numerical;
        for (d, &v) in self.x_lanes.iter_mut().zip(x) {
            *d = DualN::constant(v);
        }
        jac.fill(0.0);
        // Directions 0..n_colours are the colours, direction n_colours is `v`.
        let directions = num.n_colours + 1;
        for first in (0..directions).step_by(LANES) {
            let group = first..(first + LANES).min(directions);
            for d in group.clone() {
                if d == num.n_colours {
                    for (xj, &vj) in self.x_lanes.iter_mut().zip(&num.direction) {
                        xj.set_tangent(d - first, vj);
                    }
                } else {
                    for &j in num.columns(d) {
                        self.x_lanes[j].set_tangent(d - first, 1.0);
                    }
                }
            }
            model.derivatives(t, &self.x_lanes, &mut self.dx_lanes);
            for d in group {
                let lane = d - first;
                if d == num.n_colours {
                    for xj in self.x_lanes.iter_mut() {
                        xj.set_tangent(lane, 0.0);
                    }
                    for (jv, dx) in num.jv.iter_mut().zip(&self.dx_lanes) {
                        *jv = derivative(dx, lane);
                    }
                } else {
                    for &j in &num.columns[num.colour_start[d]..num.colour_start[d + 1]] {
                        self.x_lanes[j].set_tangent(lane, 0.0);
                        for &i in &num.col_rows[num.col_start[j]..num.col_start[j + 1]] {
                            jac[i * n + j] = derivative(&self.dx_lanes[i], lane);
                        }
                    }
                }
            }
        }
        directions
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
            *o = if d.re.is_finite() { d.eps } else { f64::NAN };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::Scalar;

    /// `ẋᵢ = xᵢ² + x₅ (x₀ + … + x₄)` for `i < 5`, `ẋ₅ = 0`: structurally the first five
    /// rows are full (six colours), but while `x₅ = 0` their numerical pattern is the
    /// diagonal and column 5 (two colours).
    struct Switch;

    const FULL: &[usize] = &[0, 1, 2, 3, 4, 5];

    impl Model for Switch {
        type Params = ();
        const NAME: &'static str = "switch";
        const STATE_NAMES: &'static [&'static str] = &["x0", "x1", "x2", "x3", "x4", "x5"];
        const OUTPUT_NAMES: &'static [&'static str] = &[];
        const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
            Some(&[FULL, FULL, FULL, FULL, FULL, &[]]);
        fn params(&self) -> &() {
            &()
        }
        fn initial_state(&self, x0: &mut [f64]) {
            x0.fill(1.0);
        }
        fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
            let sum = x[0] + x[1] + x[2] + x[3] + x[4];
            for i in 0..5 {
                dx[i] = x[i] * x[i] + x[5] * sum;
            }
            dx[5] = T::from_f64(0.0);
        }
        fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    }

    /// The numerical pattern compresses while it holds, is caught by the check when an
    /// entry outside it turns non-zero (then evaluated in full, and learnt), and is
    /// forgotten by `restart`; every Jacobian equals the structurally compressed one.
    #[test]
    fn numerical_compression_is_checked_and_learns() {
        let mut numerical = JacobianEvaluator::new(&Switch);
        let mut structural = numerical.clone();
        assert_eq!(structural.n_colours(), 6);
        let (mut got, mut want) = (vec![0.0; 36], vec![0.0; 36]);
        let mut evaluate = |numerical: &mut JacobianEvaluator, x: &[f64], directions: usize| {
            let count = numerical.evaluate_numerical(&Switch, 0.0, x, &mut got);
            assert_eq!(count, directions, "at {x:?}");
            structural.evaluate(&Switch, 0.0, x, &mut want);
            assert_eq!(got, want, "at {x:?}");
        };
        let at_rest = [0.5, -1.0, 2.0, 0.25, 3.0, 0.0];
        let moving = [0.5, -1.0, 2.0, 0.25, 3.0, 0.1];
        // The structural colouring first; then two colours and the check.
        evaluate(&mut numerical, &at_rest, 6);
        evaluate(&mut numerical, &[1.5, 1.0, -2.0, 0.75, 0.0, 0.0], 3);
        // x₅ ≠ 0: the check fails, the Jacobian is evaluated in full and learnt; the
        // pattern is then the structural one, and no longer compressed.
        evaluate(&mut numerical, &moving, 3 + 6);
        evaluate(&mut numerical, &moving, 6);
        evaluate(&mut numerical, &at_rest, 6);
        numerical.restart();
        evaluate(&mut numerical, &at_rest, 6);
        evaluate(&mut numerical, &at_rest, 3);
    }

    /// `ẋ₀ = x₀² + (x₁ + 1e20 x₂) − 1e20 x₂`, `ẋ₁ = ẋ₂ = 0`: column by column the
    /// entry for `x₂` is exactly zero, but `J v` along a direction with a non-zero
    /// second and third component rounds to garbage. The check fails without a missing
    /// entry, and the run stops compressing.
    struct Cancelling;

    impl Model for Cancelling {
        type Params = ();
        const NAME: &'static str = "cancelling";
        const STATE_NAMES: &'static [&'static str] = &["x0", "x1", "x2", "x3"];
        const OUTPUT_NAMES: &'static [&'static str] = &[];
        const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
            Some(&[&[0, 1, 2, 3], &[0, 1, 2, 3], &[], &[]]);
        fn params(&self) -> &() {
            &()
        }
        fn initial_state(&self, x0: &mut [f64]) {
            x0.fill(1.0);
        }
        fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
            let big = T::from_f64(1e20);
            dx[0] = x[0] * x[0] + (x[1] + big * x[2]) - big * x[2];
            dx[1] = x[0] * x[3];
            dx[2] = T::from_f64(0.0);
            dx[3] = T::from_f64(0.0);
        }
        fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    }

    #[test]
    fn a_check_defeated_by_rounding_stops_the_compression() {
        let mut evaluator = JacobianEvaluator::new(&Cancelling);
        assert_eq!(evaluator.n_colours(), 4);
        let mut jac = vec![0.0; 16];
        // Numerically only (0, 0), (0, 1) and (1, 3) are non-zero (∂ẋ₁/∂x₀ = x₃ = 0):
        // two colours.
        let x = [0.5, 1.0, 2.0, 0.0];
        assert_eq!(
            evaluator.evaluate_numerical(&Cancelling, 0.0, &x, &mut jac),
            4
        );
        // Compressed (two colours and the check), check failed, full evaluation, no
        // new entry: given up.
        assert_eq!(
            evaluator.evaluate_numerical(&Cancelling, 0.0, &x, &mut jac),
            3 + 4
        );
        assert_eq!(
            evaluator.evaluate_numerical(&Cancelling, 0.0, &x, &mut jac),
            4
        );
        assert_eq!(jac[1], 1.0);
        evaluator.restart();
        assert_eq!(
            evaluator.evaluate_numerical(&Cancelling, 0.0, &x, &mut jac),
            4
        );
        assert_eq!(
            evaluator.evaluate_numerical(&Cancelling, 0.0, &x, &mut jac),
            3 + 4
        );
    }
}
