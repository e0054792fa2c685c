//! Events and modes written in the language, end to end: the generated
//! `event_indicators` / `apply_event` / modes against closed forms, run by the
//! runtime's event driver. Every tolerance is stated where it is used.

mod common;

use bgdsl_runtime::event::{Direction, EventAction, ModeKind};
use bgdsl_runtime::{bond_graph, Model, Simulation, Solver, Trajectory};
use common::{dopri5, initial_state};

bond_graph! {
    /// A ball dropped from `h0` on a floor, bouncing with a coefficient of restitution.
    pub model Ball {
        param m = 0.5 in "kg";
        param g = 9.81 in "m/s²";
        param restitution = 0.8;
        param h0 = 1.0 in "m";

        Se weight = -m * g;
        I ball = m, p in "kg·m/s";
        weight -> ball;

        /// Height above the floor.
        state x: f64 = h0 in "m";
        der x = ball.f;

        /// The ball reaches the floor: its momentum turns over, scaled by the restitution.
        when impact: x < 0.0 {
            reinit ball.p = -restitution * ball.p;
        }
        output height = x;
    }
}

bond_graph! {
    /// A mass pushed by a constant force from rest; a brake (a damper whose law
    /// depends on a mode) engages when the speed reaches `v_on`.
    pub model Brake {
        param m = 2.0 in "kg";
        param force = 1.0 in "N";
        param c = 4.0 in "N·s/m";
        param v_on = 0.3 in "m/s";

        Se push = force;
        I mass = m;
        R brake { e = if braking { c * f } else { 0.0 * f } };
        1 v;
        push -> v -> { mass, brake };

        /// Whether the brake is on.
        mode braking: bool = false;
        when v.f > v_on { braking = true; }
        output on = if braking { 1.0 } else { 0.0 };
    }
}

bond_graph! {
    /// An undamped oscillator that counts the zero crossings of its displacement in an
    /// `i64` mode and keeps the time of the last one in an `f64` mode.
    pub model Counter {
        param k = 4.0;
        Se zero = 0.0;
        C spring = k;
        I mass = 1.0;
        1 v;
        zero -> v -> { spring, mass };
        init spring.q = 1.0;

        mode count: i64 = 0;
        mode last: f64 = -1.0;
        when crossing(spring.q) {
            count = count + 1;
            last = t;
        }
        output third = if count >= 3 { 1.0 } else { 0.0 };
        output since = t - last;
    }
}

bond_graph! {
    /// A wall: when `gap` falls through zero, `body`'s momentum turns over, and the
    /// wall counts its hits.
    submodel Wall(body, gap) {
        mode hits: i64 = 0;
        when gap < 0.0 {
            reinit body.p = -body.p;
            hits = hits + 1;
        }
    }

    /// A cart moving freely between two walls at x = -1 m and x = 1 m.
    pub model Corridor {
        Se none = 0.0;
        I cart = 1.0;
        none -> cart;
        init cart.p = 1.0;
        state x: f64 = 0.0;
        der x = cart.f;
        Wall right(body = cart, gap = 1.0 - x);
        Wall left(body = cart, gap = x + 1.0);
    }
}

bond_graph! {
    /// Two free masses whose momenta are swapped at t = 0.5 s, and a flag that reads
    /// the pre-event momentum of `a` while `a` is reset in the same event.
    pub model Swap {
        Se none_a = 0.0;
        Se none_b = 0.0;
        I a = 1.0;
        I b = 1.0;
        none_a -> a;
        none_b -> b;
        init a.p = 1.0;
        init b.p = 2.0;
        mode saw: bool = false;
        output flag = if saw { 1.0 } else { 0.0 };
        when swap: t > 0.5 {
            reinit a.p = b.p;
            reinit b.p = a.p;
            if a.p > 0.5 { saw = true; } else { saw = false; }
        }
    }

    /// A mass pushed from rest by a constant force; the run stops when it has moved 1 m
    /// (a threshold written as a parameter expression, which the model caches).
    pub model Stopper {
        param force = 2.0;
        param half = 0.5;
        Se push = force;
        I mass = 1.0;
        push -> mass;
        state x: f64 = 0.0;
        der x = mass.f;
        when x > (2.0 * half).sqrt() { stop; }
    }
}

bond_graph! {
    /// A capacitor charged from a source through two resistors in series (an algebraic
    /// loop, solved at every evaluation); when its voltage passes `level` a mode
    /// lowers the second resistance.
    #[allow(algebraic_loops)]
    pub model Charger {
        param e1 = 1.0;
        param r_1 = 1.0;
        param r_2 = 2.0;
        param r_fast = 0.5;
        param c = 0.1;
        param level = 0.5;

        Se source = e1;
        R r1 = r_1;
        R r2 = if fast { r_fast } else { r_2 };
        C cap = 1.0 / c;
        1 current;
        0 node;
        source -> current -> { r1, r2, node };
        node -> cap;

        mode fast: bool = false;
        when node.e > level { fast = true; }
        output e2 = node.e;
    }
}

