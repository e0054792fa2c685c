//! The energy account every generated model carries (`Model::power_balance`), built
//! from the graph: stored energy from the C and I laws, input power from the sources,
//! dissipated power from the resistors.

use bgdsl_runtime::{Dual, Model, Scalar};
use models::quick_return::QuickReturn;
use models::{DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

fn next(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *seed;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) as f64 / u64::MAX as f64 * 2.0 - 1.0
}

/// d(stored)/dt = input − dissipated, exactly: the time derivative of the stored
/// energy along the model's own dx/dt, by a dual-number directional derivative, at
/// `samples` states around the initial one (each state perturbed by `spread` times
/// its own scale, at least `floor`).
fn check_balance<M: Model>(model: &M, samples: usize, spread: f64, floor: f64) {
    let n = M::N_STATES;
    let mut x0 = vec![0.0; n];
    model.initial_state(&mut x0);
    let mut seed = 17;
    for _ in 0..samples {
        let x: Vec<f64> = x0
            .iter()
            .map(|&v| v + next(&mut seed) * spread * v.abs().max(floor))
            .collect();
        let mut dx = vec![0.0; n];
        model.derivatives(0.3, &x, &mut dx);
        let along: Vec<Dual> = x.iter().zip(&dx).map(|(&v, &d)| Dual::new(v, d)).collect();
        let balance = model
            .power_balance(0.3, &along)
            .expect("generated models keep an account");
        let rate = balance.stored.eps;
        let (input, dissipated) = (balance.input.to_f64(), balance.dissipated.to_f64());
        let scale = input.abs() + dissipated.abs() + rate.abs();
        assert!(
            (rate - (input - dissipated)).abs() <= 1e-9 * scale.max(1e-12),
            "{}: dE/dt {rate} vs input {input} - dissipated {dissipated}",
            M::NAME
        );
        assert!(dissipated >= 0.0, "{}: resistors absorb power", M::NAME);
    }
}

#[test]
fn balance_power_in_every_scalar_model() {
    check_balance(&Oscillator::default(), 200, 1.0, 0.1);
    check_balance(&SeriesRlc::default(), 200, 1.0, 0.1);
    check_balance(&DcMotor::default(), 200, 1.0, 0.1);
    check_balance(&QuarterCar::default(), 200, 1.0, 0.01);
    check_balance(&Duffing::default(), 200, 1.0, 0.5);
}

/// The flagship: 117 states, five rigid bodies (kinetic energy ½ p·v + ½ h·w, with the
/// angular momentum's law modulated by the orientation), nine joints, gravity and the
/// drive as sources.
#[test]
fn balance_power_in_the_quick_return_mechanism() {
    check_balance(&QuickReturn::default(), 100, 0.05, 1e-3);
}

/// A cubic spring stores ½ k q² + ¼ k3 q⁴ and the mass p²/2m: the quadrature is exact
/// for polynomial laws, so the account equals the closed form to round-off.
#[test]
fn integrate_a_nonlinear_law_exactly() {
    let model = Duffing::default();
    let p = &model.params;
    let mut seed = 5;
    for _ in 0..50 {
        let x = [next(&mut seed) * 2.0, next(&mut seed) * 3.0];
        let names = Duffing::STATE_NAMES;
        let (q, mom) = if names[0].ends_with(".q") {
            (x[0], x[1])
        } else {
            (x[1], x[0])
        };
        let expected = mom * mom / (2.0 * p.m) + 0.5 * p.k * q * q + 0.25 * p.k3 * q.powi(4);
        let stored = model.power_balance(0.0, &x).unwrap().stored;
        assert!(
            (stored - expected).abs() <= 1e-13 * expected.abs().max(1.0),
            "{stored} vs {expected}"
        );
    }
}
