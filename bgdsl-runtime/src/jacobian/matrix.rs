//! The Jacobian the stiff methods factor from: the values of the entries of a
//! sparsity pattern, row by row (compressed-row storage), dense only when the pattern
//! is.

use std::sync::Arc;

use super::SparsityPattern;

/// A Jacobian ∂(dx/dt)/∂x stored over a [`SparsityPattern`]: one value per entry of
/// the pattern, row by row, columns increasing within a row (compressed-row storage);
/// every entry outside the pattern is zero. For the dense pattern the values are the
/// whole `n × n` matrix, row-major.
///
/// The pattern is the model's declared one, or, for a hand-written Jacobian without a
/// declared pattern, the non-zeros found by evaluating it; that detected pattern may
/// grow during a run, and each change of pattern increments
/// [`Jacobian::generation`], so that what was built for the old one (an LU's
/// structure) can be built again.
///
/// ```
/// use bgdsl_runtime::{Jacobian, SparsityPattern};
///
/// let pattern = SparsityPattern::from_rows(&[vec![0, 2], vec![1], vec![]]).unwrap();
/// let mut jac = Jacobian::new(pattern.into());
/// jac.values_mut().copy_from_slice(&[1.0, 2.0, 3.0]);
/// assert_eq!(jac.get(0, 2), 2.0);
/// assert_eq!(jac.get(1, 0), 0.0);
/// assert_eq!(jac.row(0), (&[0, 2][..], &[1.0, 2.0][..]));
/// assert_eq!(jac.nnz(), 3);
/// ```
#[derive(Clone, Debug)]
pub struct Jacobian {
    pattern: Arc<SparsityPattern>,
    values: Vec<f64>,
    generation: u64,
}

impl Jacobian {
    /// The zero Jacobian over `pattern`, with storage for its entries.
    pub fn new(pattern: Arc<SparsityPattern>) -> Self {
        Jacobian {
            values: vec![0.0; pattern.nnz()],
            pattern,
            generation: 0,
        }
    }

    /// The number of states `n` (the Jacobian is `n × n`).
    pub fn n(&self) -> usize {
        self.pattern.n()
    }

    /// The pattern the values are stored over.
    pub fn pattern(&self) -> &Arc<SparsityPattern> {
        &self.pattern
    }

    /// Whether the storage is dense (`n × n`, row-major).
    pub fn is_dense(&self) -> bool {
        self.pattern.is_dense()
    }

    /// The number of stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// The values, in the pattern's order (row by row).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The values, in the pattern's order, to be written.
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// Where row `i`'s values are in [`Jacobian::values`].
    ///
    /// # Panics
    /// If `i >= n`.
    pub fn row_range(&self, i: usize) -> core::ops::Range<usize> {
        self.pattern.row_range(i)
    }

    /// Row `i`: its columns (increasing) and their values.
    ///
    /// # Panics
    /// If `i >= n`.
    pub fn row(&self, i: usize) -> (&[usize], &[f64]) {
        (self.pattern.row(i), &self.values[self.row_range(i)])
    }

    /// Entry `(i, j)`: its value, or zero outside the pattern.
    ///
    /// # Panics
    /// If `i >= n`.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (cols, values) = self.row(i);
        cols.binary_search(&j).map_or(0.0, |k| values[k])
    }

    /// Where entry `(i, j)` is in [`Jacobian::values`], if it is in the pattern.
    ///
    /// # Panics
    /// If `i >= n`.
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let range = self.row_range(i);
        self.pattern
            .row(i)
            .binary_search(&j)
            .ok()
            .map(|k| range.start + k)
    }

    /// How many times the pattern has changed ([`Jacobian::set_pattern`]).
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Replaces the pattern (zeroing every value), reallocating the values when the
    /// new pattern has more entries.
    pub fn set_pattern(&mut self, pattern: Arc<SparsityPattern>) {
        self.values.clear();
        self.values.resize(pattern.nnz(), 0.0);
        self.pattern = pattern;
        self.generation += 1;
    }

    /// Copies the dense row-major `n × n` matrix `dense` into the pattern's entries;
    /// returns the first entry outside the pattern that is not zero (NaN counts), if
    /// any.
    ///
    /// # Panics
    /// If `dense.len() != n²`.
    pub fn gather_dense(&mut self, dense: &[f64]) -> Option<(usize, usize)> {
        let n = self.n();
        assert_eq!(dense.len(), n * n, "dense Jacobian length");
        if self.is_dense() {
            self.values.copy_from_slice(dense);
            return None;
        }
        let mut outside = None;
        for i in 0..n {
            let row = &dense[i * n..(i + 1) * n];
            let range = self.pattern.row_range(i);
            let cols = self.pattern.row(i);
            let mut next = 0;
            for (j, &v) in row.iter().enumerate() {
                if next < cols.len() && cols[next] == j {
                    self.values[range.start + next] = v;
                    next += 1;
                } else if v != 0.0 && outside.is_none() {
                    outside = Some((i, j));
                }
            }
        }
        outside
    }

    /// Writes the Jacobian into the dense row-major `n × n` matrix `dense`.
    ///
    /// # Panics
    /// If `dense.len() != n²`.
    pub fn to_dense(&self, dense: &mut [f64]) {
        let n = self.n();
        assert_eq!(dense.len(), n * n, "dense Jacobian length");
        if self.is_dense() {
            dense.copy_from_slice(&self.values);
            return;
        }
        dense.fill(0.0);
        for i in 0..n {
            let (cols, values) = self.row(i);
            for (&j, &v) in cols.iter().zip(values) {
                dense[i * n + j] = v;
            }
        }
    }
}
