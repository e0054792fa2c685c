//! Physics of the generated models against closed-form solutions and conservation
//! laws. Every tolerance says where it comes from: the solver's tolerance, the number
//! of steps, or rounding.

mod common;

use bgdsl_runtime::{Model, Solver};
use common::{dopri5, initial_state, max_abs, run, underdamped};
use models::{Duffing, DuffingParams, Oscillator, OscillatorParams, SeriesRlc, SeriesRlcParams};

/// Checks a trajectory column against a closed form: the largest error over the run,
/// relative to the largest value of the closed form, is below `tol`.
fn assert_matches(
    what: &str,
    times: &[f64],
    computed: &[f64],
    exact: impl Fn(f64) -> f64,
    tol: f64,
) {
    let expected: Vec<f64> = times.iter().map(|&t| exact(t)).collect();
    let scale = max_abs(expected.iter().copied());
    let error = max_abs(computed.iter().zip(&expected).map(|(c, e)| c - e));
    assert!(
        error <= tol * scale,
        "{what}: max error {error:e} exceeds {tol:e} x amplitude {scale:e} (relative {:e})",
        error / scale
    );
    eprintln!("{what}: max error {:e} of the amplitude", error / scale);
}

/// The two integrators used against closed forms, each tight enough for 1e-8: DP5
/// with local tolerance 1e-12 (global error over a few hundred steps stays near
/// 1e-10), and RK4 whose global error for an oscillator of angular frequency ω is about
/// `t ω (ω h)⁴ / 120` relative: with ω = 10 rad/s, h = 5e-4 s, t = 5 s that is 3e-10.
fn tight_solvers(atol: f64) -> [Solver; 2] {
    [dopri5(1e-12, atol), Solver::rk4(5e-4)]
}

mod should {
    use super::*;

    /// Mass-spring-damper released from rest with no force (the declared x(0) =
    /// 0.05 m) and, separately, a step force from rest at x = 0, against the closed
    /// form of the underdamped oscillator, over 5 s (8 periods). Defaults: m = 1 kg,
    /// k = 100 N/m, c = 0.4 N·s/m, so ω0 = 10 rad/s, α = c/2m = 0.2 1/s.
    #[test]
    fn oscillator_follows_its_closed_form_free_and_step_response() {
        let free = OscillatorParams {
            force: 0.0,
            ..Default::default()
        };
        let step = OscillatorParams {
            force: 1.0,
            ..Default::default()
        };
        for (case, params, x0) in [("free", free, None), ("step", step, Some(0.0))] {
            let model = Oscillator::new(params.clone());
            let mut state = initial_state(&model);
            assert_eq!(Oscillator::STATE_NAMES, ["mass.p", "spring.q"]);
            if let Some(x0) = x0 {
                state[1] = x0;
            }
            let (m, k, c, force) = (params.m, params.k, params.c, params.force);
            let (omega0, alpha) = ((k / m).sqrt(), c / (2.0 * m));
            let (y0, v0) = (state[1], state[0] / m);
            // x ~ 1e-2 m, p ~ 1e-1 kg·m/s: atol 1e-15 is at most 1e-13 of either scale.
            for solver in tight_solvers(1e-15) {
                let (traj, _) = run(&model, solver, &state, 5.0, 2001);
                let t = traj.times();
                let exact = |t: f64| underdamped(force / k, y0, v0, omega0, alpha, t);
                let label = format!("{case} response, {}", solver.name());
                assert_matches(
                    &format!("{label}: x"),
                    t,
                    traj.column("x").unwrap(),
                    |t| exact(t).0,
                    1e-8,
                );
                assert_matches(
                    &format!("{label}: speed"),
                    t,
                    traj.column("speed").unwrap(),
                    |t| exact(t).1,
                    1e-8,
                );
            }
        }
    }

