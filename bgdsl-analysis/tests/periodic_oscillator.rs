//! The periodic orbit of a linear damped oscillator under sinusoidal forcing against its
//! closed form: the steady response `x(t) = F |H(jω)| sin(ωt + arg H(jω))` with
//! `H(s) = 1/(m s² + c s + k)`, and the Floquet multipliers `e^{λT}` for the roots `λ`
//! of `m λ² + c λ + k = 0` (the monodromy matrix of a linear system with constant
//! coefficients is `e^{AT}`).

use bgdsl_analysis::periodic::{periodic_orbit, PeriodicOptions};
use bgdsl_runtime::{Model, Scalar};
use nalgebra::Complex;

const M: f64 = 1.0;
const C: f64 = 0.4;
const K: f64 = 4.0;
const F: f64 = 1.0;
const W: f64 = 1.5;

/// `m x'' + c x' + k x = F sin(ω t)`.
struct Forced;

impl Model for Forced {
    type Params = ();
    const NAME: &'static str = "forced";
    const STATE_NAMES: &'static [&'static str] = &["x", "v"];
    const OUTPUT_NAMES: &'static [&'static str] = &["x"];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0)
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[1];
        dx[1] = (T::from_f64(F * (W * t).sin()) - T::from_f64(C) * x[1] - T::from_f64(K) * x[0])
            / T::from_f64(M);
    }
    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        y[0] = x[0]
    }
}

#[test]
fn orbit_is_the_steady_sine_response_and_multipliers_are_exp_lambda_t() {
    let period = core::f64::consts::TAU / W;
    let mut options = PeriodicOptions::new(period);
    // A smooth two-state model: the period map is accurate to the solver's 1e-9.
    options.tolerance = 1e-9;
    let orbit = periodic_orbit(&Forced, &[0.0, 0.0], &[], &options).unwrap();

    let h = Complex::new(1.0, 0.0) / Complex::new(K - M * W * W, C * W);
    let (amp, phase) = (F * h.norm(), h.arg());
    let exact = [amp * phase.sin(), amp * W * phase.cos()];
    for (got, want) in orbit.x0.iter().zip(exact) {
        let err = (got - want).abs() / amp;
        assert!(err < 1e-7, "x0 = {got} vs {want}: {err:e}");
    }
    // A linear problem: Newton's step is exact but for the monodromy matrix's
    // discretisation error (about 1e-5), so each iteration gains about five digits.
    assert!(orbit.iterations <= 3, "{} iterations", orbit.iterations);

    let sigma = -C / (2.0 * M);
    let omega_d = (K / M - sigma * sigma).sqrt();
    let lambda = Complex::new(sigma, omega_d);
    let expected = (lambda * period).exp();
    assert_eq!(orbit.multipliers.len(), 2);
    for mu in &orbit.multipliers {
        let closest = if mu.im >= 0.0 {
            expected
        } else {
            expected.conj()
        };
        let err = (mu - closest).norm() / closest.norm();
        assert!(err < 1e-5, "multiplier {mu} vs {closest}: {err:e}");
    }
    assert_eq!(orbit.neutral.dimension, 0);
}
