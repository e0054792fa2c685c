//! `Tangent<S>`: a dual number over any scalar. On `f64` it equals `Dual` lane by lane;
//! on `Dual` it carries exact second derivatives; it keeps `Dual`'s conventions at
//! singular points and works inside nalgebra's vectors and matrices and the multibond
//! helpers.

use bgdsl_runtime::multibond::{rot_z, skew, vec3, Matrix3, Vector3};
use bgdsl_runtime::{Dual, DualN, Scalar, Tangent};

/// Bit equality, with every NaN equal to every NaN.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn t64(re: f64, eps: f64) -> Tangent<f64> {
    Tangent::new(re, eps)
}

/// `Tangent<f64>` computes what `Dual` computes, value and tangent, bit for bit (atan2
/// to a few ulps of its terms: it scales by max(|x|, |y|) where `Dual` uses `hypot`).
#[test]
fn tangent_of_f64_equals_dual() {
    type Unary = (
        &'static str,
        fn(Tangent<f64>) -> Tangent<f64>,
        fn(Dual) -> Dual,
    );
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
    let points = [0.3, -1.7, 0.0, -0.0, 1.0, -1.0, 2.5, 1e-300, 40.0];
    let tangents = [1.0, 0.0, -2.5];
    for (name, f, g) in unary {
        for x in points {
            for e in tangents {
                let (got, want) = (f(t64(x, e)), g(Dual::new(x, e)));
                assert!(
                    same(got.re, want.re) && same(got.eps, want.eps),
                    "{name}({x} + {e}ε): {got} against {want}"
                );
            }
        }
    }
    type Binary = (
        &'static str,
        fn(Tangent<f64>, Tangent<f64>) -> Tangent<f64>,
        fn(Dual, Dual) -> Dual,
    );
    let binary: [Binary; 7] = [
        ("add", |a, b| a + b, |a, b| a + b),
        ("sub", |a, b| a - b, |a, b| a - b),
        ("mul", |a, b| a * b, |a, b| a * b),
        ("div", |a, b| a / b, |a, b| a / b),
        ("powf", Scalar::powf, Scalar::powf),
        ("min", Scalar::min, Scalar::min),
        ("max", Scalar::max, Scalar::max),
    ];
    let others = [0.0, 0.5, 2.0, -1.0, 1.5, 0.3];
    for (name, f, g) in binary {
        for x in points {
            for y in others {
                for (ex, ey) in [(1.0, 0.0), (0.0, 2.0), (-1.0, 1.0), (0.0, 0.0)] {
                    let got = f(t64(x, ex), t64(y, ey));
                    let want = g(Dual::new(x, ex), Dual::new(y, ey));
                    assert!(
                        same(got.re, want.re) && same(got.eps, want.eps),
                        "{name}({x} + {ex}ε, {y} + {ey}ε): {got} against {want}"
                    );
                }
            }
        }
    }
    for x in points {
        for y in others {
            for (ex, ey) in [(1.0, 0.0), (0.0, 2.0), (-1.0, 1.0), (0.0, 0.0)] {
                let got = t64(y, ey).atan2(t64(x, ex));
                let want = Dual::new(y, ey).atan2(Dual::new(x, ex));
                // Round-off relative to the terms of (x y' − y x') / (x² + y²).
                let scale = ((x * ey).abs() + (y * ex).abs()) / (x * x + y * y);
                let close = same(got.eps, want.eps)
                    || (got.eps - want.eps).abs() <= 8.0 * f64::EPSILON * scale;
                assert!(
                    same(got.re, want.re) && close,
                    "atan2({y} + {ey}ε, {x} + {ex}ε): {got} against {want}"
                );
            }
        }
    }
    // Assignment operators, constants and conversions.
    let mut a = t64(0.7, 1.0);
    a += t64(0.1, 1.0);
    a -= Tangent::constant(0.2);
    a *= t64(3.0, 0.5);
    a /= t64(1.5, 1.0);
    let mut b = Dual::new(0.7, 1.0);
    b += Dual::new(0.1, 1.0);
    b -= Dual::constant(0.2);
    b *= Dual::new(3.0, 0.5);
    b /= Dual::new(1.5, 1.0);
    assert!(same(a.re, b.re) && same(a.eps, b.eps), "{a} against {b}");
    use num_traits::{One, Zero};
    assert!(Tangent::<f64>::zero().is_zero() && !t64(0.0, 1.0).is_zero());
    assert_eq!(Tangent::<f64>::one(), Tangent::from_f64(1.0));
    assert_eq!(Tangent::<Dual>::from_f64(2.5).to_f64(), 2.5);
    assert_eq!(Tangent::<f64>::from(3.0).eps, 0.0);
    assert_eq!(Tangent::variable(2.0).eps, 1.0);
}

