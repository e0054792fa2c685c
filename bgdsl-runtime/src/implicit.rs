//! The per-evaluation solve of a model's implicit unknowns: algebraic loops and the
//! constraint system of dependent storage.
//!
//! A model that opts in with `#[allow(algebraic_loops)]` or
//! `#[allow(derivative_causality)]` has `K` unknowns `z` (fixed at compile time) that its
//! equations define only implicitly, through a residual `r(z) = 0` that the generated
//! code evaluates. At every evaluation of the derivatives (and of the outputs and the
//! energy account), the generated code
//!
//! 1. calls [`solve`] from the previous solution ([`ImplicitMemory::guess`]): Newton's
//!    method on `f64`, with the exact Jacobian `∂r/∂z` from one evaluation of the
//!    residual on [`DualN<K>`] per iteration (`z` seeded with the identity);
//! 2. evaluates the residual once more on the scalar `T` of the call, at the solution
//!    `z*` held constant, and takes [`Solution::refine`]: `z_T = z* − J⁻¹ r_T`. This is
//!    the implicit function theorem: for a dual `T` the tangents of `z_T` are exactly
//!    `dz/dθ = −J⁻¹ ∂r/∂θ`, so the stiff solvers' Jacobians stay exact through the
//!    solve; for `T = f64` it is one more (harmless) Newton step;
//! 3. remembers `z*` for the next call ([`ImplicitMemory::remember`], which also
//!    forgets any earlier failure), or, if the solve failed,
//!    fills in the time, records the [`Failure`] ([`ImplicitMemory::record`]) and
//!    writes `T::from_f64(f64::NAN)` into the derivatives (or outputs);
//!    [`Model::evaluation_error`](crate::Model::evaluation_error) then returns
//!    [`Failure::to_model_error`] with the elements concerned. A NaN value with zero
//!    tangents is enough on dual numbers too: the
//!    [`JacobianEvaluator`](crate::JacobianEvaluator) makes the row of a non-finite
//!    value NaN, so the solvers see the failure there as well.
//!
//! Everything here is allocation-free and works without the standard library: the
//! Jacobian is factored by a fixed-size LU decomposition with partial pivoting over
//! `[[f64; K]; K]` on the stack.

#[cfg(target_has_atomic = "64")]
use core::sync::atomic::AtomicU64;
use core::sync::atomic::{AtomicU32, AtomicU8, AtomicUsize, Ordering};

use crate::dual::DualN;
use crate::model::ModelError;
use crate::scalar::Scalar;

/// The scaled residual at which a non-linear solve has converged:
/// `max_j |r_j| / (1 + |z_j|)`.
pub const TOLERANCE: f64 = 1e-10;

/// The most Newton iterations a non-linear solve takes.
pub const MAX_ITERATIONS: usize = 25;

/// A pivot at most this fraction of the largest `|J|` entry makes the Jacobian singular.
pub const SINGULAR_PIVOT: f64 = 1e-13;

/// The most times a Newton step is halved in one iteration when the residual does not
/// decrease along it.
const MAX_HALVINGS: usize = 10;

/// How the solve of the implicit unknowns failed (see [`Failure`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FailureKind {
    /// Newton's method did not reach the tolerance within its iterations.
    NotConverged,
    /// The Jacobian `∂r/∂z` is singular (a redundant constraint, a dead point of a
    /// mechanism) or not finite.
    Singular,
    /// The residual is NaN or infinite at the guess.
    NonFinite,
}

/// A failed solve: what went wrong, for which unknown, when, and by how much.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Failure {
    /// What went wrong.
    pub kind: FailureKind,
    /// The unknown concerned (its index in `z`): the worst-converged one, the one whose
    /// pivot failed, or the one whose residual is not finite.
    pub unknown: usize,
    /// The time of the evaluation. [`solve`] does not know it and leaves NaN: the
    /// caller fills it in.
    pub t: f64,
    /// The residual of that unknown (for a singular Jacobian: the largest `|r_j|`).
    pub residual: f64,
}

