//! LU factorizations, real and complex, of the iteration matrices `σ I - J` of the
//! implicit solvers, chosen once per model from the Jacobian's sparsity pattern
//! ([`Structure::of_pattern`]):
//!
//! - **sparse** ([`sparse`]): a fill-reducing (Markowitz) elimination order and the
//!   exact structure of the factors, computed for the *numerical* pattern of the
//!   Jacobians (their non-zeros, within the declared pattern; analysed again when it
//!   grows); each factorization touches only that structure, with the diagonal entries
//!   as pivots, and checks its own backward error. For the flagship quick return model
//!   (117 states, 2187 structural entries, 653 numerically non-zero) a real
//!   factorization costs about 1,500 multiply-adds, against 11,000 for the structural
//!   pattern in Markowitz order and 530,000 for the dense matrix. Radau IIA's real and
//!   complex matrices are factored together, in one pass ([`RadauMatrices`]). When the
//!   check fails (a pivot too small for the entries it eliminates) the matrix is
//!   factored again by the banded code with partial pivoting, and the solves use that
//!   factorization; the solver counts these fallbacks.
//! - **banded** ([`banded`]): Gaussian elimination with partial pivoting, limited to
//!   the band of the pattern in the model's state order; the choice for dense patterns
//!   and for small or narrow-banded ones, where it is cheaper.
//!
//! Storage is linear in the entries of the pattern and of the factors (the band for
//! the banded code): no `n × n` buffer unless the pattern is dense. It is all allocated
//! at set-up, and factoring (analysis included) and solving allocate nothing, with two
//! exceptions: the fallback band of a sparse structure whose band is much wider than
//! its factors is allocated at the first fallback ([`FALLBACK_BAND_FACTOR`]), and a
//! Jacobian whose pattern changed ([`Jacobian::generation`]: a hand-written one that
//! showed a new non-zero) gets new storage.

mod banded;
pub(crate) mod bench;
mod shifted;
mod sparse;
mod symbolic;

use std::sync::Arc;

pub(crate) use banded::{Band, ComplexLu, Lu};
pub use shifted::ShiftedLu;
pub(crate) use sparse::{SparseLu, SparseRadauLu, Structural};

use crate::jacobian::{Jacobian, SparsityPattern};

/// The factorization met a zero (or non-finite) pivot: the matrix is singular to
/// working precision, or holds a NaN or an infinity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Singular {
    /// The column whose pivot vanished.
    pub column: usize,
}

/// How much more one multiply-add of the sparse factorization is taken to cost than
/// one of the banded one (indirect addressing against contiguous row operations): the
/// sparse one is used when its count of multiply-adds, times this, is below the
/// banded one's.
const SPARSE_PENALTY: usize = 4;

/// How the iteration matrices of a model are stored and factored: decided once, from
/// the Jacobian's sparsity pattern.
#[derive(Clone, Debug)]
pub(crate) struct Structure {
    /// The band of the pattern in the state order (the banded factorization's, also
    /// the fallback of the sparse one).
    band: Band,
    /// The structural pattern and its analysis, when the sparse factors are the
    /// cheaper choice.
    sparse: Option<Arc<Structural>>,
}

impl Structure {
    /// The structure for Jacobians with sparsity `pattern` (`σ I - J` also has the
    /// diagonal): sparse when cheaper than banded.
    pub fn of_pattern(pattern: &SparsityPattern) -> Self {
        let n = pattern.n();
        let band = Band::of_pattern(n, |i| pattern.row(i));
        if pattern.is_dense() {
            return Structure { band, sparse: None };
        }
        let structural = Structural::analyse(n, |i| pattern.row(i));
        let sparse =
            (SPARSE_PENALTY * structural.flops() < band.flops()).then(|| Arc::new(structural));
        Structure { band, sparse }
    }

    /// The banded structure `band`, never sparse.
    #[cfg(test)]
    pub fn banded(band: Band) -> Self {
        Structure { band, sparse: None }
    }

