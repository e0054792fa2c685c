//! Events through the FMI interface, on a hand-written bouncing ball whose closed form
//! is known: the test binary exports its own FMI symbols with `export_fmi2!` and plays
//! the importer.
//!
//! The ball falls from `h0` under gravity `g` and bounces with restitution `e`. Two
//! events watch the same indicator `h`, falling: `hit` reverses the velocity
//! (`v <- -e v`), `count` counts the bounce in the integer mode `bounces`, copies the
//! velocity the previous action left into the real mode `rebound`, and stops the run at
//! the `stop_after`-th bounce. So `rebound` says whether simultaneous events are
//! handled in index order, each on the state the previous one left.
//!
//! Closed form: the first impact at `t1 = sqrt(2 h0 / g)` with speed `v1 = g t1`;
//! bounce `k` at `t_k = t1 + (2 v1 / g) (e + e^2 + ... + e^(k-1))`, leaving upwards at
//! `e^k v1`.

use core::ffi::{c_char, c_int, c_void, CStr};
use std::ffi::CString;
use std::sync::Mutex;

use bgdsl_fmi_core::fmi2::{
    CallbackFunctions, CallbackLogger, Component, EventInfo, Status, FALSE, TRUE,
};
use bgdsl_fmi_core::{model_description_xml, ModelDescription, ModelEntry};
use bgdsl_runtime::{
    Direction, EventAction, EventInfo as Event, InputInfo, ModeInfo, ModeKind, Model, Scalar,
    Solver, WithInputs,
};

const G: f64 = 9.81;
const E: f64 = 0.8;
const H0: f64 = 1.0;

/// The bouncing ball, stopping at its `STOP`-th bounce.
#[derive(Clone, Debug, Default)]
struct Ball<const STOP: i64>;

impl<const STOP: i64> Model for Ball<STOP> {
    type Params = ();
    const NAME: &'static str = "Ball";
    const STATE_NAMES: &'static [&'static str] = &["h", "v", "bounces", "rebound"];
    const OUTPUT_NAMES: &'static [&'static str] = &["height"];
    const EVENTS: &'static [Event] = &[
        Event {
            name: "hit",
            direction: Direction::Falling,
            doc: "the ball reaches the floor: v <- -e v",
        },
        Event {
            name: "count",
            direction: Direction::Falling,
            doc: "counts the bounce, keeps the rebound speed, stops at the last bounce",
        },
    ];
    const MODES: &'static [ModeInfo] = &[
        ModeInfo {
            name: "bounces",
            kind: ModeKind::Integer,
            doc: "bounces so far",
        },
        ModeInfo {
            name: "rebound",
            kind: ModeKind::Real,
            doc: "the velocity after the last bounce",
        },
    ];

    fn params(&self) -> &() {
        &()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[H0, 0.0, 0.0, 0.0]);
    }

    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[1];
        dx[1] = T::from_f64(-G);
        dx[2] = T::from_f64(0.0);
        dx[3] = T::from_f64(0.0);
    }

    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        y[0] = x[0];
    }

    fn default_solver(&self) -> Solver {
        Solver::dopri5()
    }

    fn event_indicators(&self, _t: f64, x: &[f64], g: &mut [f64]) {
        g[0] = x[0];
        g[1] = x[0];
    }

    fn apply_event(&self, index: usize, _t: f64, x: &mut [f64]) -> EventAction {
        if index == 0 {
            x[1] *= -E;
            return EventAction::Continue;
        }
        x[2] += 1.0;
        x[3] = x[1];
        if x[2] >= STOP as f64 {
            EventAction::Stop
        } else {
            EventAction::Continue
        }
    }
}

impl<const STOP: i64> WithInputs for Ball<STOP> {
    type Inputs = ();
    const INPUTS: &'static [InputInfo] = &[];
    fn inputs(&self) {}
    fn set_inputs(&mut self, _: ()) {}
    fn input_values(&self, _: &mut [f64]) {}
    fn set_input_values(&mut self, _: &[f64]) {}
}

/// Bounces on, never stopping.
type Bouncing = Ball<{ i64::MAX }>;
/// Stops at the third bounce.
type Stopping = Ball<3>;

