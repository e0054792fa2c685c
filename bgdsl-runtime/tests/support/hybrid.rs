//! Hand-written hybrid models for the event tests and benches, with their closed forms.
#![allow(dead_code)]

use bgdsl_runtime::{
    Direction, EventAction, EventInfo, ModeInfo, ModeKind, Model, PowerBalance, Scalar,
};

/// A ball of unit mass dropped from rest at height `h0` onto a floor at 0 under
/// gravity `g`: `h' = v`, `v' = -g`; when `h` falls through 0, `v -> -e v`. With `stop`,
/// every impact (the bounce applied) also ends the run. `floor` shifts the floor (far below: the
/// same free fall without events, for comparisons).
#[derive(Clone, Debug)]
pub struct Ball {
    pub g: f64,
    pub e: f64,
    pub h0: f64,
    pub floor: f64,
    pub stop: bool,
}

impl Default for Ball {
    fn default() -> Self {
        Ball {
            g: 9.81,
            e: 0.9,
            h0: 1.0,
            floor: 0.0,
            stop: false,
        }
    }
}

impl Ball {
    /// The speed at the first impact.
    pub fn impact_speed(&self) -> f64 {
        (2.0 * self.g * self.h0).sqrt()
    }

    /// The time of impact `k` (1-based): `t_1 = sqrt(2 h0 / g)`, then each flight
    /// lasts `2 e^j v_1 / g`.
    pub fn impact_time(&self, k: usize) -> f64 {
        let v1 = self.impact_speed();
        let mut t = v1 / self.g;
        for j in 1..k {
            t += 2.0 * self.e.powi(j as i32) * v1 / self.g;
        }
        t
    }

    /// The apex after impact `k`: its time and height `e^(2k) h0`.
    pub fn apex(&self, k: usize) -> (f64, f64) {
        let u = self.e.powi(k as i32) * self.impact_speed();
        (self.impact_time(k) + u / self.g, u * u / (2.0 * self.g))
    }
}

const BALL_EVENTS: &[EventInfo] = &[EventInfo {
    name: "floor",
    direction: Direction::Falling,
    doc: "The ball reaches the floor.",
}];

impl Model for Ball {
    type Params = ();
    const NAME: &'static str = "ball";
    const STATE_NAMES: &'static [&'static str] = &["h", "v"];
    const OUTPUT_NAMES: &'static [&'static str] = &["h_out"];
    const EVENTS: &'static [EventInfo] = BALL_EVENTS;
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[self.h0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[1];
        dx[1] = T::from_f64(-self.g);
    }
    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        y[0] = x[0];
    }
    fn power_balance<T: Scalar>(&self, _t: f64, x: &[T]) -> Option<PowerBalance<T>> {
        let c = T::from_f64;
        Some(PowerBalance {
            stored: c(0.5) * x[1] * x[1] + c(self.g) * x[0],
            input: c(0.0),
            dissipated: c(0.0),
        })
    }
    fn event_indicators(&self, _t: f64, x: &[f64], g: &mut [f64]) {
        g[0] = x[0] - self.floor;
    }
    fn apply_event(&self, _index: usize, _t: f64, x: &mut [f64]) -> EventAction {
        x[1] *= -self.e;
        if self.stop {
            EventAction::Stop
        } else {
            EventAction::Continue
        }
    }
}

/// A body that falls (`v' = -g`) until it reaches `h = 0`, where a mode switches its
/// acceleration to `+a` (no reinit): the dynamics change at the event. States `h`,
/// `v`, and the mode `thrust` (0 or 1).
#[derive(Clone, Debug)]
pub struct Switched {
    pub g: f64,
    pub a: f64,
    pub h0: f64,
}

impl Default for Switched {
    fn default() -> Self {
        Switched {
            g: 9.81,
            a: 30.0,
            h0: 1.0,
        }
    }
}

impl Switched {
    /// The closed form `(h, v)` at `t`.
    pub fn exact(&self, t: f64) -> (f64, f64) {
        let ts = (2.0 * self.h0 / self.g).sqrt();
        if t <= ts {
            return (self.h0 - 0.5 * self.g * t * t, -self.g * t);
        }
        let (s, vs) = (t - ts, -self.g * ts);
        (vs * s + 0.5 * self.a * s * s, vs + self.a * s)
    }
}

const SWITCHED_EVENTS: &[EventInfo] = &[EventInfo {
    name: "ground",
    direction: Direction::Falling,
    doc: "The body reaches h = 0: the thrust comes on.",
}];

const SWITCHED_MODES: &[ModeInfo] = &[ModeInfo {
    name: "thrust",
    kind: ModeKind::Bool,
    doc: "Whether the thrust is on.",
}];

