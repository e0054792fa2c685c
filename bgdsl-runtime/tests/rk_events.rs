//! Events in the allocation-free integrators of `bgdsl_runtime::rk` (`Rk4`,
//! `DormandPrince`), on the hand-written bouncing ball of `support/hybrid.rs`: impacts
//! against the closed form, the same event times as the std driver's, continuation
//! across calls, a stop, the call's list of events, the chattering rule, and no heap
//! allocation (counted by this binary's global allocator, `support/counting.rs`).

#[path = "support/counting.rs"]
mod counting;
#[path = "support/hybrid.rs"]
mod hybrid;

use bgdsl_runtime::rk::{CallEvents, DormandPrince, Rk4};
use bgdsl_runtime::{
    DormandPrinceOptions, EventAction, EventOptions, FixedStep, Model, Simulation, Solver,
    SolverError, Trajectory,
};
use counting::{allocations_in, Counting};
use hybrid::Ball;

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The fixed step of the RK4 runs: RK4 is exact on the ball's quadratic flights, so
/// only the location of the impacts matters.
const STEP: f64 = 0.01;

/// The ball's first 20 impact times from the std driver with `solver`, in one run to
/// `t_end`.
fn driver_times(ball: &Ball, solver: Solver, t_end: f64) -> Vec<f64> {
    let mut sim = Simulation::new(ball, solver).unwrap();
    let mut traj = Trajectory::for_model::<Ball>(1).with_event_capacity(32);
    sim.run(0.0, &start(ball), &[t_end], &mut traj).unwrap();
    traj.events().times().to_vec()
}

fn start(ball: &Ball) -> [f64; 2] {
    let mut x0 = [0.0; 2];
    ball.initial_state(&mut x0);
    x0
}

/// Checks 20 impacts found in one call against the closed form (times to 1e-9 s, the
/// state before each at the floor with the closed-form speed, the state after it the
/// speed reversed and scaled by e) and against the driver's event times (to 1e-12 s).
fn check_twenty_impacts(name: &str, found: &[(f64, [f64; 2], [f64; 2])], driver: &[f64]) {
    let ball = Ball::default();
    assert_eq!(found.len(), 20, "{name}: one event per impact");
    assert_eq!(driver.len(), 20, "{name}: the driver's");
    let mut worst: f64 = 0.0;
    let mut worst_driver: f64 = 0.0;
    for (k, (t, before, after)) in found.iter().enumerate() {
        worst = worst.max((t - ball.impact_time(k + 1)).abs());
        worst_driver = worst_driver.max((t - driver[k]).abs());
        let speed = ball.e.powi(k as i32) * ball.impact_speed();
        assert!(before[0].abs() < 1e-9, "{name}: at the floor");
        assert!((before[1] + speed).abs() < 1e-9, "{name}: impact speed");
        assert_eq!(after[1], -ball.e * before[1], "{name}: the action");
    }
    println!("{name}: impacts within {worst:.1e} s of the closed form, {worst_driver:.1e} s of the driver");
    assert!(worst < 1e-9, "{name}: impact times off by {worst:e}");
    assert!(
        worst_driver < 1e-12,
        "{name}: {worst_driver:e} from the driver"
    );
}

mod should {
    use super::*;

    /// RK4 with a step of 0.01 s in one call past the 20th impact: each impact at its
    /// closed-form time, and at the time the driver's RK4 finds with the same step.
    #[test]
    fn bounce_a_ball_on_rk4_as_the_closed_form_and_the_driver() {
        let ball = Ball::default();
        let t_end = ball.apex(20).0;
        let mut rk4 = Rk4::<2, 1, 32>::new(FixedStep::new(STEP)).unwrap();
        let (mut t, mut x) = (0.0, start(&ball));
        let (allocations, result) = allocations_in(|| rk4.advance_to(&ball, &mut t, &mut x, t_end));
        result.unwrap();
        assert_eq!(
            allocations, 0,
            "stepping across 20 events allocates nothing"
        );
        assert_eq!(t, t_end);
        let found: Vec<_> = rk4
            .events()
            .iter()
            .map(|e| (e.t, [e.before[0], e.before[1]], [e.after[0], e.after[1]]))
            .collect();
        let driver = driver_times(&ball, Solver::Rk4(FixedStep::new(STEP)), t_end);
        check_twenty_impacts("rk4", &found, &driver);
        assert_eq!(rk4.stats().events, 20);
        assert!(rk4.stats().n_event_fn > rk4.stats().accepted);
        // At the apex after the 20th impact: e^40 h0.
        assert!((x[0] - ball.apex(20).1).abs() < 1e-9, "{}", x[0]);
    }

