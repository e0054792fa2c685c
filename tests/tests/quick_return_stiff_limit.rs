//! The flagship written in the language (`models::quick_return::QuickReturn`) in the
//! near-rigid limit, against the rigid-body reference `models::quick_return_rigid`:
//! with every translational joint and the drive coupling 100× stiffer and more damped,
//! the compliant model must move and load like the rigid mechanism. The same check as
//! test (e) of `tests/quick_return_hand.rs` on the hand-written model, with the same
//! tolerances; every tolerance says where it comes from.
//!
//! The rigid reference is an inverse dynamics: given the crank's angle, angular
//! velocity and angular acceleration it returns the drive torque and the joint forces.
//! The generated model has no outputs for the crank's rates, so they are computed here
//! from the state at each sample, exactly: `w = R J⁻¹ Rᵀ h` from the crank's orientation
//! `R1` and angular momentum `h1` (the rigid body's own law), and `dw/dt` as the exact
//! directional derivative of that expression along the model's own state derivative
//! (dual numbers seeded with `dx/dt` at the sample). That is what the hand-written
//! model's `w1`/`dw1` outputs compute (`dw/dt = M (dh/dt − w × h)`, `M = R J⁻¹ Rᵀ`),
//! so both models are compared with the reference at the same quantities, with no
//! differentiation error. In this run the crank's speed stays within 4.9955–5.0008 rad/s
//! and its acceleration within ±0.08 rad/s² after the transient, so the choice matters
//! little at the 1 % tolerance, but it is measurable: taking the nominal 5 rad/s and 0
//! instead moves the reference torque by 0.058 N·m (0.1 % of its peak), and central
//! differences of the 1 ms crank angle get the acceleration wrong by 0.04 rad/s²
//! (half of it), moving the torque by 0.004 N·m.

use core::f64::consts::{PI, TAU};

use bgdsl_runtime::multibond::{box_inertia, vec3, Matrix3, Vector3};
use bgdsl_runtime::{Dual, Model, Radau5Options, Simulation, Solver, Trajectory};
use models::quick_return::{QuickReturn, QuickReturnParams};
use models::quick_return_rigid::{quick_return_cycle, rigid_state, RigidParams, RigidSolution};

/// The stiff limit of the issue: every translational coupling's stiffness and damping
/// (K01, R01, K12, R12, K03, R03, K34, R34, K45, R45 and the y, z entries of K3C, R3C,
/// K5C, R5C) and the drive coupling's K_C and R_C 100× larger; the slide frictions
/// R3C.x and R5C.x (20 N·s/m, which the rigid reference also has) and the slider's
/// rotational coupling K23r, R23r unchanged.
fn stiff_limit() -> QuickReturnParams {
    let d = QuickReturnParams::default();
    let f = 100.0;
    QuickReturnParams {
        K01: f * d.K01,
        R01: f * d.R01,
        K12: f * d.K12,
        R12: f * d.R12,
        K03: f * d.K03,
        R03: f * d.R03,
        K3C: [d.K3C[0], f * d.K3C[1], f * d.K3C[2]],
        R3C: [d.R3C[0], f * d.R3C[1], f * d.R3C[2]],
        K_C: f * d.K_C,
        R_C: f * d.R_C,
        K34: f * d.K34,
        R34: f * d.R34,
        K45: f * d.K45,
        R45: f * d.R45,
        K5C: [d.K5C[0], f * d.K5C[1], f * d.K5C[2]],
        R5C: [d.R5C[0], f * d.R5C[1], f * d.R5C[2]],
        ..d
    }
}

fn output(name: &str) -> usize {
    QuickReturn::OUTPUT_NAMES
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("no output {name}"))
}

