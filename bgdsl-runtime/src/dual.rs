//! Forward-mode automatic differentiation: a dual number `re + eps·ε` with `ε² = 0`.
//!
//! Evaluating a function on [`Dual`] numbers whose `eps` parts hold a direction `v`
//! yields its value in the `re` parts and its directional derivative `J·v` in the `eps`
//! parts, exact to round-off (no step size, no truncation error). Generated models are
//! generic over [`Scalar`], so [`Model::derivatives`](crate::Model::derivatives) runs on
//! `Dual` unchanged; [`JacobianEvaluator`](crate::JacobianEvaluator) builds Jacobians
//! from that.
//!
//! # Conventions
//!
//! - **Comparison is by value.** `==`, `<`, … compare `re` only, exactly as the same
//!   code compares `f64`s, so a dual evaluation takes the same branches as the plain
//!   one and its `re` parts equal the `f64` results.
//! - **The value is the `f64` function's.** Every method computes `re` with the
//!   matching `f64` method, bit for bit.
//! - **A zero tangent stays zero.** Where the derivative of an elementary function is
//!   infinite or undefined at a point where the function itself is finite (`sqrt` and
//!   `cbrt` at 0, `asin`/`acos` at ±1, `powf` at a zero base, `atan2` at the origin),
//!   an argument whose `eps` is exactly zero gives a result whose `eps` is zero, not
//!   `0·∞ = NaN`. The chain rule with a zero inner derivative is zero; this keeps
//!   Jacobian columns the value does not depend on free of NaN. A non-zero tangent at
//!   such a point gives the one-sided limit (`±∞`) or `NaN` (`atan2` at the origin).
//! - **Kinks take the midpoint of the one-sided derivatives**, as JAX and PyTorch do:
//!   `abs` has derivative 0 at 0 (midpoint of −1 and 1); `min` and `max` of two equal
//!   values take the mean of the two tangents (so `x.max(x)` has `x`'s tangent and
//!   `x.max(-x)` at 0 has tangent 0, like `abs`).
//! - **Step functions have derivative zero**: `signum` (including at its jump).
//! - `powi(0)` is the constant 1 (derivative 0, even at 0).

use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::scalar::Scalar;

/// A dual number `re + eps·ε` (`ε² = 0`): a value and its derivative along one
/// direction. See the [module documentation](self) for the conventions at
/// non-differentiable points.
#[derive(Clone, Copy, Debug, Default)]
pub struct Dual {
    /// The value.
    pub re: f64,
    /// The derivative of the value along the seeded direction (the tangent).
    pub eps: f64,
}

impl Dual {
    /// The dual number `re + eps·ε`.
    #[inline(always)]
    pub const fn new(re: f64, eps: f64) -> Self {
        Dual { re, eps }
    }

    /// A constant: tangent zero.
    #[inline(always)]
    pub const fn constant(re: f64) -> Self {
        Dual { re, eps: 0.0 }
    }

    /// The independent variable: tangent one.
    #[inline(always)]
    pub const fn variable(re: f64) -> Self {
        Dual { re, eps: 1.0 }
    }

    /// The result `value` with tangent `self.eps · slope` (the chain rule), or a zero
    /// tangent when `self.eps` is zero whatever `slope` is (see the module's
    /// conventions: `slope` may be infinite or NaN there).
    #[inline(always)]
    fn chain_guarded(self, value: f64, slope: f64) -> Self {
        let eps = if self.eps == 0.0 {
            0.0
        } else {
            self.eps * slope
        };
        Dual { re: value, eps }
    }

    /// The result `value` with tangent `self.eps · slope`, for a `slope` that is finite
    /// wherever `value` is.
    #[inline(always)]
    fn chain(self, value: f64, slope: f64) -> Self {
        Dual {
            re: value,
            eps: self.eps * slope,
        }
    }
}

impl From<f64> for Dual {
    /// A constant.
    #[inline(always)]
    fn from(re: f64) -> Self {
        Dual::constant(re)
    }
}

impl PartialEq for Dual {
    /// Equality of the values (the tangents are ignored, as the comparison in the
    /// generated code is about values).
    #[inline(always)]
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

impl PartialOrd for Dual {
    /// Ordering of the values.
    #[inline(always)]
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl fmt::Display for Dual {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} + {}ε", self.re, self.eps)
    }
}

impl Neg for Dual {
    type Output = Dual;
    #[inline(always)]
    fn neg(self) -> Dual {
        Dual::new(-self.re, -self.eps)
    }
}

impl Add for Dual {
    type Output = Dual;
    #[inline(always)]
    fn add(self, rhs: Dual) -> Dual {
        Dual::new(self.re + rhs.re, self.eps + rhs.eps)
    }
}

