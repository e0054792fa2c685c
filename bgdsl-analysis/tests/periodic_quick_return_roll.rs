//! The quick return's out-of-plane Floquet multiplier 1.0817 (the periodic variant,
//! K3C's point under the slider) is an artefact of how the flagship writes its two
//! rotational joints, not of the mechanism: `docs/quick-return-floquet.md`.
//!
//! The flagship's `j23r` and `jC` are `Coupling`s whose spring state is the integral
//! of the relative angular velocity in frame 0, not a function of the two orientations.
//! `QuickReturnRotationSprings` is the same model with those two springs written as
//! the potential `k (3 − tr(R_aᵀ R_b))/2` of the relative orientation; every other joint
//! is already a spring of the configuration (checked here for `j3C`). With them the
//! growing multiplier is gone and every multiplier is inside the unit circle or 1.

use bgdsl_analysis::periodic::{periodic_orbit, PeriodicOptions, PeriodicOrbit};
use bgdsl_runtime::multibond::{rot_z, Matrix3, Vector3};
use bgdsl_runtime::{FromParams, Model, Simulation};
use models::quick_return::configuration_springs::{
    rotation_energy, rotation_moment, QuickReturnRotationSprings,
};
use models::quick_return::{QuickReturn, QuickReturnParams};
use nalgebra::Complex;

fn flagship() -> QuickReturn {
    QuickReturn::from_params(QuickReturnParams {
        k3c_point_under_slider: 1.0,
        ..Default::default()
    })
}

fn index<M: Model>(name: &str) -> usize {
    M::STATE_NAMES
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("no state {name}"))
}

fn vector<M: Model>(x: &[f64], name: &str) -> Vector3<f64> {
    Vector3::from_fn(|i, _| x[index::<M>(&format!("{name}_{}", ["x", "y", "z"][i]))])
}

fn rotation<M: Model>(x: &[f64], body: &str) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| x[index::<M>(&format!("{body}.R_{}{}", i + 1, j + 1))])
}

/// The assembled state of `M` with the crank and the slider rolled by 1e-3 rad about
/// their own long axes (each joint's spring starting unstretched as assembled), so the
/// motion leaves the plane.
fn tilted<M: Model>(model: &M) -> Vec<f64> {
    let mut x = vec![0.0; M::N_STATES];
    model.initial_state(&mut x);
    let roll = nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), 1e-3).into_inner();
    for body in ["crank", "slider"] {
        let r = rotation::<M>(&x, body) * roll;
        for i in 0..3 {
            for j in 0..3 {
                x[index::<M>(&format!("{body}.R_{}{}", i + 1, j + 1))] = r[(i, j)];
            }
        }
    }
    x
}

/// States and outputs at `times` of a run of `model` from `x0` at t = 0 (Radau5 at
/// `rtol` 1e-10, `atol` 1e-12).
fn run<M: Model>(model: &M, x0: &[f64], times: &[f64]) -> Vec<(Vec<f64>, Vec<f64>)> {
    let solver = bgdsl_runtime::Solver::Radau5(bgdsl_runtime::Radau5Options {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    });
    let mut sim = Simulation::new(model, solver).unwrap();
    let mut out = Vec::new();
    sim.run(0.0, x0, times, &mut |_t: f64, x: &[f64], y: &[f64]| {
        out.push((x.to_vec(), y.to_vec()))
    })
    .unwrap();
    out
}

/// `E(t_end) − E(0)`, the drive's work and the dampers' loss (trapezoids) over `times`
/// of a run from [`tilted`].
fn balance<M: Model>(model: &M, times: &[f64]) -> (f64, f64, f64) {
    let samples = run(model, &tilted(model), times);
    let col = |n: &str| M::OUTPUT_NAMES.iter().position(|o| *o == n).unwrap();
    let (e, p_in, p_diss) = (col("E_stored"), col("P_in"), col("P_diss"));
    let (mut work, mut loss) = (0.0, 0.0);
    for (k, pair) in samples.windows(2).enumerate() {
        let h = times[k + 1] - times[k];
        work += 0.5 * h * (pair[0].1[p_in] + pair[1].1[p_in]);
        loss += 0.5 * h * (pair[0].1[p_diss] + pair[1].1[p_diss]);
    }
    (samples.last().unwrap().1[e] - samples[0].1[e], work, loss)
}