/// The crank's angular velocity and angular acceleration about Z0 at state `x`:
/// `w = R J⁻¹ Rᵀ h` on the outputs `R1` and `h1` evaluated at `x + ε dx/dt`, whose
/// ε-part is `dw/dt`.
fn crank_rates(model: &QuickReturn, t: f64, x: &[f64]) -> (f64, f64) {
    let mut dx = vec![0.0; QuickReturn::N_STATES];
    model.derivatives(t, x, &mut dx);
    let xd: Vec<Dual> = x.iter().zip(&dx).map(|(&v, &d)| Dual::new(v, d)).collect();
    let mut y = vec![Dual::constant(0.0); QuickReturn::N_OUTPUTS];
    model.outputs(t, &xd, &mut y);
    let r = Matrix3::from_fn(|i, j| y[output(&format!("R1_{}{}", i + 1, j + 1))]);
    let h = Vector3::from_fn(|i, _| y[output(["h1_x", "h1_y", "h1_z"][i])]);
    let p = &model.params;
    let j = box_inertia(p.m1, p.l1[0], p.l1[1], p.l1[2]);
    let j_inv = Matrix3::from_diagonal(&vec3(
        Dual::constant(1.0 / j.x),
        Dual::constant(1.0 / j.y),
        Dual::constant(1.0 / j.z),
    ));
    let w = r * j_inv * r.transpose() * h;
    (w.z.re, w.z.eps)
}

/// What a run gives the comparison: the samples after the transient and the crank's
/// rates at each.
struct Run {
    traj: Trajectory,
    /// The first sample at or after 2.5 s.
    first: usize,
    /// The crank's angular velocity and acceleration about Z0 at each sample from
    /// `first` on, rad/s and rad/s².
    rates: Vec<(f64, f64)>,
}

/// 0–5 s of `params` with Radau5 at rtol 1e-7, atol 1e-11 (the joints' deflections
/// are ~1e-5 m in the stiff limit: 10–300 N on 1e7 N/m; Radau5 scales atol by
/// `0.1 rtol^(-1/3)` ≈ 20, so they are held to ~2e-10 m, 2e-5 of themselves), sampled
/// every 1 ms: the sampling the turning points are interpolated on.
fn run(params: QuickReturnParams) -> Run {
    let model = QuickReturn::new(params);
    let mut x0 = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x0);
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-7,
        atol: 1e-11,
        ..Default::default()
    });
    let mut sim = Simulation::new(&model, solver).unwrap();
    let n = 5001;
    let mut traj = Trajectory::for_model::<QuickReturn>(n);
    let mut rates = Vec::with_capacity(n);
    let started = std::time::Instant::now();
    let times: Vec<f64> = (0..n).map(|k| k as f64 / 1000.0).collect();
    let stats = sim
        .run(0.0, &x0, &times, &mut |t: f64, x: &[f64], y: &[f64]| {
            bgdsl_runtime::Recorder::record(&mut traj, t, x, y);
            if t >= 2.5 {
                rates.push(crank_rates(&model, t, x));
            }
        })
        .unwrap();
    eprintln!(
        "k3c_point_under_slider = {}: radau5 0-5 s: {stats:?} in {:?}",
        model.params.k3c_point_under_slider,
        started.elapsed()
    );
    let first = traj.times().iter().position(|&t| t >= 2.5).unwrap();
    assert_eq!(rates.len(), n - first);
    Run { traj, first, rates }
}

/// The output slider's turning points after the transient: `(time, at the right end)`
/// where its momentum `p5_x` changes sign, interpolated linearly between samples (the
/// momentum crosses zero with a finite slope: O(h²) of the 1 ms spacing, ~1e-5 s).
fn turning_points(run: &Run) -> Vec<(f64, bool)> {
    let p5 = &run.traj.column("p5_x").unwrap()[run.first..];
    let t = &run.traj.times()[run.first..];
    let mut turns = Vec::new();
    for k in 1..p5.len() {
        if p5[k - 1] != 0.0 && p5[k - 1].signum() != p5[k].signum() {
            let frac = p5[k - 1] / (p5[k - 1] - p5[k]);
            turns.push((t[k - 1] + frac * (t[k] - t[k - 1]), p5[k - 1] > 0.0));
        }
    }
    turns
}

