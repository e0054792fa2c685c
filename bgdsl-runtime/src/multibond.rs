//! Multibonds: the vectors and matrices an n-dimensional bond carries, and the helpers
//! a law uses to build them.
//!
//! A 3-D multibond's effort and flow are [`Vector3`]s of the model's scalar type; a
//! modulus or a stiffness may be a number or a [`Matrix3`]. Everything here is generic
//! over [`Scalar`], so laws written with these helpers differentiate exactly.
//!
//! ```
//! use bgdsl_runtime::multibond::{skew, vec3};
//! let a = vec3(1.0, 2.0, 3.0);
//! let b = vec3(-1.0, 0.5, 4.0);
//! assert_eq!(skew(a) * b, a.cross(&b));
//! ```

pub use nalgebra::{SMatrix, SVector};

use crate::scalar::Scalar;

/// A 3-vector of the model's scalar type.
pub type Vector3<S> = SVector<S, 3>;
/// A 3×3 matrix of the model's scalar type.
pub type Matrix3<S> = SMatrix<S, 3, 3>;

/// The vector `(x, y, z)`.
#[inline]
pub fn vec3<S: Scalar>(x: S, y: S, z: S) -> Vector3<S> {
    Vector3::new(x, y, z)
}

/// The diagonal matrix `diag(a, b, c)`, e.g. a stiffness free along x.
#[inline]
pub fn diag3<S: Scalar>(a: S, b: S, c: S) -> Matrix3<S> {
    let zero = S::from_f64(0.0);
    Matrix3::new(a, zero, zero, zero, b, zero, zero, zero, c)
}

/// The 3×3 identity.
#[inline]
pub fn identity3<S: Scalar>() -> Matrix3<S> {
    diag3(S::from_f64(1.0), S::from_f64(1.0), S::from_f64(1.0))
}

/// The skew-symmetric matrix of `a`: `skew(a) * b == a × b`.
#[inline]
pub fn skew<S: Scalar>(a: Vector3<S>) -> Matrix3<S> {
    let zero = S::from_f64(0.0);
    Matrix3::new(zero, -a.z, a.y, a.z, zero, -a.x, -a.y, a.x, zero)
}

/// A rotation by `angle` (radians, counter-clockwise) about the z-axis.
#[inline]
pub fn rot_z<S: Scalar>(angle: S) -> Matrix3<S> {
    let (s, c) = (angle.sin(), angle.cos());
    let (zero, one) = (S::from_f64(0.0), S::from_f64(1.0));
    Matrix3::new(c, -s, zero, s, c, zero, zero, zero, one)
}

/// The principal moments of inertia of a solid box of mass `m` and edge lengths
/// `lx`, `ly`, `lz` about its centre: `m (ly² + lz²) / 12`, and so on.
#[inline]
pub fn box_inertia<S: Scalar>(m: S, lx: S, ly: S, lz: S) -> Vector3<S> {
    let twelfth = S::from_f64(1.0 / 12.0);
    vec3(
        m * (ly * ly + lz * lz) * twelfth,
        m * (lx * lx + lz * lz) * twelfth,
        m * (lx * lx + ly * ly) * twelfth,
    )
}

/// A parameter vector (`[f64; N]` in the parameter struct) in the scalar type.
#[inline]
pub fn vector_param<S: Scalar, const N: usize>(value: &[f64; N]) -> SVector<S, N> {
    SVector::from_fn(|i, _| S::from_f64(value[i]))
}

/// A parameter vector whose first component is parameter number `first` (see
/// [`Scalar::parameter`]), in the scalar type: [`vector_param`] for `f64` and dual
/// numbers in the state, seeded component by component for parameter derivatives.
#[inline]
pub fn vector_parameter<S: Scalar, const N: usize>(
    value: &[f64; N],
    first: usize,
) -> SVector<S, N> {
    SVector::from_fn(|i, _| S::parameter(value[i], first + i))
}

/// A parameter matrix (`[[f64; C]; R]`, rows first) whose entry (0, 0) is parameter
/// number `first` (see [`Scalar::parameter`]; the entries follow row by row), in the
/// scalar type.
#[inline]
pub fn matrix_parameter<S: Scalar, const R: usize, const C: usize>(
    value: &[[f64; C]; R],
    first: usize,
) -> SMatrix<S, R, C> {
    SMatrix::from_fn(|i, j| S::parameter(value[i][j], first + i * C + j))
}