static MODELS: &[ModelEntry] = &[
    ModelEntry::new::<Bouncing>("bouncing"),
    ModelEntry::new::<Renamed>("stopping"),
    ModelEntry::new::<Alarm>("alarm"),
    ModelEntry::new::<Relay>("relay"),
];

/// A relay the host drives: its input `u` rising through 1 switches the mode `on`
/// (the only state), an event the host causes by setting the input.
#[derive(Clone, Debug)]
struct Relay {
    u: f64,
}

impl Default for Relay {
    fn default() -> Self {
        Relay { u: 0.0 }
    }
}

impl Model for Relay {
    type Params = ();
    const NAME: &'static str = "Relay";
    const STATE_NAMES: &'static [&'static str] = &["on"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const EVENTS: &'static [Event] = &[Event {
        name: "pull_in",
        direction: Direction::Rising,
        doc: "u rises through 1",
    }];
    const MODES: &'static [ModeInfo] = &[ModeInfo {
        name: "on",
        kind: ModeKind::Bool,
        doc: "the relay has pulled in",
    }];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 0.0;
    }
    fn derivatives<T: Scalar>(&self, _t: f64, _x: &[T], dx: &mut [T]) {
        dx[0] = T::from_f64(0.0);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    fn event_indicators(&self, _t: f64, _x: &[f64], g: &mut [f64]) {
        g[0] = self.u - 1.0;
    }
    fn apply_event(&self, _index: usize, _t: f64, x: &mut [f64]) -> EventAction {
        x[0] = 1.0;
        EventAction::Continue
    }
}

impl WithInputs for Relay {
    type Inputs = f64;
    const INPUTS: &'static [InputInfo] = &[InputInfo {
        name: "u",
        unit: "",
        doc: "the drive",
    }];
    fn inputs(&self) -> f64 {
        self.u
    }
    fn set_inputs(&mut self, u: f64) {
        self.u = u;
    }
    fn input_values(&self, out: &mut [f64]) {
        out[0] = self.u;
    }
    fn set_input_values(&mut self, values: &[f64]) {
        self.u = values[0];
    }
}

/// A clock whose alarm stops the run at `t = 1` (`x' = 1`, event `ring` when `t - 1`
/// rises through 0): a stop that can fall on a communication point exactly.
#[derive(Clone, Debug, Default)]
struct Alarm;

impl Model for Alarm {
    type Params = ();
    const NAME: &'static str = "Alarm";
    const STATE_NAMES: &'static [&'static str] = &["x"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const EVENTS: &'static [Event] = &[Event {
        name: "ring",
        direction: Direction::Rising,
        doc: "stops the run at t = 1",
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
    fn default_solver(&self) -> Solver {
        Solver::dopri5()
    }
    fn event_indicators(&self, t: f64, _x: &[f64], g: &mut [f64]) {
        g[0] = t - 1.0;
    }
    fn apply_event(&self, _index: usize, _t: f64, _x: &mut [f64]) -> EventAction {
        EventAction::Stop
    }
}

impl WithInputs for Alarm {
    type Inputs = ();
    const INPUTS: &'static [InputInfo] = &[];
    fn inputs(&self) {}
    fn set_inputs(&mut self, _: ()) {}
    fn input_values(&self, _: &mut [f64]) {}
    fn set_input_values(&mut self, _: &[f64]) {}
}

/// [`Stopping`] under a name of its own: `fmi2Instantiate` picks a model by its GUID,
/// which hashes the name and the variables, the same for both balls otherwise.
#[derive(Clone, Debug, Default)]
struct Renamed(Stopping);

impl Model for Renamed {
    type Params = ();
    const NAME: &'static str = "StoppingBall";
    const STATE_NAMES: &'static [&'static str] = Stopping::STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = Stopping::OUTPUT_NAMES;
    const EVENTS: &'static [Event] = Stopping::EVENTS;
    const MODES: &'static [ModeInfo] = Stopping::MODES;
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
    fn default_solver(&self) -> Solver {
        self.0.default_solver()
    }
    fn event_indicators(&self, t: f64, x: &[f64], g: &mut [f64]) {
        self.0.event_indicators(t, x, g);
    }
    fn apply_event(&self, index: usize, t: f64, x: &mut [f64]) -> EventAction {
        self.0.apply_event(index, t, x)
    }
}

