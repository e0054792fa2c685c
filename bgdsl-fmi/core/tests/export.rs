//! The export machinery on models made for the purpose: a generated model with an
//! input, and a hand-written one that fails on demand (a non-finite derivative, a
//! panic). The test binary exports its own FMI symbols with `export_fmi2!` and calls
//! them as an importer would.

use core::ffi::{c_char, c_int, c_void, CStr};
use std::ffi::CString;
use std::sync::Mutex;

use bgdsl_fmi_core::fmi2::{CallbackFunctions, CallbackLogger, Component, Status, FALSE, TRUE};
use bgdsl_fmi_core::{model_description_xml, ModelDescription, ModelEntry, Role};
use bgdsl_runtime::implicit::{Failure, FailureKind, ImplicitMemory};
use bgdsl_runtime::{
    bond_graph, InputInfo, Model, ModelError, Scalar, Solver, Stepper, WithInputs,
};

bond_graph! {
    /// A mass pushed by a force the host sets.
    pub model Pushed {
        /// the push
        input force = 1.5 in "N";
        /// mass
        param m = 2.0 in "kg";
        I mass = m;
        MSe push = force;
        push -> mass;
        output speed = mass.f;
    }
}

bond_graph! {
    /// A force turned into a frame by an MTF whose law gives an inverse: the true one
    /// when `wrong` is 0, another rotation otherwise.
    pub model Turned {
        param theta = 0.4;
        param wrong = 0.5;
        Se push = bgdsl_runtime::multibond::vec3(1.0, 2.0, 3.0);
        MTF to_frame = bgdsl_runtime::multibond::rot_z(theta).transpose(),
            inverse = bgdsl_runtime::multibond::rot_z(theta + wrong);
        I[3] mass = 1.0;
        push -> to_frame -> mass;
    }
}

/// `dx/dt = -x`, but a non-finite derivative after t = 0.5 (a solver failure) and a
/// panic when x passes 100 (a bug in model code).
#[derive(Clone, Debug, Default)]
struct Fragile;

impl Model for Fragile {
    type Params = ();
    const NAME: &'static str = "Fragile";
    const STATE_NAMES: &'static [&'static str] = &["x"];
    const OUTPUT_NAMES: &'static [&'static str] = &["twice_x"];

    fn params(&self) -> &() {
        &()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let x0 = x[0].to_f64();
        assert!(x0 <= 100.0, "Fragile: x = {x0} is past 100");
        dx[0] = if t > 0.5 {
            T::from_f64(f64::NAN)
        } else {
            -x[0]
        };
    }

    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        y[0] = T::from_f64(2.0) * x[0];
    }

    fn default_solver(&self) -> Solver {
        Solver::dopri5()
    }
}

impl WithInputs for Fragile {
    type Inputs = ();
    const INPUTS: &'static [InputInfo] = &[];
    fn inputs(&self) {}
    fn set_inputs(&mut self, _: ()) {}
    fn input_values(&self, _: &mut [f64]) {}
    fn set_input_values(&mut self, _: &[f64]) {}
}

/// `dx/dt = -x` through an algebraic loop (`d1, d2`) that stops converging after
/// t = 0.5: its evaluations then write NaN and record why, as generated code does.
#[derive(Clone, Debug, Default)]
struct Looped {
    memory: ImplicitMemory<1>,
}

impl Looped {
    fn solve(&self, t: f64) -> bool {
        if t > 0.5 {
            self.memory.record(Failure {
                kind: FailureKind::NotConverged,
                unknown: 0,
                t,
                residual: 3.2e-3,
            });
            return false;
        }
        self.memory.clear_failure();
        true
    }
}

