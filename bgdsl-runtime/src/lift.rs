//! Values computed in `f64` taken into a model's scalar type: the parameter
//! expressions a generated model computes once (see the `bond_graph!` docs,
//! "Parameter expressions") enter its laws through [`lift`].

use crate::multibond::SMatrix;
use crate::Scalar;

/// An `f64` value (a number, vector or matrix) that has a counterpart in the scalar
/// type `S`.
pub trait Lift<S: Scalar> {
    /// The counterpart: `S`, or a vector or matrix of `S`.
    type Output;
    /// The value in `S` (a constant: for dual numbers, no derivative).
    fn lift(self) -> Self::Output;
}

impl<S: Scalar> Lift<S> for f64 {
    type Output = S;
    fn lift(self) -> S {
        S::from_f64(self)
    }
}

impl<S: Scalar, const R: usize, const C: usize> Lift<S> for SMatrix<f64, R, C> {
    type Output = SMatrix<S, R, C>;
    fn lift(self) -> SMatrix<S, R, C> {
        self.map(S::from_f64)
    }
}

/// `value` in the scalar type `S`: `lift::<S, _>(2.0)` is `S::from_f64(2.0)`, and
/// vectors and matrices are lifted entry by entry.
pub fn lift<S: Scalar, V: Lift<S>>(value: V) -> V::Output {
    value.lift()
}

#[cfg(test)]
mod should {
    use super::*;
    use crate::multibond::vec3;
    use crate::DualN;

    #[test]
    fn lift_numbers_and_vectors_as_constants() {
        let x: DualN<2> = lift(1.5);
        assert_eq!((x.value(), *x.tangents()), (1.5, [0.0, 0.0]));
        let v = lift::<DualN<2>, _>(vec3(1.0, 2.0, 3.0));
        assert_eq!((v.y.value(), *v.y.tangents()), (2.0, [0.0, 0.0]));
        assert_eq!(lift::<f64, _>(vec3(1.0, 2.0, 3.0)), vec3(1.0, 2.0, 3.0));
    }
}
