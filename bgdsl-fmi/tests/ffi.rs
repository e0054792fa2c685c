//! The FMI C functions called from Rust, as an importer calls them: the exported
//! `extern "C"` symbols of the library, through its rlib.

use core::ffi::{c_char, c_int, c_void, CStr};
use std::ffi::CString;
use std::sync::Mutex;

use bgdsl_fmi::fmi2::*;
use bgdsl_fmi_core::fmi2::{
    CallbackFunctions, CallbackLogger, Component, EventInfo, Status, ValueReference, FALSE, TRUE,
};
use bgdsl_fmi_core::{ModelDescription, Role};
use bgdsl_runtime::{Model, Stepper};
use models::quick_return::QuickReturn;
use models::{DcMotor, Oscillator, OscillatorParams};

const MODEL_EXCHANGE: c_int = 0;
const CO_SIMULATION: c_int = 1;

/// What the FMU logged: status and message.
#[derive(Default)]
struct Log(Mutex<Vec<(c_int, String, String)>>);

impl Log {
    fn messages(&self) -> Vec<(c_int, String, String)> {
        self.0.lock().unwrap().clone()
    }

    /// The last message, which must have status fmi2Error.
    fn last_error(&self) -> String {
        let messages = self.messages();
        let (status, category, message) = messages.last().expect("a logged message").clone();
        assert_eq!(status, Status::Error as c_int, "{message}");
        assert_eq!(category, "logStatusError");
        message
    }
}

/// A logger as an importer writes one. Rust cannot define a variadic function, so it
/// takes the five fixed arguments only; the FMU passes no others.
unsafe extern "C" fn capture(
    env: *mut c_void,
    _instance: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: `env` is the `Log` given as componentEnvironment; the strings are the
    // FMU's NUL-terminated arguments.
    let (log, category, message) = unsafe {
        (
            &*(env as *const Log),
            CStr::from_ptr(category).to_string_lossy().into_owned(),
            CStr::from_ptr(message).to_string_lossy().into_owned(),
        )
    };
    log.0.lock().unwrap().push((status, category, message));
}

fn callbacks(log: Option<&Log>) -> CallbackFunctions {
    type Fixed =
        unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);
    // SAFETY: the FMU calls the logger with exactly the five fixed arguments (its
    // format has no conversions), which a non-variadic function receives in the same
    // places on the platforms FMI serves.
    let logger = unsafe { core::mem::transmute::<Fixed, CallbackLogger>(capture) };
    CallbackFunctions {
        logger: log.map(|_| logger),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: log
            .map_or(core::ptr::null_mut(), |l| l as *const Log as *mut c_void),
    }
}

fn guid(model: &str) -> CString {
    CString::new(bgdsl_fmi::describe(model).unwrap().guid).unwrap()
}

fn instantiate(kind: c_int, guid: &CStr, callbacks: &CallbackFunctions) -> Component {
    // SAFETY: valid strings and callbacks, as the standard asks.
    unsafe {
        fmi2Instantiate(
            c"test".as_ptr(),
            kind,
            guid.as_ptr(),
            c"file:///nowhere".as_ptr(),
            callbacks,
            FALSE,
            FALSE,
        )
    }
}

fn vr(model: &str, name: &str) -> ValueReference {
    let description = bgdsl_fmi::describe(model).unwrap();
    description
        .variables
        .find(name)
        .unwrap_or_else(|| panic!("no {name}"))
        .value_reference
}

/// Instantiated, initialised and in Continuous-Time Mode.
fn running_oscillator(callbacks: &CallbackFunctions, k: f64) -> Component {
    let c = instantiate(MODEL_EXCHANGE, &guid("oscillator"), callbacks);
    assert!(!c.is_null());
    // SAFETY: a live component and arrays of the lengths passed.
    unsafe {
        assert_eq!(fmi2SetReal(c, &vr("oscillator", "k"), 1, &k), Status::Ok);
        assert_eq!(
            fmi2SetupExperiment(c, FALSE, 0.0, 0.0, FALSE, 0.0),
            Status::Ok
        );
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        let mut info = EventInfo::QUIET;
        info.new_discrete_states_needed = TRUE;
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(info, EventInfo::QUIET);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
    }
    c
}