fn simulate<M: Model>(model: &M, solver: Solver, t_end: f64, n: usize) -> Trajectory {
    let mut sim = Simulation::new(model, solver).expect("valid solver options");
    let mut traj = Trajectory::for_model::<M>(n).with_event_capacity(64);
    sim.run_uniform(0.0, &initial_state(model), t_end, n, &mut traj)
        .expect("the run succeeds");
    traj
}

/// The impact times of a ball dropped from rest at height h0 with restitution e:
/// t1 = √(2 h0 / g), then flights of 2 eᵏ v1 / g with v1 = g t1.
fn impact_times(h0: f64, g: f64, e: f64, n: usize) -> Vec<f64> {
    let t1 = (2.0 * h0 / g).sqrt();
    let v1 = g * t1;
    let mut times = vec![t1];
    for k in 1..n {
        times.push(times[k - 1] + 2.0 * e.powi(k as i32) * v1 / g);
    }
    times
}

mod should {
    use super::*;

    #[test]
    fn describe_modes_and_events_and_store_modes_as_trailing_states() {
        assert_eq!(Ball::STATE_NAMES, ["ball.p", "x"]);
        assert_eq!(Ball::EVENTS.len(), 1);
        assert_eq!(Ball::EVENTS[0].name, "impact");
        assert_eq!(Ball::EVENTS[0].direction, Direction::Falling);
        assert_eq!(
            Ball::EVENTS[0].doc,
            "The ball reaches the floor: its momentum turns over, scaled by the restitution."
        );
        assert!(Ball::MODES.is_empty());
        assert_eq!(
            Counter::STATE_NAMES,
            ["spring.q", "mass.p", "count", "last"]
        );
        assert_eq!(Counter::MODES.len(), 2);
        assert_eq!(Counter::MODES[0].kind, ModeKind::Integer);
        assert_eq!(Counter::MODES[1].kind, ModeKind::Real);
        assert_eq!(Counter::EVENTS[0].name, "when_1");
        assert_eq!(Counter::EVENTS[0].direction, Direction::Both);
        assert_eq!(Brake::EVENTS[0].direction, Direction::Rising);
        assert_eq!(Brake::MODES[0].doc, "Whether the brake is on.");
        assert_eq!(Brake::STATES[1].doc, "Whether the brake is on.");
        // The named state view has the mode too.
        let state = BrakeState::from_slice(&[0.5, 1.0]);
        assert_eq!(state.braking, 1.0);
        let counter = CounterState::from_slice(&initial_state(&Counter::default()));
        assert_eq!((counter.count, counter.last), (0.0, -1.0));
        // Mode rows of the sparsity are empty, and no row reads a mode's column: a
        // law reads a mode as a plain value, with no derivative.
        assert_eq!(
            Brake::JACOBIAN_SPARSITY,
            Some(&[&[0usize] as &[usize], &[]] as &[&[usize]])
        );
        assert_eq!(
            Corridor::STATE_NAMES,
            ["cart.p", "x", "right.hits", "left.hits"]
        );
        assert_eq!(Corridor::EVENTS[0].name, "right.when_1");
        assert_eq!(Corridor::EVENTS[1].name, "left.when_1");
    }

    /// The actions alone, on the state vector: a swap reads pre-event values, a flag
    /// set in an `if` reads `a.p` before its reset, `stop` says so.
    #[test]
    fn apply_actions_to_the_state_simultaneously() {
        let swap = Swap::default();
        let mut x = initial_state(&swap);
        assert_eq!(x, [1.0, 2.0, 0.0]);
        assert_eq!(swap.apply_event(0, 0.5, &mut x), EventAction::Continue);
        assert_eq!(x, [2.0, 1.0, 1.0]);
        let mut g = [0.0];
        swap.event_indicators(0.25, &x, &mut g);
        assert_eq!(g, [0.25 - 0.5]);
        let stopper = Stopper::default();
        let mut x = initial_state(&stopper);
        assert_eq!(stopper.apply_event(0, 1.0, &mut x), EventAction::Stop);
        let ball = Ball::default();
        let mut x = [-2.0, 0.0];
        assert_eq!(ball.apply_event(0, 0.45, &mut x), EventAction::Continue);
        assert_eq!(x, [-0.8 * -2.0, 0.0]);
        let corridor = Corridor::default();
        let mut x = [1.0, 1.0, 0.0, 0.0];
        let mut g = [0.0; 2];
        corridor.event_indicators(1.0, &x, &mut g);
        assert_eq!(g, [0.0, 2.0]);
        corridor.apply_event(0, 1.0, &mut x);
        assert_eq!(x, [-1.0, 1.0, 1.0, 0.0]);
    }