    /// Series RLC switched onto a 1 V source at t = 0, from an empty capacitor and no
    /// current: `L q'' + R q' + q/Cap = V` is the oscillator again with q_eq = Cap·V,
    /// α = R/2L = 500 1/s, ω0 = 1/√(L·Cap) ≈ 3162 rad/s. Over 10 ms (5 periods).
    #[test]
    fn series_rlc_follows_its_closed_form() {
        let params = SeriesRlcParams::default();
        let model = SeriesRlc::new(params.clone());
        assert_eq!(SeriesRlc::STATE_NAMES, ["inductor.p", "capacitor.q"]);
        let (r, l, cap, v) = (
            params.resistance,
            params.inductance,
            params.capacitance,
            params.voltage,
        );
        let (omega0, alpha) = (1.0 / (l * cap).sqrt(), r / (2.0 * l));
        let exact = |t: f64| underdamped(cap * v, 0.0, 0.0, omega0, alpha, t);
        // q ~ 1e-5 C and λ ~ 1e-4 Wb: atol 1e-18 is 1e-13 of the smaller scale. RK4
        // needs h = 5e-4 / (ω0 / 10 rad/s) for the accuracy argued in `tight_solvers`.
        let solvers = [dopri5(1e-12, 1e-18), Solver::rk4(5e-4 * 10.0 / omega0)];
        for solver in solvers {
            let (traj, _) = run(&model, solver, &initial_state(&model), 0.01, 2001);
            let t = traj.times();
            let label = solver.name();
            let vc = traj.column("capacitor_voltage").unwrap();
            assert_matches(
                &format!("{label}: capacitor voltage"),
                t,
                vc,
                |t| exact(t).0 / cap,
                1e-8,
            );
            let i = traj.column("current").unwrap();
            assert_matches(&format!("{label}: current"), t, i, |t| exact(t).1, 1e-8);
        }
    }

    /// Lossless oscillator (c = 0, F = 0) and lossless LC circuit (R = 0, V = 0): the
    /// stored energy stays constant. Dormand–Prince is not symplectic, so the energy
    /// wanders with the global error: each accepted step changes the state by at most
    /// about rtol relative (its local error is controlled to that), hence the energy
    /// (quadratic in the state) by at most 2·rtol relative, and after N steps the drift
    /// is at most 2·N·rtol. Over 20 periods with rtol = 1e-10 that bound is about 1e-7;
    /// the drift seen is far below it.
    #[test]
    fn lossless_models_conserve_energy_to_the_integrators_tolerance() {
        let rtol = 1e-10;
        let oscillator = Oscillator::new(OscillatorParams {
            c: 0.0,
            force: 0.0,
            ..Default::default()
        });
        let period =
            2.0 * std::f64::consts::PI / (oscillator.params.k / oscillator.params.m).sqrt();
        let (traj, steps) = run(
            &oscillator,
            dopri5(rtol, 1e-16),
            &initial_state(&oscillator),
            20.0 * period,
            4001,
        );
        check_energy("oscillator", traj.column("energy").unwrap(), 2, steps, rtol);

        let lc = SeriesRlc::new(SeriesRlcParams {
            resistance: 0.0,
            voltage: 0.0,
            ..Default::default()
        });
        let p = &lc.params;
        let period = 2.0 * std::f64::consts::PI * (p.inductance * p.capacitance).sqrt();
        // Charge the capacitor to 1e-5 C and let it ring.
        let x0 = [0.0, 1e-5];
        let (traj, steps) = run(&lc, dopri5(rtol, 1e-20), &x0, 20.0 * period, 4001);
        check_energy("LC circuit", traj.column("energy").unwrap(), 2, steps, rtol);
    }