impl Failure {
    /// The model error that reports this failure, naming `members` (the elements of
    /// the loop or the constraint, comma-separated): a singular Jacobian is a
    /// [`ModelError::SingularConstraint`], anything else a
    /// [`ModelError::UnsolvedLoop`].
    pub fn to_model_error(&self, members: &'static str) -> ModelError {
        match self.kind {
            FailureKind::Singular => ModelError::SingularConstraint { members, t: self.t },
            FailureKind::NotConverged | FailureKind::NonFinite => ModelError::UnsolvedLoop {
                members,
                t: self.t,
                residual: self.residual,
            },
        }
    }
}

/// What a model remembers between evaluations of its implicit unknowns: the previous
/// solution (the next guess) and the last failure.
///
/// It is a field of the generated model, written through `&self` (evaluations take
/// `&self`): the values are kept as `f64` bits in atomics with relaxed ordering, so a
/// model stays `Sync` and `no_std`. That is enough: the guess only speeds a solve up,
/// and a stale one (two threads evaluating one model) still converges to the same
/// solution.
///
/// Where the target has no 64-bit atomics (Cortex-M0 to M4), each number is kept as
/// two 32-bit halves: a read racing a write may then see a torn value, which is only a
/// worse guess (a non-finite one is replaced by zero).
///
/// `Clone` copies the values; every memory equals every other (`PartialEq`), because it
/// holds no part of the model's value, only a starting point, so two models with the
/// same parameters compare equal whatever they last evaluated.
pub struct ImplicitMemory<const K: usize> {
    guess: [SharedF64; K],
    /// 0: no failure; otherwise 1 + the index of the `FailureKind`.
    failure_kind: AtomicU8,
    failure_unknown: AtomicUsize,
    failure_t: SharedF64,
    failure_residual: SharedF64,
}

impl<const K: usize> ImplicitMemory<K> {
    /// A memory with the guess `z = 0` and no failure.
    pub const fn new() -> Self {
        ImplicitMemory {
            guess: [const { SharedF64::new() }; K],
            failure_kind: AtomicU8::new(0),
            failure_unknown: AtomicUsize::new(0),
            failure_t: SharedF64::new(),
            failure_residual: SharedF64::new(),
        }
    }

    /// The last solution remembered (zero at first): the guess of the next solve.
    pub fn guess(&self) -> [f64; K] {
        core::array::from_fn(|j| {
            // Only a value torn by a concurrent write (where 64-bit atomics are
            // missing) could be non-finite: start from zero then.
            let value = self.guess[j].get();
            if value.is_finite() {
                value
            } else {
                0.0
            }
        })
    }

    /// Remembers `z`, a solution, as the guess of the next solve, and forgets any
    /// recorded failure: [`ImplicitMemory::failure`] describes the last solve, so a
    /// failure a solver met on a step it then shortened is not reported later.
    pub fn remember(&self, z: &[f64; K]) {
        for (cell, value) in self.guess.iter().zip(z) {
            cell.set(*value);
        }
        self.clear_failure();
    }

    /// Records a failure, replacing any earlier one.
    pub fn record(&self, failure: Failure) {
        self.failure_unknown
            .store(failure.unknown, Ordering::Relaxed);
        self.failure_t.set(failure.t);
        self.failure_residual.set(failure.residual);
        let kind = match failure.kind {
            FailureKind::NotConverged => 1,
            FailureKind::Singular => 2,
            FailureKind::NonFinite => 3,
        };
        self.failure_kind.store(kind, Ordering::Relaxed);
    }

    /// The last failure recorded, until [`ImplicitMemory::clear_failure`] or the next
    /// [`ImplicitMemory::remember`] (a solve that succeeded).
    pub fn failure(&self) -> Option<Failure> {
        let kind = match self.failure_kind.load(Ordering::Relaxed) {
            1 => FailureKind::NotConverged,
            2 => FailureKind::Singular,
            3 => FailureKind::NonFinite,
            _ => return None,
        };
        Some(Failure {
            kind,
            unknown: self.failure_unknown.load(Ordering::Relaxed),
            t: self.failure_t.get(),
            residual: self.failure_residual.get(),
        })
    }