    #[test]
    fn give_every_mode_a_derivative_of_exactly_zero() {
        let model = Counter::default();
        let x = [0.3, -1.2, 7.0, 2.5];
        let mut dx = [f64::NAN; 4];
        model.derivatives(0.1, &x, &mut dx);
        assert_eq!(&dx[2..], [0.0, 0.0]);
        // dq/dt = p / m, dp/dt = -k q: the continuous part is untouched by the modes.
        assert_eq!(&dx[..2], [-1.2, -4.0 * 0.3]);
    }

    #[test]
    fn switch_a_law_by_a_mode() {
        let model = Brake::default();
        let mut dx = [0.0; 2];
        // p = 1 kg·m/s: f = 0.5 m/s. Off: dp/dt = F; on: dp/dt = F − c f.
        model.derivatives(0.0, &[1.0, 0.0], &mut dx);
        assert_eq!(dx, [1.0, 0.0]);
        model.derivatives(0.0, &[1.0, 1.0], &mut dx);
        assert_eq!(dx, [1.0 - 4.0 * 0.5, 0.0]);
        let mut g = [0.0];
        model.event_indicators(0.0, &[1.0, 0.0], &mut g);
        assert_eq!(g, [0.5 - 0.3]);
    }

    /// The brake engages at t_on = m v_on / F = 0.6 s (p = F t before); after it,
    /// p(t) = F m / c + (p_on − F m / c) exp(−c (t − t_on) / m). DOPRI5 at rtol 1e-10
    /// and an event tolerance of 1e-12 s keep both within 1e-8.
    #[test]
    fn engage_a_brake_at_the_event_and_follow_the_braked_closed_form() {
        let model = Brake::default();
        let traj = simulate(&model, dopri5(1e-10, 1e-12), 2.0, 201);
        let events = traj.events();
        assert_eq!(events.len(), 1);
        let event = events.get(0).unwrap();
        let t_on = 2.0 * 0.3 / 1.0;
        assert!((event.t - t_on).abs() < 1e-8, "t_on {}", event.t);
        assert_eq!((event.before[1], event.after[1]), (0.0, 1.0));
        let (p_on, p_inf) = (2.0 * 0.3, 1.0 * 2.0 / 4.0);
        let exact = p_inf + (p_on - p_inf) * (-4.0 * (2.0 - t_on) / 2.0f64).exp();
        let last = traj.len() - 1;
        let p_end = traj.value(last, "mass.p").unwrap();
        assert!((p_end - exact).abs() < 1e-8, "{p_end} vs {exact}");
        assert_eq!(traj.value(last, "on"), Some(1.0));
    }

    /// Impacts against the closed form: between impacts the motion is a parabola, which
    /// DOPRI5 (order 5) and RK4 integrate exactly up to rounding, so the impact times
    /// carry only the location tolerance (1e-12 s) and rounding: 1e-9 s is generous.
    #[test]
    fn bounce_a_ball_at_the_closed_form_impact_times() {
        let model = Ball::default();
        let expected = impact_times(1.0, 9.81, 0.8, 6);
        for solver in [dopri5(1e-10, 1e-12), Solver::rk4(1e-3)] {
            let traj = simulate(&model, solver, 3.0, 301);
            let events = traj.events();
            let times: Vec<f64> = events.iter().map(|e| e.t).collect();
            assert_eq!(times.len(), expected.len(), "{times:?} vs {expected:?}");
            for (t, t_exact) in times.iter().zip(&expected) {
                assert!((t - t_exact).abs() < 1e-9, "{t} vs {t_exact}");
            }
            for event in events.iter() {
                assert_eq!(event.name, "impact");
                // p⁺ = −e p⁻, exactly as written.
                assert_eq!(event.after[0], -0.8 * event.before[0]);
                assert!(event.before[1].abs() < 1e-9);
            }
            let lowest = traj
                .column("height")
                .unwrap()
                .iter()
                .cloned()
                .fold(f64::INFINITY, f64::min);
            assert!(lowest > -1e-9, "the ball went through the floor: {lowest}");
        }
    }

    /// x = cos(2 t) crosses zero at t = (j + ½) π / 2: 6 times before 10 s, the last at
    /// 5.5 π / 2. The modes count them and keep the last time.
    #[test]
    fn count_crossings_in_an_integer_mode_and_keep_a_time_in_a_real_mode() {
        let model = Counter::default();
        let traj = simulate(&model, dopri5(1e-10, 1e-12), 10.0, 101);
        let events = traj.events();
        assert_eq!(events.len(), 6);
        let last = traj.len() - 1;
        assert_eq!(traj.value(last, "count"), Some(6.0));
        let t_last = 5.5 * core::f64::consts::PI / 2.0;
        assert!((traj.value(last, "last").unwrap() - t_last).abs() < 1e-8);
        assert_eq!(traj.value(last, "third"), Some(1.0));
        assert_eq!(traj.value(0, "third"), Some(0.0));
    }

