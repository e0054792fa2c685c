//! Forward-mode AD and the compressed Jacobian evaluator on hand-written models:
//!
//! - every [`Scalar`] method of [`Dual`] against a central finite difference, plus
//!   exact cases and the documented conventions at non-differentiable points;
//! - the greedy column colouring on patterns whose optimum is known by hand;
//! - [`JacobianEvaluator`] on a 120-state stiff chain (compressed = dense bit for bit,
//!   = finite differences to 1e-6, inside the declared pattern, 5 colours), on a model
//!   with a hand-written Jacobian (used: zero evaluations) and on malformed patterns.

#[path = "support/chain.rs"]
mod chain;

use bgdsl_runtime::{
    Colouring, Dual, Jacobian, JacobianEvaluator, Model, Scalar, SparsityError, SparsityPattern,
};
use chain::Chain;

/// SplitMix64: a small seeded generator, so every run tests the same points.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
}

/// The finite-difference step for a value of typical magnitude `scale` at `x`:
/// `ε^(1/3)` relative. A central difference errs by `h² |f'''| / 6` (truncation) plus
/// about `ε |f| / h` (round-off); `h ∝ ε^(1/3)` balances the two at `~ε^(2/3) ≈ 4e-11`
/// of the function's scale, four orders of magnitude inside the tolerances below.
fn step(x: f64, scale: f64) -> f64 {
    f64::EPSILON.cbrt() * x.abs().max(scale)
}

/// Central difference of `f` at `x`, with the step actually taken (after rounding of
/// `x ± h`) as the divisor. The step is relative to `|x|` (1 at 0): the elementary
/// functions vary on the scale of their argument (`ln` at 0.01 does, on 0.01).
fn central(f: impl Fn(f64) -> f64, x: f64) -> f64 {
    let h = step(x, if x == 0.0 { 1.0 } else { f64::MIN_POSITIVE });
    let (above, below) = (x + h, x - h);
    (f(above) - f(below)) / (above - below)
}

mod dual_arithmetic {
    use super::*;

    /// Checks `f` at each point: the dual value equals the `f64` value bit for bit and
    /// the dual derivative equals the central difference to 1e-7 relative.
    fn check_unary(name: &str, f: impl Fn(f64) -> f64, g: impl Fn(Dual) -> Dual, points: &[f64]) {
        for &x in points {
            let d = g(Dual::variable(x));
            assert_eq!(
                d.re.to_bits(),
                f(x).to_bits(),
                "{name} at {x}: value {} differs from f64 {}",
                d.re,
                f(x)
            );
            let fd = central(&f, x);
            assert!(
                (d.eps - fd).abs() <= 1e-7 * d.eps.abs(),
                "{name} at {x}: AD {} vs central difference {fd}",
                d.eps
            );
        }
    }

    /// As `check_unary` for a function of two arguments, each partial derivative in
    /// turn.
    fn check_binary(
        name: &str,
        f: impl Fn(f64, f64) -> f64,
        g: impl Fn(Dual, Dual) -> Dual,
        points: &[(f64, f64)],
    ) {
        for &(a, b) in points {
            let da = g(Dual::variable(a), Dual::constant(b));
            let db = g(Dual::constant(a), Dual::variable(b));
            assert_eq!(
                da.re.to_bits(),
                f(a, b).to_bits(),
                "{name} at ({a}, {b}): value"
            );
            assert_eq!(
                db.re.to_bits(),
                f(a, b).to_bits(),
                "{name} at ({a}, {b}): value"
            );
            let fa = central(|a| f(a, b), a);
            let fb = central(|b| f(a, b), b);
            assert!(
                (da.eps - fa).abs() <= 1e-7 * da.eps.abs(),
                "{name} at ({a}, {b}): ∂/∂a AD {} vs central difference {fa}",
                da.eps
            );
            assert!(
                (db.eps - fb).abs() <= 1e-7 * db.eps.abs(),
                "{name} at ({a}, {b}): ∂/∂b AD {} vs central difference {fb}",
                db.eps
            );
        }
    }

    /// `unary!(name, |x| expr, points)`: the same expression on `f64` and on `Dual`
    /// (methods resolve to `f64`'s inherent ones and to `Scalar`'s respectively).
    macro_rules! unary {
        ($name:literal, |$x:ident| $e:expr, $points:expr) => {
            check_unary($name, |$x: f64| $e, |$x: Dual| $e, &$points)
        };
    }