    /// DOPRI5 at its default tolerances in one call past the 20th impact, located on
    /// its continuous extension: closed form and the driver's DOPRI5.
    #[test]
    fn bounce_a_ball_on_dormand_prince_as_the_closed_form_and_the_driver() {
        let ball = Ball::default();
        let t_end = ball.apex(20).0;
        let options = DormandPrinceOptions::default();
        let mut dopri = DormandPrince::<2, 1, 32>::new(options).unwrap();
        let (mut t, mut x) = (0.0, start(&ball));
        let (allocations, result) =
            allocations_in(|| dopri.advance_to(&ball, &mut t, &mut x, t_end));
        result.unwrap();
        assert_eq!(
            allocations, 0,
            "stepping across 20 events allocates nothing"
        );
        assert_eq!(t, t_end);
        let found: Vec<_> = dopri
            .events()
            .iter()
            .map(|e| (e.t, [e.before[0], e.before[1]], [e.after[0], e.after[1]]))
            .collect();
        let driver = driver_times(&ball, Solver::DormandPrince(options), t_end);
        check_twenty_impacts("dopri5", &found, &driver);
        assert!((x[0] - ball.apex(20).1).abs() < 1e-9, "{}", x[0]);
    }

    /// Calls that end at each apex (a host's ticks): each call lists the one impact
    /// before it, at its closed-form time, and ends at the closed-form apex height;
    /// an event never fires twice across a call boundary.
    #[test]
    fn carry_events_from_call_to_call() {
        let ball = Ball::default();
        let mut rk4 = Rk4::<2, 1>::new(FixedStep::new(STEP)).unwrap();
        let mut dopri = DormandPrince::<2, 1>::new(DormandPrinceOptions::default()).unwrap();
        let (mut t4, mut x4) = (0.0, start(&ball));
        let (mut t5, mut x5) = (0.0, start(&ball));
        for k in 1..=20 {
            let (apex, height) = ball.apex(k);
            rk4.advance_to(&ball, &mut t4, &mut x4, apex).unwrap();
            dopri.advance_to(&ball, &mut t5, &mut x5, apex).unwrap();
            for (name, events, x) in [
                ("rk4", rk4.events().times(), x4),
                ("dopri5", dopri.events().times(), x5),
            ] {
                assert_eq!(events.len(), 1, "{name}: call {k}");
                assert!(
                    (events[0] - ball.impact_time(k)).abs() < 1e-9,
                    "{name}: {k}"
                );
                assert!((x[0] - height).abs() < 1e-9, "{name}: apex {k}");
            }
        }
        assert_eq!(rk4.stats().events, 20);
        assert_eq!(dopri.stats().events, 20);
    }

    /// A ball whose impact stops the run: the call ends at the first impact (its
    /// closed-form time) with the state after it, the event listed as a stop; the
    /// next call goes on from there and stops at the second impact.
    #[test]
    fn stop_at_an_event_and_go_on_from_it() {
        let ball = Ball {
            stop: true,
            ..Ball::default()
        };
        let mut rk4 = Rk4::<2, 1>::new(FixedStep::new(STEP)).unwrap();
        let mut dopri = DormandPrince::<2, 1>::new(DormandPrinceOptions::default()).unwrap();
        let (mut t4, mut x4) = (0.0, start(&ball));
        let (mut t5, mut x5) = (0.0, start(&ball));
        for k in 1..=2 {
            rk4.advance_to(&ball, &mut t4, &mut x4, 10.0).unwrap();
            dopri.advance_to(&ball, &mut t5, &mut x5, 10.0).unwrap();
            let rebound = ball.e.powi(k) * ball.impact_speed();
            let list = |events: &CallEvents<2, 4>| -> Vec<(f64, EventAction)> {
                events.iter().map(|e| (e.t, e.action)).collect()
            };
            for (name, t, x, events) in [
                ("rk4", t4, x4, list(rk4.events())),
                ("dopri5", t5, x5, list(dopri.events())),
            ] {
                assert!(
                    (t - ball.impact_time(k as usize)).abs() < 1e-9,
                    "{name} {k}: {t}"
                );
                assert!(x[0].abs() < 1e-9, "{name} {k}: at the floor");
                assert!((x[1] - rebound).abs() < 1e-9, "{name} {k}: bounced");
                assert_eq!(events, [(t, EventAction::Stop)], "{name} {k}");
            }
        }
    }