/// `f` on `Tangent<Dual>` seeded with `x + ε₁ + ε₂` (the outer tangent in `Tangent`,
/// the inner one in `Dual`): `(f(x), f'(x), f'(x), f''(x))`.
fn second(f: impl Fn(Tangent<Dual>) -> Tangent<Dual>, x: f64) -> [f64; 4] {
    let y = f(Tangent::new(Dual::variable(x), Dual::constant(1.0)));
    [y.re.re, y.re.eps, y.eps.re, y.eps.eps]
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-300) || (a == b)
}

/// Every elementary function's first and second derivative on `Tangent<Dual>` against
/// its closed form, to 1e-13 relative.
#[test]
fn second_derivatives_of_every_elementary_function() {
    type Case = (
        &'static str,
        fn(Tangent<Dual>) -> Tangent<Dual>,
        fn(f64) -> [f64; 3],
        f64,
    );
    let cases: [Case; 19] = [
        (
            "sqrt",
            Scalar::sqrt,
            |x| [x.sqrt(), 0.5 / x.sqrt(), -0.25 * x.powf(-1.5)],
            0.7,
        ),
        (
            "cbrt",
            Scalar::cbrt,
            |x| {
                [
                    x.cbrt(),
                    x.powf(-2.0 / 3.0) / 3.0,
                    -2.0 / 9.0 * x.powf(-5.0 / 3.0),
                ]
            },
            1.9,
        ),
        ("exp", Scalar::exp, |x| [x.exp(), x.exp(), x.exp()], 0.4),
        ("ln", Scalar::ln, |x| [x.ln(), 1.0 / x, -1.0 / (x * x)], 2.2),
        ("sin", Scalar::sin, |x| [x.sin(), x.cos(), -x.sin()], 0.9),
        ("cos", Scalar::cos, |x| [x.cos(), -x.sin(), -x.cos()], 0.9),
        (
            "tan",
            Scalar::tan,
            |x| {
                let t = x.tan();
                [t, 1.0 + t * t, 2.0 * t * (1.0 + t * t)]
            },
            0.6,
        ),
        (
            "asin",
            Scalar::asin,
            |x| {
                let s = 1.0 - x * x;
                [x.asin(), 1.0 / s.sqrt(), x / s.powf(1.5)]
            },
            0.35,
        ),
        (
            "acos",
            Scalar::acos,
            |x| {
                let s = 1.0 - x * x;
                [x.acos(), -1.0 / s.sqrt(), -x / s.powf(1.5)]
            },
            -0.45,
        ),
        (
            "atan",
            Scalar::atan,
            |x| {
                let s = 1.0 + x * x;
                [x.atan(), 1.0 / s, -2.0 * x / (s * s)]
            },
            1.3,
        ),
        (
            "sinh",
            Scalar::sinh,
            |x| [x.sinh(), x.cosh(), x.sinh()],
            0.8,
        ),
        (
            "cosh",
            Scalar::cosh,
            |x| [x.cosh(), x.sinh(), x.cosh()],
            0.8,
        ),
        (
            "tanh",
            Scalar::tanh,
            |x| {
                let t = x.tanh();
                [t, 1.0 - t * t, -2.0 * t * (1.0 - t * t)]
            },
            0.55,
        ),
        ("abs", Scalar::abs, |x| [x.abs(), x.signum(), 0.0], -1.5),
        ("signum", Scalar::signum, |x| [x.signum(), 0.0, 0.0], -1.5),
        (
            "powi(4)",
            |x| x.powi(4),
            |x| [x.powi(4), 4.0 * x.powi(3), 12.0 * x * x],
            1.1,
        ),
        (
            "powi(-3)",
            |x| x.powi(-3),
            |x| [x.powi(-3), -3.0 * x.powi(-4), 12.0 * x.powi(-5)],
            0.7,
        ),
        (
            "recip",
            Scalar::recip,
            |x| [1.0 / x, -1.0 / (x * x), 2.0 / (x * x * x)],
            -0.8,
        ),
        (
            "powf(2.5)",
            |x| x.powf(Tangent::from_f64(2.5)),
            |x| [x.powf(2.5), 2.5 * x.powf(1.5), 3.75 * x.sqrt()],
            1.7,
        ),
    ];
    for (name, f, exact, x) in cases {
        let [value, d_inner, d_outer, d2] = second(f, x);
        let [v, d, dd] = exact(x);
        assert!(
            close(value, v, 1e-15),
            "{name}({x}) = {value}, expected {v}"
        );
        assert!(
            close(d_inner, d, 1e-14),
            "{name}'({x}) inner {d_inner}, expected {d}"
        );
        assert!(
            close(d_outer, d, 1e-14),
            "{name}'({x}) outer {d_outer}, expected {d}"
        );
        assert!(close(d2, dd, 1e-13), "{name}''({x}) = {d2}, expected {dd}");
    }
}