    macro_rules! binary {
        ($name:literal, |$a:ident, $b:ident| $e:expr, $points:expr) => {
            check_binary(
                $name,
                |$a: f64, $b: f64| $e,
                |$a: Dual, $b: Dual| $e,
                &$points,
            )
        };
    }

    /// The constant `v`, of the same type as `_like` (`f64` has several `Add`
    /// implementations, so the type cannot be left to inference).
    fn c<T: Scalar>(_like: T, v: f64) -> T {
        T::from_f64(v)
    }

    #[test]
    fn field_operations_match_central_differences() {
        unary!("neg", |x| -x, [-2.0, 0.5, 3.0]);
        unary!("add constant", |x| x + c(x, 3.0), [-2.0, 0.5]);
        unary!("square", |x| x * x, [-2.0, 0.5, 3.0]);
        unary!("cube", |x| x * x * x, [-2.0, 0.5, 3.0]);
        unary!(
            "reciprocal by division",
            |x| c(x, 1.0) / x,
            [-4.0, 0.3, 7.0]
        );
        unary!("rational", |x| x / (c(x, 1.0) + x * x), [-4.0, 0.3, 7.0]);
        unary!(
            "compound assignment",
            |x| {
                let mut r = x;
                r += c(x, 2.0);
                r *= x;
                r -= c(x, 0.5) * x;
                r /= x + c(x, 10.0);
                r
            },
            [-2.0, 0.7, 5.0]
        );
        binary!("add", |a, b| a + b, [(1.0, 2.0), (-3.0, 0.5)]);
        binary!("sub", |a, b| a - b, [(1.0, 2.0), (-3.0, 0.5)]);
        binary!("mul", |a, b| a * b, [(1.5, 2.0), (-3.0, 0.5)]);
        binary!("div", |a, b| a / b, [(1.5, 2.0), (-3.0, 0.5), (7.0, -0.1)]);
    }

    #[test]
    fn elementary_functions_match_central_differences() {
        unary!("sqrt", |x| x.sqrt(), [0.3, 2.0, 1.0e4]);
        unary!("cbrt", |x| x.cbrt(), [-8.5, 0.3, 2.0, 1.0e3]);
        unary!("exp", |x| x.exp(), [-3.0, 0.5, 5.0]);
        unary!("ln", |x| x.ln(), [0.01, 1.5, 1.0e3]);
        unary!("sin", |x| x.sin(), [-2.0, 0.3, 1.0, 10.0]);
        unary!("cos", |x| x.cos(), [-2.0, 0.3, 1.0, 10.0]);
        unary!("tan", |x| x.tan(), [-1.0, 0.3, 1.2]);
        unary!("asin", |x| x.asin(), [-0.9, 0.2, 0.7]);
        unary!("acos", |x| x.acos(), [-0.9, 0.2, 0.7]);
        unary!("atan", |x| x.atan(), [-3.0, 0.2, 10.0]);
        unary!("sinh", |x| x.sinh(), [-2.0, 0.5, 3.0]);
        unary!("cosh", |x| x.cosh(), [-2.0, 0.5, 3.0]);
        unary!("tanh", |x| x.tanh(), [-3.0, 0.1, 1.0, 4.0]);
        unary!("abs", |x| x.abs(), [-2.5, 0.7]);
        unary!("recip", |x| x.recip(), [-4.0, 0.3, 7.0]);
        for n in [-3, -1, 2, 3, 7] {
            unary!("powi", |x| x.powi(n), [-1.3, 0.4, 2.5]);
        }
        unary!(
            "powf constant exponent",
            |x| x.powf(c(x, 2.5)),
            [0.3, 1.7, 40.0]
        );
        unary!(
            "powf negative exponent",
            |x| x.powf(c(x, -0.7)),
            [0.3, 1.7, 40.0]
        );
        unary!(
            "composite",
            |x| (x.sin() * (-x).exp()) / (c(x, 1.0) + x * x).sqrt(),
            [-1.0, 0.4, 2.0]
        );
        binary!(
            "atan2",
            |y, x| y.atan2(x),
            [
                (1.0, 2.0),
                (1.0, -2.0),
                (-1.0, -2.0),
                (-0.5, 3.0),
                (1.0e-3, 5.0e-4)
            ]
        );
        binary!(
            "powf",
            |x, y| x.powf(y),
            [(0.3, 2.5), (1.7, -0.7), (4.0, 0.5)]
        );
        binary!("min", |a, b| a.min(b), [(1.0, 2.0), (3.0, -1.0)]);
        binary!("max", |a, b| a.max(b), [(1.0, 2.0), (3.0, -1.0)]);
    }

