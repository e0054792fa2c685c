//! The C types of the FMI 2.0 interface (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`),
//! written from the standard's text.
//!
//! Enumerations that the importer passes *in* (`fmi2Type`, `fmi2StatusKind`) are taken
//! as plain `c_int`s and checked ([`FmuKind::from_c`], [`StatusKind::from_c`]): a Rust
//! enum holding a value outside its variants would be undefined behaviour. [`Status`] is
//! only ever passed *out*, so it is a `#[repr(C)]` enum.

use core::ffi::{c_char, c_int, c_uint, c_void};

/// `fmi2Real`.
pub type Real = f64;
/// `fmi2Integer`.
pub type Integer = c_int;
/// `fmi2Boolean`: `fmi2True` is 1, `fmi2False` 0.
pub type Boolean = c_int;
/// `fmi2String`: a NUL-terminated UTF-8 string.
pub type FmiString = *const c_char;
/// `fmi2Byte`.
pub type Byte = c_char;
/// `fmi2ValueReference`.
pub type ValueReference = c_uint;
/// `fmi2Component`: the FMU instance, opaque to the importer.
pub type Component = *mut c_void;
/// `fmi2ComponentEnvironment`: the importer's pointer, handed back to its callbacks.
pub type ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`: a saved FMU state (not supported here).
pub type FmuState = *mut c_void;

/// `fmi2True`.
pub const TRUE: Boolean = 1;
/// `fmi2False`.
pub const FALSE: Boolean = 0;

/// `fmi2TypesPlatform`: the only platform this library is built for.
pub const TYPES_PLATFORM: &core::ffi::CStr = c"default";
/// `fmi2Version`.
pub const VERSION: &core::ffi::CStr = c"2.0";

/// `fmi2Status`: what every FMI function returns.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Status {
    /// `fmi2OK`: all well.
    Ok = 0,
    /// `fmi2Warning`: something is not right, the call went ahead.
    Warning = 1,
    /// `fmi2Discard`: the call could not be completed (Co-Simulation: step not done).
    Discard = 2,
    /// `fmi2Error`: the call failed; see the logged message.
    Error = 3,
    /// `fmi2Fatal`: the instance is unusable.
    Fatal = 4,
    /// `fmi2Pending`: an asynchronous step is running (never returned here).
    Pending = 5,
}

impl Status {
    /// The status as the standard spells it, for log messages.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "fmi2OK",
            Status::Warning => "fmi2Warning",
            Status::Discard => "fmi2Discard",
            Status::Error => "fmi2Error",
            Status::Fatal => "fmi2Fatal",
            Status::Pending => "fmi2Pending",
        }
    }
}

/// `fmi2Type`: which interface an instance serves, chosen at `fmi2Instantiate`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmuKind {
    /// `fmi2ModelExchange` (0): the importer integrates.
    ModelExchange,
    /// `fmi2CoSimulation` (1): the FMU integrates, with its own solver.
    CoSimulation,
}

impl FmuKind {
    /// The kind for the C value, `None` for a value the standard does not define.
    pub fn from_c(value: c_int) -> Option<Self> {
        match value {
            0 => Some(FmuKind::ModelExchange),
            1 => Some(FmuKind::CoSimulation),
            _ => None,
        }
    }

    /// The kind as the standard names it.
    pub fn name(self) -> &'static str {
        match self {
            FmuKind::ModelExchange => "Model Exchange",
            FmuKind::CoSimulation => "Co-Simulation",
        }
    }
}

/// `fmi2StatusKind`: what `fmi2Get*Status` asks about (Co-Simulation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    /// `fmi2DoStepStatus` (0).
    DoStepStatus,
    /// `fmi2PendingStatus` (1).
    PendingStatus,
    /// `fmi2LastSuccessfulTime` (2).
    LastSuccessfulTime,
    /// `fmi2Terminated` (3).
    Terminated,
}

impl StatusKind {
    /// The kind for the C value, `None` for a value the standard does not define.
    pub fn from_c(value: c_int) -> Option<Self> {
        match value {
            0 => Some(StatusKind::DoStepStatus),
            1 => Some(StatusKind::PendingStatus),
            2 => Some(StatusKind::LastSuccessfulTime),
            3 => Some(StatusKind::Terminated),
            _ => None,
        }
    }
}

/// `fmi2CallbackLogger`: `void logger(env, instanceName, status, category, message, ...)`.
/// `message` is a `printf` format; the arguments follow it.
pub type CallbackLogger =
    unsafe extern "C" fn(ComponentEnvironment, FmiString, Status, FmiString, FmiString, ...);
/// `fmi2CallbackAllocateMemory`: `calloc`-like.
pub type CallbackAllocateMemory = unsafe extern "C" fn(usize, usize) -> *mut c_void;
/// `fmi2CallbackFreeMemory`: `free`-like.
pub type CallbackFreeMemory = unsafe extern "C" fn(*mut c_void);
/// `fmi2StepFinished`: the end of an asynchronous Co-Simulation step (never used here).
pub type StepFinished = unsafe extern "C" fn(ComponentEnvironment, Status);

/// `fmi2CallbackFunctions`: the importer's callbacks, passed to `fmi2Instantiate`.
///
/// Every pointer may be NULL as far as this library is concerned: it allocates with
/// Rust's allocator (the model description says `canNotUseMemoryManagementFunctions`)
/// and logs only when a logger is given.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct CallbackFunctions {
    /// `logger`.
    pub logger: Option<CallbackLogger>,
    /// `allocateMemory`.
    pub allocate_memory: Option<CallbackAllocateMemory>,
    /// `freeMemory`.
    pub free_memory: Option<CallbackFreeMemory>,
    /// `stepFinished`.
    pub step_finished: Option<StepFinished>,
    /// `componentEnvironment`: passed back as the logger's first argument.
    pub component_environment: ComponentEnvironment,
}

/// `fmi2EventInfo`: what `fmi2NewDiscreteStates` reports (Model Exchange).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventInfo {
    /// `newDiscreteStatesNeeded`.
    pub new_discrete_states_needed: Boolean,
    /// `terminateSimulation`.
    pub terminate_simulation: Boolean,
    /// `nominalsOfContinuousStatesChanged`.
    pub nominals_of_continuous_states_changed: Boolean,
    /// `valuesOfContinuousStatesChanged`.
    pub values_of_continuous_states_changed: Boolean,
    /// `nextEventTimeDefined`.
    pub next_event_time_defined: Boolean,
    /// `nextEventTime`.
    pub next_event_time: Real,
}

impl EventInfo {
    /// "Nothing happens": no new discrete states needed, no time events, nothing
    /// changed, no termination: the answer of an event iteration in which no event
    /// fired (the models have no time events).
    pub const QUIET: EventInfo = EventInfo {
        new_discrete_states_needed: FALSE,
        terminate_simulation: FALSE,
        nominals_of_continuous_states_changed: FALSE,
        values_of_continuous_states_changed: FALSE,
        next_event_time_defined: FALSE,
        next_event_time: 0.0,
    };
}