impl Model for Looped {
    type Params = ();
    const NAME: &'static str = "Looped";
    const STATE_NAMES: &'static [&'static str] = &["x"];
    const OUTPUT_NAMES: &'static [&'static str] = &["twice_x"];
    const ALGEBRAIC_LOOPS: &'static [&'static [&'static str]] = &[&["d1", "d2"]];

    fn params(&self) -> &() {
        &()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = if self.solve(t) {
            -x[0]
        } else {
            T::from_f64(f64::NAN)
        };
    }

    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        y[0] = if self.solve(t) {
            T::from_f64(2.0) * x[0]
        } else {
            T::from_f64(f64::NAN)
        };
    }

    fn evaluation_error(&self) -> Option<ModelError> {
        self.memory.failure().map(|f| f.to_model_error("d1, d2"))
    }

    fn default_solver(&self) -> Solver {
        Solver::dopri5()
    }
}

impl WithInputs for Looped {
    type Inputs = ();
    const INPUTS: &'static [InputInfo] = &[];
    fn inputs(&self) {}
    fn set_inputs(&mut self, _: ()) {}
    fn input_values(&self, _: &mut [f64]) {}
    fn set_input_values(&mut self, _: &[f64]) {}
}

static MODELS: &[ModelEntry] = &[
    ModelEntry::new::<Pushed>("pushed"),
    ModelEntry::new::<Fragile>("fragile"),
    ModelEntry::new::<Turned>("turned"),
    ModelEntry::new::<Looped>("looped"),
];

bgdsl_fmi_core::export_fmi2!(MODELS);

use fmi2::*;

#[derive(Default)]
struct Log(Mutex<Vec<(c_int, String)>>);

impl Log {
    fn last(&self) -> (c_int, String) {
        self.0
            .lock()
            .unwrap()
            .last()
            .cloned()
            .expect("a logged message")
    }
}

unsafe extern "C" fn capture(
    env: *mut c_void,
    _instance: *const c_char,
    status: c_int,
    _category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: `env` is the `Log`; `message` the FMU's NUL-terminated string.
    let (log, message) = unsafe {
        (
            &*(env as *const Log),
            CStr::from_ptr(message).to_string_lossy().into_owned(),
        )
    };
    log.0.lock().unwrap().push((status, message));
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

fn instantiate<M: bgdsl_fmi_core::Exportable>(kind: c_int, cb: &CallbackFunctions) -> Component {
    let guid = CString::new(ModelDescription::of::<M>().guid).unwrap();
    // SAFETY: valid strings and callbacks.
    let c = unsafe {
        fmi2Instantiate(
            c"t".as_ptr(),
            kind,
            guid.as_ptr(),
            core::ptr::null(),
            cb,
            FALSE,
            TRUE,
        )
    };
    assert!(!c.is_null());
    c
}

#[test]
fn an_input_is_described_with_its_start_value() {
    let description = ModelDescription::of::<Pushed>();
    let force = description.variables.find("force").unwrap();
    assert_eq!(force.role, Role::Input(0));
    assert_eq!(force.start, Some(1.5));
    let xml = model_description_xml(&description, "pushed");
    // No events: no indicators, and fmi2CompletedIntegratorStep has nothing to do.
    assert!(xml.contains("numberOfEventIndicators=\"0\""), "{xml}");
    assert!(
        xml.contains("completedIntegratorStepNotNeeded=\"true\""),
        "{xml}"
    );
    assert!(
        xml.contains("name=\"force\" valueReference=\"4\" description=\"the push\" causality=\"input\" variability=\"continuous\">\n      <Real unit=\"N\" start=\"1.5\"/>"),
        "{xml}"
    );
}

#[test]
fn co_simulation_holds_the_inputs_over_a_step_and_takes_new_ones_between_steps() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = instantiate::<Pushed>(1, &cb);
    let description = ModelDescription::of::<Pushed>();
    let force = description.variables.find("force").unwrap().value_reference;
    let speed = description.variables.find("speed").unwrap().value_reference;
    let mut v = [0.0; 2];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, TRUE), Status::Ok); // 1.5 N for 1 s
        assert_eq!(fmi2GetReal(c, &speed, 1, &mut v[0]), Status::Ok);
        assert_eq!(fmi2SetReal(c, &force, 1, &-4.0), Status::Ok);
        assert_eq!(fmi2DoStep(c, 1.0, 0.5, TRUE), Status::Ok); // -4 N for 0.5 s
        assert_eq!(fmi2GetReal(c, &speed, 1, &mut v[1]), Status::Ok);
        fmi2FreeInstance(c);
    }
    // v = F t / m with m = 2 kg.
    assert!((v[0] - 0.75).abs() < 1e-9, "{v:?}");
    assert!((v[1] - (0.75 - 1.0)).abs() < 1e-9, "{v:?}");
    // And exactly what a Stepper does with the same inputs.
    let mut stepper = Stepper::new(Pushed::default(), Pushed::default().default_solver()).unwrap();
    let after_one = stepper
        .advance_with(1.0, PushedInputs { force: 1.5 })
        .unwrap()[0];
    let after_two = stepper
        .advance_with(1.5, PushedInputs { force: -4.0 })
        .unwrap()[0];
    assert_eq!(v, [after_one, after_two]);
}