    /// The Duffing oscillator without damping or drive conserves
    /// `p²/2m + k q²/2 + k3 q⁴/4`; same bound as for the linear models (the energy is
    /// quartic in q, so a relative state error δ moves it by at most 4δ: bound 4·N·rtol).
    #[test]
    fn undamped_duffing_conserves_its_non_quadratic_energy() {
        let rtol = 1e-10;
        let model = Duffing::new(DuffingParams {
            c: 0.0,
            force: 0.0,
            x0: 2.0,
            ..Default::default()
        });
        let (traj, steps) = run(
            &model,
            dopri5(rtol, 1e-14),
            &initial_state(&model),
            30.0,
            3001,
        );
        let energy = traj.column("energy").unwrap();
        // At x0 = 2 m: k x0²/2 + k3 x0⁴/4 = 2 + 4 J.
        assert!((energy[0] - 6.0).abs() < 1e-15 * 6.0);
        check_energy("Duffing", energy, 4, steps, rtol);
    }

    /// From rest at amplitude A, the undamped Duffing oscillator `m x'' + k x + k3 x³ = 0`
    /// is `x = A cn(ω t | μ)` with `ω² = (k + k3 A²)/m`, `μ = k3 A² / (2 (k + k3 A²))`,
    /// so its period is `4 K(μ) / ω`. Integrating exactly one predicted period must
    /// bring the state back to `(A, 0)`. Near t = T the momentum is
    /// `p ≈ -(k A + k3 A³)(t - T)`, so `p(T) / (k A + k3 A³)` is the error of the
    /// predicted period: below 1e-9 T (DP5 at rtol 1e-12 over about a hundred steps;
    /// a 1 % error in k3 would move the period by about 0.3 %).
    #[test]
    fn duffing_period_matches_the_elliptic_integral() {
        // K(0.25), published (DLMF 19 / Abramowitz & Stegun table 17.1).
        assert!((elliptic_k(0.25) - 1.685_750_354_812_596).abs() < 4e-16);
        for amplitude in [0.5, 1.0, 3.0] {
            let params = DuffingParams {
                c: 0.0,
                force: 0.0,
                x0: amplitude,
                ..Default::default()
            };
            let (m, k, k3) = (params.m, params.k, params.k3);
            let model = Duffing::new(params);
            let omega = ((k + k3 * amplitude * amplitude) / m).sqrt();
            let mu = k3 * amplitude * amplitude / (2.0 * (k + k3 * amplitude * amplitude));
            let period = 4.0 * elliptic_k(mu) / omega;
            let (traj, _) = run(
                &model,
                dopri5(1e-12, 1e-15),
                &initial_state(&model),
                period,
                2,
            );
            let (p, q) = (traj.state(1, 0).unwrap(), traj.state(1, 1).unwrap());
            let restoring = k * amplitude + k3 * amplitude.powi(3);
            let period_error = p / restoring;
            assert!(
                period_error.abs() < 1e-9 * period,
                "A = {amplitude}: the orbit closes {period_error:e} s away from T = {period}"
            );
            assert!(
                (q - amplitude).abs() < 1e-9 * amplitude,
                "A = {amplitude}: q(T) = {q}"
            );
            eprintln!("A = {amplitude}: T = {period} s, orbit closes within {period_error:e} s");
        }
    }
}

/// Energy drift of a conservative run: `max |H - H(0)| / H(0)` must not exceed
/// `degree · steps · rtol`, where `degree` bounds how much a relative state error is
/// amplified in the energy (2 for a quadratic energy, 4 for a quartic one).
fn check_energy(what: &str, energy: &[f64], degree: u32, steps: usize, rtol: f64) {
    let h0 = energy[0];
    let drift = max_abs(energy.iter().map(|h| h - h0)) / h0;
    let bound = f64::from(degree) * steps as f64 * rtol;
    assert!(
        drift <= bound,
        "{what}: energy drift {drift:e} exceeds {degree}·N·rtol = {bound:e}"
    );
    eprintln!("{what}: energy drift {drift:e} over {steps} steps (bound {bound:e})");
}

/// The complete elliptic integral of the first kind in the parameter convention,
/// `K(μ) = π / (2 AGM(1, √(1 − μ)))`.
fn elliptic_k(mu: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - mu).sqrt());
    for _ in 0..32 {
        if (a - b).abs() <= 1e-16 * a {
            break;
        }
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (a + b)
}
