//! Hand-written chain models of any size, for the large-model benchmark
//! (`benches/large.rs`) and the allocation tests: the number of states is a const
//! parameter, and the declared Jacobian pattern is built at compile time (each row is
//! a contiguous range of columns, a window of one `0, 1, …, S − 1` table).
//!
//! - [`MassChain`]: `S / 2` unit masses in a line, each joined to its neighbours (and
//!   the end ones to walls) by a spring `k` and a damper `c`; states `q_k` (position)
//!   and `v_k` (velocity). [`Interleaved`] orders them `q_0, v_0, q_1, v_1, …` (a band
//!   of half-width 3: the banded LU); the split order is all positions, then all
//!   velocities (the band is the whole matrix, the entries few: the sparse LU).
//! - [`BlockChain`]: blocks of [`BLOCK`] states, dense within a block and coupled to
//!   the neighbouring blocks (standing in for rigid bodies joined in a chain):
//!   `ẏ_bi = −d_i y_bi + Σ_j W_ij sin y_bj + κ Σ_j V_ij (y_(b−1)j + y_(b+1)j)`, with
//!   `d_i` from 1 to 1000 (stiff).
#![allow(dead_code)]

use bgdsl_runtime::{Model, Scalar};

/// States per block of [`BlockChain`].
pub const BLOCK: usize = 20;

/// `[0, 1, …, S − 1]`.
const fn iota<const S: usize>() -> [usize; S] {
    let mut a = [0; S];
    let mut i = 0;
    while i < S {
        a[i] = i;
        i += 1;
    }
    a
}