    /// Forgets the recorded failure.
    pub fn clear_failure(&self) {
        self.failure_kind.store(0, Ordering::Relaxed);
    }
}

impl<const K: usize> Default for ImplicitMemory<K> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const K: usize> Clone for ImplicitMemory<K> {
    fn clone(&self) -> Self {
        let copy = Self::new();
        copy.remember(&self.guess());
        if let Some(failure) = self.failure() {
            copy.record(failure);
        }
        copy
    }
}

impl<const K: usize> PartialEq for ImplicitMemory<K> {
    /// Always `true`: a memory is no part of a model's value (see the type's docs).
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

impl<const K: usize> core::fmt::Debug for ImplicitMemory<K> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ImplicitMemory")
            .field("guess", &self.guess())
            .field("failure", &self.failure())
            .finish()
    }
}

/// An `f64` shared through `&self`: its bits in a 64-bit atomic where the target has
/// one, else in [`SplitF64`]'s two 32-bit halves.
#[cfg(target_has_atomic = "64")]
struct SharedF64(AtomicU64);

#[cfg(target_has_atomic = "64")]
impl SharedF64 {
    const fn new() -> Self {
        SharedF64(AtomicU64::new(0))
    }
    fn get(&self) -> f64 {
        f64::from_bits(self.0.load(Ordering::Relaxed))
    }
    fn set(&self, value: f64) {
        self.0.store(value.to_bits(), Ordering::Relaxed);
    }
}

#[cfg(not(target_has_atomic = "64"))]
type SharedF64 = SplitF64;

/// An `f64` as two 32-bit atomic halves, for targets without 64-bit atomics (compiled
/// everywhere, so that its test runs on the host).
#[cfg_attr(target_has_atomic = "64", allow(dead_code))]
struct SplitF64 {
    high: AtomicU32,
    low: AtomicU32,
}

#[cfg_attr(target_has_atomic = "64", allow(dead_code))]
impl SplitF64 {
    const fn new() -> Self {
        SplitF64 {
            high: AtomicU32::new(0),
            low: AtomicU32::new(0),
        }
    }
    fn get(&self) -> f64 {
        let high = u64::from(self.high.load(Ordering::Relaxed));
        let low = u64::from(self.low.load(Ordering::Relaxed));
        f64::from_bits(high << 32 | low)
    }
    fn set(&self, value: f64) {
        let bits = value.to_bits();
        self.high.store((bits >> 32) as u32, Ordering::Relaxed);
        self.low.store(bits as u32, Ordering::Relaxed);
    }
}

/// An LU decomposition with partial pivoting, `P J = L U`, of a `K × K` matrix held in
/// one array: `L` (unit diagonal, not stored) below the diagonal, `U` on and above.
#[derive(Clone, Copy, Debug)]
struct Lu<const K: usize> {
    factors: [[f64; K]; K],
    /// Row `i` of `P J` is row `rows[i]` of `J`.
    rows: [usize; K],
}

// Index loops: the textbook triangular algorithms read best with their indices.
#[allow(clippy::needless_range_loop)]
impl<const K: usize> Lu<K> {
    /// Factors `matrix`, or returns the column (unknown) whose pivot is at most
    /// [`SINGULAR_PIVOT`] times the largest `|entry|`, or not finite.
    fn factor(matrix: [[f64; K]; K]) -> Result<Self, usize> {
        let mut factors = matrix;
        let mut rows: [usize; K] = core::array::from_fn(|i| i);
        let mut largest = 0.0_f64;
        for row in &matrix {
            for (j, &entry) in row.iter().enumerate() {
                if !entry.is_finite() {
                    return Err(j);
                }
                largest = largest.max(entry.abs());
            }
        }
        let threshold = SINGULAR_PIVOT * largest;
        for k in 0..K {
            let mut pivot_row = k;
            for i in k + 1..K {
                if factors[i][k].abs() > factors[pivot_row][k].abs() {
                    pivot_row = i;
                }
            }
            let pivot = factors[pivot_row][k];
            if pivot.abs() <= threshold || pivot == 0.0 || !pivot.is_finite() {
                return Err(k);
            }
            factors.swap(k, pivot_row);
            rows.swap(k, pivot_row);
            for i in k + 1..K {
                let l = factors[i][k] / pivot;
                factors[i][k] = l;
                for j in k + 1..K {
                    factors[i][j] -= l * factors[k][j];
                }
            }
        }
        Ok(Lu { factors, rows })
    }

