//! The C boundary: every FMI 2.0 function as a Rust function over the C arguments.
//! [`export_fmi2!`](crate::export_fmi2) defines the `extern "C"` symbols that call
//! these; this module is where pointers become references and slices, and the only
//! place (with the logger's callback) that needs `unsafe`.
//!
//! Each function:
//! - refuses a component that is NULL or not a live instance of this library (freed, or
//!   never made here) with `fmi2Error`; it cannot log then, having no logger;
//! - checks the call against the state machine ([`Instance::check`]);
//! - turns `(pointer, length)` pairs into slices, refusing a NULL pointer with a
//!   non-zero length;
//! - runs the call under [`catch_unwind`], so that no panic crosses into C: a panic
//!   becomes `fmi2Error`, a logged message and [`Phase::Error`](crate::Phase::Error);
//! - logs the call once, after it, with its outcome: a failure always (`fmi2Error`,
//!   the function's name and arguments, then why), a success only in category
//!   `logCalls` (`fmi2OK`, the name and arguments).
//!
//! # Safety contract
//!
//! Every public function here is `unsafe` with the same contract, the standard's: the
//! component is NULL or one that this library's `fmi2Instantiate` returned (it is then
//! checked to be live), and no other thread calls the same instance meanwhile; an
//! array argument holds as many elements as its length argument says (it may be NULL
//! when that is 0), and an output pointer points to a variable of its type. What a
//! function needs beyond that, its own documentation says.

use core::ffi::{c_char, c_int, CStr};
use std::collections::BTreeSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

use crate::fmi2::{
    Boolean, Byte, CallbackFunctions, Component, EventInfo, FmiString, FmuKind, FmuState, Integer,
    Real, Status, StatusKind, ValueReference, FALSE, TRUE,
};
use crate::instance::{CallError, CallResult, Instance};
use crate::logger::Logger;
use crate::machine::Call;
use crate::registry::ModelEntry;

/// The addresses of the instances this library made and has not freed. A component
/// that is not here is refused, not dereferenced: a call after `fmi2FreeInstance`, or
/// with a pointer from another library, returns `fmi2Error` instead of crashing.
static LIVE: Mutex<BTreeSet<usize>> = Mutex::new(BTreeSet::new());

fn live_instances() -> std::sync::MutexGuard<'static, BTreeSet<usize>> {
    // The set is consistent after any panic (insert and remove are single steps).
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn is_live(c: Component) -> bool {
    !c.is_null() && live_instances().contains(&(c as usize))
}

/// The text of a panic's payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// Runs `body` on the instance behind `c` after the checks every call shares (see the
/// module documentation), and turns its result into the status the importer sees.
///
/// # Safety
///
/// `c` is NULL, or a component that this library's `fmi2Instantiate` returned (which
/// is then checked to be live), not used concurrently by another thread (the standard
/// forbids calling one instance from two threads at once).
unsafe fn with_instance(
    c: Component,
    call: Call,
    args: impl FnOnce() -> String,
    body: impl FnOnce(&mut Instance) -> CallResult,
) -> Status {
    if !is_live(c) {
        return Status::Error;
    }
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: `c` is live, so it is the `Box<Instance>` that `instantiate` leaked
        // and `free_instance` has not reclaimed; no other reference to it exists during
        // this call (the caller's contract).
        let instance = unsafe { &mut *c.cast::<Instance>() };
        let result = instance.check(call).and_then(|()| body(&mut *instance));
        match result {
            Ok(status) => {
                // A step that failed (fmi2Discard) said why itself.
                if status == Status::Ok {
                    instance.trace(call, args);
                }
                status
            }
            Err(error) => {
                if let CallError::Failed(_) = error {
                    instance.enter_error();
                }
                instance.log(
                    Status::Error,
                    &format!("{}({}): {}", call.name(), args(), error.message()),
                );
                Status::Error
            }
        }
    }));
    outcome.unwrap_or_else(|payload| {
        let message = panic_message(payload.as_ref());
        // A second panic (in logging) must not escape either.
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: as above; the closure that held the reference has ended.
            let instance = unsafe { &mut *c.cast::<Instance>() };
            instance.enter_error();
            instance.log(
                Status::Error,
                &format!(
                    "{}: internal error ({message}). The instance cannot go on: call \
                     fmi2Reset or fmi2FreeInstance",
                    call.name()
                ),
            );
        }));
        Status::Error
    })
}

