//! Exact ∂f/∂p, ∂g/∂p, ∂f/∂u, ∂g/∂u against central differences and closed forms.
//!
//! Central differences here are computed independently of the library (the model's
//! `f64` code at `p ± h`, `h = 1e-4·|p|` (`1e-4` at 0)); their error is about
//! `h²·|f'''|/6 + ε·|f|/h`, so each comparison allows `1e-6` of the column's largest
//! entry (truncation) plus `1000·ε·max|f|/h` (the round-off of a difference of two
//! large values, which a stiff joint's `1e5 N/m` makes large, with a margin for the
//! cancellation inside the model's own sums).

use bgdsl_analysis::{input_partials, parameter_jacobian, parameter_partials, Method};
use bgdsl_runtime::{bond_graph, Model, WithInputs};
use models::quick_return::QuickReturn;
use models::{DcMotor, Duffing};

/// `model`'s initial state, moved off its rest point deterministically so that every
/// term (angular momenta, spring deflections) is non-zero.
fn moved_state<M: Model>(model: &M) -> Vec<f64> {
    let mut x = vec![0.0; M::N_STATES];
    model.initial_state(&mut x);
    for (i, v) in x.iter_mut().enumerate() {
        *v += 0.01 * (1.0 + i as f64).sin();
    }
    x
}

/// Central differences of `f` and `g` in parameter `i`, by the model's own `f64` code.
fn central<M: Model + Clone>(model: &M, t: f64, x: &[f64], i: usize) -> (Vec<f64>, Vec<f64>, f64) {
    let mut values = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    let h = 1e-4
        * if values[i] == 0.0 {
            1.0
        } else {
            values[i].abs()
        };
    let eval = |value: f64| {
        let mut copy = model.clone();
        let mut v = values.clone();
        v[i] = value;
        copy.set_parameter_values(&v);
        let (mut f, mut g) = (vec![0.0; M::N_STATES], vec![0.0; M::N_OUTPUTS]);
        copy.derivatives(t, x, &mut f);
        copy.outputs(t, x, &mut g);
        (f, g)
    };
    let ((fp, gp), (fm, gm)) = (eval(values[i] + h), eval(values[i] - h));
    let diff = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| (a - b) / (2.0 * h)).collect();
    (diff(&fp, &fm), diff(&gp, &gm), h)
}