mod model_exchange {
    use super::*;

    #[test]
    fn gives_the_models_derivatives_with_the_parameters_set() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = running_oscillator(&cb, 250.0);
        let model = Oscillator::new(OscillatorParams {
            k: 250.0,
            ..OscillatorParams::default()
        });
        for (t, x) in [(0.0, [0.3, -0.02]), (1.5, [-1.0, 0.5])] {
            let mut expected = [0.0; 2];
            model.derivatives::<f64>(t, &x, &mut expected);
            let mut dx = [f64::NAN; 2];
            // SAFETY: a live component and arrays of the lengths passed.
            unsafe {
                assert_eq!(fmi2SetTime(c, t), Status::Ok);
                assert_eq!(fmi2SetContinuousStates(c, x.as_ptr(), 2), Status::Ok);
                assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 2), Status::Ok);
            }
            assert_eq!(dx, expected);
            // The same through fmi2GetReal, with the outputs.
            let names = ["der(mass.p)", "der(spring.q)", "x", "speed", "k"];
            let vrs: Vec<_> = names.iter().map(|n| vr("oscillator", n)).collect();
            let mut values = [0.0; 5];
            // SAFETY: as above.
            let status = unsafe { fmi2GetReal(c, vrs.as_ptr(), 5, values.as_mut_ptr()) };
            assert_eq!(status, Status::Ok);
            let mut y = [0.0; Oscillator::N_OUTPUTS];
            model.outputs::<f64>(t, &x, &mut y);
            assert_eq!(values, [expected[0], expected[1], y[0], y[1], 250.0]);
        }
        assert!(log.messages().is_empty(), "{:?}", log.messages());
        // SAFETY: a live component, freed once.
        unsafe { fmi2FreeInstance(c) };
    }

    #[test]
    fn starts_from_the_initial_state_the_parameters_give() {
        let cb = callbacks(None);
        let c = instantiate(MODEL_EXCHANGE, &guid("quick_return"), &cb);
        let theta = vr("quick_return", "theta0");
        let mut x = vec![0.0; QuickReturn::N_STATES];
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            assert_eq!(fmi2SetReal(c, &theta, 1, &1.0), Status::Ok);
            assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
            assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
            assert_eq!(
                fmi2GetContinuousStates(c, x.as_mut_ptr(), x.len()),
                Status::Ok
            );
            fmi2FreeInstance(c);
        }
        let mut model = QuickReturn::default();
        let mut p = vec![0.0; QuickReturn::N_PARAMETER_VALUES];
        model.parameter_values(&mut p);
        let description = ModelDescription::of::<QuickReturn>();
        let Some(Role::Parameter(i)) = description.variables.find("theta0").map(|v| v.role) else {
            panic!("theta0 is a parameter")
        };
        p[i] = 1.0;
        model.set_parameter_values(&p);
        let mut expected = vec![0.0; QuickReturn::N_STATES];
        model.initial_state(&mut expected);
        assert_eq!(x, expected);
    }

    #[test]
    fn takes_parameters_in_event_mode_but_not_in_continuous_time_mode() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = running_oscillator(&cb, 100.0);
        let k = vr("oscillator", "k");
        let mut value = 0.0;
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            assert_eq!(fmi2SetReal(c, &k, 1, &300.0), Status::Error);
            assert!(log.last_error().contains("Event Mode"));
            assert_eq!(fmi2EnterEventMode(c), Status::Ok);
            assert_eq!(fmi2SetReal(c, &k, 1, &300.0), Status::Ok);
            assert_eq!(fmi2GetReal(c, &k, 1, &mut value), Status::Ok);
            fmi2FreeInstance(c);
        }
        assert_eq!(value, 300.0);
    }
}

mod co_simulation {
    use super::*;

