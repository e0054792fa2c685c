//! Forward-mode automatic differentiation: a dual number `re + eps·ε` with `ε² = 0`.
//!
//! Evaluating a function on [`Dual`] numbers whose `eps` parts hold a direction `v`
//! yields its value in the `re` parts and its directional derivative `J·v` in the `eps`
//! parts, exact to round-off (no step size, no truncation error). Generated models are
//! generic over [`Scalar`], so [`Model::derivatives`](crate::Model::derivatives) runs on
//! `Dual` unchanged; [`JacobianEvaluator`](crate::JacobianEvaluator) builds Jacobians
//! from that, several directions per evaluation with [`DualN`] (a value with `N`
//! tangents, equal lane by lane to [`Dual`]).
//!
//! # Conventions
//!
//! - **Comparison is by value.** `==`, `<`, … compare `re` only, exactly as the same
//!   code compares `f64`s, so a dual evaluation takes the same branches as the plain
//!   one and its `re` parts equal the `f64` results.
//! - **The value is the `f64` function's.** Every method computes `re` with the
//!   matching method of [`Scalar`] for `f64`, bit for bit (the `f64` method of the same
//!   name; without the `std` feature, `libm`'s function).
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

use crate::math;
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

/// The rules that are the same for one tangent ([`Dual`]) and for N ([`DualN`]): each
/// is the value and the slope of an elementary function, applied by the type's own
/// `chain` (or `chain_guarded`, which keeps a zero tangent zero where the slope is
/// infinite).
macro_rules! chain_rules {
    () => {
        #[inline(always)]
        fn from_f64(value: f64) -> Self {
            Self::constant(value)
        }
        #[inline(always)]
        fn to_f64(self) -> f64 {
            self.re
        }
        /// `√x' = x' / (2√x)`; at `x = 0` the slope is `+∞` (a zero tangent stays zero).
        #[inline]
        fn sqrt(self) -> Self {
            let r = math::sqrt(self.re);
            self.chain_guarded(r, 0.5 / r)
        }
        /// `∛x' = x' / (3 ∛x²)`; at `x = 0` the slope is `+∞` (a zero tangent stays zero).
        #[inline]
        fn cbrt(self) -> Self {
            let r = math::cbrt(self.re);
            self.chain_guarded(r, 1.0 / (3.0 * r * r))
        }
        #[inline]
        fn exp(self) -> Self {
            let e = math::exp(self.re);
            self.chain(e, e)
        }
        /// `ln x' = x' / x` (a zero tangent stays zero at `x = 0`, where the value is −∞).
        #[inline]
        fn ln(self) -> Self {
            self.chain_guarded(math::ln(self.re), 1.0 / self.re)
        }
        #[inline]
        fn sin(self) -> Self {
            let (s, c) = math::sin_cos(self.re);
            self.chain(s, c)
        }
        #[inline]
        fn cos(self) -> Self {
            let (s, c) = math::sin_cos(self.re);
            self.chain(c, -s)
        }
        /// `tan x' = x' (1 + tan² x)`.
        #[inline]
        fn tan(self) -> Self {
            let t = math::tan(self.re);
            self.chain(t, 1.0 + t * t)
        }
        /// `asin x' = x' / √(1 − x²)`; at `x = ±1` the slope is `+∞` (a zero tangent stays
        /// zero).
        #[inline]
        fn asin(self) -> Self {
            let x = self.re;
            self.chain_guarded(math::asin(x), 1.0 / math::sqrt((1.0 - x) * (1.0 + x)))
        }
        /// `acos x' = −x' / √(1 − x²)`; at `x = ±1` the slope is `−∞` (a zero tangent stays
        /// zero).
        #[inline]
        fn acos(self) -> Self {
            let x = self.re;
            self.chain_guarded(math::acos(x), -1.0 / math::sqrt((1.0 - x) * (1.0 + x)))
        }
        /// `atan x' = x' / (1 + x²)`.
        #[inline]
        fn atan(self) -> Self {
            let x = self.re;
            self.chain(math::atan(x), 1.0 / (1.0 + x * x))
        }
        #[inline]
        fn sinh(self) -> Self {
            self.chain(math::sinh(self.re), math::cosh(self.re))
        }
        #[inline]
        fn cosh(self) -> Self {
            self.chain(math::cosh(self.re), math::sinh(self.re))
        }
        /// `tanh x' = x' / cosh² x`, which keeps full relative accuracy where `tanh x` is
        /// close to ±1 (unlike `1 − tanh² x`).
        #[inline]
        fn tanh(self) -> Self {
            let sech = 1.0 / math::cosh(self.re);
            self.chain(math::tanh(self.re), sech * sech)
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
            Self::constant(self.re.signum())
        }
    };
}

