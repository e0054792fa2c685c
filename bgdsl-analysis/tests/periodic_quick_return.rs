//! The quick return's steady cycle at 5 rad/s (the periodic variant, K3C's point under
//! the slider's centre), found directly by shooting from the assembled initial state
//! after two periods of warm-up, against the last turn of a long run (20 periods); its
//! Floquet multipliers.

use bgdsl_analysis::periodic::{periodic_orbit, PeriodicOptions, PeriodicOrbit};
use bgdsl_runtime::{FromParams, Model, Simulation};
use models::quick_return::{QuickReturn, QuickReturnParams};

fn periodic_variant() -> QuickReturn {
    QuickReturn::from_params(QuickReturnParams {
        k3c_point_under_slider: 1.0,
        ..Default::default()
    })
}

fn index(name: &str) -> usize {
    QuickReturn::STATE_NAMES
        .iter()
        .position(|n| *n == name)
        .unwrap()
}

/// The states at `times` of a run from `x0` at `t0`.
fn states_at(
    model: &QuickReturn,
    options: &PeriodicOptions,
    t0: f64,
    x0: &[f64],
    times: &[f64],
) -> Vec<Vec<f64>> {
    let mut sim = Simulation::new(model, options.solver).unwrap();
    let mut out = Vec::new();
    sim.run(t0, x0, times, &mut |_t: f64, x: &[f64], _y: &[f64]| {
        out.push(x.to_vec())
    })
    .unwrap();
    out
}

fn orbit() -> (QuickReturn, PeriodicOptions, PeriodicOrbit) {
    let model = periodic_variant();
    let period = core::f64::consts::TAU / model.params().w_drive;
    let mut x0 = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x0);
    let mut options = PeriodicOptions::new(period);
    options.warmup_periods = 2;
    if let Ok(v) = std::env::var("NEUTRAL") {
        options.neutral_tolerance = v.parse().unwrap();
    }
    if let Ok(v) = std::env::var("TOL") {
        options.tolerance = v.parse().unwrap();
    }
    options.steps = std::env::var("STEPS").map_or(400, |s| s.parse().unwrap());
    let orbit = periodic_orbit(&model, &x0, &[], &options).unwrap();
    (model, options, orbit)
}

/// The orbit, one period sampled 100 times from the state found, equals the 20th turn
/// of a run from rest sampled at the same drive angles (the model is autonomous: the
/// orbit's phase is the drive angle its state says, the crank's angle plus the drive
/// coupling's twist), to 2e-4 of each state's range over the turn (measured: see the
/// printed value; the long run has itself settled to about 1e-5 of it, the slowest
/// decaying multiplier being printed too).
///
/// Ignored: it fails today. Shooting converges (3 Newton iterations after the warm-up,
/// scaled residual 7e-5 against a tolerance of 1e-4), but the orbit found is not the
/// long run's: at the same drive angle the crank is 1.8e-4 rad ahead and the drive
/// coupling's twist 1.8e-4 rad less, and `rod.R_11` differs by 2.6e-2 of its range,
/// while the long run has settled (turn 19 against turn 20: 1e-11). With a tolerance of
/// 1e-5 Newton stalls at 4e-5 (the period map's integration noise, in `rocker.R_32`).
/// See `docs/periodic-and-fitting.md`, "Open".
#[test]
#[ignore = "fails: the orbit found differs from the long run's settled turn (see the doc comment)"]
fn quick_return_cycle_equals_the_last_turn_of_a_long_run() {
    let (model, options, orbit) = orbit();
    let period = options.period;
    eprintln!(
        "iterations {} residual {:e} (neutral {:e}) periods {}",
        orbit.iterations, orbit.residual, orbit.neutral_residual, orbit.periods_integrated
    );
    let x = &orbit.x0;
    let drive_angle =
        x[index("crank.R_21")].atan2(x[index("crank.R_11")]) + x[index("jC.spring.q_z")];
    let theta0 = model.params().theta0;
    let tau = (drive_angle - theta0).rem_euclid(core::f64::consts::TAU) / model.params().w_drive;
    let samples = 100;
    let offsets: Vec<f64> = (0..samples)
        .map(|j| j as f64 * period / samples as f64)
        .collect();
    let on_orbit = states_at(&model, &options, 0.0, x, &offsets);
    let mut start = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut start);
    let long: Vec<f64> = offsets.iter().map(|o| 19.0 * period + tau + o).collect();
    let settled = states_at(&model, &options, 0.0, &start, &long);
    let earlier: Vec<f64> = long.iter().map(|t| t - period).collect();
    let before = states_at(&model, &options, 0.0, &start, &earlier);
    for name in [
        "rod.R_11",
        "crank.R_11",
        "jC.spring.q_z",
        "output_slider.r_x",
        "rocker.R_11",
    ] {
        let i = index(name);
        let d1 = on_orbit
            .iter()
            .zip(&settled)
            .fold(0.0f64, |m, (a, b)| m.max((a[i] - b[i]).abs()));
        let d2 = before
            .iter()
            .zip(&settled)
            .fold(0.0f64, |m, (a, b)| m.max((a[i] - b[i]).abs()));
        eprintln!(
            "{name}: orbit vs turn 20 {d1:e}; turn 19 vs 20 {d2:e}; x* {} turn-20 start {}",
            x[i], settled[0][i]
        );
    }
    let big = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = (0.0, "");
    for i in 0..QuickReturn::N_STATES {
        if orbit.free_states.iter().any(|f| f.index == i) {
            continue;
        }
        let (lo, hi) = on_orbit
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x[i]), hi.max(x[i]))
            });
        let range = hi - lo + 1e-3 * big;
        for (a, b) in on_orbit.iter().zip(&settled) {
            let e = (a[i] - b[i]).abs() / range;
            if e > worst.0 {
                worst = (e, QuickReturn::STATE_NAMES[i]);
            }
        }
    }
    eprintln!(
        "largest difference: {:e} of the range of {}",
        worst.0, worst.1
    );
    assert!(worst.0 < 2e-4, "{worst:?}");
}

/// Multipliers inside the unit circle but for the neutral directions: their subspace
/// contains the velocity along the orbit (the model is autonomous: moving along the
/// orbit is neutral, multiplier exactly 1).
///
/// Ignored: it fails today: the Schur iteration does not converge on the monodromy
/// matrix restricted to the rotations, so no multiplier is reported.
#[test]
#[ignore = "fails: no multipliers (Schur does not converge on the reduced monodromy)"]
fn quick_return_multipliers() {
    let (_model, _options, orbit) = orbit();
    for mu in orbit.multipliers.iter().take(30) {
        eprintln!("  mu = {:.6} {:+.6}i |mu| = {:.6}", mu.re, mu.im, mu.norm());
    }
    eprintln!("multipliers: {}", orbit.multipliers.len());
    eprintln!("neutral: {:?}", orbit.neutral);
    eprintln!("free: {:?}", orbit.free_states);
    assert!(!orbit.multipliers.is_empty());
    assert!(orbit.multipliers.iter().all(|m| m.norm() < 1.0 + 1e-3));
    assert!(
        orbit.neutral.along_flow > 0.99,
        "{}",
        orbit.neutral.along_flow
    );
}