impl WithInputs for Renamed {
    type Inputs = ();
    const INPUTS: &'static [InputInfo] = &[];
    fn inputs(&self) {}
    fn set_inputs(&mut self, _: ()) {}
    fn input_values(&self, _: &mut [f64]) {}
    fn set_input_values(&mut self, _: &[f64]) {}
}

bgdsl_fmi_core::export_fmi2!(MODELS);

use fmi2::*;

/// The time of bounce `k` (from 1) and the speed the ball leaves the floor with.
fn bounce(k: i32) -> (f64, f64) {
    let t1 = (2.0 * H0 / G).sqrt();
    let v1 = G * t1;
    let flights: f64 = (1..k).map(|j| 2.0 * E.powi(j) * v1 / G).sum();
    (t1 + flights, E.powi(k) * v1)
}

/// The closed-form height and velocity at `t`.
fn exact(t: f64) -> (f64, f64) {
    let (t1, _) = bounce(1);
    if t < t1 {
        return (H0 - 0.5 * G * t * t, -G * t);
    }
    let mut k = 1;
    while bounce(k + 1).0 <= t {
        k += 1;
    }
    let (tk, up) = bounce(k);
    let s = t - tk;
    (up * s - 0.5 * G * s * s, up - G * s)
}

#[derive(Default)]
struct Log(Mutex<Vec<(c_int, String, String)>>);

impl Log {
    fn all(&self) -> Vec<(c_int, String, String)> {
        self.0.lock().unwrap().clone()
    }

    fn last(&self) -> String {
        self.all().last().map(|m| m.2.clone()).unwrap_or_default()
    }
}

unsafe extern "C" fn capture(
    env: *mut c_void,
    _instance: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: `env` is the `Log`; the strings are the FMU's NUL-terminated ones.
    let (log, category, message) = unsafe {
        (
            &*(env as *const Log),
            CStr::from_ptr(category).to_string_lossy().into_owned(),
            CStr::from_ptr(message).to_string_lossy().into_owned(),
        )
    };
    log.0.lock().unwrap().push((status, category, message));
}

fn callbacks(log: &Log) -> CallbackFunctions {
    type Fixed =
        unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);
    // SAFETY: the FMU passes the five fixed arguments only (see `bgdsl-fmi/tests/ffi.rs`).
    let logger = unsafe { core::mem::transmute::<Fixed, CallbackLogger>(capture) };
    CallbackFunctions {
        logger: Some(logger),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: log as *const Log as *mut c_void,
    }
}

/// An instance of `M` (kind 0: Model Exchange, 1: Co-Simulation), initialised.
fn running<M: bgdsl_fmi_core::Exportable>(kind: c_int, cb: &CallbackFunctions) -> Component {
    let guid = CString::new(ModelDescription::of::<M>().guid).unwrap();
    // SAFETY: valid strings and callbacks.
    unsafe {
        let c = fmi2Instantiate(
            c"ball".as_ptr(),
            kind,
            guid.as_ptr(),
            core::ptr::null(),
            cb,
            FALSE,
            TRUE,
        );
        assert!(!c.is_null());
        assert_eq!(
            fmi2SetupExperiment(c, FALSE, 0.0, 0.0, FALSE, 0.0),
            Status::Ok
        );
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        c
    }
}