impl Sub for Dual {
    type Output = Dual;
    #[inline(always)]
    fn sub(self, rhs: Dual) -> Dual {
        Dual::new(self.re - rhs.re, self.eps - rhs.eps)
    }
}

impl Mul for Dual {
    type Output = Dual;
    #[inline(always)]
    fn mul(self, rhs: Dual) -> Dual {
        Dual::new(self.re * rhs.re, self.eps * rhs.re + self.re * rhs.eps)
    }
}

impl Div for Dual {
    type Output = Dual;
    /// `(a/b)' = (a' − (a/b)·b') / b`.
    #[inline(always)]
    fn div(self, rhs: Dual) -> Dual {
        let q = self.re / rhs.re;
        Dual::new(q, (self.eps - q * rhs.eps) / rhs.re)
    }
}

impl AddAssign for Dual {
    #[inline(always)]
    fn add_assign(&mut self, rhs: Dual) {
        *self = *self + rhs;
    }
}

impl SubAssign for Dual {
    #[inline(always)]
    fn sub_assign(&mut self, rhs: Dual) {
        *self = *self - rhs;
    }
}

impl MulAssign for Dual {
    #[inline(always)]
    fn mul_assign(&mut self, rhs: Dual) {
        *self = *self * rhs;
    }
}

impl DivAssign for Dual {
    #[inline(always)]
    fn div_assign(&mut self, rhs: Dual) {
        *self = *self / rhs;
    }
}

impl num_traits::Zero for Dual {
    fn zero() -> Self {
        Dual::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        self.re == 0.0 && self.eps == 0.0
    }
}

impl num_traits::One for Dual {
    fn one() -> Self {
        Dual::constant(1.0)
    }
}

