//! The bouncing ball against its closed form: impact times and apex heights over 20
//! bounces, the rest time, and the energy account with the impact losses.
//!
//! Closed form (free fall under constant g, Newton's restitution law): dropped from
//! rest at h0, the ball first hits at `t₁ = √(2 h0 / g)` with speed `u₁ = g t₁`; the
//! k-th rebound speed is `wₖ = e^k u₁`, the next impact comes `2 wₖ / g` later with
//! speed `wₖ`, and the apex between them is `wₖ² / 2g` at `wₖ / g` after the rebound.
//! The ball comes to rest at the first impact whose rebound speed `e u` is below
//! `v_rest`.

use bgdsl_runtime::{
    event_energy, DormandPrinceOptions, Model, Simulation, Solver, SolverError, Trajectory,
};
use models::hybrid::{BouncingBall, BouncingBallParams};

/// The closed form's impacts: (time, speed just before), up to and including the
/// one that comes to rest.
fn impacts(p: &BouncingBallParams) -> Vec<(f64, f64)> {
    let mut t = (2.0 * p.h0 / p.g).sqrt();
    let mut u = p.g * t;
    let mut out = vec![(t, u)];
    while p.restitution * u >= p.v_rest {
        let w = p.restitution * u;
        t += 2.0 * w / p.g;
        u = w;
        out.push((t, u));
    }
    out
}

fn solver() -> Solver {
    // Free flight is a quadratic in t, which DOPRI5 integrates exactly: what remains
    // is rounding and the event location (1e-12 s), so the tolerance is not what
    // limits the accuracy.
    Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    })
}

fn initial_state(model: &BouncingBall) -> Vec<f64> {
    let mut x = vec![0.0; BouncingBall::STATE_NAMES.len()];
    model.initial_state(&mut x);
    x
}

/// Impact times to 1e-9 s and apex heights to 1e-9 m over the first 20 bounces. The
/// apex heights are sampled at the closed form's apex times, where the velocity is 0,
/// so a time error there does not move them to first order.
#[test]
fn impact_times_and_apex_heights_match_the_closed_form() {
    let model = BouncingBall::default();
    let p = model.params.clone();
    let hits = impacts(&p);
    assert!(hits.len() > 21, "the default ball bounces more than 20 times");
    let apexes: Vec<(f64, f64)> = hits[..20]
        .iter()
        .map(|&(t, u)| {
            let w = p.restitution * u;
            (t + w / p.g, w * w / (2.0 * p.g))
        })
        .collect();
    let times: Vec<f64> = apexes.iter().map(|a| a.0).collect();
    let mut traj = Trajectory::for_model::<BouncingBall>(times.len()).with_event_capacity(64);
    let mut sim = Simulation::new(&model, solver()).unwrap();
    sim.run(0.0, &initial_state(&model), &times, &mut traj).unwrap();

    let events = traj.events();
    assert!(events.len() >= 20);
    for (k, (event, &(t, _))) in events.iter().zip(&hits).take(20).enumerate() {
        assert_eq!(event.index, 0, "bounce {k}: the impact event");
        assert!(
            (event.t - t).abs() < 1e-9,
            "impact {k}: {} vs closed form {t}",
            event.t
        );
    }
    let height = traj.column("height").unwrap();
    for (k, &(t, h)) in apexes.iter().enumerate() {
        assert!(
            (height[k] - h).abs() < 1e-9,
            "apex {k} at {t}: {} vs closed form {h}",
            height[k]
        );
    }
}

