//! A tangent over any scalar: `re + eps·ε` (`ε² = 0`) whose parts are themselves
//! [`Scalar`]s.
//!
//! [`Dual`](crate::Dual) carries one derivative of an `f64` computation. `Tangent<S>`
//! carries one derivative of an `S` computation, whatever `S` is: on `Tangent<f64>` it
//! is `Dual` again, and on `Tangent<Dual>` or `Tangent<DualN<N>>` its `eps` part holds a
//! time derivative *and* that derivative's own derivatives along `S`'s directions, so
//! mixed second derivatives come out exact (no step size, nothing approximated).
//!
//! The generated code of a model with dependent storage (`#[allow(derivative_causality)]`)
//! uses it to differentiate a dependent storage element's energy variable `E(x, t)`
//! along the motion: it evaluates `E` on `Tangent<T>` with `re = x`, `eps = dx/dt`
//! (and `t` with tangent 1), and reads `dE/dt` from the `eps` parts; when the model
//! itself is evaluated on a dual `T` (for an exact Jacobian), those parts carry
//! `∂(dE/dt)/∂x` too.
//!
//! # Conventions
//!
//! Exactly those of [`Dual`](crate::dual#conventions), applied to the parts in `S`:
//! comparison is by the value `re` (as `S` compares it, i.e. by the innermost value); a
//! tangent that is exactly zero (every part of `eps` zero, as
//! [`Zero::is_zero`] says) stays zero where the slope of an
//! elementary function is infinite or undefined (`sqrt`, `cbrt` and `ln` at 0, `asin`
//! and `acos` at ±1, a negative `powi` at 0, `powf` at a zero base, `atan2` at the
//! origin); kinks take the midpoint of the one-sided slopes (`abs` at 0, `min`/`max` of
//! equal values); `signum` has derivative zero; `powi(0)` is the constant 1. Every slope
//! is computed in `S` from `re` with `S`'s own methods, so the slope's derivatives (the
//! second derivatives) follow `S`'s conventions in turn.
//!
//! On `Tangent<f64>` every method computes what `Dual`'s does with the same operations
//! in the same order (bit for bit), except `atan2`, whose slope is scaled by the larger
//! of `|x|` and `|y|` instead of `hypot` (`S` has no `hypot`): equal to a few ulps.

use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use num_traits::{One, Zero};

use crate::scalar::Scalar;

/// A value and its derivative along one direction, both of scalar type `S`. See the
/// [module documentation](self).
#[derive(Clone, Copy, Debug, Default)]
pub struct Tangent<S> {
    /// The value.
    pub re: S,
    /// Its derivative along the seeded direction (for the generated code: with respect
    /// to time, along the motion).
    pub eps: S,
}

impl<S> Tangent<S> {
    /// The tangent `re + eps·ε`.
    #[inline(always)]
    pub const fn new(re: S, eps: S) -> Self {
        Tangent { re, eps }
    }
}

impl<S: Scalar> Tangent<S> {
    /// A constant: tangent zero.
    #[inline(always)]
    pub fn constant(re: S) -> Self {
        Tangent { re, eps: S::zero() }
    }

    /// The independent variable: tangent one.
    #[inline(always)]
    pub fn variable(re: S) -> Self {
        Tangent { re, eps: S::one() }
    }

    /// `value` with tangent `self.eps · slope` (the chain rule).
    #[inline(always)]
    fn chain(self, value: S, slope: S) -> Self {
        Tangent {
            re: value,
            eps: self.eps * slope,
        }
    }

    /// `value` with tangent `self.eps · slope()`, or a zero tangent when `self.eps` is
    /// zero (the slope may be infinite or NaN there, and is then not computed at all).
    #[inline(always)]
    fn chain_guarded(self, value: S, slope: impl FnOnce() -> S) -> Self {
        let eps = if self.eps.is_zero() {
            S::zero()
        } else {
            self.eps * slope()
        };
        Tangent { re: value, eps }
    }

    /// `value` with the tangent `(a + b) / 2` (min and max of equal values).
    #[inline(always)]
    fn mean(self, other: Self, value: S) -> Self {
        Tangent {
            re: value,
            eps: S::from_f64(0.5) * (self.eps + other.eps),
        }
    }
}

/// Whether `x` is NaN, for a scalar that compares by value (NaN is unequal to itself).
#[inline(always)]
#[allow(clippy::eq_op)]
fn is_nan<S: Scalar>(x: S) -> bool {
    x != x
}

impl<S: Scalar> From<f64> for Tangent<S> {
    /// A constant.
    #[inline(always)]
    fn from(re: f64) -> Self {
        Tangent::constant(S::from_f64(re))
    }
}