/// The slice behind a C array argument.
///
/// # Safety
///
/// If `ptr` is not NULL and `len` is not 0, `ptr` points to `len` initialised values
/// of `T` that stay valid and unaliased by writes for `'a`.
unsafe fn slice<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], CallError> {
    check_array(ptr, len, what)?;
    if len == 0 {
        return Ok(&[]);
    }
    // SAFETY: non-NULL, aligned and not too long (checked), valid for `len` values
    // (the caller's contract).
    Ok(unsafe { core::slice::from_raw_parts(ptr, len) })
}

/// The mutable slice behind a C array argument the function writes.
///
/// # Safety
///
/// If `ptr` is not NULL and `len` is not 0, `ptr` points to `len` values of `T` that
/// stay valid, and are not accessed otherwise, for `'a`.
unsafe fn slice_mut<'a, T>(ptr: *mut T, len: usize, what: &str) -> Result<&'a mut [T], CallError> {
    check_array(ptr, len, what)?;
    if len == 0 {
        return Ok(&mut []);
    }
    // SAFETY: as in `slice`, and the caller grants exclusive access.
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, len) })
}

fn check_array<T>(ptr: *const T, len: usize, what: &str) -> Result<(), CallError> {
    if len == 0 {
        return Ok(());
    }
    if ptr.is_null() {
        return Err(CallError::Refused(format!(
            "{what} is NULL but should hold {len} values"
        )));
    }
    if !ptr.is_aligned() {
        return Err(CallError::Refused(format!(
            "{what} is not aligned for its type"
        )));
    }
    if len > isize::MAX as usize / core::mem::size_of::<T>().max(1) {
        return Err(CallError::Refused(format!(
            "{what} cannot hold {len} values"
        )));
    }
    Ok(())
}

/// A pointer the function writes one value through.
fn out<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, CallError> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(CallError::Refused(format!("{what} is NULL or misaligned")));
    }
    // SAFETY: non-NULL and aligned; the standard makes the importer pass a pointer to
    // a variable of the type, which it does not touch during the call.
    Ok(unsafe { &mut *ptr })
}

/// A C string argument as Rust text (invalid UTF-8 replaced), `None` for NULL.
///
/// # Safety
///
/// `ptr` is NULL or points to a NUL-terminated string valid for the call.
unsafe fn text(ptr: FmiString) -> Option<String> {
    if ptr.is_null() {
        return None;
    }
    // SAFETY: non-NULL and NUL-terminated (the caller's contract).
    let c_str = unsafe { CStr::from_ptr(ptr) };
    Some(c_str.to_string_lossy().into_owned())
}

// ----- creation and destruction -------------------------------------------------------