/// A parameter matrix (`[[f64; C]; R]`, rows first) in the scalar type.
pub fn matrix_param<S: Scalar, const R: usize, const C: usize>(
    value: &[[f64; C]; R],
) -> SMatrix<S, R, C> {
    SMatrix::from_fn(|i, j| S::from_f64(value[i][j]))
}

/// The product `a b` of an `R`×`K` matrix and a `K`×`C` matrix (a vector is `K`×1),
/// written out entry by entry: `sum_k a[(i, k)] b[(k, j)]`, `k` in increasing order.
///
/// For `f64` it is nalgebra's product bit for bit (the same sums in the same order);
/// for dual numbers it is much cheaper: nalgebra's generic product computes
/// `a x · 1 + 1 · y` per term through an out-of-line loop, which costs a dual number
/// three multiplications where one suffices. The macro writes `mat_mul` for every
/// product whose left factor it knows to be a matrix (see [`MatMul`]).
#[inline(always)]
pub fn mat_mul<S: Scalar, const R: usize, const K: usize, const C: usize>(
    a: &SMatrix<S, R, K>,
    b: &SMatrix<S, K, C>,
) -> SMatrix<S, R, C> {
    // Built in place (nalgebra's `from_fn` is not always inlined for dual numbers).
    let (a, b) = (&a.data.0, &b.data.0);
    let mut out = [[S::zero(); R]; C];
    for (j, column) in out.iter_mut().enumerate() {
        for (i, entry) in column.iter_mut().enumerate() {
            if K > 0 {
                // Column-major storage: `a[(i, k)]` is `a[k][i]`.
                let mut sum = a[0][i] * b[j][0];
                for k in 1..K {
                    sum += a[k][i] * b[j][k];
                }
                *entry = sum;
            }
        }
    }
    SMatrix::from_array_storage(nalgebra::ArrayStorage(out))
}

/// `self * rhs` for a matrix `self`: [`mat_mul`] when `rhs` is a matrix or a vector,
/// nalgebra's scaling when it is a number. Generated code calls
/// `MatMul::mat_mul(a, b)` for a law's `a * b` when `a` is a matrix.
pub trait MatMul<Rhs> {
    /// The product's type.
    type Output;
    /// `self * rhs`.
    fn mat_mul(self, rhs: Rhs) -> Self::Output;
}

impl<S: Scalar, const R: usize, const K: usize, const C: usize> MatMul<SMatrix<S, K, C>>
    for SMatrix<S, R, K>
{
    type Output = SMatrix<S, R, C>;
    #[inline(always)]
    fn mat_mul(self, rhs: SMatrix<S, K, C>) -> SMatrix<S, R, C> {
        mat_mul(&self, &rhs)
    }
}

impl<S: Scalar, const R: usize, const C: usize> MatMul<S> for SMatrix<S, R, C> {
    type Output = SMatrix<S, R, C>;
    #[inline(always)]
    fn mat_mul(self, rhs: S) -> SMatrix<S, R, C> {
        self * rhs
    }
}

/// How a linear coefficient acts on an n-dimensional bond variable: a number scales
/// it, a matrix multiplies it. The macro writes `apply(&k, q)` for a law `e = k q`
/// without knowing which of the two `k` is.
pub trait Linear<S: Scalar, const N: usize> {
    /// `k v`.
    fn apply(&self, v: SVector<S, N>) -> SVector<S, N>;
    /// `kᵀ v`.
    fn apply_transpose(&self, v: SVector<S, N>) -> SVector<S, N>;
    /// `k⁻¹ v` (a singular matrix gives non-finite values, which the solver reports).
    fn solve(&self, v: SVector<S, N>) -> SVector<S, N>;
    /// `k⁻ᵀ v`.
    fn solve_transpose(&self, v: SVector<S, N>) -> SVector<S, N>;
}

impl<S: Scalar, const N: usize> Linear<S, N> for S {
    #[inline(always)]
    fn apply(&self, v: SVector<S, N>) -> SVector<S, N> {
        v * *self
    }
    fn apply_transpose(&self, v: SVector<S, N>) -> SVector<S, N> {
        v * *self
    }
    fn solve(&self, v: SVector<S, N>) -> SVector<S, N> {
        v / *self
    }
    fn solve_transpose(&self, v: SVector<S, N>) -> SVector<S, N> {
        v / *self
    }
}