    /// Whether the matrices are factored by the sparse code.
    #[cfg(test)]
    pub fn is_sparse(&self) -> bool {
        self.sparse.is_some()
    }
}

/// Which factorization a successful `factor` produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Factored {
    /// The structure's own (sparse with static pivots, or banded).
    AsPlanned,
    /// The sparse factorization failed its stability test: the banded one with
    /// partial pivoting was computed instead.
    FellBack,
}

/// The sparse factorization's fallback (banded, with partial pivoting) is given its
/// storage at set-up only when the band holds at most this many times the entries of
/// the sparse factors; a wider band (up to `n²` for a pattern with entries far from
/// the diagonal) is allocated on the first fallback, which then allocates once.
const FALLBACK_BAND_FACTOR: usize = 8;

impl Structure {
    /// Whether the banded storage is allocated at set-up (see
    /// [`FALLBACK_BAND_FACTOR`]).
    fn band_up_front(&self) -> bool {
        match &self.sparse {
            None => true,
            Some(st) => self.band.storage() <= FALLBACK_BAND_FACTOR * (st.nnz() + self.band.n()),
        }
    }
}

/// The real iteration matrix `σ I - J`, factored.
#[derive(Clone, Debug)]
pub(crate) struct RealMatrix {
    band: Band,
    sparse: Option<SparseLu>,
    /// The banded factorization (allocated when first needed if the band is wide).
    banded: Option<Lu>,
    /// The last factorization is the banded one.
    use_banded: bool,
    /// The [`Jacobian::generation`] of the pattern the storage was built for.
    generation: u64,
}

impl RealMatrix {
    /// Storage for the matrices of `structure`.
    pub fn new(structure: &Structure) -> Self {
        RealMatrix {
            band: structure.band,
            sparse: structure.sparse.clone().map(SparseLu::new),
            banded: structure.band_up_front().then(|| Lu::new(structure.band)),
            use_banded: structure.sparse.is_none(),
            generation: 0,
        }
    }

    /// Forgets the Jacobians seen: a new run starts.
    pub fn restart(&mut self) {
        if let Some(lu) = &mut self.sparse {
            lu.restart();
        }
    }

    /// Factors `shift I - jac`; `new_jacobian` says that `jac` may differ from the last
    /// call's. A Jacobian whose pattern changed (a hand-written one that grew) gets new
    /// storage for it.
    pub fn factor(
        &mut self,
        shift: f64,
        jac: &Jacobian,
        new_jacobian: bool,
    ) -> Result<Factored, Singular> {
        if jac.generation() != self.generation {
            *self = RealMatrix::new(&Structure::of_pattern(jac.pattern()));
            self.generation = jac.generation();
        }
        let planned = match &mut self.sparse {
            Some(lu) => {
                if lu.factor(shift, jac, new_jacobian).is_ok() {
                    self.use_banded = false;
                    return Ok(Factored::AsPlanned);
                }
                Factored::FellBack
            }
            None => Factored::AsPlanned,
        };
        self.use_banded = true;
        let band = self.band;
        let banded = self.banded.get_or_insert_with(|| Lu::new(band));
        banded.set_shifted(shift, jac);
        banded.factor()?;
        Ok(planned)
    }

    /// Solves `A x = b` with the last successful factorization, overwriting `b`.
    pub fn solve(&self, b: &mut [f64]) {
        match (&self.sparse, &self.banded) {
            (Some(lu), _) if !self.use_banded => lu.solve(b),
            (_, Some(lu)) => lu.solve(b),
            _ => unreachable!("solve before a successful factorization"),
        }
    }
}

/// The two iteration matrices of Radau IIA, `E1 = γ I - J` (real) and
/// `E2 = (α + iβ) I - J` (complex), factored together.
#[derive(Clone, Debug)]
pub(crate) struct RadauMatrices {
    band: Band,
    sparse: Option<SparseRadauLu>,
    /// The banded factorizations (allocated when first needed if the band is wide).
    banded: Option<(Lu, ComplexLu)>,
    /// The last factorizations are the banded ones.
    use_banded: bool,
    /// The [`Jacobian::generation`] of the pattern the storage was built for.
    generation: u64,
}