impl<S: Scalar> PartialEq for Tangent<S> {
    /// Equality of the values (the tangents are ignored, as for [`Dual`](crate::Dual)).
    #[inline(always)]
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

impl<S: Scalar> PartialOrd for Tangent<S> {
    /// Ordering of the values.
    #[inline(always)]
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<S: fmt::Display> fmt::Display for Tangent<S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}) + ({})ε", self.re, self.eps)
    }
}

impl<S: Scalar> Neg for Tangent<S> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Tangent::new(-self.re, -self.eps)
    }
}

impl<S: Scalar> Add for Tangent<S> {
    type Output = Self;
    #[inline(always)]
    fn add(self, rhs: Self) -> Self {
        Tangent::new(self.re + rhs.re, self.eps + rhs.eps)
    }
}

impl<S: Scalar> Sub for Tangent<S> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, rhs: Self) -> Self {
        Tangent::new(self.re - rhs.re, self.eps - rhs.eps)
    }
}

impl<S: Scalar> Mul for Tangent<S> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, rhs: Self) -> Self {
        Tangent::new(self.re * rhs.re, self.eps * rhs.re + self.re * rhs.eps)
    }
}

impl<S: Scalar> Div for Tangent<S> {
    type Output = Self;
    /// `(a/b)' = (a' − (a/b)·b') / b`.
    #[inline(always)]
    fn div(self, rhs: Self) -> Self {
        let q = self.re / rhs.re;
        Tangent::new(q, (self.eps - q * rhs.eps) / rhs.re)
    }
}

impl<S: Scalar> AddAssign for Tangent<S> {
    #[inline(always)]
    fn add_assign(&mut self, rhs: Self) {
        *self = *self + rhs;
    }
}

impl<S: Scalar> SubAssign for Tangent<S> {
    #[inline(always)]
    fn sub_assign(&mut self, rhs: Self) {
        *self = *self - rhs;
    }
}

impl<S: Scalar> MulAssign for Tangent<S> {
    #[inline(always)]
    fn mul_assign(&mut self, rhs: Self) {
        *self = *self * rhs;
    }
}

impl<S: Scalar> DivAssign for Tangent<S> {
    #[inline(always)]
    fn div_assign(&mut self, rhs: Self) {
        *self = *self / rhs;
    }
}

impl<S: Scalar> Zero for Tangent<S> {
    #[inline(always)]
    fn zero() -> Self {
        Tangent::new(S::zero(), S::zero())
    }
    #[inline]
    fn is_zero(&self) -> bool {
        self.re.is_zero() && self.eps.is_zero()
    }
}

impl<S: Scalar> One for Tangent<S> {
    #[inline(always)]
    fn one() -> Self {
        Tangent::constant(S::one())
    }
}