impl Scalar for Dual {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        Dual::constant(value)
    }

    #[inline(always)]
    fn to_f64(self) -> f64 {
        self.re
    }

    /// `√x' = x' / (2√x)`; at `x = 0` the slope is `+∞` (a zero tangent stays zero).
    #[inline]
    fn sqrt(self) -> Self {
        let r = self.re.sqrt();
        self.chain_guarded(r, 0.5 / r)
    }

    /// `∛x' = x' / (3 ∛x²)`; at `x = 0` the slope is `+∞` (a zero tangent stays zero).
    #[inline]
    fn cbrt(self) -> Self {
        let r = self.re.cbrt();
        self.chain_guarded(r, 1.0 / (3.0 * r * r))
    }

    #[inline]
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }

    /// `ln x' = x' / x` (a zero tangent stays zero at `x = 0`, where the value is −∞).
    #[inline]
    fn ln(self) -> Self {
        self.chain_guarded(self.re.ln(), 1.0 / self.re)
    }

    #[inline]
    fn sin(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(s, c)
    }

    #[inline]
    fn cos(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(c, -s)
    }

    /// `tan x' = x' (1 + tan² x)`.
    #[inline]
    fn tan(self) -> Self {
        let t = self.re.tan();
        self.chain(t, 1.0 + t * t)
    }

    /// `asin x' = x' / √(1 − x²)`; at `x = ±1` the slope is `+∞` (a zero tangent stays
    /// zero).
    #[inline]
    fn asin(self) -> Self {
        let x = self.re;
        self.chain_guarded(x.asin(), 1.0 / ((1.0 - x) * (1.0 + x)).sqrt())
    }

    /// `acos x' = −x' / √(1 − x²)`; at `x = ±1` the slope is `−∞` (a zero tangent stays
    /// zero).
    #[inline]
    fn acos(self) -> Self {
        let x = self.re;
        self.chain_guarded(x.acos(), -1.0 / ((1.0 - x) * (1.0 + x)).sqrt())
    }

    /// `atan x' = x' / (1 + x²)`.
    #[inline]
    fn atan(self) -> Self {
        let x = self.re;
        self.chain(x.atan(), 1.0 / (1.0 + x * x))
    }

    /// `atan2(y, x)' = (x y' − y x') / (x² + y²)`, computed with `r = hypot(x, y)` so it
    /// neither overflows nor underflows. At the origin (where `atan2` jumps) the tangent
    /// is zero if both tangents are zero, NaN otherwise.
    #[inline]
    fn atan2(self, other: Self) -> Self {
        let (y, x) = (self, other);
        let value = y.re.atan2(x.re);
        if y.eps == 0.0 && x.eps == 0.0 {
            return Dual::constant(value);
        }
        let r = y.re.hypot(x.re);
        let (c, s) = (x.re / r, y.re / r);
        Dual::new(value, (c * y.eps - s * x.eps) / r)
    }

    #[inline]
    fn sinh(self) -> Self {
        self.chain(self.re.sinh(), self.re.cosh())
    }

    #[inline]
    fn cosh(self) -> Self {
        self.chain(self.re.cosh(), self.re.sinh())
    }

    /// `tanh x' = x' / cosh² x`, which keeps full relative accuracy where `tanh x` is
    /// close to ±1 (unlike `1 − tanh² x`).
    #[inline]
    fn tanh(self) -> Self {
        let sech = 1.0 / self.re.cosh();
        self.chain(self.re.tanh(), sech * sech)
    }

    /// `|x|' = sign(x) x'`; at `x = 0` (either sign of zero) the slope is 0.
    #[inline]
    fn abs(self) -> Self {
        let slope = if self.re > 0.0 {
            1.0
        } else if self.re < 0.0 {
            -1.0
        } else {
            0.0
        };
        self.chain(self.re.abs(), slope)
    }

    /// The value's `f64::signum`, with a zero tangent (also at the jump).
    #[inline]
    fn signum(self) -> Self {
        Dual::constant(self.re.signum())
    }

    /// `(xⁿ)' = n xⁿ⁻¹ x'`; `x⁰` is the constant 1. At `x = 0` with `n < 0` the slope is
    /// infinite (a zero tangent stays zero).
    #[inline]
    fn powi(self, n: i32) -> Self {
        match n {
            0 => Dual::constant(1.0),
            1 => self,
            _ => {
                let value = self.re.powi(n);
                // xⁿ⁻¹ (n = i32::MIN has no n − 1 in i32: xⁿ / x there).
                let below = match n.checked_sub(1) {
                    Some(m) => self.re.powi(m),
                    None => value / self.re,
                };
                let slope = f64::from(n) * below;
                if n > 0 {
                    // Finite wherever x is: no guard needed (and none paid for).
                    self.chain(value, slope)
                } else {
                    self.chain_guarded(value, slope)
                }
            }
        }
    }

    /// `(xʸ)' = y xʸ⁻¹ x' + xʸ ln x · y'`. Each term is taken only when its tangent is
    /// non-zero. The first term is 0 for `y = 0` (`x⁰` is constant); at `x = 0` it is
    /// `y · 0ʸ⁻¹` (0 for `y > 1`, 1 for `y = 1`, ±∞ for `0 < y < 1`). The second term is
    /// 0 where `xʸ = 0` (the limit at `x = 0` for `y > 0`); for `x < 0` it is NaN (`xʸ`
    /// is not real for non-integer `y`).
    #[inline]
    fn powf(self, n: Self) -> Self {
        let (x, y) = (self, n);
        let value = x.re.powf(y.re);
        let mut eps = 0.0;
        if x.eps != 0.0 && y.re != 0.0 {
            eps += y.re * x.re.powf(y.re - 1.0) * x.eps;
        }
        if y.eps != 0.0 && value != 0.0 {
            eps += value * x.re.ln() * y.eps;
        }
        Dual::new(value, eps)
    }

    /// The argument with the smaller value (as `f64::min`, a NaN loses); for equal
    /// values the mean of the two tangents.
    #[inline]
    fn min(self, other: Self) -> Self {
        if self.re < other.re || other.re.is_nan() {
            self
        } else if other.re < self.re || self.re.is_nan() {
            other
        } else {
            Dual::new(self.re.min(other.re), 0.5 * (self.eps + other.eps))
        }
    }

    /// The argument with the larger value (as `f64::max`, a NaN loses); for equal
    /// values the mean of the two tangents.
    #[inline]
    fn max(self, other: Self) -> Self {
        if self.re > other.re || other.re.is_nan() {
            self
        } else if other.re > self.re || self.re.is_nan() {
            other
        } else {
            Dual::new(self.re.max(other.re), 0.5 * (self.eps + other.eps))
        }
    }

    /// `(1/x)' = −x' / x²`.
    #[inline]
    fn recip(self) -> Self {
        let r = self.re.recip();
        self.chain(r, -r * r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_match_f64_bit_for_bit() {
        let x = Dual::new(0.3, 1.0);
        assert_eq!(Scalar::sin(x).re.to_bits(), 0.3f64.sin().to_bits());
        assert_eq!(x.powi(5).re.to_bits(), 0.3f64.powi(5).to_bits());
        assert_eq!(Scalar::tanh(x).re.to_bits(), 0.3f64.tanh().to_bits());
    }

    #[test]
    fn comparison_ignores_the_tangent() {
        assert_eq!(Dual::new(1.0, 2.0), Dual::new(1.0, -3.0));
        assert!(Dual::new(1.0, 5.0) < Dual::new(2.0, 0.0));
    }
}