/// Mixed second derivatives of the two-argument functions: `∂²f/∂x∂y` with `x`
/// carried by the outer tangent and `y` by the inner one.
#[test]
fn mixed_second_derivatives_of_binary_functions() {
    let (x0, y0) = (1.3, 0.6);
    let x = Tangent::new(Dual::constant(x0), Dual::constant(1.0));
    let y = Tangent::new(Dual::variable(y0), Dual::constant(0.0));
    let r2 = x0 * x0 + y0 * y0;
    // atan2(y, x): ∂/∂x = −y / r², ∂²/∂x∂y = (y² − x²) / r⁴.
    let f = y.atan2(x);
    assert!(close(f.eps.re, -y0 / r2, 1e-14));
    assert!(close(f.eps.eps, (y0 * y0 - x0 * x0) / (r2 * r2), 1e-13));
    // x^y: ∂/∂x = y x^(y−1), ∂²/∂x∂y = x^(y−1) (1 + y ln x).
    let f = x.powf(y);
    assert!(close(f.eps.re, y0 * x0.powf(y0 - 1.0), 1e-14));
    assert!(close(
        f.eps.eps,
        x0.powf(y0 - 1.0) * (1.0 + y0 * x0.ln()),
        1e-13
    ));
    // x y / (x + y): mul and div.
    let f = x * y / (x + y);
    let s = x0 + y0;
    assert!(close(f.eps.re, y0 * y0 / (s * s), 1e-14));
    assert!(close(f.eps.eps, 2.0 * x0 * y0 / (s * s * s), 1e-13));
    // min and max pick the argument whose value wins, tangent and all.
    assert_eq!(x.max(y).eps.re, 1.0);
    assert_eq!(x.min(y).re.eps, 1.0);
    // On DualN: each lane its own mixed derivative (sin(x y): ∂²/∂x∂y = cos − x y sin).
    let xn = Tangent::new(DualN::<2>::constant(x0), DualN::constant(1.0));
    let yn = Tangent::new(DualN::new(y0, [1.0, 2.0]), DualN::constant(0.0));
    let f = (xn * yn).sin();
    let want = (x0 * y0).cos() - x0 * y0 * (x0 * y0).sin();
    assert!(close(f.eps.tangents()[0], want, 1e-13));
    assert!(close(f.eps.tangents()[1], 2.0 * want, 1e-13));
}