fn vr<M: bgdsl_fmi_core::Exportable>(name: &str) -> u32 {
    ModelDescription::of::<M>()
        .variables
        .find(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

/// The whole event iteration an importer runs once it located an event at `t` with
/// continuous state `x`: returns the event info and the state after.
///
/// # Safety
///
/// `c` is a live Model Exchange instance in Continuous-Time Mode.
unsafe fn event_at(c: Component, t: f64, x: [f64; 2]) -> (EventInfo, [f64; 2]) {
    let mut info = EventInfo::QUIET;
    let mut after = [0.0; 2];
    // SAFETY: the caller's contract; arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2SetTime(c, t), Status::Ok);
        assert_eq!(fmi2SetContinuousStates(c, x.as_ptr(), 2), Status::Ok);
        assert_eq!(fmi2EnterEventMode(c), Status::Ok);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(
            fmi2GetContinuousStates(c, after.as_mut_ptr(), 2),
            Status::Ok
        );
    }
    (info, after)
}

#[test]
fn the_description_declares_the_indicators_and_the_modes_as_discrete_variables() {
    let description = ModelDescription::of::<Bouncing>();
    let xml = model_description_xml(&description, "bouncing");
    assert!(xml.contains("numberOfEventIndicators=\"2\""), "{xml}");
    // Each accepted step's end is the reference the crossings are measured from.
    assert!(
        xml.contains("completedIntegratorStepNotNeeded=\"false\""),
        "{xml}"
    );
    for mode in ["bounces", "rebound"] {
        let at = xml.find(&format!("name=\"{mode}\"")).expect(mode);
        let line = &xml[at..at + xml[at..].find('>').unwrap()];
        assert!(
            line.contains("causality=\"local\" variability=\"discrete\" initial=\"exact\""),
            "{line}"
        );
        assert!(!xml.contains(&format!("der({mode})")), "{xml}");
    }
    assert!(xml.contains("name=\"der(v)\""), "{xml}");
    // Only the two continuous states have derivatives in the model structure.
    let derivatives = &xml[xml.find("<Derivatives>").unwrap()..xml.find("</Derivatives>").unwrap()];
    assert_eq!(derivatives.matches("<Unknown").count(), 2, "{derivatives}");
}

#[test]
fn model_exchange_handles_an_impact_where_the_importer_located_it() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Bouncing>(0, &cb);
    let t1 = bounce(1).0;
    let v1 = (2.0 * G * H0).sqrt(); // the speed of the first impact
    let mut z = [0.0; 2];
    let mut dx = [0.0; 2];
    let modes = [vr::<Bouncing>("bounces"), vr::<Bouncing>("rebound")];
    let mut mode_values = [0.0; 2];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        let mut info = EventInfo::QUIET;
        // The event iteration after initialisation: nothing fires at the start.
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(info.values_of_continuous_states_changed, FALSE);
        assert_eq!(info.new_discrete_states_needed, FALSE);
        assert_eq!(fmi2GetEventIndicators(c, z.as_mut_ptr(), 2), Status::Ok);
        assert_eq!(z, [H0, H0]);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 2), Status::Ok);
        assert_eq!(dx, [0.0, -G]);

        // The importer located the impact: just past it, h a hair below 0.
        let before = [-1e-12, -v1];
        let (mut info, after) = event_at(c, t1, before);
        assert_eq!(info.values_of_continuous_states_changed, TRUE);
        assert_eq!(info.terminate_simulation, FALSE);
        assert_eq!(info.new_discrete_states_needed, FALSE);
        assert_eq!(info.next_event_time_defined, FALSE);
        assert_eq!(after, [-1e-12, E * v1]);
        assert_eq!(
            fmi2GetReal(c, modes.as_ptr(), 2, mode_values.as_mut_ptr()),
            Status::Ok
        );
        // `count` ran after `hit` and saw the velocity `hit` left.
        assert_eq!(mode_values, [1.0, E * v1]);

        // A second call in the same Event Mode: settled, nothing changes.
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(info.values_of_continuous_states_changed, FALSE);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);

        // The ball rises through h = 0: the importer sees a sign change, the events
        // are falling ones, so nothing happens.
        let (info, after) = event_at(c, t1 + 1e-9, [1e-9, E * v1]);
        assert_eq!(info.values_of_continuous_states_changed, FALSE);
        assert_eq!(after, [1e-9, E * v1]);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);

        // The second impact: leaving at e^2 v1 (as the FMU multiplies).
        let t2 = bounce(2).0;
        let v2 = E * v1 * E;
        let (info, after) = event_at(c, t2, [-1e-12, -E * v1]);
        assert_eq!(info.values_of_continuous_states_changed, TRUE);
        assert_eq!(after[1], v2);
        assert_eq!(
            fmi2GetReal(c, modes.as_ptr(), 2, mode_values.as_mut_ptr()),
            Status::Ok
        );
        assert_eq!(mode_values, [2.0, v2]);
        assert_eq!(fmi2Terminate(c), Status::Ok);
        fmi2FreeInstance(c);
    }
}