/// `fmi2Instantiate`: an instance of the model in `registry` whose GUID is `guid`, for
/// Model Exchange (`fmu_type` 0) or Co-Simulation (1). Returns NULL, with a logged
/// message when the importer gave a logger, for an unknown GUID, an unknown type, a
/// missing instance name, or NULL callbacks.
///
/// # Safety
///
/// The string arguments are NULL or NUL-terminated; `functions` is NULL or points to an
/// `fmi2CallbackFunctions` (it is copied: it need not outlive the call) whose logger,
/// if any, has the standard's signature and stays callable while the instance lives.
#[allow(clippy::too_many_arguments)] // the standard's signature
pub unsafe fn instantiate(
    registry: &[ModelEntry],
    instance_name: FmiString,
    fmu_type: c_int,
    guid: FmiString,
    _resource_location: FmiString,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    let made = catch_unwind(AssertUnwindSafe(|| {
        if functions.is_null() || !functions.is_aligned() {
            return core::ptr::null_mut();
        }
        // SAFETY: non-NULL and aligned; points to the importer's callbacks (contract).
        let callbacks = unsafe { *functions };
        // SAFETY: the strings are NULL or NUL-terminated (contract).
        let (name, guid) = unsafe { (text(instance_name), text(guid)) };
        let logger = Logger::new(
            callbacks,
            name.as_deref().unwrap_or(""),
            logging_on != FALSE,
        );
        let fail = |message: String| {
            logger.log(Status::Error, &format!("fmi2Instantiate: {message}"));
            core::ptr::null_mut()
        };
        if name.as_deref().is_none_or(str::is_empty) {
            return fail("instanceName is NULL or empty".to_string());
        }
        let Some(kind) = FmuKind::from_c(fmu_type) else {
            return fail(format!(
                "fmuType = {fmu_type} is neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)"
            ));
        };
        let Some(guid) = guid else {
            return fail("fmuGUID is NULL".to_string());
        };
        let found = registry
            .iter()
            .map(|entry| (entry, entry.describe()))
            .find(|(_, description)| description.guid == guid);
        let Some((entry, description)) = found else {
            let known: Vec<String> = registry
                .iter()
                .map(|entry| format!("{} {}", entry.identifier(), entry.describe().guid))
                .collect();
            return fail(format!(
                "no model of this library has GUID {guid} (the FMU's modelDescription.xml \
                 and this library were not built together; rebuild the FMU). This library \
                 serves: {}",
                known.join(", ")
            ));
        };
        let instance = Instance::new(kind, logger, description, entry.create());
        let component: Component = Box::into_raw(Box::new(instance)).cast();
        live_instances().insert(component as usize);
        component
    }));
    made.unwrap_or(core::ptr::null_mut())
}

/// `fmi2FreeInstance`. A NULL, freed or foreign component is ignored.
///
/// # Safety
///
/// The [module's contract](self#safety-contract): `c` is NULL or came from this library's `fmi2Instantiate`, and
/// no other thread uses it.
pub unsafe fn free_instance(c: Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if !live_instances().remove(&(c as usize)) {
            return;
        }
        // SAFETY: it was live, so it is the leaked `Box<Instance>`; now that it is no
        // longer in the set, no later call can reach it.
        drop(unsafe { Box::from_raw(c.cast::<Instance>()) });
    }));
}

// ----- common functions ---------------------------------------------------------------

/// `fmi2SetDebugLogging`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `categories` is NULL or holds `n` NUL-terminated strings.
pub unsafe fn set_debug_logging(
    c: Component,
    logging_on: Boolean,
    n: usize,
    categories: *const FmiString,
) -> Status {
    let args = || format!("loggingOn={logging_on}, nCategories={n}");
    let body = |instance: &mut Instance| {
        // SAFETY: `categories` holds `n` strings (contract).
        let pointers = unsafe { slice(categories, n, "categories")? };
        let mut names = Vec::with_capacity(n);
        for &p in pointers {
            // SAFETY: each is NULL or NUL-terminated (contract).
            match unsafe { text(p) } {
                Some(name) => names.push(name),
                None => return Err(CallError::Refused("a category is NULL".into())),
            }
        }
        instance.set_debug_logging(logging_on != FALSE, &names)
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::SetDebugLogging, args, body) }
}

/// `fmi2SetupExperiment`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn setup_experiment(
    c: Component,
    tolerance_defined: Boolean,
    tolerance: Real,
    start_time: Real,
    stop_time_defined: Boolean,
    stop_time: Real,
) -> Status {
    let tolerance = (tolerance_defined != FALSE).then_some(tolerance);
    let stop = (stop_time_defined != FALSE).then_some(stop_time);
    let args = || format!("tolerance={tolerance:?}, startTime={start_time}, stopTime={stop:?}");
    let body = |i: &mut Instance| i.setup_experiment(tolerance, start_time, stop);
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::SetupExperiment, args, body) }
}

/// A call without arguments beyond the component.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
unsafe fn simple(c: Component, call: Call, body: fn(&mut Instance) -> CallResult) -> Status {
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, call, String::new, body) }
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn enter_initialization_mode(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        simple(
            c,
            Call::EnterInitializationMode,
            Instance::enter_initialization_mode,
        )
    }
}

/// `fmi2ExitInitializationMode`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn exit_initialization_mode(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        simple(
            c,
            Call::ExitInitializationMode,
            Instance::exit_initialization_mode,
        )
    }
}