/// At the singular points of the conventions a zero tangent stays zero, at both
/// levels; kinks take the midpoint; signum has derivative zero.
#[test]
fn singular_point_conventions() {
    let zero_tangent = |re: Dual| Tangent::new(re, Dual::constant(0.0));
    type Case = (&'static str, fn(Tangent<Dual>) -> Tangent<Dual>, f64);
    let unary: [Case; 6] = [
        ("sqrt", Scalar::sqrt, 0.0),
        ("cbrt", Scalar::cbrt, 0.0),
        ("ln", Scalar::ln, 0.0),
        ("asin", Scalar::asin, 1.0),
        ("acos", Scalar::acos, -1.0),
        ("powi(-1)", |x| x.powi(-1), 0.0),
    ];
    for (name, f, x) in unary {
        // Constant at both levels: everything but the value is zero.
        let y = f(zero_tangent(Dual::constant(x)));
        assert_eq!((y.re.eps, y.eps.re, y.eps.eps), (0.0, 0.0, 0.0), "{name}");
        // The outer tangent zero, the inner one not: the outer stays zero.
        let y = f(zero_tangent(Dual::variable(x)));
        assert_eq!((y.eps.re, y.eps.eps), (0.0, 0.0), "{name}, inner seeded");
    }
    // atan2 at the origin with zero tangents.
    let o = zero_tangent(Dual::constant(0.0));
    let y = o.atan2(o);
    assert_eq!((y.eps.re, y.eps.eps), (0.0, 0.0));
    // powf at a zero base with a zero outer tangent.
    let y = o.powf(Tangent::from_f64(0.5));
    assert_eq!((y.eps.re, y.eps.eps), (0.0, 0.0));
    // abs at 0: slope 0 (the midpoint); signum: slope 0 at and off the jump.
    let seeded = |re: f64| Tangent::new(Dual::variable(re), Dual::constant(1.0));
    assert_eq!(seeded(0.0).abs().eps.re, 0.0);
    assert_eq!(seeded(-0.0).abs().eps.re, 0.0);
    assert_eq!(seeded(-2.0).abs().eps.re, -1.0);
    for x in [0.0, 1.0, -3.0] {
        let s = seeded(x).signum();
        assert_eq!((s.re.eps, s.eps.re, s.eps.eps), (0.0, 0.0, 0.0));
    }
    // max of equal values: the mean of the two tangents (x.max(−x) at 0 is like abs).
    let m = seeded(0.0).max(-seeded(0.0));
    assert_eq!((m.eps.re, m.re.eps), (0.0, 0.0));
    let m = seeded(1.0).max(Tangent::new(Dual::new(1.0, 3.0), Dual::constant(5.0)));
    assert_eq!((m.re.eps, m.eps.re), (2.0, 3.0));
    // A NaN loses in min and max, as f64::min.
    let nan = Tangent::<f64>::from_f64(f64::NAN);
    assert_eq!(nan.max(t64(1.0, 2.0)).eps, 2.0);
    assert_eq!(t64(1.0, 2.0).min(nan).eps, 2.0);
    // powi(0) is the constant 1, even at 0.
    let p = seeded(0.0).powi(0);
    assert_eq!(
        (p.re.re, p.re.eps, p.eps.re, p.eps.eps),
        (1.0, 0.0, 0.0, 0.0)
    );
    // Comparison is by value (the innermost one).
    assert_eq!(
        seeded(1.0),
        Tangent::new(Dual::constant(1.0), Dual::constant(-7.0))
    );
    assert!(seeded(1.0) < Tangent::from_f64(1.5));
}

/// Inside nalgebra's vectors and matrices and the multibond helpers, `Tangent<Dual>`
/// differentiates a rotated lever arm twice: `d/dt (R(θ) r)` with `θ = ω t` is
/// `ω R(θ + π/2) r`, and its derivative with respect to `ω` (the inner tangent) is
/// `R(θ + π/2) r − ω t R(θ) r`.
#[test]
fn works_in_nalgebra_and_multibond_helpers() {
    let (omega, t) = (2.0, 0.3);
    let theta = Tangent::new(Dual::new(omega * t, t), Dual::variable(omega));
    let arm: Vector3<Tangent<Dual>> = vec3(
        Tangent::from_f64(0.4),
        Tangent::from_f64(0.1),
        Tangent::from_f64(0.0),
    );
    let rotated: Vector3<Tangent<Dual>> = rot_z(theta) * arm;
    let turn = |angle: f64| {
        let (s, c) = angle.sin_cos();
        [c * 0.4 - s * 0.1, s * 0.4 + c * 0.1]
    };
    let ahead = turn(omega * t + core::f64::consts::FRAC_PI_2);
    let here = turn(omega * t);
    for k in 0..2 {
        assert!(close(rotated[k].re.re, here[k], 1e-15));
        assert!(close(rotated[k].eps.re, omega * ahead[k], 1e-14));
        assert!(close(
            rotated[k].eps.eps,
            ahead[k] - omega * t * here[k],
            1e-13
        ));
    }
    // skew(a) b = a × b, and a matrix product, on Tangent<f64>.
    let a = vec3(t64(1.0, 1.0), t64(2.0, 0.0), t64(3.0, 0.0));
    let b = vec3(t64(-1.0, 0.0), t64(0.5, 0.0), t64(4.0, 0.0));
    assert_eq!(skew(a) * b, a.cross(&b));
    let m: Matrix3<Tangent<f64>> = skew(a) * skew(b);
    let d_cross = (skew(a) * b).map(|v| v.eps);
    assert_eq!(d_cross, vec3(0.0, -4.0, 0.5));
    assert!(m[(0, 0)].re.is_finite());
}