    /// Away from 0, where the derivative of these is exactly 0 and so is the central
    /// difference.
    #[test]
    fn piecewise_constant_parts_have_zero_derivative() {
        for x in [-2.0, 3.0] {
            let s = Dual::variable(x).signum();
            assert_eq!((s.re, s.eps), (x.signum(), 0.0));
        }
        let m = Dual::variable(0.5).max(Dual::constant(1.0));
        assert_eq!((m.re, m.eps), (1.0, 0.0));
        let p = Dual::variable(0.5).powi(0);
        assert_eq!((p.re, p.eps), (1.0, 0.0));
    }

    #[test]
    fn exact_cases_are_exact() {
        for x in [-3.7, 0.0, 1.7, 1.0e10] {
            let v = Dual::variable(x);
            assert_eq!((v * v).eps, 2.0 * x, "d/dx x·x at {x}");
            assert_eq!(v.powi(2).eps, 2.0 * x, "d/dx x² at {x}");
            assert_eq!(v.powi(3).eps, 3.0 * (x * x), "d/dx x³ at {x}");
            assert_eq!((c(v, 3.0) * v + c(v, 1.0)).eps, 3.0, "d/dx (3x + 1) at {x}");
            assert_eq!((-v).eps, -1.0);
        }
        let x = Dual::variable(2.5);
        assert_eq!((x / x).eps, 0.0, "d/dx x/x");
        assert_eq!((x - x).eps, 0.0, "d/dx (x − x)");
        assert_eq!(Dual::variable(0.0).sin().eps, 1.0, "sin'(0)");
        assert_eq!(Dual::variable(0.0).exp().eps, 1.0, "exp'(0)");
        assert_eq!(Dual::variable(4.0).sqrt().eps, 0.25, "sqrt'(4)");
        assert_eq!(Dual::variable(2.0).recip().eps, -0.25, "(1/x)' at 2");
        assert_eq!(Dual::new(2.0, 3.0).powi(2).eps, 12.0, "chain rule: 2·2·3");
    }

    #[test]
    fn a_zero_tangent_stays_zero_where_the_slope_is_infinite() {
        let zero = Dual::constant(0.0);
        let one = Dual::constant(1.0);
        for (name, d) in [
            ("sqrt(0)", zero.sqrt()),
            ("cbrt(0)", zero.cbrt()),
            ("ln(0)", zero.ln()),
            ("asin(1)", one.asin()),
            ("acos(1)", one.acos()),
            ("asin(-1)", (-one).asin()),
            ("powi(0, -1)", zero.powi(-1)),
            ("powf(0, 0.5)", zero.powf(Dual::constant(0.5))),
            ("atan2(0, 0)", zero.atan2(zero)),
            ("abs(0)", zero.abs()),
        ] {
            assert_eq!(d.eps, 0.0, "{name}: tangent {}", d.eps);
        }
    }

    #[test]
    fn a_non_zero_tangent_gives_the_one_sided_limit_where_the_slope_is_infinite() {
        let x = Dual::variable(0.0);
        assert_eq!(x.sqrt().eps, f64::INFINITY);
        assert_eq!(x.cbrt().eps, f64::INFINITY);
        assert_eq!(Dual::variable(1.0).asin().eps, f64::INFINITY);
        assert_eq!(Dual::variable(1.0).acos().eps, f64::NEG_INFINITY);
        assert_eq!(x.powf(Dual::constant(0.5)).eps, f64::INFINITY);
        assert!(
            x.atan2(Dual::constant(0.0)).eps.is_nan(),
            "atan2 jumps at the origin"
        );
    }

