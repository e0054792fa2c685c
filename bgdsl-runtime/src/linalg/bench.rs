//! The LU kernels of the stiff solvers behind a small public face, for the benches
//! (`benches/lu.rs`): not a public API (re-exported hidden as `__bench`).

use super::{Factored, RadauMatrices, RealMatrix, Structure};
use crate::jacobian::{Jacobian, SparsityPattern};

/// Radau IIA's pair of iteration matrices and a real one (as Rosenbrock methods use),
/// stored and factored as the solvers do for Jacobians of one sparsity pattern.
#[derive(Clone, Debug)]
pub struct Matrices {
    pair: RadauMatrices,
    real: RealMatrix,
    sparse: bool,
}

impl Matrices {
    /// Storage for the matrices of Jacobians of `pattern`, chosen as the solvers choose
    /// (sparse or banded).
    pub fn new(pattern: &SparsityPattern) -> Self {
        let structure = Structure::of_pattern(pattern);
        Matrices {
            pair: RadauMatrices::new(&structure),
            real: RealMatrix::new(&structure),
            sparse: structure.sparse.is_some(),
        }
    }

    /// Whether the sparse code factors them (else the banded one).
    pub fn is_sparse(&self) -> bool {
        self.sparse
    }

    /// The sparse factors' entries and the multiply-adds of one real factorization of
    /// the Jacobians' numerical pattern so far (none when banded).
    pub fn sparse_size(&self) -> Option<(usize, usize)> {
        self.pair.sparse_size()
    }

    /// Factors `γ I - J` and `(α + iβ) I - J` for `shifts = [γ, α, β]`; `new_jacobian`
    /// says that `jac` may differ from the last call's. Returns whether the planned
    /// factorization succeeded (`false`: the fallback with partial pivoting was used,
    /// or the matrix is singular).
    pub fn factor_pair(&mut self, shifts: [f64; 3], jac: &Jacobian, new_jacobian: bool) -> bool {
        self.pair.factor(shifts, jac, new_jacobian) == Ok(Factored::AsPlanned)
    }

    /// Solves `(γ I - J) x = b` with the last pair, overwriting `b`.
    pub fn solve_real(&self, b: &mut [f64]) {
        self.pair.solve_real(b);
    }

    /// Solves `(γ I - J) x = b` and `((α + iβ) I - J) y = c` with the last pair,
    /// overwriting `b` and `c = c_re + i c_im`.
    pub fn solve_both(&mut self, b: &mut [f64], c_re: &mut [f64], c_im: &mut [f64]) {
        self.pair.solve_both(b, c_re, c_im);
    }

    /// Factors `shift I - J` alone (the real matrix of a Rosenbrock method).
    pub fn factor_real(&mut self, shift: f64, jac: &Jacobian, new_jacobian: bool) -> bool {
        self.real.factor(shift, jac, new_jacobian) == Ok(Factored::AsPlanned)
    }

    /// Solves `(shift I - J) x = b` with the last real factorization, overwriting `b`.
    pub fn solve_real_alone(&self, b: &mut [f64]) {
        self.real.solve(b);
    }
}
