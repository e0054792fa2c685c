//! Events in the driver and the stepper, on hand-written hybrid models with closed
//! forms (`support/hybrid.rs`): location, direction, simultaneous and nested
//! crossings, stop, sampling at and around events, the restart, the chattering rule,
//! the event limit, the event log and the energy an event changes.

#[path = "support/hybrid.rs"]
mod hybrid;

use bgdsl_runtime::{
    event_energy, DormandPrinceOptions, EventAction, EventOptions, FixedStep, Model, Radau5Options,
    Rodas4Options, Simulation, Solver, SolverError, Stepper, Trajectory,
};
use hybrid::{Ball, Clock, EitherWayBall, JacobianSpy, Sine, Switched};

/// Every method, with settings under which the ball's impacts come out to 1e-9: the
/// fixed-step methods with a step of 0.01 s (they are exact on the ball's quadratic
/// motion, so only location matters), the adaptive ones at their default tolerances.
fn methods() -> Vec<(&'static str, Solver)> {
    methods_with_step(0.01)
}

/// Every method, the fixed-step ones with step `step`.
fn methods_with_step(step: f64) -> Vec<(&'static str, Solver)> {
    vec![
        ("rk4", Solver::Rk4(FixedStep::new(step))),
        ("dopri5", Solver::dopri5()),
        (
            "dopri5-fixed",
            Solver::DormandPrinceFixed(FixedStep::new(step)),
        ),
        ("radau5", Solver::Radau5(Radau5Options::default())),
        ("rodas4", Solver::Rodas4(Rodas4Options::default())),
    ]
}

fn initial<M: Model>(model: &M) -> Vec<f64> {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    x0
}

mod should {
    use super::*;