impl Model for Switched {
    type Params = ();
    const NAME: &'static str = "switched";
    const STATE_NAMES: &'static [&'static str] = &["h", "v", "thrust"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const EVENTS: &'static [EventInfo] = SWITCHED_EVENTS;
    const MODES: &'static [ModeInfo] = SWITCHED_MODES;
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[self.h0, 0.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let thrust = x[2].to_f64() != 0.0;
        dx[0] = x[1];
        dx[1] = T::from_f64(if thrust { self.a } else { -self.g });
        dx[2] = T::from_f64(0.0);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    fn event_indicators(&self, _t: f64, x: &[f64], g: &mut [f64]) {
        g[0] = x[0];
    }
    fn apply_event(&self, _index: usize, _t: f64, x: &mut [f64]) -> EventAction {
        x[2] = 1.0;
        EventAction::Continue
    }
}

/// Events at given times on a state that only events change (`x' = 0`): event `i`'s
/// indicator is `t - times[i]` in direction `directions[i]`; its action is
/// `x <- x * scale[i] + shift[i]`, so the order in which simultaneous ones apply shows
/// in the result.
#[derive(Clone, Debug)]
pub struct Clock {
    pub times: [f64; 3],
    pub scale: [f64; 3],
    pub shift: [f64; 3],
}

const CLOCK_EVENTS: &[EventInfo] = &[
    EventInfo {
        name: "first",
        direction: Direction::Rising,
        doc: "",
    },
    EventInfo {
        name: "second",
        direction: Direction::Rising,
        doc: "",
    },
    EventInfo {
        name: "third",
        direction: Direction::Rising,
        doc: "",
    },
];

impl Model for Clock {
    type Params = ();
    const NAME: &'static str = "clock";
    const STATE_NAMES: &'static [&'static str] = &["x"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const EVENTS: &'static [EventInfo] = CLOCK_EVENTS;
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }
    fn derivatives<T: Scalar>(&self, _t: f64, _x: &[T], dx: &mut [T]) {
        dx[0] = T::from_f64(0.0);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    fn event_indicators(&self, t: f64, _x: &[f64], g: &mut [f64]) {
        for (g, ti) in g.iter_mut().zip(self.times) {
            *g = t - ti;
        }
    }
    fn apply_event(&self, index: usize, _t: f64, x: &mut [f64]) -> EventAction {
        x[0] = x[0] * self.scale[index] + self.shift[index];
        EventAction::Continue
    }
}

/// The harmonic oscillator `s' = c`, `c' = -s` from `(0, 1)`: `s = sin t`, with one
/// event on `s` crossing zero in direction `D` (0 rising, 1 falling, 2 both), counted
/// in the third state.
#[derive(Clone, Debug, Default)]
pub struct Sine<const D: u8>;

const fn direction(d: u8) -> Direction {
    match d {
        0 => Direction::Rising,
        1 => Direction::Falling,
        _ => Direction::Both,
    }
}

impl<const D: u8> Model for Sine<D> {
    type Params = ();
    const NAME: &'static str = "sine";
    const STATE_NAMES: &'static [&'static str] = &["s", "c", "count"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const EVENTS: &'static [EventInfo] = &[EventInfo {
        name: "zero",
        direction: direction(D),
        doc: "",
    }];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[0.0, 1.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[1];
        dx[1] = -x[0];
        dx[2] = T::from_f64(0.0);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    fn event_indicators(&self, _t: f64, x: &[f64], g: &mut [f64]) {
        g[0] = x[0];
    }
    fn apply_event(&self, _index: usize, _t: f64, x: &mut [f64]) -> EventAction {
        x[2] += 1.0;
        EventAction::Continue
    }
}

/// The [`Ball`] with its floor event firing in both directions: a ball leaving the
/// floor after a bounce must not fire it again on the way up.
#[derive(Clone, Debug, Default)]
pub struct EitherWayBall(pub Ball);

impl Model for EitherWayBall {
    type Params = ();
    const NAME: &'static str = "either_way_ball";
    const STATE_NAMES: &'static [&'static str] = Ball::STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = Ball::OUTPUT_NAMES;
    const EVENTS: &'static [EventInfo] = &[EventInfo {
        name: "floor",
        direction: Direction::Both,
        doc: "The ball reaches the floor (or leaves it).",
    }];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        self.0.initial_state(x0);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.0.derivatives(t, x, dx);
    }
    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        self.0.outputs(t, x, y);
    }
    fn event_indicators(&self, t: f64, x: &[f64], g: &mut [f64]) {
        self.0.event_indicators(t, x, g);
    }
    fn apply_event(&self, index: usize, t: f64, x: &mut [f64]) -> EventAction {
        self.0.apply_event(index, t, x)
    }
}

/// The [`Ball`] with a hand-written Jacobian that notes the time of every evaluation,
/// to see where a stiff method evaluates its Jacobians.
#[derive(Debug, Default)]
pub struct JacobianSpy {
    pub ball: Ball,
    pub times: std::cell::RefCell<Vec<f64>>,
}

impl Model for JacobianSpy {
    type Params = ();
    const NAME: &'static str = "jacobian_spy";
    const STATE_NAMES: &'static [&'static str] = Ball::STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = Ball::OUTPUT_NAMES;
    const EVENTS: &'static [EventInfo] = Ball::EVENTS;
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        self.ball.initial_state(x0);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.ball.derivatives(t, x, dx);
    }
    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        self.ball.outputs(t, x, y);
    }
    fn jacobian(&self, t: f64, _x: &[f64], jac: &mut [f64]) -> bool {
        self.times.borrow_mut().push(t);
        jac.copy_from_slice(&[0.0, 1.0, 0.0, 0.0]);
        true
    }
    fn event_indicators(&self, t: f64, x: &[f64], g: &mut [f64]) {
        self.ball.event_indicators(t, x, g);
    }
    fn apply_event(&self, index: usize, t: f64, x: &mut [f64]) -> EventAction {
        self.ball.apply_event(index, t, x)
    }
}