#[test]
fn model_exchange_sees_an_input_set_in_continuous_time_mode() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = instantiate::<Pushed>(0, &cb);
    let force = ModelDescription::of::<Pushed>()
        .variables
        .find("force")
        .unwrap()
        .value_reference;
    let mut dx = [0.0];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        assert_eq!(fmi2SetReal(c, &force, 1, &3.0), Status::Ok);
        assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 1), Status::Ok);
        fmi2FreeInstance(c);
    }
    assert_eq!(dx, [3.0]); // dp/dt = F
}

#[test]
fn a_failed_step_is_discarded_and_the_fmu_stays_where_it_was() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = instantiate::<Fragile>(1, &cb);
    let mut last = f64::NAN;
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        assert_eq!(fmi2DoStep(c, 0.0, 0.25, TRUE), Status::Ok);
        assert_eq!(fmi2DoStep(c, 0.25, 0.5, TRUE), Status::Discard);
        let (status, message) = log.last();
        assert_eq!(status, Status::Discard as c_int);
        assert!(
            message.contains("the step from t = 0.25 to t = 0.75 failed"),
            "{message}"
        );
        assert_eq!(fmi2GetRealStatus(c, 2, &mut last), Status::Ok);
        // Step Failed: no further step, but termination.
        assert_eq!(fmi2DoStep(c, 0.25, 0.1, TRUE), Status::Error);
        assert_eq!(fmi2Terminate(c), Status::Ok);
        fmi2FreeInstance(c);
    }
    assert_eq!(last, 0.25);
}

/// Model Exchange: derivatives or outputs the model cannot evaluate (its loop did not
/// converge) are an fmi2Error with the model's sentence, and no NaN reaches the
/// importer, which may go on from another time.
#[test]
fn a_failed_evaluation_is_an_error_with_the_models_message() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = instantiate::<Looped>(0, &cb);
    let description = ModelDescription::of::<Looped>();
    let vr = |name: &str| description.variables.find(name).unwrap().value_reference;
    let (output, derivative) = (vr("twice_x"), vr("der(x)"));
    let mut dx = [7.0];
    let mut y = [7.0];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        assert_eq!(fmi2SetTime(c, 0.75), Status::Ok);
        assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 1), Status::Error);
        let (status, message) = log.last();
        assert_eq!(status, Status::Error as c_int);
        assert!(
            message.contains(
                "the derivatives of Looped cannot be evaluated at t = 0.75: the algebraic \
                 loop through d1, d2 did not converge at t = 0.75 s (residual 3.2e-3)"
            ),
            "{message}"
        );
        assert_eq!(dx, [7.0], "nothing written");
        for vr in [output, derivative] {
            assert_eq!(fmi2GetReal(c, &vr, 1, y.as_mut_ptr()), Status::Error);
            assert!(
                log.last().1.contains("did not converge"),
                "{:?}",
                log.last()
            );
        }
        assert_eq!(y, [7.0], "nothing written");
        // Nothing changed: back in time, the model evaluates.
        assert_eq!(fmi2SetTime(c, 0.25), Status::Ok);
        assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 1), Status::Ok);
        assert_eq!(fmi2GetReal(c, &output, 1, y.as_mut_ptr()), Status::Ok);
        fmi2FreeInstance(c);
    }
    assert_eq!((dx, y), ([-1.0], [2.0]));
}