    #[test]
    fn steps_with_the_models_own_solver() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = instantiate(CO_SIMULATION, &guid("dc_motor"), &cb);
        let voltage = vr("dc_motor", "voltage");
        let states: Vec<_> = DcMotor::STATE_NAMES
            .iter()
            .map(|n| vr("dc_motor", n))
            .collect();
        let mut x = vec![0.0; DcMotor::N_STATES];
        let mut last = 0.0;
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            assert_eq!(fmi2SetReal(c, &voltage, 1, &9.0), Status::Ok);
            assert_eq!(
                fmi2SetupExperiment(c, FALSE, 0.0, 0.0, TRUE, 1.0),
                Status::Ok
            );
            assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
            assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
            for n in 0..10 {
                let t = f64::from(n) * 0.01;
                assert_eq!(fmi2DoStep(c, t, 0.01, TRUE), Status::Ok);
            }
            assert_eq!(
                fmi2GetReal(c, states.as_ptr(), states.len(), x.as_mut_ptr()),
                Status::Ok
            );
            assert_eq!(fmi2GetRealStatus(c, 2, &mut last), Status::Ok);
            let mut status = Status::Error;
            assert_eq!(fmi2GetStatus(c, 0, &mut status), Status::Ok);
            assert_eq!(status, Status::Ok);
            let mut terminated = TRUE;
            assert_eq!(fmi2GetBooleanStatus(c, 3, &mut terminated), Status::Ok);
            assert_eq!(terminated, FALSE);
            assert_eq!(fmi2Terminate(c), Status::Ok);
            fmi2FreeInstance(c);
        }
        assert!((last - 0.1).abs() < 1e-15);
        let mut model = DcMotor::default();
        let mut p = vec![0.0; DcMotor::N_PARAMETER_VALUES];
        model.parameter_values(&mut p);
        p[0] = 9.0; // voltage, the first parameter
        model.set_parameter_values(&p);
        let mut x0 = vec![0.0; DcMotor::N_STATES];
        model.initial_state(&mut x0);
        let solver = model.default_solver();
        let mut stepper = Stepper::starting_at(model, solver, 0.0, &x0).unwrap();
        for n in 0..10 {
            stepper.advance_to(f64::from(n) * 0.01 + 0.01).unwrap();
        }
        assert_eq!(x, stepper.state());
        assert!(log.messages().is_empty(), "{:?}", log.messages());
    }

    #[test]
    fn refuses_a_step_from_another_time_and_goes_on_afterwards() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = instantiate(CO_SIMULATION, &guid("oscillator"), &cb);
        // SAFETY: a live component.
        unsafe {
            assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
            assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
            assert_eq!(fmi2DoStep(c, 0.0, 0.1, TRUE), Status::Ok);
            assert_eq!(fmi2DoStep(c, 0.3, 0.1, TRUE), Status::Error);
            let message = log.last_error();
            assert!(
                message.contains("currentCommunicationPoint = 0.3"),
                "{message}"
            );
            assert!(message.contains("t = 0.1"), "{message}");
            assert_eq!(fmi2DoStep(c, 0.1, 0.1, TRUE), Status::Ok);
            fmi2FreeInstance(c);
        }
    }
}

mod bad_calls {
    use super::*;