/// An indicator exactly 0 where initialisation ends (the ball thrown up from the
/// floor) takes its sign from the next accepted step, without an event there; the
/// impact that follows fires.
#[test]
fn an_indicator_zero_at_the_start_takes_its_sign_from_the_next_step() {
    let log = Log::default();
    let cb = callbacks(&log);
    let guid = CString::new(ModelDescription::of::<Bouncing>().guid).unwrap();
    let start = [vr::<Bouncing>("h"), vr::<Bouncing>("v")];
    let (mut enter, mut stop) = (FALSE, FALSE);
    let mut info = EventInfo::QUIET;
    // SAFETY: valid strings and callbacks; arrays of the lengths passed.
    unsafe {
        let c = fmi2Instantiate(
            c"ball".as_ptr(),
            0,
            guid.as_ptr(),
            core::ptr::null(),
            &cb,
            FALSE,
            TRUE,
        );
        assert_eq!(
            fmi2SetReal(c, start.as_ptr(), 2, [0.0, 2.0].as_ptr()),
            Status::Ok
        );
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(info.values_of_continuous_states_changed, FALSE);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        assert_eq!(fmi2SetTime(c, 0.1), Status::Ok);
        assert_eq!(
            fmi2SetContinuousStates(c, [0.15, 1.0].as_ptr(), 2),
            Status::Ok
        );
        assert_eq!(
            fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
            Status::Ok
        );
        assert_eq!(enter, FALSE);
        let (info, after) = event_at(c, 0.41, [-1e-12, -2.0]);
        assert_eq!(info.values_of_continuous_states_changed, TRUE);
        assert_eq!(after, [-1e-12, 2.0 * E]);
        fmi2FreeInstance(c);
    }
}

/// An importer that does not locate events (it only reports accepted steps) is asked
/// into Event Mode by `fmi2CompletedIntegratorStep` at the first step past a crossing.
#[test]
fn a_crossing_the_importer_missed_asks_for_event_mode_at_the_step() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Bouncing>(0, &cb);
    let (mut enter, mut stop) = (FALSE, FALSE);
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        for (t, h) in [(0.2, 0.8), (0.4, 0.2)] {
            assert_eq!(fmi2SetTime(c, t), Status::Ok);
            assert_eq!(
                fmi2SetContinuousStates(c, [h, -G * t].as_ptr(), 2),
                Status::Ok
            );
            assert_eq!(
                fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
                Status::Ok
            );
            assert_eq!((enter, stop), (FALSE, FALSE));
        }
        assert_eq!(fmi2SetTime(c, 0.6), Status::Ok);
        assert_eq!(
            fmi2SetContinuousStates(c, [-0.5, -G * 0.6].as_ptr(), 2),
            Status::Ok
        );
        assert_eq!(
            fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
            Status::Ok
        );
        assert_eq!((enter, stop), (TRUE, FALSE));
        // Asked again (the importer did not listen): still pending.
        assert_eq!(
            fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
            Status::Ok
        );
        assert_eq!(enter, TRUE);
        let mut info = EventInfo::QUIET;
        let mut x = [0.0; 2];
        assert_eq!(fmi2EnterEventMode(c), Status::Ok);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(fmi2GetContinuousStates(c, x.as_mut_ptr(), 2), Status::Ok);
        assert_eq!(x, [-0.5, E * G * 0.6]);
        fmi2FreeInstance(c);
    }
}

#[test]
fn a_stop_action_asks_the_importer_to_terminate() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Renamed>(0, &cb);
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(
            fmi2SetDebugLogging(c, TRUE, 1, [c"logEvents".as_ptr()].as_ptr()),
            Status::Ok
        );
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        let (mut enter, mut stop) = (FALSE, FALSE);
        for k in 1..=3 {
            let (tk, _) = bounce(k);
            // An accepted step in the air before each impact.
            assert_eq!(
                fmi2SetContinuousStates(c, [0.1, -1.0].as_ptr(), 2),
                Status::Ok
            );
            assert_eq!(
                fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
                Status::Ok
            );
            assert_eq!((enter, stop), (FALSE, FALSE));
            let (info, _) = event_at(c, tk, [-1e-12, -1.0]);
            let last = k == 3;
            assert_eq!(
                info.terminate_simulation,
                if last { TRUE } else { FALSE },
                "bounce {k}"
            );
            if !last {
                assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
            }
        }
        // The run is over: no more integration, but termination.
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Error);
        assert!(log.last().contains("call fmi2Terminate"), "{}", log.last());
        assert_eq!(
            fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
            Status::Error
        );
        assert_eq!(fmi2Terminate(c), Status::Ok);
        fmi2FreeInstance(c);
    }
    let events: Vec<_> = log
        .all()
        .into_iter()
        .filter(|(_, category, _)| category == "logEvents")
        .map(|m| m.2)
        .collect();
    assert_eq!(events.len(), 6, "{events:?}"); // hit and count, three times
    assert!(events[0].starts_with("event hit at t = "), "{events:?}");
    assert!(events[0].contains("v -1 -> 0.8"), "{events:?}");
    assert!(
        events[5].contains("bounces 2 -> 3") && events[5].ends_with("; stop"),
        "{events:?}"
    );
}