    /// 20 bounces of a ball with restitution 0.9 dropped from 1 m: the impact times
    /// `t_k` and the apex heights `e^(2k) h0` (sampled at the closed-form apex times)
    /// match the closed form to 1e-9 for every method; each impact reverses and scales
    /// the speed (`after = -e before`) at the floor.
    #[test]
    fn bounce_a_ball_to_the_closed_form_with_every_method() {
        let ball = Ball::default();
        let bounces = 20;
        let apexes: Vec<(f64, f64)> = (1..=bounces).map(|k| ball.apex(k)).collect();
        let times: Vec<f64> = apexes.iter().map(|a| a.0).collect();
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&ball, solver).unwrap();
            let mut traj = Trajectory::for_model::<Ball>(times.len()).with_event_capacity(32);
            let stats = sim.run(0.0, &initial(&ball), &times, &mut traj).unwrap();
            let events = traj.events();
            assert_eq!(events.len(), bounces, "{name}: one event per bounce");
            assert_eq!(stats.events, bounces, "{name}: counted");
            assert!(stats.n_event_fn > stats.accepted, "{name}: {stats:?}");
            let mut worst_t: f64 = 0.0;
            let mut worst_h: f64 = 0.0;
            for (k, event) in events.iter().enumerate() {
                let exact = ball.impact_time(k + 1);
                worst_t = worst_t.max((event.t - exact).abs());
                assert_eq!((event.index, event.name), (0, "floor"));
                assert_eq!(event.action, EventAction::Continue);
                assert!(event.before[0].abs() < 1e-9, "{name}: at the floor");
                assert_eq!(event.after[1], -ball.e * event.before[1]);
                let speed = ball.e.powi(k as i32) * ball.impact_speed();
                assert!(
                    (event.before[1] + speed).abs() < 1e-9,
                    "{name}: impact speed"
                );
            }
            for (row, (_, height)) in apexes.iter().enumerate() {
                worst_h = worst_h.max((traj.value(row, "h").unwrap() - height).abs());
            }
            println!("{name}: impact times within {worst_t:.1e} s, apexes within {worst_h:.1e} m");
            assert!(worst_t < 1e-9, "{name}: impact times off by {worst_t:e}");
            assert!(worst_h < 1e-9, "{name}: apex heights off by {worst_h:e}");
        }
    }

    /// `s = sin t` crossing zero: a rising-only event fires at 2π and 4π (not at π, 3π,
    /// where `s` falls, nor at the start, where it is 0); falling-only at π, 3π; both
    /// at all four.
    #[test]
    fn fire_only_in_the_events_direction() {
        use std::f64::consts::PI;
        let tight = Solver::DormandPrince(DormandPrinceOptions {
            rtol: 1e-12,
            atol: 1e-12,
            ..DormandPrinceOptions::default()
        });
        fn times<M: Model>(model: &M, solver: Solver) -> Vec<f64> {
            let mut sim = Simulation::new(model, solver).unwrap();
            let mut traj = Trajectory::for_model::<M>(2).with_event_capacity(8);
            sim.run(0.0, &initial(model), &[0.0, 13.0], &mut traj)
                .unwrap();
            assert_eq!(traj.value(1, "count").unwrap(), traj.events().len() as f64);
            traj.events().times().to_vec()
        }
        let close = |found: Vec<f64>, expected: &[f64]| {
            assert_eq!(found.len(), expected.len(), "{found:?}");
            for (f, e) in found.iter().zip(expected) {
                assert!((f - e).abs() < 1e-9, "{found:?} vs {expected:?}");
            }
        };
        close(times(&Sine::<0>, tight), &[2.0 * PI, 4.0 * PI]);
        close(times(&Sine::<1>, tight), &[PI, 3.0 * PI]);
        close(
            times(&Sine::<2>, tight),
            &[PI, 2.0 * PI, 3.0 * PI, 4.0 * PI],
        );
    }

    /// An event firing both ways fires once per impact: the ball leaving the floor
    /// after a bounce (from `h ≈ -1e-13` up) is not a crossing, for every method.
    #[test]
    fn not_fire_again_as_a_bouncing_ball_leaves_the_floor() {
        let ball = EitherWayBall(Ball::default());
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&ball, solver).unwrap();
            let stats = sim
                .run(0.0, &initial(&ball), &[ball.0.apex(5).0], &mut ())
                .unwrap();
            assert_eq!(stats.events, 5, "{name}");
        }
    }

    /// Two events at the same time are handled in index order, each on the state the
    /// one before left: `x = (1 · 2) + 1 = 3` (the other order gives 4); a third, 1e-6 s
    /// later in the same step, comes after them on its own. For every method.
    #[test]
    fn handle_simultaneous_events_in_index_order() {
        let clock = Clock {
            times: [0.5, 0.5, 0.5 + 1e-6],
            scale: [2.0, 1.0, 10.0],
            shift: [0.0, 1.0, 0.0],
        };
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&clock, solver).unwrap();
            let mut traj = Trajectory::for_model::<Clock>(2).with_event_capacity(4);
            sim.run(0.0, &[1.0], &[0.0, 1.0], &mut traj).unwrap();
            let log: Vec<_> = traj.events().iter().collect();
            assert_eq!(log.len(), 3, "{name}");
            assert_eq!(
                log.iter().map(|e| e.index).collect::<Vec<_>>(),
                [0, 1, 2],
                "{name}"
            );
            assert_eq!((log[0].before[0], log[0].after[0]), (1.0, 2.0), "{name}");
            assert_eq!((log[1].before[0], log[1].after[0]), (2.0, 3.0), "{name}");
            assert_eq!(log[0].t, log[1].t, "{name}: simultaneous");
            assert!((log[0].t - 0.5).abs() < 1e-12, "{name}: {}", log[0].t);
            assert!((log[2].t - (0.5 + 1e-6)).abs() < 1e-12, "{name}");
            assert_eq!(traj.value(1, "x"), Some(30.0), "{name}");
        }
    }

    /// Two crossings inside one step (the whole run is one step: x' = 0 for the
    /// adaptive methods, a step of 1 s for the fixed ones): the earlier is handled
    /// first, whatever the indices.
    #[test]
    fn handle_the_earliest_of_two_crossings_in_a_step_first() {
        let clock = Clock {
            times: [0.7, 0.3, 5.0],
            scale: [1.0, 1.0, 1.0],
            shift: [1.0, 10.0, 0.0],
        };
        for (name, solver) in methods_with_step(1.0) {
            let mut sim = Simulation::new(&clock, solver).unwrap();
            let mut traj = Trajectory::for_model::<Clock>(1).with_event_capacity(4);
            sim.run(0.0, &[0.0], &[1.0], &mut traj).unwrap();
            let log: Vec<_> = traj.events().iter().map(|e| (e.index, e.t)).collect();
            assert_eq!(log.len(), 2, "{name}: {log:?}");
            assert_eq!((log[0].0, log[1].0), (1, 0), "{name}: {log:?}");
            assert!((log[0].1 - 0.3).abs() < 1e-12 && (log[1].1 - 0.7).abs() < 1e-12);
            assert_eq!(traj.value(0, "x"), Some(11.0));
        }
    }

    /// A stop action ends the run at the first impact `t_1 = sqrt(2 h0 / g)`: `Ok`,
    /// `time()` is `t_1`, the last sample is there with the state after the event, and
    /// the samples before it (from the dense output) follow `h0 - g t² / 2`.
    #[test]
    fn stop_at_an_event_with_a_sample_there() {
        let ball = Ball {
            stop: true,
            ..Ball::default()
        };
        let t1 = ball.impact_time(1);
        let samples: Vec<f64> = (0..=20).map(|i| 0.05 * i as f64).collect();
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&ball, solver).unwrap();
            let mut traj = Trajectory::for_model::<Ball>(samples.len()).with_event_capacity(2);
            let stats = sim.run(0.0, &initial(&ball), &samples, &mut traj).unwrap();
            assert_eq!(stats.events, 1, "{name}");
            assert!((sim.time() - t1).abs() < 1e-9, "{name}: {}", sim.time());
            let before = samples.iter().filter(|&&t| t < sim.time()).count();
            assert_eq!(traj.len(), before + 1, "{name}: samples up to t*, then t*");
            for row in 0..before {
                let t = traj.times()[row];
                let exact = ball.h0 - 0.5 * ball.g * t * t;
                let h = traj.value(row, "h").unwrap();
                assert!(
                    (h - exact).abs() < 1e-9,
                    "{name}: h({t}) = {h}, not {exact}"
                );
            }
            assert_eq!(traj.times()[before], sim.time());
            let event = traj.events().get(0).unwrap();
            assert_eq!(event.action, EventAction::Stop);
            assert_eq!(traj.state(before, 1), Some(event.after[1]));
            assert_eq!(sim.state(), event.after);
        }
    }

    /// A sample at exactly an event's time records the state after the event (the
    /// trajectory is right-continuous); the event log keeps the state before.
    #[test]
    fn record_the_state_after_the_event_at_its_own_time() {
        let ball = Ball::default();
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&ball, solver).unwrap();
            let mut traj = Trajectory::for_model::<Ball>(1).with_event_capacity(4);
            sim.run(0.0, &initial(&ball), &[0.5], &mut traj).unwrap();
            let t_star = traj.events().times()[0];
            let mut traj = Trajectory::for_model::<Ball>(2).with_event_capacity(4);
            sim.run(0.0, &initial(&ball), &[t_star, 0.5], &mut traj)
                .unwrap();
            let event = traj.events().get(0).unwrap();
            assert_eq!(event.t, t_star, "{name}: the same location");
            assert_eq!(traj.state(0, 1), Some(event.after[1]), "{name}");
            assert!(event.after[1] > 0.0 && event.before[1] < 0.0, "{name}");
        }
    }

    /// The dynamics change at the event (the thrust comes on: v' = -g, then +a): every
    /// method follows the closed form to 1e-9 after it, which it would not if it
    /// carried the step before the event (FSAL derivative, Jacobian, start values)
    /// across.
    #[test]
    fn restart_after_a_mode_switch_that_changes_the_dynamics() {
        let model = Switched::default();
        let samples: Vec<f64> = (1..=30).map(|i| 0.05 * i as f64).collect();
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&model, solver).unwrap();
            let mut traj = Trajectory::for_model::<Switched>(samples.len()).with_event_capacity(4);
            sim.run(0.0, &initial(&model), &samples, &mut traj).unwrap();
            assert_eq!(traj.events().len(), 1, "{name}: the thrust comes on once");
            let mut worst: f64 = 0.0;
            for (row, &t) in samples.iter().enumerate() {
                let (h, v) = model.exact(t);
                worst = worst.max((traj.value(row, "h").unwrap() - h).abs());
                worst = worst.max((traj.value(row, "v").unwrap() - v).abs());
                let mode = if t > traj.events().times()[0] {
                    1.0
                } else {
                    0.0
                };
                assert_eq!(traj.value(row, "thrust"), Some(mode), "{name} at {t}");
            }
            assert!(worst < 1e-9, "{name}: off the closed form by {worst:e}");
        }
    }

    /// After every event the stiff methods evaluate a new Jacobian at the event's time
    /// (the ball's Jacobian is constant, so Radau5 would otherwise keep one for the
    /// whole run, as it does for the free fall).
    #[test]
    fn evaluate_a_new_jacobian_after_every_event() {
        let t_end = Ball::default().apex(10).0;
        for solver in [
            Solver::Radau5(Radau5Options::default()),
            Solver::Rodas4(Rodas4Options::default()),
        ] {
            let spy = JacobianSpy::default();
            let mut sim = Simulation::new(&spy, solver).unwrap();
            let mut traj = Trajectory::for_model::<JacobianSpy>(1).with_event_capacity(16);
            let stats = sim.run(0.0, &initial(&spy), &[t_end], &mut traj).unwrap();
            assert_eq!(stats.events, 10);
            let times = spy.times.borrow();
            for t in traj.events().times() {
                assert!(
                    times.contains(t),
                    "{}: no Jacobian at the event at {t}",
                    solver.name()
                );
            }
        }
        let free = JacobianSpy {
            ball: Ball {
                floor: -1e9,
                ..Ball::default()
            },
            ..JacobianSpy::default()
        };
        let mut sim = Simulation::new(&free, Solver::Radau5(Radau5Options::default())).unwrap();
        // Set-up evaluates a hand-written Jacobian to find its pattern: not counted.
        free.times.borrow_mut().clear();
        sim.run(0.0, &initial(&free), &[t_end], &mut ()).unwrap();
        assert_eq!(
            free.times.borrow().len(),
            1,
            "one Jacobian serves the free fall"
        );
    }

    /// A ball with restitution 0.5 and no rest mode bounces ever faster (Zeno): every
    /// method ends the run with `Chattering` on `floor` after a bounded amount of work
    /// (the closed form's bounce times converge to `t_1 (1 + 2e/(1-e)) = 3 t_1`).
    #[test]
    fn end_a_zeno_ball_with_chattering_after_bounded_work() {
        let ball = Ball {
            e: 0.5,
            ..Ball::default()
        };
        let zeno = ball.impact_time(1) * 3.0;
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&ball, solver).unwrap();
            let error = sim.run(0.0, &initial(&ball), &[10.0], &mut ()).unwrap_err();
            let stats = sim.stats();
            match error {
                SolverError::Chattering { event, t, .. } => {
                    assert_eq!(event, "floor");
                    assert!((t - zeno).abs() < 1e-6, "{name}: at {t}, Zeno time {zeno}");
                }
                other => panic!("{name}: {other}"),
            }
            println!("{name}: {error}; {stats:?}");
            assert!(stats.events < 100, "{name}: {stats:?}");
            assert!(stats.steps() < 5_000, "{name}: {stats:?}");
            assert!(stats.n_event_fn < 20_000, "{name}: {stats:?}");
            let text = error.to_string();
            assert!(text.contains("`floor`") && text.contains("rest or stick mode"));
        }
    }

    /// The repeat rule by itself: with `min_interval` 0.02 s and `max_repeats` 3, the
    /// Zeno ball stops at the third bounce in a row less than 0.02 s after the one
    /// before, which the closed form places.
    #[test]
    fn end_a_run_after_max_repeats_short_intervals() {
        let ball = Ball {
            e: 0.5,
            ..Ball::default()
        };
        let options = EventOptions {
            min_interval: 0.02,
            max_repeats: 3,
            ..EventOptions::default()
        };
        // The first impact k whose flight before it is shorter than 0.02 s; the third in
        // a row is k + 2.
        let k = (2..)
            .find(|&k| ball.impact_time(k) - ball.impact_time(k - 1) < 0.02)
            .unwrap();
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&ball, solver).unwrap();
            sim.set_event_options(options).unwrap();
            let error = sim.run(0.0, &initial(&ball), &[10.0], &mut ()).unwrap_err();
            let SolverError::Chattering {
                event,
                t,
                count,
                interval,
            } = error
            else {
                panic!("{name}: {error}")
            };
            assert_eq!((event, count), ("floor", 3), "{name}");
            assert!((t - ball.impact_time(k + 2)).abs() < 1e-9, "{name}");
            assert!(interval < 0.02);
            assert_eq!(sim.stats().events, k + 1, "{name}: handled before");
        }
    }

    /// More than `max_events` events end the run with `TooManyEvents` at the next
    /// impact, after `max_events` were handled.
    #[test]
    fn end_a_run_beyond_max_events() {
        let ball = Ball::default();
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&ball, solver).unwrap();
            sim.set_event_options(EventOptions {
                max_events: 5,
                ..EventOptions::default()
            })
            .unwrap();
            let error = sim.run(0.0, &initial(&ball), &[10.0], &mut ()).unwrap_err();
            let SolverError::TooManyEvents { event, t, limit } = error else {
                panic!("{name}: {error}")
            };
            assert_eq!((event, limit), ("floor", 5));
            assert!((t - ball.impact_time(6)).abs() < 1e-9, "{name}");
            assert_eq!(sim.stats().events, 5);
        }
    }

    /// An indicator that evaluates to NaN (here `sqrt(1 - t)` past t = 1) ends the run
    /// with `NonFiniteIndicator` naming the event, not with an event silently never
    /// firing.
    #[test]
    fn refuse_an_indicator_that_is_not_a_number() {
        use bgdsl_runtime::{Direction, EventInfo, Scalar};
        struct Undefined;
        impl Model for Undefined {
            type Params = ();
            const NAME: &'static str = "undefined";
            const STATE_NAMES: &'static [&'static str] = &["x"];
            const OUTPUT_NAMES: &'static [&'static str] = &[];
            const EVENTS: &'static [EventInfo] = &[EventInfo {
                name: "root",
                direction: Direction::Both,
                doc: "",
            }];
            fn params(&self) -> &() {
                &()
            }
            fn initial_state(&self, x0: &mut [f64]) {
                x0[0] = 0.0;
            }
            fn derivatives<T: Scalar>(&self, _t: f64, _x: &[T], dx: &mut [T]) {
                dx[0] = T::from_f64(1.0);
            }
            fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
            fn event_indicators(&self, t: f64, _x: &[f64], g: &mut [f64]) {
                g[0] = (1.0 - t).sqrt() + 1.0;
            }
        }
        for (name, solver) in methods() {
            let mut sim = Simulation::new(&Undefined, solver).unwrap();
            let error = sim.run(0.0, &[0.0], &[2.0], &mut ()).unwrap_err();
            let SolverError::NonFiniteIndicator { event, t, value } = error else {
                panic!("{name}: {error}")
            };
            assert_eq!(event, "root");
            assert!(t > 1.0 && value.is_nan(), "{name}: {t} {value}");
        }
    }

    /// Options out of range are refused by name.
    #[test]
    fn refuse_bad_event_options() {
        let ball = Ball::default();
        let mut sim = Simulation::new(&ball, Solver::dopri5()).unwrap();
        for (bad, option) in [
            (
                EventOptions {
                    time_tolerance: -1.0,
                    ..EventOptions::default()
                },
                "time_tolerance",
            ),
            (
                EventOptions {
                    max_repeats: 0,
                    ..EventOptions::default()
                },
                "max_repeats",
            ),
            (
                EventOptions {
                    min_interval: f64::NAN,
                    ..EventOptions::default()
                },
                "min_interval",
            ),
        ] {
            let error = sim.set_event_options(bad).unwrap_err();
            assert!(matches!(error, SolverError::InvalidOptions { option: o, .. } if o == option));
        }
        assert_eq!(*sim.event_options(), EventOptions::default());
    }

    /// `Stepper::advance_to` over intervals holding impacts reports them (time, state
    /// on both sides) and ends where one `Simulation` run through the same times ends,
    /// for every method.
    #[test]
    fn report_events_inside_stepper_advances() {
        let ball = Ball::default();
        let stops = [0.3, 0.9, 1.5, 2.4];
        for (name, solver) in methods() {
            let mut reference = Simulation::new(&ball, solver).unwrap();
            let mut traj = Trajectory::for_model::<Ball>(stops.len()).with_event_capacity(16);
            reference
                .run(0.0, &initial(&ball), &stops, &mut traj)
                .unwrap();
            let mut stepper = Stepper::new(ball.clone(), solver).unwrap();
            let mut seen = Vec::new();
            for (row, &t) in stops.iter().enumerate() {
                stepper.advance_to(t).unwrap();
                assert_eq!(stepper.events().dropped(), 0);
                seen.extend(
                    stepper
                        .events()
                        .iter()
                        .map(|e| (e.t, e.before[1], e.after[1])),
                );
                for (i, v) in stepper.state().iter().enumerate() {
                    let r = traj.state(row, i).unwrap();
                    assert!((v - r).abs() < 1e-9, "{name}: at {t}, {v} vs {r}");
                }
            }
            assert_eq!(stepper.events().len(), 1, "{name}: (2.4 - 1.5 s) holds one");
            let expected: Vec<_> = traj
                .events()
                .iter()
                .map(|e| (e.t, e.before[1], e.after[1]))
                .collect();
            assert_eq!(seen.len(), expected.len(), "{name}");
            for (s, e) in seen.iter().zip(&expected) {
                assert!(
                    (s.0 - e.0).abs() < 1e-9 && (s.2 - e.2).abs() < 1e-9,
                    "{name}"
                );
            }
            for (k, s) in seen.iter().enumerate() {
                assert!((s.0 - ball.impact_time(k + 1)).abs() < 1e-9, "{name}");
            }
        }
    }

    /// A stepper keeps the events of one advance up to its capacity and counts the
    /// rest; a stop ends the advance at the event.
    #[test]
    fn bound_the_stepper_event_log_and_stop_advances() {
        let ball = Ball::default();
        let mut stepper = Stepper::new(ball.clone(), Solver::dopri5()).unwrap();
        stepper.set_event_capacity(2);
        stepper.advance_to(ball.apex(5).0).unwrap();
        assert_eq!((stepper.events().len(), stepper.events().dropped()), (2, 3));
        let stopping = Ball {
            stop: true,
            ..Ball::default()
        };
        let mut stepper = Stepper::new(stopping.clone(), Solver::dopri5()).unwrap();
        stepper.advance_to(1.0).unwrap();
        assert!((stepper.time() - stopping.impact_time(1)).abs() < 1e-9);
        assert_eq!(stepper.events().len(), 1);
    }

    /// A stepper's advances continue each other's events: a both-ways floor event that
    /// stops every advance at an impact (bounce applied) is armed for the next advance,
    /// which does not fire again as the ball leaves the floor from `h ≈ -1e-13`; each
    /// advance ends at the next closed-form impact. `set_state` starts afresh, even at
    /// the same point (then the climb fires).
    #[test]
    fn continue_events_from_one_stepper_advance_to_the_next() {
        let ball = EitherWayBall(Ball {
            stop: true,
            ..Ball::default()
        });
        for (name, solver) in methods() {
            let mut stepper = Stepper::new(ball.clone(), solver).unwrap();
            for k in 1..=5 {
                stepper.advance_to(10.0).unwrap();
                assert_eq!(stepper.events().len(), 1, "{name}: advance {k}");
                let t = stepper.events().times()[0];
                assert!(
                    (t - ball.0.impact_time(k)).abs() < 1e-9,
                    "{name}: impact {k} at {t}"
                );
                assert_eq!(stepper.time(), t);
            }
            // `set_state` at the very same point starts afresh: the reference is where
            // the ball stands (a hair below the floor), so its climb through 0 is now a
            // crossing of the both-ways event, at once.
            let (t, x) = (stepper.time(), stepper.state().to_vec());
            assert!(x[0] <= 0.0 && x[1] > 0.0, "{name}: {x:?}");
            stepper.set_state(t, &x).unwrap();
            stepper.advance_to(10.0).unwrap();
            let first = stepper.events().times()[0];
            assert!(first - t < 1e-9, "{name}: {first} after {t}");
        }
    }

    /// The chattering rule counts on across a stepper's advances: the Zeno ball advanced
    /// 1 ms at a time ends as in one run (`max_repeats` 3, `min_interval` 0.02 s).
    #[test]
    fn count_chattering_across_stepper_advances() {
        let ball = Ball {
            e: 0.5,
            ..Ball::default()
        };
        let k = (2..)
            .find(|&k| ball.impact_time(k) - ball.impact_time(k - 1) < 0.02)
            .unwrap();
        let mut stepper = Stepper::new(ball.clone(), Solver::dopri5()).unwrap();
        stepper
            .set_event_options(EventOptions {
                min_interval: 0.02,
                max_repeats: 3,
                ..EventOptions::default()
            })
            .unwrap();
        let error = (1..10_000)
            .find_map(|i| stepper.advance_to(i as f64 * 1e-3).err())
            .unwrap();
        let SolverError::Chattering { count, t, .. } = error else {
            panic!("{error}")
        };
        assert_eq!(count, 3);
        assert!((t - ball.impact_time(k + 2)).abs() < 1e-9);
    }

    /// The energy an impact takes, `event_energy`, is `(e² - 1) v² / 2` (unit mass),
    /// and with it the ball's energy balance closes over 10 bounces:
    /// `H(t) - H(0) = Σ event_energy` (no sources, no resistors).
    #[test]
    fn close_the_energy_balance_with_event_energies() {
        let ball = Ball::default();
        let t_end = ball.apex(10).0;
        let mut sim = Simulation::new(&ball, Solver::dopri5()).unwrap();
        let mut traj = Trajectory::for_model::<Ball>(2).with_event_capacity(16);
        sim.run(0.0, &initial(&ball), &[0.0, t_end], &mut traj)
            .unwrap();
        let mut sum = 0.0;
        for e in traj.events().iter() {
            let de = event_energy(&ball, e.t, e.before, e.after).unwrap();
            let v = e.before[1];
            assert!((de - 0.5 * (ball.e * ball.e - 1.0) * v * v).abs() < 1e-12);
            sum += de;
        }
        let energy = |row| {
            let x = [traj.state(row, 0).unwrap(), traj.state(row, 1).unwrap()];
            ball.power_balance::<f64>(0.0, &x).unwrap().stored
        };
        let drift = energy(1) - energy(0) - sum;
        assert!(drift.abs() < 1e-9, "balance off by {drift:e}");
        assert!(
            sum < -0.5 * energy(0),
            "most of the energy went in the impacts"
        );
    }
}