/// Co-Simulation: a step through the failure is discarded with the model's sentence.
#[test]
fn a_step_through_a_failed_evaluation_is_discarded_with_the_models_message() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = instantiate::<Looped>(1, &cb);
    // SAFETY: a live component.
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        assert_eq!(fmi2DoStep(c, 0.0, 0.25, TRUE), Status::Ok);
        assert_eq!(fmi2DoStep(c, 0.25, 0.5, TRUE), Status::Discard);
        let (status, message) = log.last();
        assert_eq!(status, Status::Discard as c_int);
        assert!(
            message.contains("the step from t = 0.25 to t = 0.75 failed: the algebraic loop through d1, d2 did not converge at t = 0.5"),
            "{message}"
        );
        fmi2FreeInstance(c);
    }
}

#[test]
fn a_panic_in_model_code_is_an_error_not_a_crash() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = instantiate::<Fragile>(0, &cb);
    let mut dx = [0.0];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        assert_eq!(fmi2SetContinuousStates(c, [1000.0].as_ptr(), 1), Status::Ok);
        assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 1), Status::Error);
        let (status, message) = log.last();
        assert_eq!(status, Status::Error as c_int);
        assert!(
            message.contains("internal error (Fragile: x = 1000 is past 100)"),
            "{message}"
        );
        // The instance is in its error state: no more integration, but a reset.
        assert_eq!(fmi2SetTime(c, 1.0), Status::Error);
        assert_eq!(fmi2Reset(c), Status::Ok);
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        fmi2FreeInstance(c);
    }
}

/// The model's check of its initial state (a given inverse that is not one) is an
/// fmi2Error on leaving initialisation, naming the element; with the parameter
/// mended, the same instance initialises.
#[test]
fn a_wrong_inverse_is_refused_on_leaving_initialisation() {
    let log = Log::default();
    let cb = callbacks(&log);
    for kind in [0, 1] {
        let c = instantiate::<Turned>(kind, &cb);
        let description = ModelDescription::of::<Turned>();
        let wrong = description.variables.find("wrong").unwrap().value_reference;
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
            assert_eq!(fmi2ExitInitializationMode(c), Status::Error);
            let (status, message) = log.last();
            assert_eq!(status, Status::Error as c_int);
            assert!(
                message
                    .contains("the inverse given for the modulus of `to_frame` is not its inverse"),
                "{message}"
            );
            assert_eq!(fmi2SetReal(c, &wrong, 1, &0.0), Status::Ok);
            assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
            fmi2FreeInstance(c);
        }
    }
}

#[test]
fn calls_are_traced_when_logging_is_on() {
    let log = Log::default();
    let cb = callbacks(&log);
    let c = instantiate::<Pushed>(1, &cb);
    let categories = [c"logCalls".as_ptr()];
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(
            fmi2SetDebugLogging(c, TRUE, 1, categories.as_ptr()),
            Status::Ok
        );
        assert_eq!(
            fmi2SetupExperiment(c, TRUE, 1e-7, 0.0, FALSE, 0.0),
            Status::Ok
        );
        let (status, message) = log.last();
        assert_eq!(status, Status::Ok as c_int);
        assert!(
            message.starts_with("fmi2SetupExperiment(tolerance=Some(1e-7)"),
            "{message}"
        );
        let bad = [c"logEverything".as_ptr()];
        assert_eq!(fmi2SetDebugLogging(c, TRUE, 1, bad.as_ptr()), Status::Error);
        assert!(log
            .last()
            .1
            .contains("unknown log category \"logEverything\""));
        fmi2FreeInstance(c);
    }
}