    /// One step of each: a step that contains an impact ends at it, with the action
    /// applied; without `E` matching the model this would not compile.
    #[test]
    fn cut_a_single_step_at_its_event() {
        let ball = Ball::default();
        let t1 = ball.impact_time(1);
        let mut rk4 = Rk4::<2, 1>::new(FixedStep::new(STEP)).unwrap();
        let (mut t, mut x) = (0.0, start(&ball));
        rk4.step(&ball, &mut t, &mut x, 1.0).unwrap();
        assert!((t - t1).abs() < 1e-9, "{t}");
        assert!((x[1] - ball.e * ball.impact_speed()).abs() < 1e-9);
        let mut dopri = DormandPrince::<2, 1>::new(DormandPrinceOptions {
            initial_step: Some(1.0),
            max_step: 1.0,
            ..DormandPrinceOptions::default()
        })
        .unwrap();
        let (mut t, mut x) = (0.0, start(&ball));
        while dopri.events().is_empty() {
            dopri.step(&ball, &mut t, &mut x, 10.0).unwrap();
        }
        assert!((t - t1).abs() < 1e-9, "{t}");
        assert!((x[1] - ball.e * ball.impact_speed()).abs() < 1e-9);
    }

    /// A list with room for 2 events in a call with 5: the first two kept, in order,
    /// three counted as dropped; all five handled.
    #[test]
    fn keep_the_first_events_of_a_call_and_count_the_rest() {
        let ball = Ball::default();
        let mut rk4 = Rk4::<2, 1, 2>::new(FixedStep::new(STEP)).unwrap();
        let (mut t, mut x) = (0.0, start(&ball));
        rk4.advance_to(&ball, &mut t, &mut x, ball.apex(5).0)
            .unwrap();
        let events = rk4.events();
        assert_eq!((events.len(), events.dropped()), (2, 3));
        assert_eq!(rk4.stats().events, 5);
        for (k, e) in events.iter().enumerate() {
            assert!((e.t - ball.impact_time(k + 1)).abs() < 1e-9);
            assert_eq!((e.index, e.name), (0, "floor"));
        }
    }

    /// A ball with restitution 0.5 and no rest mode bounces ever faster (Zeno, the
    /// bounce times converge to `3 t_1`): both integrators end the call with
    /// `Chattering` on `floor` near that time after bounded work, allocating nothing;
    /// with `max_events` 5 the call ends at the sixth impact with `TooManyEvents`.
    #[test]
    fn end_a_zeno_ball_with_chattering() {
        let ball = Ball {
            e: 0.5,
            ..Ball::default()
        };
        let zeno = 3.0 * ball.impact_time(1);
        let mut rk4 = Rk4::<2, 1>::new(FixedStep::new(STEP)).unwrap();
        let mut dopri = DormandPrince::<2, 1>::new(DormandPrinceOptions::default()).unwrap();
        let (mut t, mut x) = (0.0, start(&ball));
        let (allocations, rk4_error) =
            allocations_in(|| rk4.advance_to(&ball, &mut t, &mut x, 10.0));
        assert_eq!(allocations, 0);
        let (mut t, mut x) = (0.0, start(&ball));
        let (allocations, dopri_error) =
            allocations_in(|| dopri.advance_to(&ball, &mut t, &mut x, 10.0));
        assert_eq!(allocations, 0);
        for (name, error, stats) in [
            ("rk4", rk4_error, rk4.stats()),
            ("dopri5", dopri_error, dopri.stats()),
        ] {
            match error {
                Err(SolverError::Chattering { event, t, .. }) => {
                    assert_eq!(event, "floor");
                    assert!((t - zeno).abs() < 1e-6, "{name}: at {t}, Zeno time {zeno}");
                }
                other => panic!("{name}: {other:?}"),
            }
            assert!(
                stats.events < 100 && stats.steps() < 5_000,
                "{name}: {stats:?}"
            );
        }
        let limit = EventOptions {
            max_events: 5,
            ..EventOptions::default()
        };
        rk4.set_event_options(limit).unwrap();
        dopri.set_event_options(limit).unwrap();
        let (mut t, mut x) = (0.0, start(&ball));
        let e4 = rk4.advance_to(&ball, &mut t, &mut x, 10.0).unwrap_err();
        let (mut t, mut x) = (0.0, start(&ball));
        let e5 = dopri.advance_to(&ball, &mut t, &mut x, 10.0).unwrap_err();
        for error in [e4, e5] {
            let SolverError::TooManyEvents { event, t, limit } = error else {
                panic!("{error}")
            };
            assert_eq!((event, limit), ("floor", 5));
            assert!((t - ball.impact_time(6)).abs() < 1e-9);
        }
        assert!(rk4
            .set_event_options(EventOptions {
                max_repeats: 0,
                ..EventOptions::default()
            })
            .is_err());
    }
}