/// The configuration springs store exactly what they absorb: along a run that leaves
/// the plane (0.2 s from [`tilted`]), the stored energy (kinetic, the joints' springs
/// with the rotation springs' potentials `k (3 − tr(R_aᵀ R_b))/2`, gravity) changes by
/// the drive's work less the dampers' loss. The trapezoids (20,000 samples) leave an
/// imbalance of 1.2e-3 J over the start's fast transient (it falls as h²: 4.3e-3 at
/// 10,000), the same in the flagship, whose `Coupling`s store `½ k q²` exactly; the
/// two imbalances agree to 2 % of the rotation springs' energy change (measured: to
/// all printed digits), where a wrong sign of the spring's torque would part them by
/// twice that change (6e-3 J). Costs under 1 s in debug.
#[test]
fn rotation_springs_close_the_power_balance() {
    type V = QuickReturnRotationSprings;
    let model = V::default();
    let n = 20000;
    let times: Vec<f64> = (0..=n).map(|k| 0.2 * k as f64 / n as f64).collect();
    let (change, work, loss) = balance(&model, &times);
    let (f_change, f_work, f_loss) = balance(&flagship(), &times);
    let (imbalance, f_imbalance) = (change - (work - loss), f_change - (f_work - f_loss));
    let p = model.params();
    let springs = |t: f64, x: &[f64]| {
        rotation_energy(
            p.K23r,
            rotation::<V>(x, "slider"),
            rotation::<V>(x, "rocker"),
        ) + rotation_energy(
            p.K_C,
            rot_z(p.theta0 + p.w_drive * t),
            rotation::<V>(x, "crank"),
        )
    };
    let ends = run(&model, &tilted(&model), &[0.0, 0.2]);
    let stored = springs(0.2, &ends[1].0) - springs(0.0, &ends[0].0);
    eprintln!(
        "variant: dE {change:.6e} work {work:.6e} loss {loss:.6e} imbalance {imbalance:.4e}; \
         flagship imbalance {f_imbalance:.4e}; rotation springs' energy change {stored:.3e}"
    );
    assert!(stored.abs() > 1e-4, "{stored}");
    assert!(
        (imbalance - f_imbalance).abs() < 0.02 * stored.abs(),
        "{imbalance} vs {f_imbalance}"
    );
}

/// Which of the flagship's joints are springs of the configuration. Along a run that
/// leaves the plane (0.6 s from [`tilted`]):
/// - `j3C` (a `FrameCoupling` in the rocker's frame, its point under the slider):
///   `q − R₃ᵀ(r_slider − r_rocker)` stays at its start to 1e-9 m (the solver's
///   tolerance; measured 1.1e-11): its spring is a function of the configuration;
/// - `j23r` and `jC` (`Coupling`s of angular velocities): `q + vee(asym(R_b R_aᵀ))`,
///   which a spring of the relative orientation would keep to second order in the
///   relative angles (1e-3 rad out of the plane, 1e-2 in it: 1e-5 rad), moves out of
///   the plane by more than 1e-4 rad (measured 5.2e-4 and 2.0e-3): the integral of the
///   relative angular velocity in frame 0 is not the relative rotation once the
///   bodies turn (for `jC` the drive turns 5 rad/s under the crank's roll).
///
/// Costs under 1 s in debug.
#[test]
fn flagship_rotational_couplings_are_not_springs_of_the_configuration() {
    type Q = QuickReturn;
    let model = flagship();
    let times: Vec<f64> = (0..=6).map(|k| 0.1 * k as f64).collect();
    let samples = run(&model, &tilted(&model), &times);
    let p = model.params();
    let j3c = |x: &[f64]| {
        vector::<Q>(x, "j3C.spring.q")
            - rotation::<Q>(x, "rocker").transpose()
                * (vector::<Q>(x, "slider.r") - vector::<Q>(x, "rocker.r"))
    };
    let phantom = |x: &[f64], t: f64, joint: &str| -> Vector3<f64> {
        let (ra, rb) = if joint == "jC" {
            (rot_z(p.theta0 + p.w_drive * t), rotation::<Q>(x, "crank"))
        } else {
            (rotation::<Q>(x, "slider"), rotation::<Q>(x, "rocker"))
        };
        vector::<Q>(x, &format!("{joint}.spring.q")) + rotation_moment(ra, rb)
    };
    let x0 = &samples[0].0;
    let (mut j3c_drift, mut drift) = (0.0f64, [0.0f64; 2]);
    for (k, (x, _)) in samples.iter().enumerate() {
        j3c_drift = j3c_drift.max((j3c(x) - j3c(x0)).norm());
        for (d, joint) in drift.iter_mut().zip(["j23r", "jC"]) {
            let change = phantom(x, times[k], joint) - phantom(x0, 0.0, joint);
            *d = d.max(change.x.hypot(change.y));
        }
    }
    eprintln!(
        "j3C drift {j3c_drift:.2e} m; out-of-plane phantom drift j23r {:.2e}, jC {:.2e} rad",
        drift[0], drift[1]
    );
    assert!(j3c_drift < 1e-9, "{j3c_drift}");
    assert!(drift.iter().all(|d| *d > 1e-4), "{drift:?}");
}