    #[test]
    fn an_unknown_value_reference_is_an_error_with_a_message() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = running_oscillator(&cb, 100.0);
        let vrs = [0, 9999];
        let mut values = [-1.0; 2];
        // SAFETY: a live component and arrays of the lengths passed.
        let status = unsafe { fmi2GetReal(c, vrs.as_ptr(), 2, values.as_mut_ptr()) };
        assert_eq!(status, Status::Error);
        let message = log.last_error();
        assert!(
            message.starts_with("fmi2GetReal(nvr=2): value reference 9999"),
            "{message}"
        );
        assert_eq!(values, [-1.0; 2], "nothing written");
        // SAFETY: as above.
        let status = unsafe { fmi2SetReal(c, vrs.as_ptr(), 2, values.as_ptr()) };
        assert_eq!(status, Status::Error);
        // SAFETY: as above; the instance still works.
        unsafe {
            assert_eq!(
                fmi2GetReal(c, vrs.as_ptr(), 1, values.as_mut_ptr()),
                Status::Ok
            );
            fmi2FreeInstance(c);
        }
    }

    #[test]
    fn a_wrong_array_length_is_an_error_with_a_message() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = running_oscillator(&cb, 100.0);
        let mut dx = [0.0; 3];
        let mut z = [0.0; 1];
        // SAFETY: a live component and arrays of (at least) the lengths passed.
        unsafe {
            assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 3), Status::Error);
            assert!(log.last_error().contains("nx = 3, but Oscillator has 2"));
            assert_eq!(fmi2GetEventIndicators(c, z.as_mut_ptr(), 1), Status::Error);
            assert!(log
                .last_error()
                .contains("ni = 1, but Oscillator has 0 event indicators"));
            assert_eq!(
                fmi2GetDerivatives(c, core::ptr::null_mut(), 2),
                Status::Error
            );
            assert!(log.last_error().contains("NULL"));
            fmi2FreeInstance(c);
        }
    }

    #[test]
    fn calls_in_the_wrong_state_are_errors_with_a_message() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = instantiate(MODEL_EXCHANGE, &guid("oscillator"), &cb);
        let mut dx = [0.0; 2];
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            // Derivatives before initialisation.
            assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 2), Status::Error);
            let message = log.last_error();
            assert!(
                message.contains("not allowed now: the instance is in Instantiated"),
                "{message}"
            );
            // A Co-Simulation function on a Model Exchange instance.
            assert_eq!(fmi2DoStep(c, 0.0, 0.1, TRUE), Status::Error);
            let message = log.last_error();
            assert!(message.contains("Co-Simulation function"), "{message}");
            // Initialisation ended twice.
            assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
            assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
            assert_eq!(fmi2ExitInitializationMode(c), Status::Error);
            // States set outside Continuous-Time Mode.
            assert_eq!(fmi2SetContinuousStates(c, dx.as_ptr(), 2), Status::Error);
            // Not supported at all.
            assert_eq!(fmi2GetFMUstate(c, core::ptr::null_mut()), Status::Error);
            assert!(log.last_error().contains("canGetAndSetFMUstate"));
            fmi2FreeInstance(c);
        }
    }

    #[test]
    fn setting_an_output_or_a_state_after_initialisation_is_an_error_with_a_message() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = running_oscillator(&cb, 100.0);
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            assert_eq!(
                fmi2SetReal(c, &vr("oscillator", "x"), 1, &1.0),
                Status::Error
            );
            assert!(log.last_error().contains("x (value reference"));
            assert_eq!(
                fmi2SetReal(c, &vr("oscillator", "spring.q"), 1, &1.0),
                Status::Error
            );
            let message = log.last_error();
            assert!(
                message.contains("before initialisation ends only")
                    && message.contains("fmi2SetContinuousStates"),
                "{message}"
            );
            fmi2FreeInstance(c);
        }
    }

    /// A state set before initialisation ends is where Model Exchange starts and what
    /// Co-Simulation integrates from; the other states follow the parameters.
    #[test]
    fn an_initial_state_set_before_initialisation_is_where_the_run_starts() {
        let (q, p) = (vr("oscillator", "spring.q"), vr("oscillator", "mass.p"));
        let model = Oscillator::default();
        let mut declared = [0.0; 2];
        model.initial_state(&mut declared);
        let q_index = Oscillator::STATE_NAMES
            .iter()
            .position(|n| *n == "spring.q")
            .unwrap();
        let mut expected = declared;
        expected[q_index] = 0.08;
        assert_ne!(
            expected, declared,
            "the test sets a state other than the declared one"
        );
        for kind in [MODEL_EXCHANGE, CO_SIMULATION] {
            let cb = callbacks(None);
            let c = instantiate(kind, &guid("oscillator"), &cb);
            let (mut before, mut after) = ([0.0; 2], [0.0; 2]);
            // SAFETY: a live component and arrays of the lengths passed.
            unsafe {
                assert_eq!(fmi2SetReal(c, &q, 1, &0.08), Status::Ok);
                assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
                assert_eq!(
                    fmi2GetReal(c, [q, p].as_ptr(), 2, before.as_mut_ptr()),
                    Status::Ok
                );
                assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
                assert_eq!(
                    fmi2GetReal(c, [q, p].as_ptr(), 2, after.as_mut_ptr()),
                    Status::Ok
                );
                if kind == CO_SIMULATION {
                    assert_eq!(fmi2DoStep(c, 0.0, 0.1, TRUE), Status::Ok);
                    let mut moved = [0.0; 2];
                    fmi2GetReal(c, [q, p].as_ptr(), 2, moved.as_mut_ptr());
                    let mut stepper =
                        Stepper::starting_at(model.clone(), model.default_solver(), 0.0, &expected)
                            .unwrap();
                    stepper.advance_to(0.1).unwrap();
                    let x = stepper.state();
                    assert_eq!(moved, [x[q_index], x[1 - q_index]]);
                }
                fmi2FreeInstance(c);
            }
            let wanted = [expected[q_index], expected[1 - q_index]];
            assert_eq!(before, wanted, "kind {kind}");
            assert_eq!(after, wanted, "kind {kind}");
        }
    }

    /// A value the catalogue's checks reject (what `models run --set` refuses) is
    /// refused at the call, with the parameter and the rule, and changes nothing.
    #[test]
    fn a_parameter_value_the_program_rejects_is_refused_at_the_call() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = instantiate(CO_SIMULATION, &guid("quick_return"), &cb);
        let m1 = vr("quick_return", "m1");
        let l4 = vr("quick_return", "l4[1]");
        let mut values = [0.0; 2];
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            assert_eq!(fmi2SetReal(c, &m1, 1, &0.0), Status::Error);
            let message = log.last_error();
            assert!(
                message.contains("parameter `m1`") && message.contains("must be > 0, found 0"),
                "{message}"
            );
            assert_eq!(fmi2SetReal(c, &m1, 1, &f64::NAN), Status::Error);
            assert!(log.last_error().contains("m1 = NaN is not finite"));
            // A rule between parameters: the rod no longer reaches the guide.
            assert_eq!(
                fmi2SetReal(c, [m1, l4].as_ptr(), 2, [2.0, 0.1].as_ptr()),
                Status::Error
            );
            assert!(log.last_error().contains("cannot be assembled"));
            assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
            assert_eq!(
                fmi2GetReal(c, [m1, l4].as_ptr(), 2, values.as_mut_ptr()),
                Status::Ok
            );
            assert_eq!(values, [0.5, 0.4], "unchanged by the refused calls");
            assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
            // Between steps too, and the FMU goes on.
            assert_eq!(fmi2SetReal(c, &m1, 1, &-1.0), Status::Error);
            assert!(log.last_error().contains("must be > 0, found -1"));
            assert_eq!(fmi2SetReal(c, &m1, 1, &0.6), Status::Ok);
            assert_eq!(fmi2DoStep(c, 0.0, 0.01, TRUE), Status::Ok);
            fmi2FreeInstance(c);
        }
    }

    /// With `logCalls` on, a call that fails is logged once, as an error naming the
    /// call, its arguments and why, and one that succeeds once, as OK.
    #[test]
    fn every_call_is_logged_once_with_its_outcome() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = running_oscillator(&cb, 100.0);
        let force = vr("oscillator", "force");
        let mut value = 0.0;
        // SAFETY: a live component and arrays of the lengths passed.
        unsafe {
            assert_eq!(
                fmi2SetDebugLogging(c, TRUE, 0, core::ptr::null()),
                Status::Ok
            );
            log.0.lock().unwrap().clear();
            assert_eq!(fmi2GetReal(c, &9999, 1, &mut value), Status::Error);
            let messages = log.messages();
            assert_eq!(messages.len(), 1, "{messages:?}");
            let (status, category, message) = &messages[0];
            assert_eq!(
                (*status, category.as_str()),
                (Status::Error as c_int, "logStatusError")
            );
            assert!(
                message.starts_with("fmi2GetReal(nvr=1): ") && message.contains("9999"),
                "{message}"
            );
            log.0.lock().unwrap().clear();
            assert_eq!(fmi2GetReal(c, &force, 1, &mut value), Status::Ok);
            assert_eq!(
                log.messages(),
                [(
                    Status::Ok as c_int,
                    "logCalls".to_string(),
                    "fmi2GetReal(nvr=1)".to_string()
                )]
            );
            fmi2FreeInstance(c);
        }
    }

    #[test]
    fn a_null_freed_or_foreign_component_is_an_error_and_no_crash() {
        let cb = callbacks(None);
        let mut x = [0.0; 2];
        let mut foreign = [0u64; 64];
        let c = instantiate(MODEL_EXCHANGE, &guid("oscillator"), &cb);
        // SAFETY: the point is that none of these is a valid component; the library
        // must refuse them without dereferencing.
        unsafe {
            fmi2FreeInstance(c);
            for bad in [
                core::ptr::null_mut(),
                c,
                foreign.as_mut_ptr().cast::<c_void>(),
            ] {
                assert_eq!(
                    fmi2GetContinuousStates(bad, x.as_mut_ptr(), 2),
                    Status::Error
                );
                assert_eq!(fmi2DoStep(bad, 0.0, 1.0, TRUE), Status::Error);
                assert_eq!(fmi2Reset(bad), Status::Error);
                fmi2FreeInstance(bad);
            }
        }
    }

    #[test]
    fn errors_without_a_logger_do_not_crash() {
        let cb = callbacks(None);
        let c = running_oscillator(&cb, 100.0);
        let mut value = 0.0;
        // SAFETY: a live component.
        unsafe {
            assert_eq!(fmi2GetReal(c, &12345, 1, &mut value), Status::Error);
            assert_eq!(fmi2DoStep(c, 0.0, 1.0, TRUE), Status::Error);
            fmi2FreeInstance(c);
        }
    }

    #[test]
    fn an_unknown_guid_or_type_is_refused_at_instantiation() {
        let log = Log::default();
        let cb = callbacks(Some(&log));
        let c = instantiate(
            MODEL_EXCHANGE,
            c"{00000000-0000-0000-0000-000000000000}",
            &cb,
        );
        assert!(c.is_null());
        let message = log.last_error();
        assert!(
            message.contains("no model of this library has GUID"),
            "{message}"
        );
        assert!(message.contains(&bgdsl_fmi::describe("oscillator").unwrap().guid));
        let c = instantiate(7, &guid("oscillator"), &cb);
        assert!(c.is_null());
        assert!(log.last_error().contains("fmuType = 7"));
        // SAFETY: NULL callbacks: the library must refuse, not dereference.
        let c = unsafe {
            fmi2Instantiate(
                c"x".as_ptr(),
                0,
                guid("oscillator").as_ptr(),
                core::ptr::null(),
                core::ptr::null(),
                FALSE,
                FALSE,
            )
        };
        assert!(c.is_null());
    }

    #[test]
    fn reset_returns_to_the_defaults() {
        let cb = callbacks(None);
        let c = running_oscillator(&cb, 321.0);
        let k = vr("oscillator", "k");
        let mut value = 0.0;
        // SAFETY: a live component.
        unsafe {
            assert_eq!(fmi2Reset(c), Status::Ok);
            assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
            assert_eq!(fmi2GetReal(c, &k, 1, &mut value), Status::Ok);
            fmi2FreeInstance(c);
        }
        assert_eq!(value, OscillatorParams::default().k);
    }
}

#[test]
fn the_library_reports_the_standards_platform_and_version() {
    // SAFETY: the functions return static NUL-terminated strings.
    let (platform, version) = unsafe {
        (
            CStr::from_ptr(fmi2GetTypesPlatform()),
            CStr::from_ptr(fmi2GetVersion()),
        )
    };
    assert_eq!(platform, c"default");
    assert_eq!(version, c"2.0");
}