impl<S: Scalar, const N: usize> Linear<S, N> for SMatrix<S, N, N> {
    #[inline(always)]
    fn apply(&self, v: SVector<S, N>) -> SVector<S, N> {
        mat_mul(self, &v)
    }
    #[inline(always)]
    fn apply_transpose(&self, v: SVector<S, N>) -> SVector<S, N> {
        mat_mul(&self.transpose(), &v)
    }
    fn solve(&self, v: SVector<S, N>) -> SVector<S, N> {
        solve(*self, v)
    }
    fn solve_transpose(&self, v: SVector<S, N>) -> SVector<S, N> {
        solve(self.transpose(), v)
    }
}

/// ‖M X − I‖ (Frobenius norm, in `f64`) for a modulus `m` and the inverse `x` a law
/// gives for it, numbers or N×N matrices: how far `x` is from being `m`'s inverse.
pub fn inverse_residual<S: Scalar, const N: usize>(
    m: &impl Linear<S, N>,
    x: &impl Linear<S, N>,
) -> f64 {
    let mut sum = 0.0;
    for i in 0..N {
        let unit = SVector::<S, N>::from_fn(|j, _| S::from_f64(if i == j { 1.0 } else { 0.0 }));
        let column = m.apply(x.apply(unit)) - unit;
        sum += column.iter().map(|v| v.to_f64().powi(2)).sum::<f64>();
    }
    sum.sqrt()
}

/// Solves `a x = b` by Gaussian elimination with partial pivoting (pivots chosen by
/// value, so the same pivots serve `f64` and dual numbers).
fn solve<S: Scalar, const N: usize>(
    mut a: SMatrix<S, N, N>,
    mut b: SVector<S, N>,
) -> SVector<S, N> {
    for k in 0..N {
        let pivot = (k..N)
            .max_by(|&i, &j| {
                a[(i, k)]
                    .to_f64()
                    .abs()
                    .total_cmp(&a[(j, k)].to_f64().abs())
            })
            .unwrap_or(k);
        a.swap_rows(k, pivot);
        b.swap_rows(k, pivot);
        for i in k + 1..N {
            let factor = a[(i, k)] / a[(k, k)];
            for j in k..N {
                let update = factor * a[(k, j)];
                a[(i, j)] -= update;
            }
            let update = factor * b[k];
            b[i] -= update;
        }
    }
    for k in (0..N).rev() {
        let mut sum = b[k];
        for j in k + 1..N {
            sum -= a[(k, j)] * b[j];
        }
        b[k] = sum / a[(k, k)];
    }
    b
}

/// A value a state can hold, laid out in the state vector: a number, a vector, or a
/// matrix stored column by column (nalgebra's order).
pub trait StateValue<S: Scalar>: Sized {
    /// How many state entries it takes.
    const LEN: usize;
    /// Reads it from `x` (exactly `LEN` entries).
    fn read(x: &[S]) -> Self;
    /// Writes it into `out` (exactly `LEN` entries).
    fn write(&self, out: &mut [S]);
}

impl<S: Scalar> StateValue<S> for S {
    const LEN: usize = 1;
    #[inline(always)]
    fn read(x: &[S]) -> Self {
        x[0]
    }
    #[inline(always)]
    fn write(&self, out: &mut [S]) {
        out[0] = *self;
    }
}