impl Scalar for Dual {
    chain_rules!();

    /// `atan2(y, x)' = (x y' − y x') / (x² + y²)`, computed with `r = hypot(x, y)` so it
    /// neither overflows nor underflows. At the origin (where `atan2` jumps) the tangent
    /// is zero if both tangents are zero, NaN otherwise.
    #[inline]
    fn atan2(self, other: Self) -> Self {
        let (y, x) = (self, other);
        let value = math::atan2(y.re, x.re);
        if y.eps == 0.0 && x.eps == 0.0 {
            return Dual::constant(value);
        }
        let r = math::hypot(y.re, x.re);
        let (c, s) = (x.re / r, y.re / r);
        Dual::new(value, (c * y.eps - s * x.eps) / r)
    }

    /// `(xⁿ)' = n xⁿ⁻¹ x'`; `x⁰` is the constant 1. At `x = 0` with `n < 0` the slope is
    /// infinite (a zero tangent stays zero).
    #[inline]
    fn powi(self, n: i32) -> Self {
        match n {
            0 => Dual::constant(1.0),
            1 => self,
            _ => {
                let value = math::powi(self.re, n);
                // xⁿ⁻¹ (n = i32::MIN has no n − 1 in i32: xⁿ / x there).
                let below = match n.checked_sub(1) {
                    Some(m) => math::powi(self.re, m),
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
        let value = math::powf(x.re, y.re);
        let mut eps = 0.0;
        if x.eps != 0.0 && y.re != 0.0 {
            eps += y.re * math::powf(x.re, y.re - 1.0) * x.eps;
        }
        if y.eps != 0.0 && value != 0.0 {
            eps += value * math::ln(x.re) * y.eps;
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

/// A dual number with `N` tangents, `re + sum_k eps_k·ε_k` (`ε_j ε_k = 0`): a value
/// and its derivatives along `N` directions at once.
///
/// One evaluation on `DualN<N>` gives what `N` evaluations on [`Dual`] give, lane by
/// lane, while the value, the branches and the elementary functions are computed once:
/// [`JacobianEvaluator`] evaluates Jacobians `N` colours at a time this way.
///
/// Every tangent is computed with the operations [`Dual`] uses, in the same order,
/// under the same conventions (see the [module documentation](self)): lane `k` equals
/// the [`Dual`] result for the direction of lane `k` bit for bit.
///
/// [`JacobianEvaluator`]: crate::JacobianEvaluator
#[derive(Clone, Copy, Debug)]
pub struct DualN<const N: usize> {
    re: f64,
    eps: [f64; N],
}

impl<const N: usize> Default for DualN<N> {
    fn default() -> Self {
        DualN::constant(0.0)
    }
}

impl<const N: usize> DualN<N> {
    /// The dual number `re + sum_k eps[k]·ε_k`.
    #[inline(always)]
    pub const fn new(re: f64, eps: [f64; N]) -> Self {
        DualN { re, eps }
    }

    /// A constant: all tangents zero.
    #[inline(always)]
    pub const fn constant(re: f64) -> Self {
        DualN { re, eps: [0.0; N] }
    }

    /// The value.
    #[inline(always)]
    pub fn value(&self) -> f64 {
        self.re
    }

    /// The tangents.
    #[inline(always)]
    pub fn tangents(&self) -> &[f64; N] {
        &self.eps
    }

    /// Sets tangent `k` to `eps`.
    ///
    /// # Panics
    /// If `k >= N`.
    #[inline]
    pub fn set_tangent(&mut self, k: usize, eps: f64) {
        self.eps[k] = eps;
    }

    /// Lane `k` as a [`Dual`].
    ///
    /// # Panics
    /// If `k >= N`.
    #[inline(always)]
    pub fn lane(&self, k: usize) -> Dual {
        Dual::new(self.re, self.eps[k])
    }

    /// `value` with tangents `slope · eps_k`: [`Dual`]'s chain rule, lane by lane.
    #[inline(always)]
    fn chain(self, value: f64, slope: f64) -> Self {
        DualN::new(value, lanes(|k| self.eps[k] * slope))
    }

    /// [`Dual`]'s guarded chain rule, lane by lane: a zero tangent stays zero whatever
    /// `slope` is.
    #[inline(always)]
    fn chain_guarded(self, value: f64, slope: f64) -> Self {
        let eps = lanes(|k| {
            let e = self.eps[k];
            if e == 0.0 {
                0.0
            } else {
                e * slope
            }
        });
        DualN::new(value, eps)
    }

    /// `value` with the tangents `(a_k + b_k) / 2` (min and max of equal values).
    #[inline(always)]
    fn mean(self, other: Self, value: f64) -> Self {
        DualN::new(value, lanes(|k| 0.5 * (self.eps[k] + other.eps[k])))
    }
}

/// `[f(0), …, f(N − 1)]`, written out lane by lane for up to 8 lanes (the widths the
/// Jacobians use): straight-line code for LLVM, where a loop in every arithmetic
/// operation of a generated model costs it a loop to unroll at each one (the build of
/// large models, `docs/large-models.md`). Each lane computes what the loop computed.
#[inline(always)]
fn lanes<const N: usize>(mut f: impl FnMut(usize) -> f64) -> [f64; N] {
    let mut out = [0.0; N];
    if N > 8 {
        for (k, o) in out.iter_mut().enumerate() {
            *o = f(k);
        }
    } else {
        macro_rules! written_out {
            ($($k:literal)*) => {$(
                if $k < N {
                    out[$k] = f($k);
                }
            )*};
        }
        written_out!(0 1 2 3 4 5 6 7);
    }
    out
}

impl<const N: usize> From<f64> for DualN<N> {
    /// A constant.
    #[inline(always)]
    fn from(re: f64) -> Self {
        DualN::constant(re)
    }
}

impl<const N: usize> PartialEq for DualN<N> {
    /// Equality of the values, as for [`Dual`].
    #[inline(always)]
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

impl<const N: usize> PartialOrd for DualN<N> {
    /// Ordering of the values.
    #[inline(always)]
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<const N: usize> fmt::Display for DualN<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.re)?;
        for (k, e) in self.eps.iter().enumerate() {
            write!(f, " + {e}ε{k}")?;
        }
        Ok(())
    }
}

impl<const N: usize> Neg for DualN<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        DualN::new(-self.re, lanes(|k| -self.eps[k]))
    }
}

impl<const N: usize> Add for DualN<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, rhs: Self) -> Self {
        DualN::new(self.re + rhs.re, lanes(|k| self.eps[k] + rhs.eps[k]))
    }
}

impl<const N: usize> Sub for DualN<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, rhs: Self) -> Self {
        DualN::new(self.re - rhs.re, lanes(|k| self.eps[k] - rhs.eps[k]))
    }
}