fn max_abs(v: impl IntoIterator<Item = f64>) -> f64 {
    v.into_iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Every parameter's column of ∂f/∂p and ∂g/∂p against central differences.
fn check_all_parameters<M: Model + Clone>(model: &M, t: f64, x: &[f64]) {
    assert!(M::EXACT_PARAMETER_DERIVATIVES, "{} keeps tangents", M::NAME);
    let which: Vec<usize> = (0..M::N_PARAMETER_VALUES).collect();
    let exact = parameter_partials(model, t, x, &which).unwrap();
    assert_eq!(exact.method, Method::Exact);
    let (mut f, mut g) = (vec![0.0; M::N_STATES], vec![0.0; M::N_OUTPUTS]);
    model.derivatives(t, x, &mut f);
    model.outputs(t, x, &mut g);
    for &i in &which {
        let (cf, cg, h) = central(model, t, x, i);
        for (what, column, reference, values) in [
            ("f", exact.df.column(i), &cf, &f),
            ("g", exact.dg.column(i), &cg, &g),
        ] {
            let tol = 1e-6 * max_abs(reference.iter().copied())
                + 1e3 * f64::EPSILON * max_abs(values.iter().copied()) / h;
            for (r, (a, b)) in column.iter().zip(reference).enumerate() {
                assert!(
                    (a - b).abs() <= tol,
                    "{}: d{what}[{r}]/dp[{i}] = {a}, central differences {b} (tolerance {tol:e})",
                    M::NAME
                );
            }
        }
    }
}

#[test]
fn the_flagship_parameter_derivatives_match_central_differences() {
    let model = QuickReturn::default();
    let x = moved_state(&model);
    check_all_parameters(&model, 0.3, &x);
}

/// `l1.y` (the crank's height) reaches the equations only through the crank's inertia
/// `box_inertia(m1, l1.x, l1.y, l1.z)`, a parameter expression the model computes once
/// in `f64`: a seeded evaluation must recompute it, not lift the cached value.
#[test]
fn a_parameter_used_only_through_the_cache_keeps_its_derivative() {
    let model = QuickReturn::default();
    let x = moved_state(&model);
    let index = |name: &str| {
        let mut at = 0;
        for p in QuickReturn::PARAMETERS {
            if p.name == name {
                return at;
            }
            at += p.len;
        }
        panic!("no parameter {name}")
    };
    let l1_y = index("l1") + 1;
    let exact = parameter_partials(&model, 0.3, &x, &[l1_y]).unwrap();
    let (cf, _, _) = central(&model, 0.3, &x, l1_y);
    let largest = max_abs(exact.df.column(0).iter().copied());
    assert!(largest > 1e-3, "∂f/∂l1.y vanished: {largest:e}");
    for (a, b) in exact.df.column(0).iter().zip(&cf) {
        assert!((a - b).abs() <= 1e-6 * largest, "{a} vs {b}");
    }
    // The same through the sensitivity integrator's column-major form.
    let mut out = vec![0.0; QuickReturn::N_STATES];
    let method = parameter_jacobian(&model, 0.3, &x, &[l1_y], &mut out).unwrap();
    assert_eq!(method, Method::Exact);
    assert_eq!(out.as_slice(), exact.df.as_slice());
}

#[test]
fn small_models_parameter_derivatives_match_central_differences() {
    let motor = DcMotor::default();
    check_all_parameters(&motor, 0.0, &moved_state(&motor));
    let duffing = Duffing::default();
    check_all_parameters(&duffing, 0.7, &moved_state(&duffing));
}

/// The DC motor's armature: dλ/dt = V − R i − k_t ω_m, so ∂/∂V = 1, ∂/∂R = −i =
/// −λ/L, ∂/∂k_t = −ω_m = −p_rotor/J_rotor.
#[test]
fn the_dc_motor_armature_derivatives_are_the_closed_forms() {
    let motor = DcMotor::default();
    let x = moved_state(&motor);
    let p = parameter_partials(&motor, 0.0, &x, &[0, 1, 3]).unwrap();
    let coil = DcMotor::STATE_NAMES
        .iter()
        .position(|n| *n == "coil.p")
        .unwrap();
    let rotor = DcMotor::STATE_NAMES
        .iter()
        .position(|n| *n == "rotor.p")
        .unwrap();
    let params = motor.params.clone();
    let current = x[coil] / params.inductance;
    let speed = x[rotor] / params.rotor_inertia;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs().max(1.0);
    assert!(close(p.df[(coil, 0)], 1.0), "{}", p.df[(coil, 0)]);
    assert!(close(p.df[(coil, 1)], -current), "{}", p.df[(coil, 1)]);
    assert!(close(p.df[(coil, 2)], -speed), "{}", p.df[(coil, 2)]);
}

bond_graph! {
    /// A mass on a spring pushed by an input force whose gain depends on a parameter
    /// through a parameter expression, and driven by an input-dependent harmonic force.
    model Pushed {
        param m = 2.0 in "kg";
        param k = 50.0 in "N/m";
        param gain = 3.0;
        param w = 4.0 in "rad/s";
        input force = 0.5 in "N";
        input phase = 0.2 in "rad";
        MSe push = gain.sqrt() * force + (w * t + phase).sin();
        I mass = m;
        C spring = k;
        1 v;
        push -> v -> { mass, spring };
        output pushing = gain.sqrt() * force + (w * t + phase).sin() in "N";
    }
}

/// ṗ = √gain·u + sin(w t + φ) − k q: ∂ṗ/∂u = √gain, ∂ṗ/∂φ = cos(w t + φ),
/// ∂ṗ/∂gain = u / (2√gain), ∂ṗ/∂w = t cos(w t + φ), and the output likewise.
#[test]
fn input_and_parameter_derivatives_through_parameter_expressions_are_the_closed_forms() {
    let model = Pushed::default();
    assert!(Pushed::EXACT_PARAMETER_DERIVATIVES);
    let x = [0.1, -0.3];
    let t = 0.9;
    let u = input_partials(&model, t, &x, &[0, 1]).unwrap();
    let p = parameter_partials(&model, t, &x, &[2, 3]).unwrap();
    let momentum = Pushed::STATE_NAMES
        .iter()
        .position(|n| *n == "mass.p")
        .unwrap();
    let (gain, force, phase, w) = (3.0f64, 0.5, 0.2, 4.0);
    let expected = [
        (u.df[(momentum, 0)], gain.sqrt()),
        (u.df[(momentum, 1)], (w * t + phase).cos()),
        (p.df[(momentum, 0)], force / (2.0 * gain.sqrt())),
        (p.df[(momentum, 1)], t * (w * t + phase).cos()),
        (u.dg[(0, 0)], gain.sqrt()),
        (p.dg[(0, 1)], t * (w * t + phase).cos()),
    ];
    for (i, (found, want)) in expected.into_iter().enumerate() {
        assert!((found - want).abs() <= 1e-14, "#{i}: {found} vs {want}");
    }
    assert_eq!(Pushed::INPUTS.len(), 2);
}

/// A hand-written model (no hook): central differences, and said so.
#[derive(Clone, Debug, Default)]
struct Decay {
    rate: f64,
}

impl Model for Decay {
    type Params = ();
    const NAME: &'static str = "decay";
    const STATE_NAMES: &'static [&'static str] = &["x"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const N_PARAMETER_VALUES: usize = 1;
    fn params(&self) -> &() {
        &()
    }
    fn parameter_values(&self, out: &mut [f64]) {
        out[0] = self.rate;
    }
    fn set_parameter_values(&mut self, values: &[f64]) {
        self.rate = values[0];
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }
    fn derivatives<T: bgdsl_runtime::Scalar>(&self, _: f64, x: &[T], dx: &mut [T]) {
        dx[0] = -T::from_f64(self.rate) * x[0];
    }
    fn outputs<T: bgdsl_runtime::Scalar>(&self, _: f64, _: &[T], _: &mut [T]) {}
}

#[test]
fn a_hand_written_model_falls_back_to_central_differences_and_says_so() {
    let model = Decay { rate: 2.0 };
    let p = parameter_partials(&model, 0.0, &[3.0], &[0]).unwrap();
    assert_eq!(p.method, Method::CentralDifferences);
    assert!((p.df[(0, 0)] + 3.0).abs() < 1e-8, "{}", p.df[(0, 0)]);
    let wrong = parameter_partials(&model, 0.0, &[3.0], &[1]).unwrap_err();
    assert!(wrong.to_string().contains("parameter index"), "{wrong}");
}
