//! The `no_std` bouncing ball (`bond_graph!` with a mode and a `when`) on the
//! allocation-free integrators, against its closed form.
//!
//! As in `closed_form.rs`, the crate and the runtime are built without `std` (libm
//! maths, the integrators of `bgdsl_runtime::rk`, which here handle the events).

use bgdsl_embedded::{BallDrop, BouncingBall, BouncingBallParams, BouncingBallState};
use bgdsl_runtime::rk::Rk4;
use bgdsl_runtime::{DormandPrinceOptions, EventAction, FixedStep, Model};

/// The closed form of a ball dropped from rest at `h0` with restitution `e`: impact
/// `k` (1-based) at `t_1 (1 + 2 Σ_{j<k} e^j)`, `t_1 = √(2 h0 / g)`, with the speed
/// `e^(k-1) v_1` before it, `v_1 = g t_1`; the first impact whose rebound `e^k v_1`
/// would be below the rest speed is the last.
struct Closed {
    t1: f64,
    v1: f64,
    e: f64,
    last: usize,
}

impl Closed {
    fn new(p: &BouncingBallParams) -> Self {
        let t1 = (2.0 * p.drop_height / p.gravity).sqrt();
        let v1 = p.gravity * t1;
        let e = p.restitution;
        let last = (1..)
            .find(|&k| e.powi(k as i32) * v1 < p.rest_speed)
            .unwrap();
        Closed { t1, v1, e, last }
    }

    fn impact(&self, k: usize) -> f64 {
        self.t1 * (1.0 + 2.0 * (1..k).map(|j| self.e.powi(j as i32)).sum::<f64>())
    }

    fn impact_speed(&self, k: usize) -> f64 {
        self.e.powi(k as i32 - 1) * self.v1
    }
}

/// Ticks of 1 ms on Dormand–Prince until well after the ball comes to rest: every
/// impact at its closed-form time (to 1e-9 s), as many as the closed form has (43 for
/// the default parameters), then the ball lies still on the floor with its rest mode
/// on.
#[test]
fn ball_ticked_on_dormand_prince_bounces_as_the_closed_form() {
    let params = BouncingBallParams::default();
    let closed = Closed::new(&params);
    assert_eq!(closed.last, 43, "the default parameters' rest");
    let options = DormandPrinceOptions {
        rtol: 1e-10,
        atol: 1e-12,
        ..DormandPrinceOptions::default()
    };
    let mut drop = BallDrop::new(params.clone(), options).unwrap();
    let mut impacts = Vec::new();
    for _ in 0..10_000 {
        drop.tick(1e-3).unwrap();
        let (times, dropped) = drop.impacts();
        assert_eq!(dropped, 0, "at most two impacts in a millisecond");
        impacts.extend_from_slice(times);
    }
    assert_eq!(impacts.len(), closed.last);
    let mut worst: f64 = 0.0;
    for (k, t) in impacts.iter().enumerate() {
        worst = worst.max((t - closed.impact(k + 1)).abs());
    }
    println!(
        "dopri5 in 1 ms ticks: {} impacts within {worst:.1e} s",
        impacts.len()
    );
    assert!(worst < 1e-9, "impact times off by {worst:e}");
    let rest: BouncingBallState<f64> = drop.state();
    assert_eq!((rest.height, rest.body_p), (0.0, 0.0));
    assert_eq!(rest.resting, 1.0);
    assert!((drop.time() - 10.0).abs() < 1e-9);
}

/// RK4 with a step of 1 ms, in one call with room for 64 events: every impact at its
/// closed-form time (RK4 is exact on the quadratic flights, so only the location
/// counts), with the closed-form speed before it and `e` times that speed, reversed,
/// after it; the last one puts the ball to rest.
#[test]
fn ball_on_rk4_bounces_as_the_closed_form() {
    let ball = BouncingBall::default();
    let closed = Closed::new(ball.params());
    let mut rk4 = Rk4::<{ BouncingBall::N_STATES }, { BouncingBall::EVENTS.len() }, 64>::new(
        FixedStep::new(1e-3),
    )
    .unwrap();
    let mut x = [0.0; BouncingBall::N_STATES];
    ball.initial_state(&mut x);
    let mut t = 0.0;
    rk4.advance_to(&ball, &mut t, &mut x, 10.0).unwrap();
    assert_eq!(t, 10.0);
    let events = rk4.events();
    assert_eq!((events.len(), events.dropped()), (closed.last, 0));
    let m = ball.params().mass;
    let mut worst: f64 = 0.0;
    for (k, event) in events.iter().enumerate() {
        let k = k + 1;
        assert_eq!(
            (event.name, event.action),
            ("impact", EventAction::Continue)
        );
        worst = worst.max((event.t - closed.impact(k)).abs());
        let (before, after) = (
            BouncingBallState::from_slice(event.before),
            BouncingBallState::from_slice(event.after),
        );
        assert!(before.height.abs() < 1e-9, "impact {k} at the floor");
        assert!(
            (before.body_p / m + closed.impact_speed(k)).abs() < 1e-9,
            "impact {k}"
        );
        if k < closed.last {
            assert!((after.body_p + closed.e * before.body_p).abs() < 1e-15);
            assert_eq!(after.resting, 0.0);
        } else {
            assert_eq!((after.body_p, after.height), (0.0, 0.0));
            assert_eq!(after.resting, 1.0);
        }
    }
    println!("rk4: {} impacts within {worst:.1e} s", events.len());
    assert!(worst < 1e-9, "impact times off by {worst:e}");
}

/// `BallDrop::set_atol`: a bad entry is refused naming the state; good ones are taken.
/// Free flight is a parabola, which Dormand–Prince integrates exactly (its error
/// estimate is rounding), so the tolerances do not move the impacts: both runs find the
/// same times, the first at `sqrt(2 h / g)` to 1e-12 s. (That per-state atol changes
/// a run is `closed_form.rs`' motor test.)
#[test]
fn per_state_atol_reaches_the_drop() {
    let options = bgdsl_runtime::DormandPrinceOptions {
        rtol: 1e-6,
        atol: 1e-6,
        ..Default::default()
    };
    let impacts = |atol: Option<[f64; BouncingBall::N_STATES]>| {
        let mut drop = BallDrop::new(BouncingBallParams::default(), options).unwrap();
        drop.set_atol(atol).unwrap();
        let mut times = Vec::new();
        for _ in 0..300 {
            drop.tick(0.01).unwrap();
            times.extend_from_slice(drop.impacts().0);
        }
        times
    };
    let height = BouncingBall::STATE_NAMES
        .iter()
        .position(|n| *n == "height")
        .unwrap();
    let mut atol = [1e-6; BouncingBall::N_STATES];
    atol[height] = 1e-12;
    let (scalar, per_state) = (impacts(None), impacts(Some(atol)));
    assert_eq!(scalar.len(), per_state.len());
    assert!(scalar.len() >= 2, "{scalar:?}");
    assert_eq!(scalar, per_state);
    assert!(
        (scalar[0] - (2.0f64 / 9.81).sqrt()).abs() < 1e-12,
        "{scalar:?}"
    );
    let mut drop = BallDrop::new(BouncingBallParams::default(), options).unwrap();
    atol[height] = f64::INFINITY;
    let err = drop.set_atol(Some(atol)).unwrap_err();
    assert_eq!(
        err.to_string(),
        "invalid absolute tolerance inf for state `height`: expected a finite number >= 0"
    );
}