impl<const N: usize> Mul for DualN<N> {
    type Output = Self;
    // The product rule adds: not a misplaced `+`.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn mul(self, rhs: Self) -> Self {
        let (x, y) = (self.re, rhs.re);
        DualN::new(x * y, lanes(|k| self.eps[k] * y + x * rhs.eps[k]))
    }
}

impl<const N: usize> Div for DualN<N> {
    type Output = Self;
    /// As [`Dual`]: `(a/b)' = (a' − (a/b)·b') / b`.
    // The quotient rule subtracts and multiplies: not misplaced operators.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn div(self, rhs: Self) -> Self {
        let q = self.re / rhs.re;
        let d = rhs.re;
        DualN::new(q, lanes(|k| (self.eps[k] - q * rhs.eps[k]) / d))
    }
}

impl<const N: usize> AddAssign for DualN<N> {
    #[inline(always)]
    fn add_assign(&mut self, rhs: Self) {
        *self = *self + rhs;
    }
}

impl<const N: usize> SubAssign for DualN<N> {
    #[inline(always)]
    fn sub_assign(&mut self, rhs: Self) {
        *self = *self - rhs;
    }
}

impl<const N: usize> MulAssign for DualN<N> {
    #[inline(always)]
    fn mul_assign(&mut self, rhs: Self) {
        *self = *self * rhs;
    }
}

impl<const N: usize> DivAssign for DualN<N> {
    #[inline(always)]
    fn div_assign(&mut self, rhs: Self) {
        *self = *self / rhs;
    }
}

impl<const N: usize> num_traits::Zero for DualN<N> {
    #[inline(always)]
    fn zero() -> Self {
        DualN::constant(0.0)
    }
    #[inline]
    fn is_zero(&self) -> bool {
        self.re == 0.0 && self.eps.iter().all(|&e| e == 0.0)
    }
}

impl<const N: usize> num_traits::One for DualN<N> {
    #[inline(always)]
    fn one() -> Self {
        DualN::constant(1.0)
    }
}

/// Every method computes what [`Dual`]'s does, lane by lane (see [`DualN`] and the
/// [module documentation](self) for the conventions).
impl<const N: usize> Scalar for DualN<N> {
    chain_rules!();