    #[test]
    fn kinks_take_the_midpoint_of_the_one_sided_derivatives() {
        for zero in [0.0, -0.0] {
            let x = Dual::variable(zero);
            assert_eq!(x.abs().eps, 0.0, "abs at {zero:?}");
            let s = x.signum();
            assert_eq!((s.re, s.eps), (zero.signum(), 0.0), "signum at {zero:?}");
        }
        let a = Dual::new(1.0, 3.0);
        let b = Dual::new(1.0, 1.0);
        assert_eq!(a.max(b).eps, 2.0);
        assert_eq!(a.min(b).eps, 2.0);
        assert_eq!(a.max(a).eps, 3.0, "x.max(x) has x's tangent");
        let x = Dual::variable(0.0);
        assert_eq!(x.max(-x).eps, 0.0, "x.max(−x) at 0 is abs");
        // As `f64::min`/`max`: a NaN loses.
        let nan = Dual::new(f64::NAN, 7.0);
        assert_eq!(nan.max(a).eps, 3.0);
        assert_eq!(a.min(nan).eps, 3.0);
    }

    #[test]
    fn zero_powers_and_zero_bases_follow_the_documented_rules() {
        let zero = Dual::variable(0.0);
        assert_eq!(zero.powi(0).eps, 0.0, "x⁰ is constant, also at 0");
        assert_eq!(zero.powf(Dual::constant(0.0)).eps, 0.0, "x^0.0 is constant");
        assert_eq!(zero.powi(2).eps, 0.0);
        assert_eq!(zero.powf(Dual::constant(2.0)).eps, 0.0);
        assert_eq!(zero.powf(Dual::constant(1.0)).eps, 1.0);
        // ∂/∂y 0^y = 0 for y > 0 (0^y ≡ 0), not 0·ln 0 = NaN.
        assert_eq!(Dual::constant(0.0).powf(Dual::variable(2.0)).eps, 0.0);
        // i32::MIN has no n − 1: xⁿ / x is used.
        let big = Dual::variable(1.0).powi(i32::MIN);
        assert_eq!((big.re, big.eps), (1.0, f64::from(i32::MIN)));
    }

    #[test]
    fn comparison_is_by_value() {
        assert_eq!(Dual::new(1.0, 2.0), Dual::new(1.0, -5.0));
        assert!(Dual::new(1.0, 9.0) < Dual::new(2.0, 0.0));
        assert!(Dual::new(f64::NAN, 0.0) != Dual::new(f64::NAN, 0.0));
        assert_eq!(Dual::from(2.5), Dual::constant(2.5));
        assert_eq!(Dual::from(2.5).eps, 0.0);
        assert_eq!(Scalar::to_f64(Dual::new(2.5, 1.0)), 2.5);
    }
}

mod colouring {
    use super::*;

    fn pattern(rows: &[Vec<usize>]) -> SparsityPattern {
        SparsityPattern::from_rows(rows).expect("a valid pattern")
    }

    /// Rows `i − w ..= i + w`, clipped.
    fn band(n: usize, w: usize) -> SparsityPattern {
        pattern(
            &(0..n)
                .map(|i| (i.saturating_sub(w)..(i + w + 1).min(n)).collect())
                .collect::<Vec<_>>(),
        )
    }

    /// No two columns of a colour share a row, every column has a colour, and each
    /// column's colour is the smallest its earlier neighbours leave free (first fit).
    fn assert_valid_greedy(p: &SparsityPattern, c: &Colouring) {
        let n = p.n();
        let mut seen = vec![false; n];
        for colour in 0..c.n_colours() {
            let mut used_rows = vec![false; n];
            let columns = c.columns(colour);
            assert!(!columns.is_empty(), "colour {colour} is empty");
            assert!(columns.windows(2).all(|w| w[0] < w[1]));
            for &j in columns {
                assert_eq!(c.colour_of(j), colour);
                assert!(!seen[j], "column {j} coloured twice");
                seen[j] = true;
                for i in (0..n).filter(|&i| p.contains(i, j)) {
                    assert!(!used_rows[i], "colour {colour} has two columns in row {i}");
                    used_rows[i] = true;
                }
            }
        }
        assert!(seen.iter().all(|&s| s), "a column has no colour");
        let shares_row = |j: usize, k: usize| (0..n).any(|i| p.contains(i, j) && p.contains(i, k));
        for j in 0..n {
            for lower in 0..c.colour_of(j) {
                assert!(
                    (0..j).any(|k| c.colour_of(k) == lower && shares_row(j, k)),
                    "column {j} could have had colour {lower}"
                );
            }
        }
    }

    #[test]
    fn columns_sharing_no_row_get_one_colour() {
        let diagonal = pattern(&(0..6).map(|i| vec![i]).collect::<Vec<_>>());
        let c = Colouring::greedy(&diagonal);
        assert_eq!(c.n_colours(), 1);
        assert_eq!(c.columns(0), &[0, 1, 2, 3, 4, 5]);
        assert_valid_greedy(&diagonal, &c);
    }

