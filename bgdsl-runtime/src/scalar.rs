//! The number type a model's equations are written in.
//!
//! Generated derivative functions are generic over [`Scalar`], so the same straight-line
//! code runs on `f64` for simulation and on dual numbers for exact Jacobians. `Zero` and
//! `One` make every `Scalar` a valid element of nalgebra's fixed-size vectors and
//! matrices, which is what multibonds are made of.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::math;

/// A real number as the generated code sees it: field arithmetic, ordering by value,
/// and the elementary functions a constitutive law may call.
///
/// Literals in a law are converted with [`Scalar::from_f64`] by the macro, so a user
/// writes `0.5 * k * q.powi(3)` and never names the scalar type.
pub trait Scalar:
    Copy
    + Debug
    + PartialEq
    + PartialOrd
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + num_traits::Zero
    + num_traits::One
{
    /// Whether this type carries derivatives with respect to parameters or inputs
    /// (seeded through [`Scalar::parameter`] and [`Scalar::input`]). When it does,
    /// generated code evaluates its parameter expressions in `Self` at every
    /// evaluation instead of lifting the `f64` values it computed once, so that no
    /// derivative is lost in the cache. `false` (the default) for `f64` and the dual
    /// numbers of Jacobians in the state, whose code is unchanged by the hook.
    const PARAMETER_TANGENTS: bool = false;

    /// A constant: no dependence on the state.
    fn from_f64(value: f64) -> Self;

    /// Parameter number `index` (in the order of
    /// [`Model::parameter_values`](crate::Model::parameter_values): declaration order,
    /// vectors component by component, matrices row by row), whose value is `value`.
    /// Generated code reads every parameter through this; the default is the constant
    /// [`Scalar::from_f64`], so `f64` and [`Dual`](crate::Dual) compile to what they did
    /// without the hook.
    #[inline(always)]
    fn parameter(value: f64, index: usize) -> Self {
        let _ = index;
        Self::from_f64(value)
    }

    /// Input number `index` (in the order of
    /// [`WithInputs::INPUTS`](crate::WithInputs::INPUTS)), whose value is `value`; the
    /// default is the constant [`Scalar::from_f64`], as for [`Scalar::parameter`].
    #[inline(always)]
    fn input(value: f64, index: usize) -> Self {
        let _ = index;
        Self::from_f64(value)
    }
    /// The value, without any derivative part.
    fn to_f64(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Cube root.
    fn cbrt(self) -> Self;
    /// e raised to `self`.
    fn exp(self) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// Sine (radians).
    fn sin(self) -> Self;
    /// Cosine (radians).
    fn cos(self) -> Self;
    /// Tangent (radians).
    fn tan(self) -> Self;
    /// Arcsine.
    fn asin(self) -> Self;
    /// Arccosine.
    fn acos(self) -> Self;
    /// Arctangent.
    fn atan(self) -> Self;
    /// Four-quadrant arctangent of `self / other`.
    fn atan2(self, other: Self) -> Self;
    /// Hyperbolic sine.
    fn sinh(self) -> Self;
    /// Hyperbolic cosine.
    fn cosh(self) -> Self;
    /// Hyperbolic tangent.
    fn tanh(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// -1, 0 or 1 with the sign of the value (1 for +0.0, as `f64::signum`).
    fn signum(self) -> Self;
    /// Integer power.
    fn powi(self, n: i32) -> Self;
    /// Real power.
    fn powf(self, n: Self) -> Self;
    /// The smaller of two values (by value).
    fn min(self, other: Self) -> Self;
    /// The larger of two values (by value).
    fn max(self, other: Self) -> Self;
    /// 1 / self.
    fn recip(self) -> Self {
        Self::from_f64(1.0) / self
    }
}

/// The `f64` methods of the same names (without the `std` feature, the elementary
/// functions come from `libm`).
impl Scalar for f64 {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        value
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        math::sqrt(self)
    }
    #[inline(always)]
    fn cbrt(self) -> Self {
        math::cbrt(self)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        math::exp(self)
    }
    #[inline(always)]
    fn ln(self) -> Self {
        math::ln(self)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        math::sin(self)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        math::cos(self)
    }
    #[inline(always)]
    fn tan(self) -> Self {
        math::tan(self)
    }
    #[inline(always)]
    fn asin(self) -> Self {
        math::asin(self)
    }
    #[inline(always)]
    fn acos(self) -> Self {
        math::acos(self)
    }
    #[inline(always)]
    fn atan(self) -> Self {
        math::atan(self)
    }
    #[inline(always)]
    fn atan2(self, other: Self) -> Self {
        math::atan2(self, other)
    }
    #[inline(always)]
    fn sinh(self) -> Self {
        math::sinh(self)
    }
    #[inline(always)]
    fn cosh(self) -> Self {
        math::cosh(self)
    }
    #[inline(always)]
    fn tanh(self) -> Self {
        math::tanh(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn signum(self) -> Self {
        f64::signum(self)
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        math::powi(self, n)
    }
    #[inline(always)]
    fn powf(self, n: Self) -> Self {
        math::powf(self, n)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f64::min(self, other)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline(always)]
    fn recip(self) -> Self {
        f64::recip(self)
    }
}