/// Columns `lo..hi` as a slice of `iota`.
const fn window(iota: &'static [usize], lo: usize, hi: usize) -> &'static [usize] {
    iota.split_at(hi).0.split_at(lo).1
}

/// The rows of an interleaved [`MassChain`]: `q̇_k` depends on `v_k`; `v̇_k` on the
/// positions and velocities of masses `k − 1..=k + 1`, which are contiguous.
const fn interleaved_rows<const S: usize>(iota: &'static [usize; S]) -> [&'static [usize]; S] {
    let mut rows: [&'static [usize]; S] = [&[]; S];
    let m = S / 2;
    let mut k = 0;
    while k < m {
        let (lo, hi) = (
            if k > 0 { k - 1 } else { 0 },
            if k + 2 < m { k + 2 } else { m },
        );
        rows[2 * k] = window(iota, 2 * k + 1, 2 * k + 2);
        rows[2 * k + 1] = window(iota, 2 * lo, 2 * hi);
        k += 1;
    }
    rows
}

/// The columns of a split [`MassChain`], row after row (`NNZ = 7 S / 2 − 4`): `q̇_k`
/// depends on `v_k`; `v̇_k` on `q_(k−1..=k+1)` and `v_(k−1..=k+1)`, two windows.
const fn split_cols<const S: usize, const NNZ: usize>() -> [usize; NNZ] {
    let mut cols = [0; NNZ];
    if NNZ == 0 {
        // The interleaved chain's: unused.
        return cols;
    }
    let m = S / 2;
    let mut next = 0;
    let mut k = 0;
    while k < m {
        cols[next] = m + k;
        next += 1;
        k += 1;
    }
    k = 0;
    while k < m {
        let (lo, hi) = (
            if k > 0 { k - 1 } else { 0 },
            if k + 2 < m { k + 2 } else { m },
        );
        let mut j = lo;
        while j < hi {
            cols[next] = j;
            next += 1;
            j += 1;
        }
        j = lo;
        while j < hi {
            cols[next] = m + j;
            next += 1;
            j += 1;
        }
        k += 1;
    }
    assert!(next == NNZ, "NNZ must be 7 S / 2 - 4");
    cols
}

/// The rows of a split [`MassChain`], as slices of [`split_cols`].
const fn split_rows<const S: usize>(cols: &'static [usize]) -> [&'static [usize]; S] {
    let mut rows: [&'static [usize]; S] = [&[]; S];
    let m = S / 2;
    let mut rest = cols;
    let mut i = 0;
    while i < S {
        let len = if i < m {
            1
        } else {
            let k = i - m;
            let (lo, hi) = (
                if k > 0 { k - 1 } else { 0 },
                if k + 2 < m { k + 2 } else { m },
            );
            2 * (hi - lo)
        };
        let (row, tail) = rest.split_at(len);
        rows[i] = row;
        rest = tail;
        i += 1;
    }
    rows
}

/// The scalar mass-spring-damper chain with `S` states (`S / 2` masses), interleaved
/// when `SPLIT_NNZ` is 0, else split (and `SPLIT_NNZ` must be the pattern's entries,
/// `7 S / 2 − 4`: a const generic cannot be computed from another).
#[derive(Clone, Debug)]
pub struct MassChain<const S: usize, const SPLIT_NNZ: usize> {
    /// Spring stiffness, N/m, and damping, N·s/m (unit masses).
    pub k: f64,
    pub c: f64,
}

/// The interleaved chain (banded LU).
pub type Interleaved<const S: usize> = MassChain<S, 0>;

impl<const S: usize, const SPLIT_NNZ: usize> Default for MassChain<S, SPLIT_NNZ> {
    fn default() -> Self {
        MassChain { k: 1e4, c: 50.0 }
    }
}

impl<const S: usize, const SPLIT_NNZ: usize> MassChain<S, SPLIT_NNZ> {
    const INTERLEAVED: bool = SPLIT_NNZ == 0;
    const IOTA: [usize; S] = iota::<S>();
    const COLS: [usize; SPLIT_NNZ] = split_cols::<S, SPLIT_NNZ>();
    const ROWS: [&'static [usize]; S] = if SPLIT_NNZ == 0 {
        interleaved_rows::<S>(&Self::IOTA)
    } else {
        split_rows::<S>(&Self::COLS)
    };

    /// Where `q_k` and `v_k` are in the state.
    #[inline]
    fn at(k: usize) -> (usize, usize) {
        if Self::INTERLEAVED {
            (2 * k, 2 * k + 1)
        } else {
            (k, S / 2 + k)
        }
    }
}

impl<const S: usize, const SPLIT_NNZ: usize> Model for MassChain<S, SPLIT_NNZ> {
    type Params = ();
    const NAME: &'static str = "mass_chain";
    const STATE_NAMES: &'static [&'static str] = &["x"; S];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&Self::ROWS);

    fn params(&self) -> &() {
        &()
    }

    /// A displacement varying from mass to mass (the same local motion at every
    /// size), at rest.
    fn initial_state(&self, x0: &mut [f64]) {
        for k in 0..S / 2 {
            let (q, v) = Self::at(k);
            x0[q] = 0.01 * (0.37 * k as f64).sin();
            x0[v] = 0.0;
        }
    }

    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let m = S / 2;
        let (k, c) = (T::from_f64(self.k), T::from_f64(self.c));
        let zero = T::from_f64(0.0);
        let state = |j: usize| {
            let (q, v) = Self::at(j);
            (x[q], x[v])
        };
        for j in 0..m {
            let (q, v) = state(j);
            let (ql, vl) = if j > 0 { state(j - 1) } else { (zero, zero) };
            let (qr, vr) = if j + 1 < m {
                state(j + 1)
            } else {
                (zero, zero)
            };
            let (iq, iv) = Self::at(j);
            dx[iq] = v;
            dx[iv] = k * (ql + qr - q - q) + c * (vl + vr - v - v);
        }
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// The rows of a [`BlockChain`]: block `b` depends on blocks `b − 1..=b + 1`.
const fn block_rows<const S: usize>(iota: &'static [usize; S]) -> [&'static [usize]; S] {
    let mut rows: [&'static [usize]; S] = [&[]; S];
    let blocks = S / BLOCK;
    let mut i = 0;
    while i < S {
        let b = i / BLOCK;
        let lo = if b > 0 { (b - 1) * BLOCK } else { 0 };
        let hi = if b + 2 < blocks { (b + 2) * BLOCK } else { S };
        rows[i] = window(iota, lo, hi);
        i += 1;
    }
    rows
}

/// The block chain with `S` states (`S / BLOCK` blocks).
#[derive(Clone, Debug, Default)]
pub struct BlockChain<const S: usize>;

impl<const S: usize> BlockChain<S> {
    const IOTA: [usize; S] = iota::<S>();
    const ROWS: [&'static [usize]; S] = block_rows::<S>(&Self::IOTA);

    /// `W_ij` and `V_ij`: fixed, of order 1 and 0.1.
    #[inline]
    fn w(i: usize, j: usize) -> f64 {
        0.5 * ((i * 7 + j * 3) % 11) as f64 / 11.0 - 0.25
    }
    #[inline]
    fn v(i: usize, j: usize) -> f64 {
        0.1 * ((i * 5 + j * 2) % 7) as f64 / 7.0
    }
}

impl<const S: usize> Model for BlockChain<S> {
    type Params = ();
    const NAME: &'static str = "block_chain";
    const STATE_NAMES: &'static [&'static str] = &["y"; S];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&Self::ROWS);

    fn params(&self) -> &() {
        &()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        for (i, x) in x0.iter_mut().enumerate() {
            *x = 0.1 * (0.37 * i as f64).sin();
        }
    }

    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let blocks = S / BLOCK;
        let mut sines = [T::from_f64(0.0); BLOCK];
        for b in 0..blocks {
            let y = &x[b * BLOCK..(b + 1) * BLOCK];
            for (s, &yj) in sines.iter_mut().zip(y) {
                *s = yj.sin();
            }
            for i in 0..BLOCK {
                let d = [1.0, 10.0, 100.0, 1000.0][i % 4];
                let mut acc = T::from_f64(-d) * y[i];
                for (j, &s) in sines.iter().enumerate() {
                    acc += T::from_f64(Self::w(i, j)) * s;
                }
                for nb in [b.wrapping_sub(1), b + 1] {
                    if nb < blocks {
                        let z = &x[nb * BLOCK..(nb + 1) * BLOCK];
                        for (j, &zj) in z.iter().enumerate() {
                            acc += T::from_f64(Self::v(i, j)) * zj;
                        }
                    }
                }
                dx[b * BLOCK + i] = acc;
            }
        }
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}