impl<S: Scalar, const R: usize, const C: usize> StateValue<S> for SMatrix<S, R, C> {
    const LEN: usize = R * C;
    #[inline(always)]
    fn read(x: &[S]) -> Self {
        SMatrix::from_column_slice(x)
    }
    #[inline(always)]
    fn write(&self, out: &mut [S]) {
        out.copy_from_slice(self.as_slice());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_is_the_cross_product_and_antisymmetric() {
        let a = vec3(0.3, -1.2, 2.0);
        let b = vec3(4.0, 0.5, -0.7);
        assert_eq!(skew(a) * b, a.cross(&b));
        assert_eq!(skew(a).transpose(), -skew(a));
    }

    #[test]
    fn rotation_about_z_turns_x_into_y() {
        let r = rot_z(core::f64::consts::FRAC_PI_2);
        let y = r * vec3(1.0, 0.0, 0.0);
        assert!((y - vec3(0.0, 1.0, 0.0)).norm() < 1e-15);
        assert!((r.transpose() * r - identity3()).norm() < 1e-15);
    }

    #[test]
    fn a_matrix_law_solves_what_it_applies() {
        let k = Matrix3::new(4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0);
        let v = vec3(1.0, -2.0, 0.5);
        let back = Linear::<f64, 3>::solve(&k, Linear::<f64, 3>::apply(&k, v));
        assert!((back - v).norm() < 1e-14);
        let back = Linear::<f64, 3>::solve_transpose(&k, Linear::<f64, 3>::apply_transpose(&k, v));
        assert!((back - v).norm() < 1e-14);
        // A pivot is needed: the first diagonal entry is zero.
        let p = Matrix3::new(0.0, 2.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 3.0);
        assert!((Linear::<f64, 3>::apply(&p, Linear::<f64, 3>::solve(&p, v)) - v).norm() < 1e-14);
    }

    #[test]
    fn measure_how_far_an_inverse_is_from_one() {
        let r = rot_z(0.3);
        assert!(inverse_residual::<f64, 3>(&r, &r.transpose()) < 1e-15);
        let wrong = inverse_residual::<f64, 3>(&r, &r);
        assert!((wrong - (r * r - identity3()).norm()).abs() < 1e-15 && wrong > 0.4);
        assert_eq!(
            inverse_residual::<f64, 3>(&2.0, &0.25),
            0.5 * 3.0_f64.sqrt()
        );
    }

    /// `mat_mul` is nalgebra's product bit for bit in `f64`, and on dual numbers its
    /// values are the `f64` product's and its tangents the product rule's.
    #[test]
    fn the_written_out_product_is_nalgebras() {
        let a = Matrix3::new(0.3, -1.2, 2.0, 4.0, 0.5, -0.7, 1e-3, 7.5, -2.25);
        let b = Matrix3::new(1.1, 0.2, -0.3, -4.0, 0.25, 9.0, 3.0, -0.6, 0.01);
        let v = vec3(0.7, -0.1, 2.5);
        assert_eq!(mat_mul(&a, &b), a * b);
        assert_eq!(mat_mul(&a, &v), a * v);
        assert_eq!(MatMul::mat_mul(a.transpose(), v), a.transpose() * v);
        assert_eq!(MatMul::mat_mul(a, 2.5), a * 2.5);
        let row = SMatrix::<f64, 1, 3>::new(1.0, 2.0, 3.0);
        assert_eq!(mat_mul(&v, &row), v * row);
        // d(A(s) B(s))/ds = A' B + A B' along A(s) = A + s A', B(s) = B + s B'.
        use crate::dual::DualN;
        let (da, db) = (skew(vec3(1.0, -2.0, 0.5)), identity3::<f64>() * 3.0);
        let dual = |m: Matrix3<f64>, d: Matrix3<f64>| {
            Matrix3::from_fn(|i, j| DualN::<2>::new(m[(i, j)], [d[(i, j)], -d[(i, j)]]))
        };
        let product = mat_mul(&dual(a, da), &dual(b, db));
        let tangent = da * b + a * db;
        for i in 0..3 {
            for j in 0..3 {
                let p = product[(i, j)];
                assert_eq!(p.value(), (a * b)[(i, j)]);
                assert!((p.tangents()[0] - tangent[(i, j)]).abs() < 1e-13);
                assert!((p.tangents()[1] + tangent[(i, j)]).abs() < 1e-13);
            }
        }
    }

    #[test]
    fn a_number_law_scales() {
        let v = vec3(1.0, 2.0, 3.0);
        assert_eq!(Linear::<f64, 3>::apply(&2.0, v), vec3(2.0, 4.0, 6.0));
        assert_eq!(Linear::<f64, 3>::solve(&2.0, v), vec3(0.5, 1.0, 1.5));
    }

    #[test]
    fn matrices_are_stored_column_by_column() {
        let m = Matrix3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0);
        let mut x = [0.0; 9];
        m.write(&mut x);
        assert_eq!(x, [1.0, 4.0, 7.0, 2.0, 5.0, 8.0, 3.0, 6.0, 9.0]);
        assert_eq!(<Matrix3<f64> as StateValue<f64>>::read(&x), m);
        assert_eq!(
            matrix_param::<f64, 3, 3>(&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]]),
            m
        );
    }
}
