//! Dual numbers seeded in parameters and inputs: exact ∂f/∂p and ∂f/∂u.
//!
//! A [`ParamDual<N>`] is a [`DualN<N>`] whose [`Scalar::parameter`] and
//! [`Scalar::input`] give the parameters and inputs chosen by [`with_seeds`] a tangent
//! (one lane each) and every other one a zero tangent, and whose
//! [`Scalar::PARAMETER_TANGENTS`] is `true`, so that a generated model evaluates its
//! parameter expressions in it rather than lifting the `f64` values it computed once:
//! a parameter that reaches the equations only through such an expression (an inertia
//! computed from a mass) keeps its derivative.
//!
//! Which parameters are seeded is said by a thread-local table rather than by the type,
//! so that the hook's signature stays `fn parameter(value, index) -> Self`, which `f64`
//! and [`Dual`](crate::Dual) implement as the constant they always were (the existing
//! paths do not change by a single instruction). The table is read only by this type.
//!
//! ```
//! use bgdsl_runtime::{param_dual, ParamDual, Scalar};
//!
//! // d(k·x)/dk at k = 3, x = 2: parameter 0 seeded in lane 0.
//! let dk = param_dual::with_seeds(&[0], &[], || {
//!     let k = <ParamDual<1> as Scalar>::parameter(3.0, 0);
//!     let x = ParamDual::<1>::from_f64(2.0);
//!     (k * x).tangents()[0]
//! });
//! assert_eq!(dk, 2.0);
//! ```

use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use std::cell::RefCell;

use crate::dual::DualN;
use crate::scalar::Scalar;

/// The seeded parameter and input indices of every active [`with_seeds`] call, one frame
/// after the other in one buffer (each frame: its parameters, then its inputs), and
/// where the innermost frame starts. Frames are pushed and truncated, so that once the
/// buffer has grown to the largest seeding, seeding allocates nothing (the partials'
/// hot loops seed once per evaluation).
#[derive(Default)]
struct Seeds {
    stack: Vec<usize>,
    frame: Frame,
}

/// Where the innermost seeding lies in [`Seeds::stack`].
#[derive(Clone, Copy, Default)]
struct Frame {
    start: usize,
    parameters: usize,
    inputs: usize,
}

thread_local! {
    static SEEDS: RefCell<Seeds> = RefCell::new(Seeds::default());
}

/// Runs `f` with parameter `parameters[k]` seeded in lane `k` and input `inputs[k]` in
/// lane `parameters.len() + k` of every [`ParamDual`] built by [`Scalar::parameter`]
/// and [`Scalar::input`] on this thread; restores the previous seeding afterwards
/// (also when `f` panics). Indices are those of
/// [`Model::parameter_values`](crate::Model::parameter_values) and
/// [`WithInputs::INPUTS`](crate::WithInputs::INPUTS). Allocates only when the seeding
/// is larger than any before it on this thread.
pub fn with_seeds<R>(parameters: &[usize], inputs: &[usize], f: impl FnOnce() -> R) -> R {
    struct Restore(Frame);
    impl Drop for Restore {
        fn drop(&mut self) {
            SEEDS.with(|seeds| {
                let mut seeds = seeds.borrow_mut();
                let start = seeds.frame.start;
                seeds.stack.truncate(start);
                seeds.frame = self.0;
            });
        }
    }
    let previous = SEEDS.with(|seeds| {
        let mut seeds = seeds.borrow_mut();
        let start = seeds.stack.len();
        seeds.stack.extend_from_slice(parameters);
        seeds.stack.extend_from_slice(inputs);
        let frame = Frame {
            start,
            parameters: parameters.len(),
            inputs: inputs.len(),
        };
        core::mem::replace(&mut seeds.frame, frame)
    });
    let _restore = Restore(previous);
    f()
}

/// The lane seeded for parameter `index` (`inputs == false`) or input `index`, if any.
fn lane(index: usize, inputs: bool) -> Option<usize> {
    SEEDS.with(|seeds| {
        let seeds = seeds.borrow();
        let Frame {
            start,
            parameters,
            inputs: n_inputs,
        } = seeds.frame;
        let seeded = &seeds.stack[start..start + parameters + n_inputs];
        let (params, ins) = seeded.split_at(parameters);
        if inputs {
            Some(parameters + ins.iter().position(|&i| i == index)?)
        } else {
            params.iter().position(|&i| i == index)
        }
    })
}

/// A value with `N` tangents in the parameters and inputs seeded by [`with_seeds`]
/// (see the [module documentation](self)). Arithmetic and elementary functions are
/// [`DualN`]'s, lane by lane, with its conventions at non-differentiable points.
#[derive(Clone, Copy, Debug, Default)]
pub struct ParamDual<const N: usize>(pub DualN<N>);

impl<const N: usize> ParamDual<N> {
    /// The value.
    #[inline]
    pub fn value(&self) -> f64 {
        self.0.value()
    }

    /// The tangents: lane `k` holds the derivative along the `k`-th seeded parameter
    /// or input.
    #[inline]
    pub fn tangents(&self) -> &[f64; N] {
        self.0.tangents()
    }

    fn seeded(value: f64, lane: Option<usize>) -> Self {
        let mut dual = DualN::constant(value);
        if let Some(k) = lane {
            assert!(k < N, "{k} seeds do not fit in ParamDual<{N}>");
            dual.set_tangent(k, 1.0);
        }
        ParamDual(dual)
    }
}

