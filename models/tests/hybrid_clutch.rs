//! The clutch that locks at a speed match, against the closed form of two shafts
//! under constant torques, and its energy account.
//!
//! Slipping, the clutch carries its slip torque tk: `w1' = (T − tk) / j1` and
//! `w2' = (tk − L) / j2`, so the speeds meet at
//! `t_e = (w1₀ − w2₀) / ((tk − L) / j2 − (T − tk) / j1)` at `w_e = w1₀ + (T − tk) t_e / j1`.
//! Locked (the torque that holds them, `(j2 T + j1 L) / (j1 + j2)`, is below ts), both
//! turn at `w_e + (T − L) (t − t_e) / (j1 + j2)`.

use bgdsl_runtime::{event_energy, DormandPrinceOptions, Model, Simulation, Solver, Trajectory};
use models::hybrid::ClutchEngagement;

const SAMPLES: usize = 4001;

fn run(model: &ClutchEngagement, t_end: f64) -> Trajectory {
    let mut x0 = vec![0.0; ClutchEngagement::STATE_NAMES.len()];
    model.initial_state(&mut x0);
    // Both phases are linear in t, which DOPRI5 integrates exactly: the errors left
    // are rounding and the event location (1e-12 s).
    let solver = Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    });
    let mut traj =
        Trajectory::for_model::<ClutchEngagement>(SAMPLES).with_event_capacity(8);
    Simulation::new(model, solver)
        .unwrap()
        .run_uniform(0.0, &x0, t_end, SAMPLES, &mut traj)
        .unwrap();
    traj
}

/// Engagement at the closed form's instant (to 1e-10 s), as the only event, and both
/// speeds on the closed form before and after it (to 1e-9 rad/s of speeds up to
/// 100 rad/s): the locked shafts share one speed, that of the combined inertia.
#[test]
fn engages_at_the_speed_match_and_turns_as_one_inertia() {
    let model = ClutchEngagement::default();
    let p = &model.params;
    let (a1, a2) = ((p.torque - p.tk) / p.j1, (p.tk - p.load) / p.j2);
    let t_e = (p.w1_0 - p.w2_0) / (a2 - a1);
    let w_e = p.w1_0 + a1 * t_e;
    let alpha = (p.torque - p.load) / (p.j1 + p.j2);
    assert!((p.j2 * p.torque + p.j1 * p.load) / (p.j1 + p.j2) < p.ts, "it locks");
    let traj = run(&model, 2.0 * t_e);

    let events = traj.events();
    assert_eq!(events.len(), 1, "one event: the engagement");
    let first = events.get(0).unwrap();
    assert!((first.t - t_e).abs() < 1e-10, "{} vs {t_e}", first.t);
    let stuck = ClutchEngagement::STATE_NAMES
        .iter()
        .position(|n| *n == "clutch.plates.stuck")
        .unwrap();
    assert_eq!((first.before[stuck], first.after[stuck]), (0.0, 1.0));

    let (w1, w2) = (
        traj.column("w_engine").unwrap(),
        traj.column("w_output").unwrap(),
    );
    for (i, &t) in traj.times().iter().enumerate() {
        let (e1, e2) = if t < t_e {
            (p.w1_0 + a1 * t, p.w2_0 + a2 * t)
        } else {
            let w = w_e + alpha * (t - t_e);
            (w, w)
        };
        assert!((w1[i] - e1).abs() < 1e-9, "t = {t}: w1 = {} vs {e1}", w1[i]);
        assert!((w2[i] - e2).abs() < 1e-9, "t = {t}: w2 = {} vs {e2}", w2[i]);
    }
}

/// The energy account closes: stored(t) − stored(0) = ∫ (input − dissipated) dt + Σ
/// event changes, and the friction loss is the closed form's `tk (w1₀ − w2₀) t_e / 2`
/// (the slip falls linearly to 0). The powers are linear in t on either side of the
/// engagement, and the run to `2 t_e` on 4001 samples puts `t_e` on sample 2000, so
/// the trapezoidal rule is exact up to rounding and the event's 1e-12 s: the test
/// allows 1e-6 J of a kinetic energy of some 2500 J. The engagement itself changes
/// no stored energy (a mode switch only), to 1e-9 J.
#[test]
fn energy_account_closes_with_the_friction_loss() {
    let model = ClutchEngagement::default();
    let p = &model.params;
    let t_e = (p.w1_0 - p.w2_0) / ((p.tk - p.load) / p.j2 - (p.torque - p.tk) / p.j1);
    let traj = run(&model, 2.0 * t_e);
    let n = ClutchEngagement::STATE_NAMES.len();
    let state =
        |row: usize| -> Vec<f64> { (0..n).map(|i| traj.state(row, i).unwrap()).collect() };
    let times = traj.times();
    let balance = |row: usize| model.power_balance(times[row], &state(row)).unwrap();
    let (mut supplied, mut dissipated) = (0.0, 0.0);
    for row in 1..times.len() {
        let (a, b) = (balance(row - 1), balance(row));
        let h = times[row] - times[row - 1];
        supplied += 0.5 * h * (a.input + b.input);
        dissipated += 0.5 * h * (a.dissipated + b.dissipated);
    }
    let loss = p.tk * (p.w1_0 - p.w2_0) * t_e / 2.0;
    assert!(
        (dissipated - loss).abs() < 1e-6,
        "friction loss {dissipated} J vs closed form {loss} J"
    );
    let events: f64 = traj
        .events()
        .iter()
        .map(|e| event_energy(&model, e.t, e.before, e.after).unwrap())
        .sum();
    assert!(events.abs() < 1e-9, "the engagement changes the stored energy by {events} J");
    let last = times.len() - 1;
    let change = balance(last).stored - balance(0).stored;
    assert!(
        (change - (supplied - dissipated) - events).abs() < 1e-6,
        "stored energy changed by {change} J; supplied {supplied} J, dissipated {dissipated} J"
    );
}