    #[test]
    fn dense_patterns_need_one_colour_per_column() {
        let c = Colouring::greedy(&SparsityPattern::dense(7));
        assert_eq!(c.n_colours(), 7);
        assert_valid_greedy(&SparsityPattern::dense(7), &c);
        // A pattern with one full row is as good as dense.
        let arrow = pattern(&[vec![0, 1, 2, 3], vec![0, 1], vec![0, 2], vec![0, 3]]);
        let c = Colouring::greedy(&arrow);
        assert_eq!(c.n_colours(), 4);
        assert_valid_greedy(&arrow, &c);
    }

    /// Columns `j` and `k` of a full band of half-width `w` share a row exactly when
    /// `|j − k| ≤ 2w`: at least `2w + 1` colours, and first fit gives `j mod (2w + 1)`.
    #[test]
    fn banded_patterns_get_the_optimal_two_w_plus_one_colours() {
        for (n, w) in [(10, 1), (40, 2), (9, 3), (3, 2)] {
            let p = band(n, w);
            let c = Colouring::greedy(&p);
            assert_eq!(c.n_colours(), (2 * w + 1).min(n), "n = {n}, w = {w}");
            for j in 0..n {
                assert_eq!(c.colour_of(j), j % (2 * w + 1));
            }
            assert_valid_greedy(&p, &c);
        }
    }

    #[test]
    fn columns_no_row_depends_on_get_colour_zero() {
        let p = pattern(&[vec![0, 2], vec![0, 2], vec![], vec![2]]);
        let c = Colouring::greedy(&p);
        assert_eq!((c.n_colours(), c.colour_of(1), c.colour_of(3)), (2, 0, 0));
        assert_valid_greedy(&p, &c);
        assert_eq!(Colouring::greedy(&SparsityPattern::dense(0)).n_colours(), 0);
    }

    #[test]
    fn random_patterns_are_validly_and_deterministically_coloured() {
        let mut rng = Rng(7);
        for _ in 0..50 {
            let n = 1 + (rng.next_u64() % 30) as usize;
            let density = rng.uniform(0.0, 0.4);
            let rows: Vec<Vec<usize>> = (0..n)
                .map(|_| (0..n).filter(|_| rng.uniform(0.0, 1.0) < density).collect())
                .collect();
            let p = pattern(&rows);
            let c = Colouring::greedy(&p);
            assert_valid_greedy(&p, &c);
            assert_eq!(c, Colouring::greedy(&p.clone()));
            let longest = rows.iter().map(Vec::len).max().unwrap_or(0);
            assert!(c.n_colours() >= longest.max(1).min(n));
        }
    }

    #[test]
    fn malformed_patterns_are_rejected_with_the_place() {
        assert_eq!(
            SparsityPattern::from_rows(&[vec![0, 2], vec![1]]),
            Err(SparsityError::ColumnOutOfRange {
                row: 0,
                column: 2,
                n: 2
            })
        );
        assert_eq!(
            SparsityPattern::from_rows(&[vec![0, 1], vec![1, 1]]),
            Err(SparsityError::NotIncreasing {
                row: 1,
                position: 1
            })
        );
        assert_eq!(
            SparsityPattern::from_rows(&[vec![1, 0], vec![1]]),
            Err(SparsityError::NotIncreasing {
                row: 0,
                position: 1
            })
        );
        assert_eq!(
            SparsityPattern::for_model::<WrongRowCount>(),
            Err(SparsityError::WrongRowCount {
                expected: 2,
                found: 1
            })
        );
        let message = SparsityError::WrongRowCount {
            expected: 2,
            found: 1,
        }
        .to_string();
        assert!(
            message.contains("expected one row per state (2), found 1"),
            "{message}"
        );
    }

    #[test]
    fn pattern_accessors() {
        let p = pattern(&[vec![0, 2], vec![], vec![1, 2]]);
        assert_eq!((p.n(), p.nnz(), p.is_dense()), (3, 4, false));
        assert_eq!(p.row(2), &[1, 2]);
        assert!(p.contains(0, 2) && !p.contains(0, 1) && !p.contains(1, 1));
        let d = SparsityPattern::dense(3);
        assert_eq!((d.nnz(), d.row(1)), (9, &[0usize, 1, 2][..]));
        assert!(d.includes(&p) && !p.includes(&d) && p.includes(&p));
        assert!(!p.includes(&pattern(&[vec![0], vec![1], vec![2]])));
    }
}