impl RadauMatrices {
    /// Storage for the matrices of `structure`.
    pub fn new(structure: &Structure) -> Self {
        let band = structure.band;
        RadauMatrices {
            band,
            sparse: structure.sparse.clone().map(SparseRadauLu::new),
            banded: structure
                .band_up_front()
                .then(|| (Lu::new(band), ComplexLu::new(band))),
            use_banded: structure.sparse.is_none(),
            generation: 0,
        }
    }

    /// Forgets the Jacobians seen: a new run starts.
    pub fn restart(&mut self) {
        if let Some(lu) = &mut self.sparse {
            lu.restart();
        }
    }

    /// Factors `E1 = gamma I - jac` and `E2 = (alpha + i beta) I - jac` for
    /// `shifts = [gamma, alpha, beta]`; `new_jacobian` says that `jac` may differ from
    /// the last call's (a changed pattern gets new storage, as for [`RealMatrix`]). If
    /// the sparse factorization of either fails its stability test, both are factored
    /// by the banded code with partial pivoting ([`Factored::FellBack`]).
    pub fn factor(
        &mut self,
        shifts: [f64; 3],
        jac: &Jacobian,
        new_jacobian: bool,
    ) -> Result<Factored, Singular> {
        if jac.generation() != self.generation {
            *self = RadauMatrices::new(&Structure::of_pattern(jac.pattern()));
            self.generation = jac.generation();
        }
        let [gamma, alpha, beta] = shifts;
        let planned = match &mut self.sparse {
            Some(lu) => {
                if lu.factor(shifts, jac, new_jacobian).is_ok() {
                    self.use_banded = false;
                    return Ok(Factored::AsPlanned);
                }
                Factored::FellBack
            }
            None => Factored::AsPlanned,
        };
        self.use_banded = true;
        let band = self.band;
        let (real, complex) = self
            .banded
            .get_or_insert_with(|| (Lu::new(band), ComplexLu::new(band)));
        real.set_shifted(gamma, jac);
        real.factor()?;
        complex.set_shifted(alpha, beta, jac);
        complex.factor()?;
        Ok(planned)
    }

    /// The sparse factors' entries and the multiply-adds of one real factorization of
    /// the numerical pattern (none when banded).
    pub fn sparse_size(&self) -> Option<(usize, usize)> {
        self.sparse.as_ref().map(SparseRadauLu::size)
    }

    /// Solves `E1 x = b` with the last successful factorization, overwriting `b`.
    pub fn solve_real(&self, b: &mut [f64]) {
        match (&self.sparse, &self.banded) {
            (Some(lu), _) if !self.use_banded => lu.solve_real(b),
            (_, Some((real, _))) => real.solve(b),
            _ => unreachable!("solve before a successful factorization"),
        }
    }

    /// Solves `E1 x = b` and `E2 y = c` (`c = c_re + i c_im`) with the last successful
    /// factorizations, overwriting `b` and `c`.
    pub fn solve_both(&mut self, b: &mut [f64], c_re: &mut [f64], c_im: &mut [f64]) {
        match (&mut self.sparse, &self.banded) {
            (Some(lu), _) if !self.use_banded => lu.solve_both(b, c_re, c_im),
            (_, Some((real, complex))) => {
                real.solve(b);
                complex.solve(c_re, c_im);
            }
            _ => unreachable!("solve before a successful factorization"),
        }
    }
}