    /// As [`Dual`]'s: a lane whose two tangents are zero gets a zero tangent (also at
    /// the origin).
    #[inline]
    fn atan2(self, other: Self) -> Self {
        let (y, x) = (self, other);
        let value = math::atan2(y.re, x.re);
        let r = math::hypot(y.re, x.re);
        let (c, s) = (x.re / r, y.re / r);
        let mut eps = y.eps;
        for (e, xe) in eps.iter_mut().zip(&x.eps) {
            *e = if *e == 0.0 && *xe == 0.0 {
                0.0
            } else {
                (c * *e - s * xe) / r
            };
        }
        DualN::new(value, eps)
    }

    #[inline]
    fn powi(self, n: i32) -> Self {
        match n {
            0 => DualN::constant(1.0),
            1 => self,
            _ => {
                let value = math::powi(self.re, n);
                let below = match n.checked_sub(1) {
                    Some(m) => math::powi(self.re, m),
                    None => value / self.re,
                };
                let slope = f64::from(n) * below;
                if n > 0 {
                    self.chain(value, slope)
                } else {
                    self.chain_guarded(value, slope)
                }
            }
        }
    }

    /// As [`Dual`]'s: each of the two terms is taken only where its tangent is
    /// non-zero.
    #[inline]
    fn powf(self, n: Self) -> Self {
        let (x, y) = (self, n);
        let value = math::powf(x.re, y.re);
        let d_base = if y.re != 0.0 {
            y.re * math::powf(x.re, y.re - 1.0)
        } else {
            0.0
        };
        let d_exp = if value != 0.0 {
            value * math::ln(x.re)
        } else {
            0.0
        };
        let mut eps = [0.0; N];
        for ((e, xe), ye) in eps.iter_mut().zip(&x.eps).zip(&y.eps) {
            if *xe != 0.0 && y.re != 0.0 {
                *e += d_base * xe;
            }
            if *ye != 0.0 && value != 0.0 {
                *e += d_exp * ye;
            }
        }
        DualN::new(value, eps)
    }

    #[inline]
    fn min(self, other: Self) -> Self {
        if self.re < other.re || other.re.is_nan() {
            self
        } else if other.re < self.re || self.re.is_nan() {
            other
        } else {
            self.mean(other, self.re.min(other.re))
        }
    }