/// The ball comes to rest at the closed form's resting impact (to 1e-9 s), with no
/// event after it, and stays there: velocity exactly 0 and height within 1e-9 m of
/// the floor one second later.
#[test]
fn comes_to_rest_at_the_closed_form_time() {
    let model = BouncingBall::default();
    let hits = impacts(&model.params);
    let &(t_rest, _) = hits.last().unwrap();
    let mut traj = Trajectory::for_model::<BouncingBall>(2).with_event_capacity(64);
    let mut sim = Simulation::new(&model, solver()).unwrap();
    let stats = sim
        .run(0.0, &initial_state(&model), &[0.0, t_rest + 1.0], &mut traj)
        .unwrap();
    assert_eq!(traj.events().len(), hits.len(), "one event per impact");
    assert_eq!(stats.events, hits.len());
    let last = traj.events().get(hits.len() - 1).unwrap();
    assert!((last.t - t_rest).abs() < 1e-9, "rest at {} vs {t_rest}", last.t);
    let resting = BouncingBall::STATE_NAMES
        .iter()
        .position(|n| *n == "floor.resting")
        .unwrap();
    assert_eq!(last.after[resting], 1.0, "the last impact puts the ball at rest");
    assert_eq!(traj.value(1, "velocity").unwrap(), 0.0);
    assert!(traj.value(1, "height").unwrap().abs() < 1e-9);
}

/// The energy account closes with the impact losses: with no source delivering power
/// (the floor's support works at zero velocity) and no resistor, stored(t_end) −
/// stored(0) = Σ event energy changes, to 1e-9 J of the 9.81 J dropped; and each
/// impact removes the closed form's `(1 − e²) m u² / 2` (all of `m u² / 2` at rest)
/// to 1e-9 J (the located impact is at most 1e-12 s late, which changes `m u² / 2` by
/// `m u g 1e-12` < 1e-10 J).
#[test]
fn energy_account_closes_with_the_impact_losses() {
    let model = BouncingBall::default();
    let p = model.params.clone();
    let hits = impacts(&p);
    let x0 = initial_state(&model);
    let t_end = hits.last().unwrap().0 + 0.5;
    let mut traj = Trajectory::for_model::<BouncingBall>(2).with_event_capacity(64);
    let mut sim = Simulation::new(&model, solver()).unwrap();
    sim.run(0.0, &x0, &[0.0, t_end], &mut traj).unwrap();
    let mut losses = 0.0;
    for (k, (event, &(_, u))) in traj.events().iter().zip(&hits).enumerate() {
        let change = event_energy(&model, event.t, event.before, event.after).unwrap();
        let kinetic = 0.5 * p.m * u * u;
        let expected = if k + 1 == hits.len() {
            -kinetic
        } else {
            -(1.0 - p.restitution * p.restitution) * kinetic
        };
        assert!(
            (change - expected).abs() < 1e-9,
            "impact {k}: {change} J vs {expected} J"
        );
        losses += change;
    }
    let stored = |x: &[f64]| model.power_balance(0.0, x).unwrap().stored;
    let x_end: Vec<f64> = (0..x0.len()).map(|i| traj.state(1, i).unwrap()).collect();
    let change = stored(&x_end) - stored(&x0);
    assert!(
        (change - losses).abs() < 1e-9,
        "stored energy changed by {change} J, the events removed {losses} J"
    );
}

/// Without a rest speed the bounces accumulate at `t∞ = t₁ + 2 e u₁ / (g (1 − e))`
/// (the geometric series of the flight times) and the run cannot pass it: it ends
/// with the runtime's chattering error, never hanging. The runtime counts impacts
/// closer than `min_interval · t` (1e-9 · t); once they are, the flights left sum to
/// `e / (1 − e)` = 4 such intervals at most, so it stops within 1e-7 s of t∞
/// (measured: 1e-10 s before it, after 120 impacts).
#[test]
fn without_a_rest_speed_the_run_ends_at_the_zeno_point_with_the_chattering_error() {
    let model = BouncingBall::new(BouncingBallParams {
        v_rest: 0.0,
        ..Default::default()
    });
    let p = &model.params;
    let t1 = (2.0 * p.h0 / p.g).sqrt();
    let zeno = t1 + 2.0 * p.restitution * p.g * t1 / (p.g * (1.0 - p.restitution));
    let mut traj = Trajectory::for_model::<BouncingBall>(2).with_event_capacity(256);
    let mut sim = Simulation::new(&model, solver()).unwrap();
    let result = sim.run(0.0, &initial_state(&model), &[0.0, zeno + 1.0], &mut traj);
    match result {
        Err(SolverError::Chattering { t, .. }) => {
            assert!(t <= zeno && zeno - t < 1e-7, "chattering at {t}, Zeno point {zeno}")
        }
        other => panic!("expected the chattering error, got {other:?}"),
    }
}