    /// From x = 0 at 1 m/s: the right wall at t = 1 s, the left at t = 3 s, the right
    /// again at t = 5 s; at t = 6 s the cart is back at x = 0.
    #[test]
    fn reinit_a_body_from_a_submodel_instance() {
        let model = Corridor::default();
        let traj = simulate(&model, Solver::rk4(0.01), 6.0, 61);
        let names: Vec<&str> = traj.events().iter().map(|e| e.name).collect();
        assert_eq!(names, ["right.when_1", "left.when_1", "right.when_1"]);
        for (t, t_exact) in traj.events().times().iter().zip([1.0, 3.0, 5.0]) {
            assert!((t - t_exact).abs() < 1e-9, "{t}");
        }
        let last = traj.len() - 1;
        assert!(traj.value(last, "x").unwrap().abs() < 1e-9);
        assert_eq!(traj.value(last, "right.hits"), Some(2.0));
        assert_eq!(traj.value(last, "left.hits"), Some(1.0));
    }

    #[test]
    fn assign_simultaneously_from_pre_event_values() {
        let model = Swap::default();
        let mut x = initial_state(&model);
        assert_eq!(x, [1.0, 2.0, 0.0]);
        assert_eq!(model.apply_event(0, 0.5, &mut x), EventAction::Continue);
        assert_eq!(x, [2.0, 1.0, 1.0]);
        // Through the driver: the swap at t = 0.5 s, both momenta constant around it.
        let traj = simulate(&model, Solver::rk4(0.1), 1.0, 11);
        assert_eq!(traj.events().len(), 1);
        assert!((traj.events().times()[0] - 0.5).abs() < 1e-9);
        let last = traj.len() - 1;
        assert_eq!(traj.value(last, "a.p"), Some(2.0));
        assert_eq!(traj.value(last, "b.p"), Some(1.0));
        assert_eq!(traj.value(last, "flag"), Some(1.0));
    }

    /// Before the switch e2 = e1 (1 − exp(−t / τ₁)) with τ₁ = (r₁ + r₂) c = 0.3 s, so
    /// it passes 0.5 V at t_on = τ₁ ln 2; after it, e2 = e1 − (e1 − 0.5) exp(−(t −
    /// t_on) / τ₂) with τ₂ = (r₁ + r_fast) c = 0.15 s. DOPRI5 at rtol 1e-10 and the
    /// loop solved to rounding keep both within 1e-8.
    #[test]
    fn switch_a_mode_in_a_model_with_an_algebraic_loop() {
        let model = Charger::default();
        assert_eq!(Charger::STATE_NAMES, ["cap.q", "fast"]);
        let traj = simulate(&model, dopri5(1e-10, 1e-12), 1.0, 101);
        assert_eq!(traj.events().len(), 1);
        let t_on = 0.3 * 2.0f64.ln();
        let event = traj.events().get(0).unwrap();
        assert!((event.t - t_on).abs() < 1e-8, "{} vs {t_on}", event.t);
        assert_eq!((event.before[1], event.after[1]), (0.0, 1.0));
        let last = traj.len() - 1;
        let exact = 1.0 - 0.5 * (-(1.0 - t_on) / 0.15f64).exp();
        let e2 = traj.value(last, "e2").unwrap();
        assert!((e2 - exact).abs() < 1e-8, "{e2} vs {exact}");
        let mut g = [0.0];
        model.event_indicators(0.0, &[0.08, 0.0], &mut g);
        assert!((g[0] - (0.8 - 0.5)).abs() < 1e-12, "{g:?}");
    }

    /// x = F t² / 2 reaches 1 m at t = √(2 / F) = 1 s: the run ends there.
    #[test]
    fn stop_the_run_at_the_event() {
        let model = Stopper::default();
        let mut x = initial_state(&model);
        assert_eq!(model.apply_event(0, 1.0, &mut x), EventAction::Stop);
        let mut sim = Simulation::new(&model, dopri5(1e-10, 1e-12)).unwrap();
        let mut traj = Trajectory::for_model::<Stopper>(11).with_event_capacity(4);
        sim.run_uniform(0.0, &initial_state(&model), 10.0, 11, &mut traj)
            .expect("a stop ends the run without error");
        assert!((sim.time() - 1.0).abs() < 1e-9, "{}", sim.time());
        assert_eq!(traj.events().len(), 1);
        assert_eq!(traj.events().get(0).unwrap().action, EventAction::Stop);
        assert!(*traj.times().last().unwrap() < 1.0 + 1e-9);
    }
}