    /// `J⁻¹ b` for a right-hand side on any scalar.
    fn solve<T: Scalar>(&self, b: &[T; K]) -> [T; K] {
        let mut x: [T; K] = core::array::from_fn(|i| b[self.rows[i]]);
        for i in 0..K {
            for j in 0..i {
                let lx = T::from_f64(self.factors[i][j]) * x[j];
                x[i] -= lx;
            }
        }
        for i in (0..K).rev() {
            for j in i + 1..K {
                let ux = T::from_f64(self.factors[i][j]) * x[j];
                x[i] -= ux;
            }
            x[i] /= T::from_f64(self.factors[i][i]);
        }
        x
    }
}

/// The solution of the implicit unknowns, with the LU factors of the Jacobian `∂r/∂z`
/// there for [`Solution::refine`].
#[derive(Clone, Copy, Debug)]
pub struct Solution<const K: usize> {
    /// The unknowns.
    pub z: [f64; K],
    lu: Lu<K>,
}

impl<const K: usize> Solution<K> {
    /// `z − J⁻¹ r` for a residual on any scalar: the implicit-function step. With `r`
    /// the residual evaluated on `T` at `z` (held constant), the result's values are a
    /// Newton step from `z` and its tangents are `dz/dθ = −J⁻¹ ∂r/∂θ` exactly.
    pub fn refine<T: Scalar>(&self, residual: &[T; K]) -> [T; K] {
        let step = self.lu.solve(residual);
        core::array::from_fn(|j| T::from_f64(self.z[j]) - step[j])
    }
}

/// One evaluation of the residual at `z`: its values and the Jacobian `∂r/∂z`.
struct Evaluation<const K: usize> {
    r: [f64; K],
    jacobian: [[f64; K]; K],
}

fn evaluate<const K: usize>(
    z: &[f64; K],
    residual: &mut impl FnMut(&[DualN<K>; K], &mut [DualN<K>; K]),
) -> Evaluation<K> {
    let seeded: [DualN<K>; K] = core::array::from_fn(|j| {
        let mut unit = [0.0; K];
        unit[j] = 1.0;
        DualN::new(z[j], unit)
    });
    let mut out = [DualN::<K>::constant(0.0); K];
    residual(&seeded, &mut out);
    Evaluation {
        r: core::array::from_fn(|i| out[i].value()),
        jacobian: core::array::from_fn(|i| *out[i].tangents()),
    }
}

/// The first unknown whose residual is not finite.
fn non_finite<const K: usize>(r: &[f64; K]) -> Option<usize> {
    r.iter().position(|v| !v.is_finite())
}

