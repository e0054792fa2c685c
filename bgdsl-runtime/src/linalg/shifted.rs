//! The stiff solvers' real iteration matrix `σ I − J` behind a public face, for code
//! outside the runtime that solves linear systems with a model's Jacobians (the
//! variational equations of `bgdsl-analysis`).

use super::{RealMatrix, Structure};
use crate::jacobian::{Jacobian, SparsityPattern};

/// `σ I − J` for Jacobians stored over one [`SparsityPattern`], factored as the stiff
/// solvers factor theirs: sparse LU on the numerical pattern of the Jacobians seen (an
/// elimination order analysed once, again only when a new non-zero appears), or banded
/// with partial pivoting when that is cheaper, with the banded code as the fallback of
/// an unstable sparse factorization (see the runtime's `linalg` module). Storage is
/// allocated by [`ShiftedLu::new`]; factoring and solving allocate nothing.
///
/// ```
/// use bgdsl_runtime::{Jacobian, ShiftedLu, SparsityPattern};
///
/// // J = [[-1, 2], [0, -3]]: (2 I − J) x = b.
/// let pattern = SparsityPattern::from_rows(&[vec![0, 1], vec![1]]).unwrap();
/// let mut jac = Jacobian::new(pattern.clone().into());
/// jac.values_mut().copy_from_slice(&[-1.0, 2.0, -3.0]);
/// let mut lu = ShiftedLu::new(&pattern);
/// lu.factor(2.0, &jac).unwrap();
/// let mut b = [1.0, 5.0];
/// lu.solve(&mut b);
/// assert!((b[1] - 1.0).abs() < 1e-15 && (3.0 * b[0] - 2.0 * b[1] - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct ShiftedLu {
    matrix: RealMatrix,
}

impl ShiftedLu {
    /// Storage for `σ I − J` with `J` over `pattern`.
    pub fn new(pattern: &SparsityPattern) -> Self {
        ShiftedLu {
            matrix: RealMatrix::new(&Structure::of_pattern(pattern)),
        }
    }

    /// Factors `shift I − jac` (`jac` stored over the pattern given to
    /// [`ShiftedLu::new`]).
    ///
    /// # Errors
    /// The column whose pivot vanished (or was not finite), when the matrix is
    /// singular to working precision even with partial pivoting.
    pub fn factor(&mut self, shift: f64, jac: &Jacobian) -> Result<(), usize> {
        self.matrix
            .factor(shift, jac, true)
            .map(|_| ())
            .map_err(|singular| singular.column)
    }

    /// Solves `(σ I − J) x = b` with the last successful [`ShiftedLu::factor`],
    /// overwriting `b` with `x`.
    ///
    /// # Panics
    /// Before a successful factorization.
    pub fn solve(&self, b: &mut [f64]) {
        self.matrix.solve(b);
    }
}
