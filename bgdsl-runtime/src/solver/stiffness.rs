//! Why an explicit method failed: an estimate of the model's stiffness, the magnitude
//! of the largest eigenvalue of its Jacobian `∂f/∂x` (its spectral radius), by power
//! iteration on Jacobian-vector products taken by finite differences. An explicit
//! Runge–Kutta method is stable on a decaying mode `λ` only while `h |λ|` stays inside
//! its stability region (along the negative real axis: 2.785 for RK4, 3.307 for
//! Dormand–Prince 5), so a step far beyond `bound / ρ` makes it blow up.

use crate::model::Model;

/// The power iterations; the growth of the last half is averaged.
const ITERATIONS: usize = 40;

/// How far along the negative real axis the stability region of the classical RK4
/// reaches (`|1 + z + z²/2 + z³/6 + z⁴/24| = 1` at `z ≈ −2.785`).
pub const RK4_STABILITY: f64 = 2.785;

/// The same for the 5th-order Dormand–Prince method (`z ≈ −3.307`).
pub const DOPRI5_STABILITY: f64 = 3.307;

/// An estimate of the spectral radius of `∂f/∂x` of `model` at `(t, x)`, 1/s: the mean
/// growth per application of the Jacobian to a vector over the last half of
/// a fixed number of power iterations (for complex or several dominant eigenvalues of one
/// magnitude this still tends to that magnitude). 0 when the derivatives do not depend
/// on the state; `None` when they are not finite there.
pub fn spectral_radius<M: Model>(model: &M, t: f64, x: &[f64]) -> Option<f64> {
    let n = x.len();
    if n == 0 {
        return Some(0.0);
    }
    let mut f0 = vec![0.0; n];
    model.derivatives(t, x, &mut f0);
    if f0.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let eps = f64::EPSILON.sqrt() * (1.0 + scale);
    // A fixed start with every component non-zero, not aligned with any one mode.
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 7919) % 101) as f64 / 101.0)
        .collect();
    normalise(&mut v);
    let (mut xp, mut fp) = (vec![0.0; n], vec![0.0; n]);
    let (mut log_growth, mut counted) = (0.0, 0usize);
    for k in 0..ITERATIONS {
        for i in 0..n {
            xp[i] = x[i] + eps * v[i];
        }
        model.derivatives(t, &xp, &mut fp);
        for i in 0..n {
            v[i] = (fp[i] - f0[i]) / eps;
        }
        let norm = normalise(&mut v);
        if !norm.is_finite() {
            return None;
        }
        if norm == 0.0 {
            return Some(0.0);
        }
        if k >= ITERATIONS / 2 {
            log_growth += norm.ln();
            counted += 1;
        }
    }
    Some((log_growth / counted as f64).exp())
}

/// Scales `v` to unit Euclidean norm; returns the norm it had.
fn normalise(v: &mut [f64]) -> f64 {
    let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    if norm > 0.0 && norm.is_finite() {
        v.iter_mut().for_each(|a| *a /= norm);
    }
    norm
}
