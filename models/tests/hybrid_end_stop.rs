//! The mass on a spring hitting an end stop, against the closed form of harmonic
//! flights joined by Newton's restitution law.
//!
//! With `ω = √(k/m)`, released at rest at `-A`, the mass reaches the stop `x_s` first at
//! `t₁ = acos(-x_s / A) / ω` with speed `u₁ = ω √(A² − x_s²)`. After the k-th impact it
//! leaves at `wₖ = e^k u₁`; the flight `x(τ) = x_s cos ωτ − (wₖ/ω) sin ωτ =
//! R cos(ωτ + φₖ)` (`φₖ = atan2(wₖ/ω, x_s)`) is back at `x_s` when `ωτ = 2π − 2φₖ`,
//! with speed `wₖ` (energy is conserved in flight).

use bgdsl_runtime::{DormandPrinceOptions, Model, Simulation, Solver, Trajectory};
use models::hybrid::{EndStop, EndStopParams};

/// (time, rebound velocity) of the closed form's first `n` impacts.
fn impacts(p: &EndStopParams, n: usize) -> Vec<(f64, f64)> {
    let omega = (p.k / p.m).sqrt();
    let mut t = (-p.x_stop / p.amplitude).acos() / omega;
    let mut u = omega * (p.amplitude.powi(2) - p.x_stop.powi(2)).sqrt();
    let mut out = Vec::new();
    for _ in 0..n {
        let w = p.restitution * u;
        out.push((t, -w));
        let phi = (w / omega).atan2(p.x_stop);
        t += (2.0 * std::f64::consts::PI - 2.0 * phi) / omega;
        u = w;
    }
    out
}

/// Eight impacts (5 s) with DOPRI5 at rtol 1e-12: instants to 1e-9 s and rebound
/// velocities to 1e-9 m/s. The flights are not polynomials, so the integration error
/// counts here: at this tolerance DOPRI5's global error over 5 s of a 10 rad/s
/// oscillator is of order 1e-11 m, which moves an impact (approach speed ≥ 0.07 m/s)
/// by well under 1e-9 s; the location itself is to 1e-12 s.
#[test]
fn impacts_and_rebounds_match_the_closed_form() {
    let model = EndStop::default();
    let hits = impacts(&model.params, 8);
    let mut x0 = vec![0.0; EndStop::STATE_NAMES.len()];
    model.initial_state(&mut x0);
    let solver = Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-12,
        atol: 1e-14,
        ..Default::default()
    });
    let t_end = hits.last().unwrap().0 + 0.1;
    let mut traj = Trajectory::for_model::<EndStop>(2).with_event_capacity(16);
    Simulation::new(&model, solver)
        .unwrap()
        .run(0.0, &x0, &[0.0, t_end], &mut traj)
        .unwrap();
    let momentum = EndStop::STATE_NAMES
        .iter()
        .position(|n| *n == "mass.p")
        .unwrap();
    let events = traj.events();
    assert_eq!(events.len(), hits.len(), "one event per impact");
    for (k, (event, &(t, w))) in events.iter().zip(&hits).enumerate() {
        let rebound = event.after[momentum] / model.params.m;
        assert!((event.t - t).abs() < 1e-9, "impact {k}: {} vs {t}", event.t);
        assert!((rebound - w).abs() < 1e-9, "rebound {k}: {rebound} vs {w}");
        let approach = event.before[momentum] / model.params.m;
        assert!(
            (rebound + model.params.restitution * approach).abs() < 1e-15,
            "restitution applied exactly"
        );
    }
}