/// `Σ r_j²`.
fn norm2<const K: usize>(r: &[f64; K]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// The unknown with the largest scaled residual `|r_j| / (1 + |z_j|)`, and that value.
fn worst<const K: usize>(z: &[f64; K], r: &[f64; K]) -> (usize, f64) {
    let mut worst = (0, 0.0);
    for j in 0..K {
        let scaled = r[j].abs() / (1.0 + z[j].abs());
        if scaled > worst.1 {
            worst = (j, scaled);
        }
    }
    worst
}

fn largest<const K: usize>(r: &[f64; K]) -> f64 {
    r.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// Solves `r(z) = 0` by Newton's method from `guess`.
///
/// `residual(z, r)` writes `r(z)`; it is called on [`DualN<K>`] with `z` seeded with
/// the identity, so each call gives the residual and its exact Jacobian. With
/// `linear = true` (the compiler knows `r` is affine in `z`) it takes exactly one step,
/// `z = guess − J⁻¹ r(guess)`, and does not evaluate again. Otherwise it iterates until
/// `max_j |r_j| / (1 + |z_j|) ≤ ` [`TOLERANCE`], at most [`MAX_ITERATIONS`] times,
/// halving a step along which the residual's norm does not decrease (a bad guess then
/// does not throw the iteration away at once). With `K = 0` there is nothing to solve:
/// it returns at once without calling `residual`.
///
/// # Errors
///
/// A [`Failure`] with `t` NaN (the caller knows the time): [`FailureKind::NonFinite`]
/// if the residual at the guess is not finite, [`FailureKind::Singular`] if a pivot of
/// `J` is at most [`SINGULAR_PIVOT`] times its largest entry (or `J` is not finite) for
/// a linear system or at a solution of a non-linear one, [`FailureKind::NotConverged`]
/// with the worst unknown and its residual otherwise (a non-linear iteration that meets
/// a vanishing derivative away from a solution has not converged).
pub fn solve<const K: usize>(
    guess: [f64; K],
    linear: bool,
    mut residual: impl FnMut(&[DualN<K>; K], &mut [DualN<K>; K]),
) -> Result<Solution<K>, Failure> {
    let failure = |kind, unknown, residual| Failure {
        kind,
        unknown,
        t: f64::NAN,
        residual,
    };
    if K == 0 {
        return Ok(Solution {
            z: guess,
            lu: Lu {
                factors: [[0.0; K]; K],
                rows: [0; K],
            },
        });
    }
    let mut z = guess;
    let mut at = evaluate(&z, &mut residual);
    if let Some(j) = non_finite(&at.r) {
        return Err(failure(FailureKind::NonFinite, j, at.r[j]));
    }
    let factor = |at: &Evaluation<K>| {
        Lu::factor(at.jacobian).map_err(|j| failure(FailureKind::Singular, j, largest(&at.r)))
    };
    if linear {
        let lu = factor(&at)?;
        let step = lu.solve(&at.r);
        return Ok(Solution {
            z: core::array::from_fn(|j| z[j] - step[j]),
            lu,
        });
    }
    for _ in 0..MAX_ITERATIONS {
        let converged = worst(&z, &at.r).1 <= TOLERANCE;
        let lu = match factor(&at) {
            Ok(lu) => lu,
            // Away from a solution, a vanishing derivative of a non-linear residual is
            // where Newton cannot go on, not a property of the system: the loop did not
            // converge, and its residual there is what to report.
            Err(_) if !converged => {
                let (j, _) = worst(&z, &at.r);
                return Err(failure(FailureKind::NotConverged, j, at.r[j]));
            }
            Err(singular) => return Err(singular),
        };
        if converged {
            return Ok(Solution { z, lu });
        }
        let step = lu.solve(&at.r);
        let norm = norm2(&at.r);
        let mut lambda = 1.0;
        let mut halvings = 0;
        loop {
            let trial: [f64; K] = core::array::from_fn(|j| z[j] - lambda * step[j]);
            let next = evaluate(&trial, &mut residual);
            let next_norm = norm2(&next.r);
            let finite = non_finite(&next.r).is_none();
            if (finite && next_norm < norm) || halvings == MAX_HALVINGS {
                if !finite {
                    let j = non_finite(&next.r).unwrap_or(0);
                    return Err(failure(FailureKind::NonFinite, j, next.r[j]));
                }
                z = trial;
                at = next;
                break;
            }
            lambda *= 0.5;
            halvings += 1;
        }
    }
    let (j, _) = worst(&z, &at.r);
    if worst(&z, &at.r).1 <= TOLERANCE {
        return Ok(Solution {
            z,
            lu: factor(&at)?,
        });
    }
    Err(failure(FailureKind::NotConverged, j, at.r[j]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_halves_keep_every_bit() {
        let cell = SplitF64::new();
        assert_eq!(cell.get().to_bits(), 0);
        for value in [1.5, -2.25e-300, f64::MAX, -0.0, f64::NAN, f64::MIN_POSITIVE] {
            cell.set(value);
            assert_eq!(cell.get().to_bits(), value.to_bits());
        }
    }

    #[test]
    fn a_non_finite_guess_reads_as_zero() {
        let memory = ImplicitMemory::<2>::new();
        memory.remember(&[f64::NAN, 3.0]);
        assert_eq!(memory.guess(), [0.0, 3.0]);
    }
}