/// Every method is [`Dual`](crate::Dual)'s rule with the value and the slope computed
/// in `S` (see the [module documentation](self)).
impl<S: Scalar> Scalar for Tangent<S> {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        Tangent::constant(S::from_f64(value))
    }

    #[inline(always)]
    fn to_f64(self) -> f64 {
        self.re.to_f64()
    }

    /// `√x' = x' / (2√x)`; at `x = 0` the slope is `+∞` (a zero tangent stays zero).
    #[inline]
    fn sqrt(self) -> Self {
        let r = self.re.sqrt();
        self.chain_guarded(r, || S::from_f64(0.5) / r)
    }

    /// `∛x' = x' / (3 ∛x²)`; at `x = 0` the slope is `+∞` (a zero tangent stays zero).
    #[inline]
    fn cbrt(self) -> Self {
        let r = self.re.cbrt();
        self.chain_guarded(r, || S::one() / (S::from_f64(3.0) * r * r))
    }

    #[inline]
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }

    /// `ln x' = x' / x` (a zero tangent stays zero at `x = 0`).
    #[inline]
    fn ln(self) -> Self {
        let re = self.re;
        self.chain_guarded(re.ln(), || S::one() / re)
    }

    #[inline]
    fn sin(self) -> Self {
        self.chain(self.re.sin(), self.re.cos())
    }

    #[inline]
    fn cos(self) -> Self {
        self.chain(self.re.cos(), -self.re.sin())
    }

    /// `tan x' = x' (1 + tan² x)`.
    #[inline]
    fn tan(self) -> Self {
        let t = self.re.tan();
        self.chain(t, S::one() + t * t)
    }

    /// `asin x' = x' / √(1 − x²)` (a zero tangent stays zero at ±1).
    #[inline]
    fn asin(self) -> Self {
        let x = self.re;
        self.chain_guarded(x.asin(), || {
            S::one() / ((S::one() - x) * (S::one() + x)).sqrt()
        })
    }

    /// `acos x' = −x' / √(1 − x²)` (a zero tangent stays zero at ±1).
    #[inline]
    fn acos(self) -> Self {
        let x = self.re;
        self.chain_guarded(x.acos(), || {
            -S::one() / ((S::one() - x) * (S::one() + x)).sqrt()
        })
    }

    /// `atan x' = x' / (1 + x²)`.
    #[inline]
    fn atan(self) -> Self {
        let x = self.re;
        self.chain(x.atan(), S::one() / (S::one() + x * x))
    }

    /// `atan2(y, x)' = (x y' − y x') / (x² + y²)`, with `x` and `y` scaled by the larger
    /// of their magnitudes so that it neither overflows nor underflows. At the origin
    /// the tangent is zero if both tangents are zero, NaN otherwise.
    #[inline]
    fn atan2(self, other: Self) -> Self {
        let (y, x) = (self, other);
        let value = y.re.atan2(x.re);
        if y.eps.is_zero() && x.eps.is_zero() {
            return Tangent::constant(value);
        }
        let m = y.re.abs().max(x.re.abs());
        let (ys, xs) = (y.re / m, x.re / m);
        let eps = (xs * y.eps - ys * x.eps) / (m * (xs * xs + ys * ys));
        Tangent::new(value, eps)
    }

    #[inline]
    fn sinh(self) -> Self {
        self.chain(self.re.sinh(), self.re.cosh())
    }

    #[inline]
    fn cosh(self) -> Self {
        self.chain(self.re.cosh(), self.re.sinh())
    }

    /// `tanh x' = x' / cosh² x`.
    #[inline]
    fn tanh(self) -> Self {
        let sech = S::one() / self.re.cosh();
        self.chain(self.re.tanh(), sech * sech)
    }

    /// `|x|' = sign(x) x'`; at `x = 0` the slope is 0.
    #[inline]
    fn abs(self) -> Self {
        let zero = S::zero();
        let slope = if self.re > zero {
            1.0
        } else if self.re < zero {
            -1.0
        } else {
            0.0
        };
        self.chain(self.re.abs(), S::from_f64(slope))
    }

    /// The value's `signum`, with a zero tangent (also at the jump).
    #[inline]
    fn signum(self) -> Self {
        Tangent::constant(self.re.signum())
    }

    /// `(xⁿ)' = n xⁿ⁻¹ x'`; `x⁰` is the constant 1 (a zero tangent stays zero at
    /// `x = 0` for `n < 0`).
    #[inline]
    fn powi(self, n: i32) -> Self {
        match n {
            0 => Tangent::constant(S::one()),
            1 => self,
            _ => {
                let value = self.re.powi(n);
                let re = self.re;
                let slope = move || {
                    let below = match n.checked_sub(1) {
                        Some(m) => re.powi(m),
                        None => value / re,
                    };
                    S::from_f64(f64::from(n)) * below
                };
                if n > 0 {
                    self.chain(value, slope())
                } else {
                    self.chain_guarded(value, slope)
                }
            }
        }
    }

    /// `(xʸ)' = y xʸ⁻¹ x' + xʸ ln x · y'`, each term taken only where its tangent is
    /// non-zero (and the first only for `y ≠ 0`, the second only where `xʸ ≠ 0`), as
    /// [`Dual`](crate::Dual)'s.
    #[inline]
    fn powf(self, n: Self) -> Self {
        let (x, y) = (self, n);
        let value = x.re.powf(y.re);
        let mut eps = S::zero();
        if !x.eps.is_zero() && !y.re.is_zero() {
            eps += y.re * x.re.powf(y.re - S::one()) * x.eps;
        }
        if !y.eps.is_zero() && !value.is_zero() {
            eps += value * x.re.ln() * y.eps;
        }
        Tangent::new(value, eps)
    }

    /// The argument with the smaller value (a NaN loses); for equal values the mean of
    /// the two tangents.
    #[inline]
    fn min(self, other: Self) -> Self {
        if self.re < other.re || is_nan(other.re) {
            self
        } else if other.re < self.re || is_nan(self.re) {
            other
        } else {
            self.mean(other, self.re.min(other.re))
        }
    }

    /// The argument with the larger value (a NaN loses); for equal values the mean of
    /// the two tangents.
    #[inline]
    fn max(self, other: Self) -> Self {
        if self.re > other.re || is_nan(other.re) {
            self
        } else if other.re > self.re || is_nan(self.re) {
            other
        } else {
            self.mean(other, self.re.max(other.re))
        }
    }

    /// `(1/x)' = −x' / x²`.
    #[inline]
    fn recip(self) -> Self {
        let r = self.re.recip();
        self.chain(r, -r * r)
    }
}