/// `fmi2Terminate`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn terminate(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe { simple(c, Call::Terminate, Instance::terminate) }
}

/// `fmi2Reset`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn reset(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe { simple(c, Call::Reset, Instance::reset) }
}

// ----- variables ----------------------------------------------------------------------

/// `fmi2GetReal`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `vr` holds `nvr` value references and `value` room for `nvr`
/// reals (either may be NULL when `nvr` is 0).
pub unsafe fn get_real(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut Real,
) -> Status {
    let body = |i: &mut Instance| {
        // SAFETY: the caller's contract on `vr` and `value`.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr")?, slice_mut(value, nvr, "value")?) };
        i.get_real(vrs, values)
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::GetReal, || format!("nvr={nvr}"), body) }
}

/// `fmi2SetReal`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `vr` and `value` hold `nvr` entries each.
pub unsafe fn set_real(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const Real,
) -> Status {
    let body = |i: &mut Instance| {
        // SAFETY: the caller's contract on `vr` and `value`.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr")?, slice(value, nvr, "value")?) };
        i.set_real(vrs, values)
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::SetReal, || format!("nvr={nvr}"), body) }
}

/// `fmi2Get/SetInteger`, `Boolean`, `String`: there are no such variables, so any
/// value reference is refused (the values are never touched).
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `vr` holds `nvr` value references.
pub unsafe fn no_variables_of_type(
    c: Component,
    call: Call,
    type_name: &'static str,
    vr: *const ValueReference,
    nvr: usize,
) -> Status {
    let body = |i: &mut Instance| {
        // SAFETY: the caller's contract on `vr`.
        let vrs = unsafe { slice(vr, nvr, "vr")? };
        i.no_variables_of_type(type_name, vrs)
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, call, || format!("nvr={nvr}"), body) }
}

/// The FMU-state and directional-derivative functions, and the Co-Simulation input
/// and output derivatives: not supported (the model description says so), refused
/// with a message saying which capability flag is false.
///
/// # Safety
///
/// The [module's contract](self#safety-contract). No other argument is read.
pub unsafe fn unsupported(c: Component, call: Call) -> Status {
    let reason = match call {
        Call::GetDirectionalDerivative => "providesDirectionalDerivative is false",
        Call::SetRealInputDerivatives => "canInterpolateInputs is false",
        Call::GetRealOutputDerivatives => "maxOutputDerivativeOrder is 0",
        _ => "canGetAndSetFMUstate and canSerializeFMUstate are false",
    };
    let body = |_: &mut Instance| {
        Err(CallError::Refused(format!(
            "not supported by this FMU ({reason} in modelDescription.xml)"
        )))
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, call, String::new, body) }
}

// ----- Model Exchange -----------------------------------------------------------------

/// `fmi2EnterEventMode`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn enter_event_mode(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe { simple(c, Call::EnterEventMode, Instance::enter_event_mode) }
}

/// `fmi2NewDiscreteStates`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `info` points to an `fmi2EventInfo`.
pub unsafe fn new_discrete_states(c: Component, info: *mut EventInfo) -> Status {
    let body = |i: &mut Instance| i.new_discrete_states(out(info, "fmi2EventInfo")?);
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::NewDiscreteStates, String::new, body) }
}

/// `fmi2EnterContinuousTimeMode`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn enter_continuous_time_mode(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        simple(
            c,
            Call::EnterContinuousTimeMode,
            Instance::enter_continuous_time_mode,
        )
    }
}

/// `fmi2CompletedIntegratorStep`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); the two flags point to `fmi2Boolean`s.
pub unsafe fn completed_integrator_step(
    c: Component,
    _no_set_fmu_state_prior_to_current_point: Boolean,
    enter_event_mode: *mut Boolean,
    terminate_simulation: *mut Boolean,
) -> Status {
    let body = |i: &mut Instance| {
        let event = out(enter_event_mode, "enterEventMode")?;
        let stop = out(terminate_simulation, "terminateSimulation")?;
        let (e, s) = i.completed_integrator_step()?;
        *event = if e { TRUE } else { FALSE };
        *stop = if s { TRUE } else { FALSE };
        Ok(Status::Ok)
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::CompletedIntegratorStep, String::new, body) }
}

