//! A stiff model whose iteration matrices take the sparse path of the linear algebra:
//! 12 damped oscillators, oscillator `k` with states `a_k = x[k]` and
//! `b_k = x[23 - k]`, so that each row has at most three entries but the band of the
//! pattern is the whole matrix. Each is forced towards `a_k = sin(t + 0.3 k)` and coupled
//! to the next by a product that vanishes at the initial rest state:
//!
//! ```text
//! a_k' = ω b_k
//! b_k' = −ω a_k − c b_k + ω sin(t + 0.3 k) + κ a_k b_(k+1)      (κ term for k < 11)
//! ```
//!
//! The eigenvalues of an oscillator are the roots of `λ² + c λ + ω² = 0`: with
//! `c = 2 ω` both are `−ω`. The entries `∂b_k'/∂b_(k+1) = κ a_k` are zero at the start
//! and become non-zero as the oscillators move, so the numerical pattern of the
//! Jacobians grows during a run. With a large `ω` the diagonal pivots of `σ I − J` are
//! tiny against the entries they eliminate once the step is long (the growth of the
//! elimination is about `ω h`), and the static pivots fail their stability test.
//!
//! `Pairs<true>` declares the pattern; `Pairs<false>` declares none (dense: banded
//! linear algebra with partial pivoting), for comparison.
#![allow(dead_code)]

use bgdsl_runtime::{Model, Scalar};

/// Oscillators.
pub const PAIRS: usize = 12;
/// States.
pub const N: usize = 2 * PAIRS;

static ROWS: [&[usize]; N] = [
    &[23],
    &[22],
    &[21],
    &[20],
    &[19],
    &[18],
    &[17],
    &[16],
    &[15],
    &[14],
    &[13],
    &[12],
    &[11, 12],
    &[10, 12, 13],
    &[9, 13, 14],
    &[8, 14, 15],
    &[7, 15, 16],
    &[6, 16, 17],
    &[5, 17, 18],
    &[4, 18, 19],
    &[3, 19, 20],
    &[2, 20, 21],
    &[1, 21, 22],
    &[0, 22, 23],
];

static NAMES: [&str; N] = [
    "a0", "a1", "a2", "a3", "a4", "a5", "a6", "a7", "a8", "a9", "a10", "a11", "b11", "b10", "b9",
    "b8", "b7", "b6", "b5", "b4", "b3", "b2", "b1", "b0",
];

/// The oscillators with their parameters; `SPARSE` says whether the pattern is declared.
#[derive(Clone, Debug)]
pub struct Pairs<const SPARSE: bool> {
    /// `ω`, 1/s.
    pub omega: f64,
    /// `κ`, 1/s.
    pub kappa: f64,
}

impl<const SPARSE: bool> Pairs<SPARSE> {
    /// Oscillators with eigenvalues `−omega` and coupling `κ = omega`.
    pub fn new(omega: f64) -> Self {
        Pairs {
            omega,
            kappa: omega,
        }
    }
}

impl<const SPARSE: bool> Model for Pairs<SPARSE> {
    type Params = ();
    const NAME: &'static str = "pairs";
    const STATE_NAMES: &'static [&'static str] = &NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
        if SPARSE { Some(&ROWS) } else { None };

    fn params(&self) -> &() {
        &()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0);
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let (omega, kappa) = (T::from_f64(self.omega), T::from_f64(self.kappa));
        let damping = T::from_f64(2.0 * self.omega);
        for k in 0..PAIRS {
            let (a, b) = (x[k], x[N - 1 - k]);
            dx[k] = omega * b;
            let force = T::from_f64(self.omega * (t + 0.3 * k as f64).sin());
            let mut db = -(omega * a) - damping * b + force;
            if k + 1 < PAIRS {
                db += kappa * a * x[N - 2 - k];
            }
            dx[N - 1 - k] = db;
        }
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}