    #[inline]
    fn max(self, other: Self) -> Self {
        if self.re > other.re || other.re.is_nan() {
            self
        } else if other.re > self.re || self.re.is_nan() {
            other
        } else {
            self.mean(other, self.re.max(other.re))
        }
    }

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
        assert_eq!(DualN::new(1.0, [2.0, 0.0]), DualN::new(1.0, [-3.0, 1.0]));
    }

    /// Tangent lanes with zeros among them (the guarded rules must keep those zero).
    const LANES: [f64; 4] = [1.0, 0.0, -2.5, 0.75];

    /// Bit equality, with every NaN equal to every NaN.
    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    /// `DualN` gives, lane by lane, what `Dual` gives, bit for bit.
    fn check_lanes(name: &str, got: DualN<4>, want: impl Fn(usize) -> Dual) {
        for (k, &eps) in got.tangents().iter().enumerate() {
            let w = want(k);
            assert!(
                same(got.value(), w.re) && same(eps, w.eps),
                "{name}, lane {k}: {got} against {w}"
            );
        }
    }

    #[test]
    fn every_method_equals_dual_lane_by_lane() {
        type Unary = (&'static str, fn(DualN<4>) -> DualN<4>, fn(Dual) -> Dual);
        let unary: [Unary; 21] = [
            ("neg", |x| -x, |x| -x),
            ("sqrt", Scalar::sqrt, Scalar::sqrt),
            ("cbrt", Scalar::cbrt, Scalar::cbrt),
            ("exp", Scalar::exp, Scalar::exp),
            ("ln", Scalar::ln, Scalar::ln),
            ("sin", Scalar::sin, Scalar::sin),
            ("cos", Scalar::cos, Scalar::cos),
            ("tan", Scalar::tan, Scalar::tan),
            ("asin", Scalar::asin, Scalar::asin),
            ("acos", Scalar::acos, Scalar::acos),
            ("atan", Scalar::atan, Scalar::atan),
            ("sinh", Scalar::sinh, Scalar::sinh),
            ("cosh", Scalar::cosh, Scalar::cosh),
            ("tanh", Scalar::tanh, Scalar::tanh),
            ("abs", Scalar::abs, Scalar::abs),
            ("signum", Scalar::signum, Scalar::signum),
            ("powi(3)", |x| x.powi(3), |x| x.powi(3)),
            ("powi(-2)", |x| x.powi(-2), |x| x.powi(-2)),
            ("powi(0)", |x| x.powi(0), |x| x.powi(0)),
            ("powi(1)", |x| x.powi(1), |x| x.powi(1)),
            ("recip", Scalar::recip, Scalar::recip),
        ];
        // Ordinary points and the special ones of the conventions.
        let points = [0.3, -1.7, 0.0, -0.0, 1.0, -1.0, 2.5, 1e-300];
        for (name, f, g) in unary {
            for x in points {
                let got = f(DualN::new(x, LANES));
                check_lanes(name, got, |k| g(Dual::new(x, LANES[k])));
            }
        }
        type Binary = (
            &'static str,
            fn(DualN<4>, DualN<4>) -> DualN<4>,
            fn(Dual, Dual) -> Dual,
        );
        let binary: [Binary; 8] = [
            ("add", |a, b| a + b, |a, b| a + b),
            ("sub", |a, b| a - b, |a, b| a - b),
            ("mul", |a, b| a * b, |a, b| a * b),
            ("div", |a, b| a / b, |a, b| a / b),
            ("atan2", Scalar::atan2, Scalar::atan2),
            ("powf", Scalar::powf, Scalar::powf),
            ("min", Scalar::min, Scalar::min),
            ("max", Scalar::max, Scalar::max),
        ];
        let other = [0.0, 0.5, 2.0, -1.0, 1.5];
        let other_lanes = [0.0, 2.0, 0.0, -1.0];
        for (name, f, g) in binary {
            for x in points {
                for y in other {
                    let got = f(DualN::new(x, LANES), DualN::new(y, other_lanes));
                    check_lanes(name, got, |k| {
                        g(Dual::new(x, LANES[k]), Dual::new(y, other_lanes[k]))
                    });
                }
            }
        }
        // Assignment operators and the constants.
        let mut a = DualN::new(0.7, LANES);
        a += DualN::new(0.1, [1.0; 4]);
        a -= DualN::constant(0.2);
        a *= DualN::new(3.0, [0.5; 4]);
        a /= DualN::new(1.5, [0.0, 1.0, 0.0, 1.0]);
        check_lanes("assign", a, |k| {
            let mut b = Dual::new(0.7, LANES[k]);
            b += Dual::new(0.1, 1.0);
            b -= Dual::constant(0.2);
            b *= Dual::new(3.0, 0.5);
            b /= Dual::new(1.5, [0.0, 1.0, 0.0, 1.0][k]);
            b
        });
        use num_traits::{One, Zero};
        assert!(DualN::<4>::zero().is_zero() && !DualN::new(0.0, LANES).is_zero());
        assert_eq!(DualN::<4>::one().value(), 1.0);
        assert_eq!(DualN::<4>::from_f64(2.0).lane(3), Dual::constant(2.0));
    }

    /// The arithmetic of width `N` against [`Dual`], lane by lane, bit for bit.
    fn arithmetic_matches_dual<const N: usize>() {
        let lane = |k: usize, scale: f64| [1.0, 0.0, -2.5, 0.75, 3.0][k % 5] * scale + k as f64;
        let (a, b) = (
            DualN::new(0.7, core::array::from_fn::<f64, N, _>(|k| lane(k, 1.0))),
            DualN::new(-1.3, core::array::from_fn::<f64, N, _>(|k| lane(k, -0.5))),
        );
        let results = [
            -a,
            a + b,
            a - b,
            a * b,
            a / b,
            a.sqrt(),
            a.powi(-2),
            a.min(a),
            b.abs(),
        ];
        for (op, got) in results.iter().enumerate() {
            for k in 0..N {
                let (x, y) = (a.lane(k), b.lane(k));
                let want = [
                    -x,
                    x + y,
                    x - y,
                    x * y,
                    x / y,
                    x.sqrt(),
                    x.powi(-2),
                    x.min(x),
                    y.abs(),
                ];
                assert!(
                    same(got.value(), want[op].re) && same(got.tangents()[k], want[op].eps),
                    "width {N}, operation {op}, lane {k}: {got} against {}",
                    want[op]
                );
            }
        }
    }

    /// The lanes written out (up to 8) and the loop beyond compute every lane, none
    /// left at zero or taken from a neighbour, at the widths around the boundary.
    #[test]
    fn every_width_equals_dual_lane_by_lane() {
        arithmetic_matches_dual::<1>();
        arithmetic_matches_dual::<3>();
        arithmetic_matches_dual::<7>();
        arithmetic_matches_dual::<8>();
        arithmetic_matches_dual::<9>();
        arithmetic_matches_dual::<12>();
    }
}
