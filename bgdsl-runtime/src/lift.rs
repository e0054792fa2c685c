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

/// A value computed in `f64` on its way into the scalar type `S`, for generated code
/// that does not know the value's type: [`ViaLift`] lifts what implements [`Lift`]
/// (numbers, vectors, matrices), [`ViaIdentity`] passes anything else through
/// unchanged (an integer, a flag, a user's enum). Call
/// `(&Lifting::<S, _>::new(value)).lift_value()` with both traits in scope: method
/// resolution prefers `ViaLift` when it applies.
pub struct Lifting<S, V>(V, core::marker::PhantomData<S>);

impl<S, V> Lifting<S, V> {
    /// Wraps `value`.
    pub fn new(value: V) -> Self {
        Lifting(value, core::marker::PhantomData)
    }
}

/// The preferred way through [`Lifting`]: a value with a counterpart in `S`.
pub trait ViaLift {
    /// The counterpart.
    type Output;
    /// The value in the scalar type.
    fn lift_value(&self) -> Self::Output;
}

impl<S: Scalar, V: Lift<S> + Copy> ViaLift for Lifting<S, V> {
    type Output = V::Output;
    fn lift_value(&self) -> V::Output {
        self.0.lift()
    }
}

/// The fallback way through [`Lifting`]: any other value, unchanged.
pub trait ViaIdentity {
    /// The value's own type.
    type Output;
    /// The value itself.
    fn lift_value(&self) -> Self::Output;
}

impl<S, V: Clone> ViaIdentity for &Lifting<S, V> {
    type Output = V;
    fn lift_value(&self) -> V {
        self.0.clone()
    }
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

    #[derive(Clone, Debug, PartialEq)]
    enum Mode {
        Fast,
    }

    #[test]
    // The borrow is how generated code chooses between the two ways.
    #[allow(clippy::needless_borrow)]
    fn lift_what_has_a_counterpart_and_pass_anything_else_through() {
        #[allow(unused_imports)]
        use super::{ViaIdentity as _, ViaLift as _};
        let x: DualN<1> = (&Lifting::<DualN<1>, _>::new(2.0)).lift_value();
        assert_eq!((x.value(), *x.tangents()), (2.0, [0.0]));
        let v = (&Lifting::<DualN<1>, _>::new(vec3(1.0, 2.0, 3.0))).lift_value();
        assert_eq!(v.z.value(), 3.0);
        assert_eq!(
            (&Lifting::<DualN<1>, _>::new(Mode::Fast)).lift_value(),
            Mode::Fast
        );
        assert_eq!((&Lifting::<DualN<1>, _>::new(3_i32)).lift_value(), 3);
    }
}