/// `fmi2SetTime`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn set_time(c: Component, time: Real) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(
            c,
            Call::SetTime,
            || format!("time={time}"),
            |i| i.set_time(time),
        )
    }
}

/// `fmi2SetContinuousStates`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `x` holds `nx` reals.
pub unsafe fn set_continuous_states(c: Component, x: *const Real, nx: usize) -> Status {
    let body = |i: &mut Instance| {
        // SAFETY: the caller's contract on `x`.
        i.set_continuous_states(unsafe { slice(x, nx, "x")? })
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::SetContinuousStates, || format!("nx={nx}"), body) }
}

/// `fmi2GetDerivatives`, `fmi2GetContinuousStates`,
/// `fmi2GetNominalsOfContinuousStates` and `fmi2GetEventIndicators`: fill an array.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `values` has room for `n` reals.
pub unsafe fn get_array(
    c: Component,
    call: Call,
    values: *mut Real,
    n: usize,
    body: fn(&mut Instance, &mut [f64]) -> CallResult,
) -> Status {
    let body = |i: &mut Instance| {
        // SAFETY: the caller's contract on `values`.
        body(i, unsafe { slice_mut(values, n, "the array")? })
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, call, || format!("n={n}"), body) }
}

// ----- Co-Simulation ------------------------------------------------------------------

/// `fmi2DoStep`.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn do_step(c: Component, t: Real, h: Real, _no_set_prior: Boolean) -> Status {
    let args = || format!("currentCommunicationPoint={t}, communicationStepSize={h}");
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, Call::DoStep, args, |i| i.do_step(t, h)) }
}

/// `fmi2CancelStep`: steps are never asynchronous, so there is nothing to cancel.
///
/// # Safety
///
/// The [module's contract](self#safety-contract).
pub unsafe fn cancel_step(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe { simple(c, Call::CancelStep, |_| Ok(Status::Ok)) }
}

/// `fmi2GetStatus`, `fmi2GetRealStatus`, `fmi2GetIntegerStatus`,
/// `fmi2GetBooleanStatus`, `fmi2GetStringStatus`: `write` answers for a status kind
/// and writes through the importer's pointer.
///
/// # Safety
///
/// The [module's contract](self#safety-contract); `value` points to a variable of type `T`.
pub unsafe fn get_status<T>(
    c: Component,
    call: Call,
    kind: c_int,
    value: *mut T,
    answer: fn(&Instance, StatusKind) -> Result<T, CallError>,
) -> Status {
    let body = |i: &mut Instance| {
        let Some(kind) = StatusKind::from_c(kind) else {
            return Err(CallError::Refused(format!(
                "s = {kind} is not an fmi2StatusKind (0 to 3)"
            )));
        };
        let target = out(value, "value")?;
        *target = answer(i, kind)?;
        Ok(Status::Ok)
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance(c, call, || format!("s={kind}"), body) }
}

/// `fmi2GetIntegerStatus` and `fmi2GetStringStatus`: no status kind has an integer or
/// string answer here.
pub fn no_status<T>(_: &Instance, kind: StatusKind) -> Result<T, CallError> {
    Err(CallError::Refused(format!(
        "{kind:?} has no answer of this type: steps are never asynchronous"
    )))
}

/// `fmi2GetBooleanStatus` as an `fmi2Boolean`.
pub fn boolean_status(i: &Instance, kind: StatusKind) -> Result<Boolean, CallError> {
    i.get_boolean_status(kind)
        .map(|b| if b { TRUE } else { FALSE })
}

/// The types the FMU-state functions take, named so the export macro's signatures read
/// like the standard's.
pub type FmuStateOut = *mut FmuState;
/// `const fmi2Byte[]`.
pub type ByteArray = *const Byte;
/// `fmi2Byte[]` to write.
pub type ByteArrayOut = *mut Byte;
/// `fmi2Integer` to write.
pub type IntegerOut = *mut Integer;
/// `fmi2String` to write.
pub type StringOut = *mut FmiString;

/// `fmi2GetTypesPlatform` and `fmi2GetVersion` return static strings.
pub fn static_string(s: &'static CStr) -> *const c_char {
    s.as_ptr()
}