/// A Jacobian over the pattern of `dense`'s non-zeros (`n × n`, row-major), for tests.
#[cfg(test)]
pub(crate) fn jacobian_of(n: usize, dense: &[f64]) -> Jacobian {
    let rows: Vec<Vec<usize>> = (0..n)
        .map(|i| (0..n).filter(|&j| dense[i * n + j] != 0.0).collect())
        .collect();
    let mut jac = Jacobian::new(SparsityPattern::from_rows(&rows).unwrap().into());
    jac.gather_dense(dense);
    jac
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pattern(rows: &[Vec<usize>]) -> SparsityPattern {
        SparsityPattern::from_rows(rows).unwrap()
    }

    /// Oscillators `k` and `n - 1 - k` coupled across the matrix: a full band, three
    /// entries a row at most.
    fn crossed(n: usize) -> Vec<Vec<usize>> {
        (0..n)
            .map(|i| {
                let mut row = vec![i, n - 1 - i];
                row.sort_unstable();
                row.dedup();
                row
            })
            .collect()
    }

    #[test]
    fn the_cheaper_factorization_is_chosen() {
        // Narrow band: banded. Wide band, few entries: sparse. Dense: banded.
        let tridiagonal: Vec<Vec<usize>> = (0..50usize)
            .map(|i| (i.saturating_sub(1)..(i + 2).min(50)).collect())
            .collect();
        assert!(!Structure::of_pattern(&pattern(&tridiagonal)).is_sparse());
        assert!(Structure::of_pattern(&pattern(&crossed(50))).is_sparse());
        assert!(!Structure::of_pattern(&SparsityPattern::dense(50)).is_sparse());
        // Tiny matrices stay banded.
        assert!(!Structure::of_pattern(&pattern(&crossed(3))).is_sparse());
    }

    /// When the static pivots fail, the matrices are factored with partial pivoting,
    /// reported as a fallback, and solved right; the next factorization tries the
    /// sparse code again.
    #[test]
    fn unstable_sparse_factorizations_fall_back() {
        let n = 40;
        let structure = Structure::of_pattern(&pattern(&crossed(n)));
        assert!(structure.is_sparse());
        let mut real = RealMatrix::new(&structure);
        let mut pair = RadauMatrices::new(&structure);
        // J couples x_k and x_(n-1-k) antisymmetrically with weight w.
        let jacobian = |w: f64| {
            let mut jac = vec![0.0; n * n];
            for k in 0..n / 2 {
                jac[k * n + (n - 1 - k)] = w;
                jac[(n - 1 - k) * n + k] = -w;
            }
            jac
        };
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        for (w, expected) in [(1e12, Factored::FellBack), (2.0, Factored::AsPlanned)] {
            let jac = jacobian(w);
            let mut stored = Jacobian::new(pattern(&crossed(n)).into());
            assert_eq!(stored.gather_dense(&jac), None);
            assert_eq!(real.factor(1.0, &stored, true), Ok(expected), "w = {w}");
            assert_eq!(pair.factor([1.0, 0.5, 0.25], &stored, true), Ok(expected));
            // Residuals of (σ I - J) x = b.
            let residual = |shift: (f64, f64), x: (&[f64], &[f64]), k: usize| {
                let m = n - 1 - k;
                let (re, im) = x;
                let r = shift.0 * re[k] - shift.1 * im[k] - jac[k * n + m] * re[m] - b[k];
                let i = shift.0 * im[k] + shift.1 * re[k] - jac[k * n + m] * im[m];
                (r.abs() + i.abs()) / (1.0 + w)
            };
            let mut x = b.clone();
            real.solve(&mut x);
            let zero = vec![0.0; n];
            let mut y = b.clone();
            pair.solve_real(&mut y);
            let (mut z_re, mut z_im, mut z1) = (b.clone(), vec![0.0; n], b.clone());
            pair.solve_both(&mut z1, &mut z_re, &mut z_im);
            for k in 0..n {
                assert!(residual((1.0, 0.0), (&x, &zero), k) < 1e-14, "w = {w}");
                assert!(residual((1.0, 0.0), (&y, &zero), k) < 1e-14);
                assert!(residual((1.0, 0.0), (&z1, &zero), k) < 1e-14);
                assert!(residual((0.5, 0.25), (&z_re, &z_im), k) < 1e-14);
            }
        }
    }
}