#[test]
fn wrong_event_calls_are_errors_with_a_message_and_no_crash() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Bouncing>(0, &cb);
    let mut info = EventInfo::QUIET;
    let mut z = [0.0; 3];
    let mut x = [0.0; 4];
    // SAFETY: a live component; arrays at least as long as passed (or NULL on purpose).
    unsafe {
        assert_eq!(
            fmi2NewDiscreteStates(c, core::ptr::null_mut()),
            Status::Error
        );
        assert!(log.last().contains("fmi2EventInfo"), "{}", log.last());
        assert_eq!(fmi2GetEventIndicators(c, z.as_mut_ptr(), 3), Status::Error);
        assert!(
            log.last()
                .contains("ni = 3, but Ball has 2 event indicators"),
            "{}",
            log.last()
        );
        assert_eq!(
            fmi2GetEventIndicators(c, core::ptr::null_mut(), 2),
            Status::Error
        );
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Error);
        assert!(log.last().contains("Event Mode"), "{}", log.last());
        // The modes are not continuous states: nx counts h and v only.
        assert_eq!(fmi2GetContinuousStates(c, x.as_mut_ptr(), 4), Status::Error);
        assert!(
            log.last()
                .contains("nx = 4, but Ball has 2 continuous states (and 2 discrete modes"),
            "{}",
            log.last()
        );
        assert_eq!(fmi2SetContinuousStates(c, x.as_ptr(), 3), Status::Error);
        assert_eq!(fmi2GetDerivatives(c, x.as_mut_ptr(), 4), Status::Error);
        assert_eq!(
            fmi2GetNominalsOfContinuousStates(c, x.as_mut_ptr(), 2),
            Status::Ok
        );
        assert_eq!(x[..2], [1.0, 1.0]);
        // Still working after the refused calls.
        assert_eq!(fmi2GetEventIndicators(c, z.as_mut_ptr(), 2), Status::Ok);
        assert_eq!(z[..2], [H0, H0]);
        fmi2FreeInstance(c);
    }
}

/// Co-Simulation: a step across impacts lands on the closed form (DOPRI5 integrates
/// the ball's quadratic flights exactly, and the runtime locates each impact to
/// 1e-12 s, so agreement to 1e-9 is the locating and rounding error, not the method's).
#[test]
fn a_co_simulation_step_across_impacts_lands_on_the_closed_form() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Bouncing>(1, &cb);
    let vrs = [
        vr::<Bouncing>("h"),
        vr::<Bouncing>("v"),
        vr::<Bouncing>("bounces"),
    ];
    let mut values = [0.0; 3];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        for (t, h) in [(0.0, 1.0), (1.0, 0.5), (1.5, 0.7)] {
            assert_eq!(fmi2DoStep(c, t, h, TRUE), Status::Ok, "{}", log.last());
            assert_eq!(
                fmi2GetReal(c, vrs.as_ptr(), 3, values.as_mut_ptr()),
                Status::Ok
            );
            let end = t + h;
            let (h_exact, v_exact) = exact(end);
            let bounces = (1..).take_while(|&k| bounce(k).0 <= end).count() as f64;
            eprintln!(
                "t = {end}: h off by {:.1e} m, v by {:.1e} m/s",
                (values[0] - h_exact).abs(),
                (values[1] - v_exact).abs()
            );
            assert!(
                (values[0] - h_exact).abs() < 1e-9,
                "t = {end}: {values:?} vs {h_exact}"
            );
            assert!(
                (values[1] - v_exact).abs() < 1e-9,
                "t = {end}: {values:?} vs {v_exact}"
            );
            assert_eq!(values[2], bounces, "t = {end}");
        }
        fmi2FreeInstance(c);
    }
}