/// The crank's period: the time between its first and last crossing of a multiple of
/// 2π after the transient, over the whole turns between them (crossings interpolated
/// linearly on the unwrapped angle, which advances steadily at ~5 rad/s).
fn crank_period(run: &Run) -> f64 {
    let angle = &run.traj.column("crank_angle").unwrap()[run.first..];
    let t = &run.traj.times()[run.first..];
    let mut unwrapped = vec![angle[0]];
    for k in 1..angle.len() {
        let step = (angle[k] - angle[k - 1] + PI).rem_euclid(TAU) - PI;
        unwrapped.push(unwrapped[k - 1] + step);
    }
    let mut crossings = Vec::new();
    for k in 1..unwrapped.len() {
        let (a, b) = (unwrapped[k - 1] / TAU, unwrapped[k] / TAU);
        if a.floor() != b.floor() {
            let frac = (b.floor() - a) / (b - a);
            crossings.push(t[k - 1] + frac * (t[k] - t[k - 1]));
        }
    }
    assert!(crossings.len() >= 2, "crank crossings {crossings:?}");
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

/// The comparison, for one choice of K3C's rocker point; returns the worst deviation
/// of the drive torque and joint forces as a fraction of their peaks.
fn check_against_rigid(params: QuickReturnParams) -> f64 {
    let rigid = RigidParams::of_model(&params);
    // The reference's own cycle: ratio exactly 2 (240° forward, 120° back).
    assert!((quick_return_cycle(&rigid).time_ratio - 2.0).abs() < 1e-12);
    let run = run(params);
    let col = |name: &str| &run.traj.column(name).unwrap()[run.first..];
    let angle = col("crank_angle");
    let solutions: Vec<RigidSolution> = angle
        .iter()
        .zip(&run.rates)
        .map(|(&theta, &(w, dw))| rigid_state(theta, w, dw, &rigid))
        .collect();
    let (w_lo, w_hi) = run.rates.iter().fold((f64::MAX, f64::MIN), |(lo, hi), r| {
        (lo.min(r.0), hi.max(r.0))
    });
    eprintln!("crank speed after the transient: {w_lo:.4} to {w_hi:.4} rad/s");

    // Drive torque and joint forces: within 1 % of each signal's peak. What remains in
    // the stiff limit is the joints' compliance and damping (the 100× stiffer joints
    // still deflect ~1e-5 m and their dampers carry the vibration). Seen: 0.13–0.35 %
    // (the largest on F_O1_y, whose peak is small), as on the hand-written model.
    type Pick = fn(&RigidSolution) -> f64;
    let signals: [(&str, Pick); 9] = [
        ("Tc_z", |s| s.tc[2]),
        ("F_O1_x", |s| s.f_o1[0]),
        ("F_O1_y", |s| s.f_o1[1]),
        ("F_A2_x", |s| s.f_a2[0]),
        ("F_A2_y", |s| s.f_a2[1]),
        ("F_O3_x", |s| s.f_o3[0]),
        ("F_O3_y", |s| s.f_o3[1]),
        ("F_O5_x", |s| s.f_o5[0]),
        ("F_O5_y", |s| s.f_o5[1]),
    ];
    let mut worst: f64 = 0.0;
    for (name, pick) in signals {
        let simulated = col(name);
        let reference: Vec<f64> = solutions.iter().map(pick).collect();
        let peak = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let error = simulated
            .iter()
            .zip(&reference)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        worst = worst.max(error / peak);
        eprintln!(
            "{name}: peak {peak:.4}, largest difference {:.3} % of the peak",
            100.0 * error / peak
        );
        assert!(
            error <= 0.01 * peak,
            "{name}: difference {error} > 1 % of peak {peak}"
        );
    }

    // The output slider within 1 mm: the joints' deflections (~1e-5 m) reach it
    // magnified by the rocker's lever (0.7 m over the slider's 0.2 m from O3 at the
    // quick return's end) and the rod. Seen: 0.42 mm, as on the hand-written model.
    let x5 = col("r_C5_x");
    let error = x5
        .iter()
        .zip(&solutions)
        .fold(0.0f64, |m, (a, s)| m.max((a - s.output_x.value).abs()));
    eprintln!("output slider: largest difference {:.3} mm", 1e3 * error);
    assert!(error <= 1e-3, "output slider off by {error} m");

    // The quick-return time ratio 2.00 ± 0.01: the rigid kinematics gives exactly 2,
    // the compliance shifts the turning points by ~1e-4 s (1.9994 is seen on the
    // hand-written model and here), the interpolation locates them to ~1e-5 s.
    let turns = turning_points(&run);
    assert!(turns.len() >= 4, "turning points {turns:?}");
    let (mut forward, mut back) = (Vec::new(), Vec::new());
    for pair in turns.windows(2) {
        let duration = pair[1].0 - pair[0].0;
        if pair[0].1 {
            forward.push(duration);
        } else {
            back.push(duration);
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let ratio = mean(&forward) / mean(&back);
    eprintln!("turning points {turns:?}, time ratio {ratio:.5}");
    assert!((ratio - 2.0).abs() <= 0.01, "time ratio {ratio}");

    // The period 2π/5 s ± 0.2 %: from successive same-side turning points of the
    // output slider (located to ~1e-5 s, 1e-5 of the period; the rest is how far the
    // motion is from periodic after 2.5 s), and from the crank's crossings of multiples
    // of 2π (the drive coupling only lets the crank lag by a bounded angle, so it
    // turns at exactly 5 rad/s on average).
    let period = TAU / 5.0;
    let crank = crank_period(&run);
    eprintln!(
        "crank period {crank:.6} s ({:+.4} %)",
        100.0 * (crank / period - 1.0)
    );
    assert!((crank / period - 1.0).abs() <= 2e-3, "crank period {crank}");
    for same in [true, false] {
        let at: Vec<f64> = turns.iter().filter(|t| t.1 == same).map(|t| t.0).collect();
        for pair in at.windows(2) {
            let measured = pair[1] - pair[0];
            eprintln!(
                "slider period {measured:.6} s ({:+.4} %)",
                100.0 * (measured / period - 1.0)
            );
            assert!(
                (measured / period - 1.0).abs() <= 2e-3,
                "period {measured} vs {period}"
            );
        }
    }
    worst
}

/// The check for both choices of K3C's rocker point (under the crank pin, the authors'
/// choice; under the slider's centre): each run takes under 0.5 s in the test profile.
#[test]
fn agree_with_the_rigid_reference_in_the_stiff_limit() {
    for k3c_point_under_slider in [0.0, 1.0] {
        let worst = check_against_rigid(QuickReturnParams {
            k3c_point_under_slider,
            ..stiff_limit()
        });
        eprintln!("worst force deviation: {:.3} % of the peak", 100.0 * worst);
    }
}

/// The parameters are the issue's: only the listed entries are 100× the defaults.
#[test]
fn scale_only_the_translational_joints_and_the_drive() {
    let (d, s) = (QuickReturnParams::default(), stiff_limit());
    for (stiff, default) in [
        (s.K01, d.K01),
        (s.R01, d.R01),
        (s.K12, d.K12),
        (s.R12, d.R12),
        (s.K03, d.K03),
        (s.R03, d.R03),
        (s.K34, d.K34),
        (s.R34, d.R34),
        (s.K45, d.K45),
        (s.R45, d.R45),
        (s.K_C, d.K_C),
        (s.R_C, d.R_C),
        (s.K3C[1], d.K3C[1]),
        (s.K3C[2], d.K3C[2]),
        (s.R3C[1], d.R3C[1]),
        (s.R3C[2], d.R3C[2]),
        (s.K5C[1], d.K5C[1]),
        (s.K5C[2], d.K5C[2]),
        (s.R5C[1], d.R5C[1]),
        (s.R5C[2], d.R5C[2]),
    ] {
        assert_eq!(stiff, 100.0 * default);
    }
    assert_eq!([s.R3C[0], s.R5C[0]], [20.0, 20.0]);
    assert_eq!([s.K3C[0], s.K5C[0]], [0.0, 0.0]);
    assert_eq!([s.K23r, s.R23r], [d.K23r, d.R23r]);
    assert_eq!(s.k3c_point_under_slider, 0.0);
}