/// A model whose declared pattern has the wrong number of rows.
struct WrongRowCount;

impl Model for WrongRowCount {
    type Params = ();
    const NAME: &'static str = "wrong_row_count";
    const STATE_NAMES: &'static [&'static str] = &["a", "b"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&[&[0, 1]]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[0] * x[1];
        dx[1] = x[1];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// Robertson's stiff chemical kinetics, with its Jacobian written by hand when
/// `hand_written` is set (and a declared pattern: rows 0 and 1 read all three species,
/// row 2 only `x₁`).
struct Robertson {
    hand_written: bool,
}

impl Model for Robertson {
    type Params = ();
    const NAME: &'static str = "robertson";
    const STATE_NAMES: &'static [&'static str] = &["a", "b", "c"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
        Some(&[&[0, 1, 2], &[0, 1, 2], &[1]]);
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let (k1, k2, k3) = (T::from_f64(0.04), T::from_f64(3.0e7), T::from_f64(1.0e4));
        dx[0] = -k1 * x[0] + k3 * x[1] * x[2];
        dx[1] = k1 * x[0] - k3 * x[1] * x[2] - k2 * x[1] * x[1];
        dx[2] = k2 * x[1] * x[1];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    fn jacobian(&self, _t: f64, x: &[f64], jac: &mut [f64]) -> bool {
        if !self.hand_written {
            return false;
        }
        let (k1, k2, k3) = (0.04, 3.0e7, 1.0e4);
        jac.copy_from_slice(&[
            -k1,
            k3 * x[2],
            k3 * x[1],
            k1,
            -k3 * x[2] - 2.0 * k2 * x[1],
            -k3 * x[1],
            0.0,
            2.0 * k2 * x[1],
            0.0,
        ]);
        true
    }
}

/// The same equations with no declared pattern: dense.
struct DenseRobertson;

impl Model for DenseRobertson {
    type Params = ();
    const NAME: &'static str = "dense_robertson";
    const STATE_NAMES: &'static [&'static str] = &["a", "b", "c"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        Robertson {
            hand_written: false,
        }
        .derivatives(t, x, dx);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// A central-difference Jacobian of `model` (row-major), state `j` stepped by
/// [`step`]`(x[j], scales[j])`.
fn finite_difference_jacobian<M: Model>(model: &M, t: f64, x: &[f64], scales: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut jac = vec![0.0; n * n];
    let (mut above, mut below) = (vec![0.0; n], vec![0.0; n]);
    let mut xs = x.to_vec();
    for j in 0..n {
        let h = step(x[j], scales[j]);
        xs[j] = x[j] + h;
        let up = xs[j];
        model.derivatives(t, &xs, &mut above);
        xs[j] = x[j] - h;
        let down = xs[j];
        model.derivatives(t, &xs, &mut below);
        xs[j] = x[j];
        for i in 0..n {
            jac[i * n + j] = (above[i] - below[i]) / (up - down);
        }
    }
    jac
}

/// `|a − b| ≤ tol · max_k |a_ik|` entry by entry (row-scaled relative error).
fn assert_rows_close(a: &[f64], b: &[f64], n: usize, tol: f64, what: &str) {
    for i in 0..n {
        let row = &a[i * n..(i + 1) * n];
        let scale = row
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        for j in 0..n {
            let (x, y) = (a[i * n + j], b[i * n + j]);
            assert!(
                (x - y).abs() <= tol * scale,
                "{what}: entry ({i}, {j}): {x} vs {y} (row scale {scale})"
            );
        }
    }
}

mod evaluator {
    use super::*;

    /// A random chain state: elongations of ~1 mm (where the cubic term is ~1 % of the
    /// linear one) and momenta of ~0.01 kg·m/s.
    fn chain_state(rng: &mut Rng) -> (Vec<f64>, Vec<f64>) {
        let scales: Vec<f64> = (0..chain::N_STATES)
            .map(|r| if r.is_multiple_of(2) { 1.0e-3 } else { 1.0e-2 })
            .collect();
        let x = scales.iter().map(|&s| rng.uniform(-s, s)).collect();
        (x, scales)
    }

    /// The chain's rows have at most 5 columns, so at least 5 colours; and the pattern
    /// lies inside the full band of half-width 2, which first fit colours with 5 (see
    /// `banded_patterns_get_the_optimal_two_w_plus_one_colours`).
    #[test]
    fn the_chain_needs_five_colours_instead_of_120() {
        let model = Chain::default();
        let evaluator = JacobianEvaluator::new(&model);
        assert_eq!(evaluator.n_states(), 120);
        assert_eq!(evaluator.n_colours(), 5);
        assert_eq!(evaluator.pattern().nnz(), 60 * 2 - 1 + 60 * 5 - 3);
        assert_eq!(
            JacobianEvaluator::with_pattern(SparsityPattern::dense(120)).n_colours(),
            120
        );
    }

    #[test]
    fn compressed_equals_dense_bit_for_bit_and_finite_differences_to_1e_6() {
        let model = Chain::default();
        let n = chain::N_STATES;
        let mut compressed = JacobianEvaluator::new(&model);
        let mut dense = JacobianEvaluator::with_pattern(SparsityPattern::dense(n));
        let (mut jc, mut jd) = (vec![f64::NAN; n * n], vec![f64::NAN; n * n]);
        let mut stored = Jacobian::new(compressed.pattern().clone().into());
        let mut js = vec![f64::NAN; n * n];
        let mut rng = Rng(2024);
        for _ in 0..20 {
            let (x, scales) = chain_state(&mut rng);
            let t = rng.uniform(0.0, 1.0);
            assert_eq!(compressed.evaluate(&model, t, &x, &mut jc), 5);
            assert_eq!(dense.evaluate(&model, t, &x, &mut jd), n);
            // Stored over the pattern: the same numbers, bit for bit.
            assert_eq!(compressed.evaluate_sparse(&model, t, &x, &mut stored), 5);
            stored.to_dense(&mut js);
            assert!(jc.iter().zip(&js).all(|(a, b)| a.to_bits() == b.to_bits()));
            // Bit for bit inside the pattern; +0.0 outside it, where the dense Jacobian
            // may hold −0.0 (checked to be zero just below).
            for (k, (a, b)) in jc.iter().zip(&jd).enumerate() {
                let (i, j) = (k / n, k % n);
                let expected = if compressed.pattern().contains(i, j) {
                    *b
                } else {
                    0.0
                };
                assert_eq!(
                    a.to_bits(),
                    expected.to_bits(),
                    "entry ({i}, {j}): {a} vs {b}"
                );
            }
            for i in 0..n {
                for j in 0..n {
                    if jd[i * n + j] != 0.0 {
                        assert!(
                            compressed.pattern().contains(i, j),
                            "({i}, {j}) outside the pattern"
                        );
                    }
                }
            }
            let fd = finite_difference_jacobian(&model, t, &x, &scales);
            assert_rows_close(&jc, &fd, n, 1e-6, "chain AD vs central differences");
        }
    }

    /// Every declared entry is non-zero somewhere: the hand-written pattern is exact.
    #[test]
    fn the_chain_pattern_is_exact() {
        let model = Chain::default();
        let n = chain::N_STATES;
        let mut evaluator = JacobianEvaluator::new(&model);
        let mut jac = vec![0.0; n * n];
        let (x, _) = chain_state(&mut Rng(5));
        evaluator.evaluate(&model, 0.3, &x, &mut jac);
        for i in 0..n {
            for &j in evaluator.pattern().row(i) {
                assert_ne!(jac[i * n + j], 0.0, "declared entry ({i}, {j}) is zero");
            }
        }
    }

    #[test]
    fn jvp_is_the_jacobian_times_the_direction() {
        let model = Chain::default();
        let n = chain::N_STATES;
        let mut evaluator = JacobianEvaluator::new(&model);
        let mut jac = vec![0.0; n * n];
        let mut out = vec![f64::NAN; n];
        let mut rng = Rng(99);
        for _ in 0..20 {
            let (x, _) = chain_state(&mut rng);
            let v: Vec<f64> = (0..n).map(|_| rng.uniform(-1.0, 1.0)).collect();
            evaluator.evaluate(&model, 0.1, &x, &mut jac);
            evaluator.jvp(&model, 0.1, &x, &v, &mut out);
            for i in 0..n {
                let row = &jac[i * n..(i + 1) * n];
                let product: f64 = row.iter().zip(&v).map(|(a, b)| a * b).sum();
                let scale: f64 = row.iter().zip(&v).map(|(a, b)| (a * b).abs()).sum();
                assert!(
                    (out[i] - product).abs() <= 1e-14 * scale,
                    "row {i}: jvp {} vs J·v {product}",
                    out[i]
                );
            }
        }
    }

    #[test]
    fn a_hand_written_jacobian_is_used_and_agrees_with_ad() {
        let model = Robertson { hand_written: true };
        let mut evaluator = JacobianEvaluator::new(&model);
        assert_eq!(evaluator.n_colours(), 3);
        let (mut hand, mut ad) = ([f64::NAN; 9], [f64::NAN; 9]);
        let mut rng = Rng(11);
        for _ in 0..20 {
            let x = [
                rng.uniform(0.0, 1.0),
                rng.uniform(0.0, 1.0e-4),
                rng.uniform(0.0, 1.0),
            ];
            assert_eq!(
                evaluator.evaluate(&model, 0.0, &x, &mut hand),
                0,
                "no derivative evaluation"
            );
            let mut expected = [0.0; 9];
            assert!(model.jacobian(0.0, &x, &mut expected));
            assert_eq!(hand, expected);
            assert_eq!(evaluator.evaluate_ad(&model, 0.0, &x, &mut ad), 3);
            assert_rows_close(&hand, &ad, 3, 1e-14, "hand-written vs AD");
        }
        // Without the hand-written Jacobian, AD: one evaluation per colour.
        let model = Robertson {
            hand_written: false,
        };
        assert_eq!(
            evaluator.evaluate(&model, 0.0, &[1.0, 1.0e-5, 0.1], &mut ad),
            3
        );
        assert_eq!(
            ad[6..],
            [0.0, 2.0 * 3.0e7 * 1.0e-5, 0.0],
            "row 2 (zeros outside the pattern)"
        );
    }

    #[test]
    fn a_model_without_a_pattern_is_dense() {
        let mut evaluator = JacobianEvaluator::new(&DenseRobertson);
        assert!(evaluator.pattern().is_dense());
        assert_eq!(evaluator.n_colours(), 3);
        let x = [0.7, 2.0e-5, 0.3];
        let (mut dense, mut sparse) = ([f64::NAN; 9], [f64::NAN; 9]);
        assert_eq!(evaluator.evaluate(&DenseRobertson, 0.0, &x, &mut dense), 3);
        let model = Robertson {
            hand_written: false,
        };
        JacobianEvaluator::new(&model).evaluate(&model, 0.0, &x, &mut sparse);
        assert_eq!(dense, sparse);
    }

    #[test]
    #[should_panic(
        expected = "model `wrong_row_count`: Jacobian sparsity pattern: expected one row per state"
    )]
    fn a_malformed_declared_pattern_panics_at_set_up() {
        let _ = JacobianEvaluator::new(&WrongRowCount);
    }

    #[test]
    #[should_panic(expected = "the Jacobian evaluator was built for 120")]
    fn a_model_of_another_size_is_refused() {
        let mut evaluator = JacobianEvaluator::new(&Chain::default());
        let mut jac = [0.0; 9];
        evaluator.evaluate(&DenseRobertson, 0.0, &[1.0, 0.0, 0.0], &mut jac);
    }

    #[test]
    #[should_panic(expected = "`jac` length")]
    fn a_wrongly_sized_jacobian_is_refused() {
        let mut evaluator = JacobianEvaluator::new(&DenseRobertson);
        let mut jac = [0.0; 8];
        evaluator.evaluate(&DenseRobertson, 0.0, &[1.0, 0.0, 0.0], &mut jac);
    }

    /// With debug assertions, an evaluator whose pattern misses entries the model
    /// declares (built for another model of the same size) is caught.
    #[cfg(debug_assertions)]
    #[test]
    #[should_panic(expected = "does not include")]
    fn a_pattern_that_misses_declared_entries_is_caught() {
        let diagonal = SparsityPattern::from_rows(&[[0], [1], [2]]).unwrap();
        let mut evaluator = JacobianEvaluator::with_pattern(diagonal);
        let mut jac = [0.0; 9];
        let model = Robertson {
            hand_written: false,
        };
        evaluator.evaluate(&model, 0.0, &[1.0, 0.0, 0.0], &mut jac);
    }
}