/// Co-Simulation: a stop action ends the step early, as the standard has it: the step
/// returns fmi2Discard, `fmi2Terminated` is true, `fmi2LastSuccessfulTime` is the
/// event's time, and the state is the one after the event.
#[test]
fn a_stop_inside_a_co_simulation_step_is_reported_through_the_status() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Renamed>(1, &cb);
    let (t3, v3) = bounce(3);
    let (mut last, mut terminated) = (0.0, FALSE);
    let vrs = [vr::<Renamed>("v"), vr::<Renamed>("bounces")];
    let mut values = [0.0; 2];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(
            fmi2SetDebugLogging(c, TRUE, 1, [c"logEvents".as_ptr()].as_ptr()),
            Status::Ok
        );
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, TRUE), Status::Ok);
        assert_eq!(fmi2GetBooleanStatus(c, 3, &mut terminated), Status::Ok);
        assert_eq!(terminated, FALSE);
        assert_eq!(fmi2DoStep(c, 1.0, 9.0, TRUE), Status::Discard);
        assert!(
            log.last()
                .contains("the event count stopped StoppingBall at t = 1.75"),
            "{}",
            log.last()
        );
        assert_eq!(fmi2GetBooleanStatus(c, 3, &mut terminated), Status::Ok);
        assert_eq!(terminated, TRUE);
        assert_eq!(fmi2GetRealStatus(c, 2, &mut last), Status::Ok);
        assert_eq!(
            fmi2GetReal(c, vrs.as_ptr(), 2, values.as_mut_ptr()),
            Status::Ok
        );
        // No step after the stop, but termination.
        assert_eq!(fmi2DoStep(c, last, 0.1, TRUE), Status::Error);
        assert_eq!(fmi2Terminate(c), Status::Ok);
        fmi2FreeInstance(c);
    }
    eprintln!(
        "stopped {:.1e} s from the closed form's third bounce, v off by {:.1e} m/s",
        (last - t3).abs(),
        (values[0] - v3).abs()
    );
    assert!(
        (last - t3).abs() < 1e-9,
        "stopped at {last}, the third bounce is at {t3}"
    );
    // The events inside the steps, in the log: hit and count at each bounce.
    let events: Vec<_> = log
        .all()
        .into_iter()
        .filter(|(_, category, _)| category == "logEvents")
        .map(|m| m.2)
        .collect();
    assert_eq!(events.len(), 6, "{events:?}");
    assert!(events[4].starts_with("event hit at t = 1.75"), "{events:?}");
    assert!(events[5].ends_with("; stop"), "{events:?}");
    assert!((values[0] - v3).abs() < 1e-9, "{values:?} vs {v3}");
    assert_eq!(values[1], 3.0);
}

/// A stop on the communication point that ends a step is still a stop: the step
/// returns fmi2Discard and `fmi2Terminated` is true, at that point.
#[test]
fn a_stop_at_the_end_of_a_co_simulation_step_is_reported_too() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Alarm>(1, &cb);
    let (mut last, mut terminated) = (0.0, FALSE);
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2DoStep(c, 0.0, 0.5, TRUE), Status::Ok);
        assert_eq!(
            fmi2DoStep(c, 0.5, 0.5, TRUE),
            Status::Discard,
            "{}",
            log.last()
        );
        assert_eq!(fmi2GetBooleanStatus(c, 3, &mut terminated), Status::Ok);
        assert_eq!(fmi2GetRealStatus(c, 2, &mut last), Status::Ok);
        fmi2FreeInstance(c);
    }
    assert_eq!(terminated, TRUE);
    assert!((last - 1.0).abs() <= 1e-12, "stopped at {last}");
}