/// The multipliers of the orbit at `steps` SDIRK steps per period.
fn multipliers<M: Model>(model: &M, steps: usize) -> (PeriodicOrbit, Vec<Complex<f64>>) {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut options = PeriodicOptions::new(core::f64::consts::TAU / 5.0);
    options.warmup_periods = 2;
    options.steps = steps;
    let orbit = periodic_orbit(model, &x0, &[], &options).unwrap();
    let mu = orbit.multipliers.clone();
    eprintln!(
        "{steps} steps: {:?}",
        mu.iter().take(5).map(|m| (m.re, m.im)).collect::<Vec<_>>()
    );
    (orbit, mu)
}

/// The real multipliers above `1 + 1e-3`.
fn real_growing(mu: &[Complex<f64>]) -> Vec<f64> {
    mu.iter()
        .filter(|m| m.im.abs() < 1e-9 && m.re > 1.0 + 1e-3)
        .map(|m| m.re)
        .collect()
}

/// The decisive comparison, at 800 and 1,600 SDIRK steps per period (the multipliers'
/// error is that of the monodromy matrix's integration; a genuine multiplier does not
/// move when the steps double, the √ε split of a neutral Jordan block shrinks):
///
/// - the flagship has one real multiplier 1.0817 at both (to 1e-3; s24 measured it to
///   6,400 steps), beside a complex pair whose distance from 1 shrinks by more than
///   3× when the steps double (0.39 → 0.099: the neutral roll's Jordan block split);
/// - with configuration springs there is no real multiplier above 1 + 1e-3 at either;
///   the same spurious pair shrinks the same way; all others are inside the unit circle
///   or 1 to 1e-3: the neutral ones (first integrals of the point joints, the cyclic
///   rolls of the axisymmetric rocker with the slider and of the rod, the output
///   slider's free spin);
/// - the two orbits' states at t₀ agree (bodies' positions, orientations and momenta)
///   to 5e-3 of each state's scale (measured 1.8e-3, the crank's momentum: the
///   springs differ by `sin θ` against `θ`, and the flagship's phase is its own).
///
/// Four orbits: 17 s in release, several minutes in debug, so ignored:
/// `cargo test --release -p bgdsl-analysis --test periodic_quick_return_roll -- --ignored --nocapture`.
#[test]
#[ignore]
fn configuration_springs_remove_the_growing_multiplier() {
    let spread = |mu: &[Complex<f64>]| {
        mu.iter()
            .filter(|m| m.im.abs() > 1e-9 && m.norm() > 1.0 + 1e-3)
            .map(|m| (*m - 1.0).norm())
            .fold(0.0f64, f64::max)
    };
    let flag = flagship();
    let (_, coarse) = multipliers(&flag, 800);
    let (orbit, fine) = multipliers(&flag, 1600);
    for mu in [&coarse, &fine] {
        let real = real_growing(mu);
        assert!(
            real.len() == 1 && (real[0] - 1.0817).abs() < 1e-3,
            "{real:?}"
        );
    }
    assert!(
        spread(&coarse) > 3.0 * spread(&fine),
        "{} {}",
        spread(&coarse),
        spread(&fine)
    );

    let variant = QuickReturnRotationSprings::default();
    let (_, v_coarse) = multipliers(&variant, 800);
    let (v_orbit, v_fine) = multipliers(&variant, 1600);
    for mu in [&v_coarse, &v_fine] {
        assert!(real_growing(mu).is_empty(), "{:?}", real_growing(mu));
    }
    assert!(
        spread(&v_coarse) > 3.0 * spread(&v_fine),
        "{} {}",
        spread(&v_coarse),
        spread(&v_fine)
    );
    for m in v_fine
        .iter()
        .filter(|m| m.im.abs() < 1e-9 || m.norm() <= 1.0 + 1e-3)
    {
        assert!(m.norm() < 1.0 || (m - 1.0).norm() < 1e-3, "{m}");
    }

    let mut worst = (0.0f64, "");
    let peak = orbit.x0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (j, name) in QuickReturnRotationSprings::STATE_NAMES.iter().enumerate() {
        let body = ["crank.", "slider.", "rocker.", "rod.", "output_slider."];
        if !body.iter().any(|b| name.starts_with(b)) {
            continue;
        }
        let i = index::<QuickReturn>(name);
        let scale = if name.contains(".R_") {
            1.0
        } else {
            orbit.x0[i].abs() + 1e-3 * peak
        };
        let e = (orbit.x0[i] - v_orbit.x0[j]).abs() / scale;
        if e > worst.0 {
            worst = (e, name);
        }
    }
    eprintln!(
        "orbits differ by {:.2e} of the scale of {}",
        worst.0, worst.1
    );
    assert!(worst.0 < 5e-3, "{worst:?}");
}
