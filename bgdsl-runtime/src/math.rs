//! The elementary functions of `f64`, with and without the standard library.
//!
//! `core` has no `sqrt`, `sin`, `exp`, ...: they live in `std`, which calls the
//! platform's maths library. With the `std` feature every function here is the `f64`
//! method of the same name, so a build with `std` computes exactly what it did before
//! this module existed; without it they come from `libm` (a Rust port of musl's maths
//! library), and [`powi`] multiplies by repeated squaring. Everything in the crate that
//! needs one of these functions on `f64` (the [`Scalar`](crate::Scalar) implementation
//! for `f64`, the dual numbers, the integrators) calls it from here, so the two builds
//! differ in this one place.

/// Defines `pub(crate) fn $name(x: f64) -> f64` as `f64::$name` with `std` and as
/// `libm::$libm` without.
macro_rules! unary {
    ($($(#[$doc:meta])* $name:ident => $libm:ident;)*) => {$(
        $(#[$doc])*
        #[inline(always)]
        pub(crate) fn $name(x: f64) -> f64 {
            #[cfg(feature = "std")]
            {
                f64::$name(x)
            }
            #[cfg(not(feature = "std"))]
            {
                libm::$libm(x)
            }
        }
    )*};
}

/// Defines `pub(crate) fn $name(x: f64, y: f64) -> f64` as `f64::$name` with `std` and
/// as `libm::$libm` without.
macro_rules! binary {
    ($($(#[$doc:meta])* $name:ident => $libm:ident;)*) => {$(
        $(#[$doc])*
        #[inline(always)]
        pub(crate) fn $name(x: f64, y: f64) -> f64 {
            #[cfg(feature = "std")]
            {
                f64::$name(x, y)
            }
            #[cfg(not(feature = "std"))]
            {
                libm::$libm(x, y)
            }
        }
    )*};
}

unary! {
    /// Square root.
    sqrt => sqrt;
    /// Cube root.
    cbrt => cbrt;
    /// `e^x`.
    exp => exp;
    /// Natural logarithm.
    ln => log;
    /// Sine.
    sin => sin;
    /// Cosine.
    cos => cos;
    /// Tangent.
    tan => tan;
    /// Arcsine.
    asin => asin;
    /// Arccosine.
    acos => acos;
    /// Arctangent.
    atan => atan;
    /// Hyperbolic sine.
    sinh => sinh;
    /// Hyperbolic cosine.
    cosh => cosh;
    /// Hyperbolic tangent.
    tanh => tanh;
}

binary! {
    /// Four-quadrant arctangent of `x / y` (`x` is the ordinate).
    atan2 => atan2;
    /// `sqrt(x² + y²)` without undue overflow or underflow.
    hypot => hypot;
    /// `x` raised to the real power `y`.
    powf => pow;
}

/// Sine and cosine at once.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    #[cfg(feature = "std")]
    {
        f64::sin_cos(x)
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sincos(x)
    }
}

/// `x` raised to the integer power `n`.
#[inline(always)]
pub(crate) fn powi(x: f64, n: i32) -> f64 {
    #[cfg(feature = "std")]
    {
        f64::powi(x, n)
    }
    #[cfg(not(feature = "std"))]
    {
        powi_by_squaring(x, n)
    }
}

/// `x^n` by binary exponentiation, `1 / x^|n|` for negative `n` (the algorithm of
/// compiler-rt's `__powidf2`, which `f64::powi` calls where the exponent is not a
/// constant): at most `2 log2 |n|` multiplications. `x^0` is 1 for every `x`, NaN
/// included, as with `f64::powi`.
#[cfg(any(not(feature = "std"), test))]
fn powi_by_squaring(x: f64, n: i32) -> f64 {
    let mut base = x;
    let mut exponent = n.unsigned_abs();
    let mut result = 1.0;
    while exponent != 0 {
        if exponent & 1 == 1 {
            result *= base;
        }
        exponent >>= 1;
        if exponent != 0 {
            base *= base;
        }
    }
    if n < 0 {
        1.0 / result
    } else {
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powi_by_squaring_agrees_with_std() {
        let bases = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.3,
            -2.5,
            1.0 + 1e-12,
            7.0,
            1e10,
            1e-10,
        ];
        let powers = [
            0,
            1,
            2,
            3,
            4,
            5,
            7,
            10,
            31,
            -1,
            -2,
            -3,
            -7,
            i32::MAX,
            i32::MIN,
        ];
        for x in bases {
            for n in powers {
                let (mine, std) = (powi_by_squaring(x, n), x.powi(n));
                let close = mine == std
                    || (mine.is_nan() && std.is_nan())
                    || (mine - std).abs() <= 4.0 * f64::EPSILON * std.abs();
                assert!(close, "{x}^{n}: {mine} vs {std}");
            }
        }
        assert_eq!(powi_by_squaring(f64::NAN, 0), 1.0);
        assert!(powi_by_squaring(f64::NAN, 2).is_nan());
        assert_eq!(powi_by_squaring(0.0, -1), f64::INFINITY);
        assert_eq!(powi_by_squaring(-0.0, -1), f64::NEG_INFINITY);
    }
}