impl<const N: usize> PartialEq for ParamDual<N> {
    /// Equality of the values, as [`DualN`]'s.
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}

impl<const N: usize> PartialOrd for ParamDual<N> {
    /// Ordering of the values, as [`DualN`]'s.
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        self.0.partial_cmp(&other.0)
    }
}

impl<const N: usize> fmt::Display for ParamDual<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl<const N: usize> Neg for ParamDual<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        ParamDual(-self.0)
    }
}

macro_rules! binary_ops {
    ($($op:ident $method:ident $assign:ident $assign_method:ident),*) => {$(
        impl<const N: usize> $op for ParamDual<N> {
            type Output = Self;
            #[inline]
            fn $method(self, rhs: Self) -> Self {
                ParamDual($op::$method(self.0, rhs.0))
            }
        }
        impl<const N: usize> $assign for ParamDual<N> {
            #[inline]
            fn $assign_method(&mut self, rhs: Self) {
                $assign::$assign_method(&mut self.0, rhs.0);
            }
        }
    )*};
}

binary_ops!(
    Add add AddAssign add_assign,
    Sub sub SubAssign sub_assign,
    Mul mul MulAssign mul_assign,
    Div div DivAssign div_assign
);

impl<const N: usize> num_traits::Zero for ParamDual<N> {
    fn zero() -> Self {
        ParamDual(DualN::constant(0.0))
    }
    fn is_zero(&self) -> bool {
        self.0.is_zero()
    }
}

impl<const N: usize> num_traits::One for ParamDual<N> {
    fn one() -> Self {
        ParamDual(DualN::constant(1.0))
    }
}

macro_rules! unary_functions {
    ($($name:ident),*) => {$(
        #[inline]
        fn $name(self) -> Self {
            ParamDual(Scalar::$name(self.0))
        }
    )*};
}

macro_rules! binary_functions {
    ($($name:ident),*) => {$(
        #[inline]
        fn $name(self, other: Self) -> Self {
            ParamDual(Scalar::$name(self.0, other.0))
        }
    )*};
}

impl<const N: usize> Scalar for ParamDual<N> {
    const PARAMETER_TANGENTS: bool = true;

    #[inline]
    fn from_f64(value: f64) -> Self {
        ParamDual(DualN::constant(value))
    }
    fn parameter(value: f64, index: usize) -> Self {
        Self::seeded(value, lane(index, false))
    }
    fn input(value: f64, index: usize) -> Self {
        Self::seeded(value, lane(index, true))
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self.0.value()
    }
    unary_functions!(
        sqrt, cbrt, exp, ln, sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, abs, signum, recip
    );
    binary_functions!(atan2, powf, min, max);
    #[inline]
    fn powi(self, n: i32) -> Self {
        ParamDual(self.0.powi(n))
    }
}

#[cfg(test)]
mod should {
    use super::*;

    #[test]
    fn seed_only_the_chosen_parameters_and_inputs_in_their_lanes() {
        let (p0, p1, u0, p2) = with_seeds(&[2, 0], &[1], || {
            (
                ParamDual::<3>::parameter(1.0, 0),
                ParamDual::<3>::parameter(1.0, 1),
                ParamDual::<3>::input(1.0, 1),
                ParamDual::<3>::parameter(1.0, 2),
            )
        });
        assert_eq!(p0.tangents(), &[0.0, 1.0, 0.0]);
        assert_eq!(p1.tangents(), &[0.0, 0.0, 0.0]);
        assert_eq!(u0.tangents(), &[0.0, 0.0, 1.0]);
        assert_eq!(p2.tangents(), &[1.0, 0.0, 0.0]);
        // Outside `with_seeds`, nothing is seeded.
        assert_eq!(ParamDual::<3>::parameter(1.0, 0).tangents(), &[0.0; 3]);
    }

    #[test]
    fn restore_the_outer_seeding_after_a_nested_one_and_after_a_panic() {
        let lane_of = |p| ParamDual::<2>::parameter(1.0, p).tangents()[0];
        with_seeds(&[3], &[], || {
            with_seeds(&[5, 6], &[3], || {
                assert_eq!(lane_of(5), 1.0);
                assert_eq!(lane_of(3), 0.0);
                assert_eq!(ParamDual::<3>::input(1.0, 3).tangents(), &[0.0, 0.0, 1.0]);
            });
            assert_eq!(lane_of(3), 1.0);
            assert_eq!(lane_of(5), 0.0);
            let caught = std::panic::catch_unwind(|| with_seeds(&[5], &[], || panic!("inside")));
            assert!(caught.is_err());
            assert_eq!(lane_of(3), 1.0);
            assert_eq!(lane_of(5), 0.0);
        });
        assert_eq!(lane_of(3), 0.0);
        SEEDS.with(|seeds| assert!(seeds.borrow().stack.is_empty()));
    }

    #[test]
    fn differentiate_like_dual_numbers() {
        let y = with_seeds(&[0], &[], || {
            let k = ParamDual::<1>::parameter(0.5, 0);
            (k * k).sin()
        });
        assert_eq!(y.value(), 0.25f64.sin());
        assert_eq!(y.tangents()[0], 0.25f64.cos() * 2.0 * 0.5);
    }
}
