//! The stick-slip oscillator (a mass on a spring riding a moving belt, Coulomb friction
//! with stiction) against an independent event-driven closed-form solution
//! (`belt_friction/reference.rs`).

#[path = "belt_friction/reference.rs"]
mod reference;

use reference::{Belt, Phase};

/// The catalogue's default belt: m = 1 kg, k = 10 N/m, v_b = 0.1 m/s, μs = 0.6,
/// μk = 0.4, g = 9.81 m/s².
fn belt() -> Belt {
    Belt {
        m: 1.0,
        k: 10.0,
        v_b: 0.1,
        fs: 0.6 * 9.81,
        fc: 0.4 * 9.81,
    }
}

/// The reference itself: energy closes phase by phase (the closed forms of the loss and
/// the belt's work against the state's energy), and the limit cycle has the textbook
/// durations: stick 2 (fs − fc) / (k v_b), slip (π + 2 atan(v_b / (ω d))) / ω with
/// d = (fs − fc) / k.
#[test]
fn the_reference_closes_its_energy_and_reaches_the_textbook_limit_cycle() {
    let b = belt();
    let segments = b.solve(-1.0, 0.0, 40.0);
    let phases: Vec<Phase> = segments.iter().take(4).map(|s| s.phase).collect();
    assert_eq!(
        phases,
        [Phase::SlipSlower, Phase::SlipFaster, Phase::Stick, Phase::SlipSlower]
    );
    for s in &segments {
        let (x1, v1) = b.state(s.phase, s.x0, s.v0, s.t1 - s.t0);
        let change = b.energy(x1, v1) - b.energy(s.x0, s.v0);
        let account = b.belt_work(s) - b.friction_loss(s);
        assert!(
            (change - account).abs() < 1e-12,
            "{s:?}: ΔE {change} vs {account}"
        );
    }
    let w = (b.k / b.m).sqrt();
    let d = (b.fs - b.fc) / b.k;
    let stick = 2.0 * (b.fs - b.fc) / (b.k * b.v_b);
    let slip = (core::f64::consts::PI + 2.0 * (b.v_b / (w * d)).atan()) / w;
    let full: Vec<_> = segments[2..segments.len() - 1].to_vec();
    assert!(full.len() >= 10, "{} phases", full.len());
    for s in &full[1..] {
        let expected = if s.phase == Phase::Stick { stick } else { slip };
        assert!(
            (s.t1 - s.t0 - expected).abs() < 1e-12,
            "{s:?}: {} vs {expected}",
            s.t1 - s.t0
        );
    }
}