/// Co-Simulation: the ball without a rest mode is Zeno (its impacts accumulate at
/// `t1 (1 + 2e / (1 - e))`, 4.06 s); the runtime's chattering rule ends the step there,
/// which the FMU reports as a failed step (fmi2Discard, with the runtime's sentence)
/// and not as a hang, and it stays where the last good step ended.
#[test]
fn a_zeno_ball_fails_its_step_with_the_chattering_message() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = running::<Bouncing>(1, &cb);
    let (mut last, mut terminated) = (0.0, TRUE);
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(
            fmi2SetDebugLogging(c, TRUE, 1, [c"logEvents".as_ptr()].as_ptr()),
            Status::Ok
        );
        assert_eq!(fmi2DoStep(c, 0.0, 4.0, TRUE), Status::Ok);
        // Two events at each bounce of the closed form's before 4 s: within the log's 64.
        let early = 2 * (1..).take_while(|&k| bounce(k).0 < 4.0).count();
        let logged = |log: &Log| log.all().iter().filter(|m| m.1 == "logEvents").count();
        assert_eq!(logged(&log), early);
        assert_eq!(fmi2DoStep(c, 4.0, 1.0, TRUE), Status::Discard);
        let message = log.last();
        assert!(
            message.contains("the step from t = 4 to t = 5 failed")
                && message.contains("chattered"),
            "{message}"
        );
        // The events of the failed step: the 64 the log keeps, then how many more.
        let events: Vec<_> = log
            .all()
            .into_iter()
            .filter(|m| m.1 == "logEvents")
            .collect();
        assert_eq!(events.len(), early + 64 + 1);
        assert!(
            events[early + 64].2.starts_with("and ")
                && events[early + 64]
                    .2
                    .contains(" more events in the step from t = 4 to t = 5"),
            "{:?}",
            events[early + 64]
        );
        assert_eq!(fmi2GetRealStatus(c, 2, &mut last), Status::Ok);
        assert_eq!(fmi2GetBooleanStatus(c, 3, &mut terminated), Status::Ok);
        fmi2FreeInstance(c);
    }
    assert_eq!(last, 4.0);
    assert_eq!(terminated, FALSE, "a failure is not a stop");
}

/// Model Exchange: an event the host causes by setting an input is found, whether the
/// host sets it in Event Mode or in Continuous-Time Mode (then the next
/// `fmi2CompletedIntegratorStep` asks for Event Mode). The relay has no continuous
/// state: `nx` is 0. Not in Co-Simulation, inside a step (a stated limit).
#[test]
fn an_event_the_host_causes_through_an_input_is_handled() {
    let log = Log::default();
    let cb = callbacks(&log);
    let (u, on) = (vr::<Relay>("u"), vr::<Relay>("on"));
    let mut value = 0.0;
    let mut info = EventInfo::QUIET;
    let (mut enter, mut stop) = (FALSE, FALSE);
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        // In Continuous-Time Mode, found at the step.
        let c = running::<Relay>(0, &cb);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        assert_eq!(fmi2SetReal(c, &u, 1, &0.5), Status::Ok);
        assert_eq!(
            fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
            Status::Ok
        );
        assert_eq!(enter, FALSE, "0.5 is below the threshold");
        assert_eq!(fmi2SetReal(c, &u, 1, &2.0), Status::Ok);
        assert_eq!(
            fmi2CompletedIntegratorStep(c, TRUE, &mut enter, &mut stop),
            Status::Ok
        );
        assert_eq!(enter, TRUE);
        assert_eq!(fmi2EnterEventMode(c), Status::Ok);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(info.values_of_continuous_states_changed, FALSE); // a mode only
        assert_eq!(fmi2GetReal(c, &on, 1, &mut value), Status::Ok);
        assert_eq!(value, 1.0);
        fmi2FreeInstance(c);

        // In Event Mode, found by fmi2NewDiscreteStates.
        let c = running::<Relay>(0, &cb);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(fmi2SetReal(c, &u, 1, &2.0), Status::Ok);
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(fmi2GetReal(c, &on, 1, &mut value), Status::Ok);
        assert_eq!(value, 1.0);
        fmi2FreeInstance(c);

        // Co-Simulation: the limit the README states. The step takes its indicators'
        // reference afresh at its start, after the host set the input, so the relay
        // does not pull in.
        let c = running::<Relay>(1, &cb);
        assert_eq!(fmi2DoStep(c, 0.0, 0.5, TRUE), Status::Ok);
        assert_eq!(fmi2SetReal(c, &u, 1, &2.0), Status::Ok);
        assert_eq!(fmi2DoStep(c, 0.5, 0.5, TRUE), Status::Ok);
        assert_eq!(fmi2GetReal(c, &on, 1, &mut value), Status::Ok);
        assert_eq!(value, 0.0);
        fmi2FreeInstance(c);
    }
}
