//! The FMI 2.0 state machine: the phases an instance goes through and which calls each
//! phase allows, for Model Exchange and for Co-Simulation.
//!
//! ```text
//! Model Exchange                                 Co-Simulation
//!
//! fmi2Instantiate -> Instantiated               fmi2Instantiate -> Instantiated
//!   fmi2EnterInitializationMode                   fmi2EnterInitializationMode
//! InitializationMode                             InitializationMode
//!   fmi2ExitInitializationMode                    fmi2ExitInitializationMode
//! EventMode <-> ContinuousTimeMode               StepComplete <-> fmi2DoStep
//!   fmi2Terminate                                 (a failed step: StepFailed)
//! Terminated                                       fmi2Terminate
//!                                                Terminated
//! ```
//!
//! Any phase goes to `Error` when a call fails part-way (a solver failure, a panic in
//! model code), and back to `Instantiated` on `fmi2Reset`. A call the phase does not
//! allow, or one with bad arguments, is refused *before* it changes anything: it returns
//! `fmi2Error` with a logged message and leaves the instance as it was.

use crate::fmi2::FmuKind;

/// Where an instance is in its life.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// After `fmi2Instantiate` or `fmi2Reset`: parameters and inputs may be set.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    InitializationMode,
    /// Model Exchange: event mode (after initialisation, or `fmi2EnterEventMode`).
    EventMode,
    /// Model Exchange: the importer integrates.
    ContinuousTimeMode,
    /// Co-Simulation: between steps.
    StepComplete,
    /// Co-Simulation: the last `fmi2DoStep` failed; the state is where it failed.
    StepFailed,
    /// After `fmi2Terminate`: results may be read.
    Terminated,
    /// A call failed part-way; only reading, `fmi2Reset` and `fmi2FreeInstance` remain.
    Error,
}

impl Phase {
    /// The phase as the standard names it, for log messages.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Instantiated => "Instantiated",
            Phase::InitializationMode => "Initialization Mode",
            Phase::EventMode => "Event Mode",
            Phase::ContinuousTimeMode => "Continuous-Time Mode",
            Phase::StepComplete => "Step Complete",
            Phase::StepFailed => "Step Failed",
            Phase::Terminated => "Terminated",
            Phase::Error => "Error",
        }
    }

    /// Whether the model's state exists yet (it is fixed when initialisation ends; before
    /// that it follows the parameters).
    pub fn is_initialised(self) -> bool {
        !matches!(self, Phase::Instantiated | Phase::InitializationMode)
    }
}

/// The FMI functions that take an instance, for the state machine and for messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)] // each variant is the FMI function of the same name
pub enum Call {
    SetDebugLogging,
    FreeInstance,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetReal,
    GetInteger,
    GetBoolean,
    GetString,
    SetReal,
    SetInteger,
    SetBoolean,
    SetString,
    GetFmuState,
    SetFmuState,
    FreeFmuState,
    SerializedFmuStateSize,
    SerializeFmuState,
    DeSerializeFmuState,
    GetDirectionalDerivative,
    EnterEventMode,
    NewDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
    GetRealStatus,
    GetIntegerStatus,
    GetBooleanStatus,
    GetStringStatus,
}

/// Which kinds of instance a call belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Interface {
    Both,
    ModelExchange,
    CoSimulation,
}

impl Call {
    /// The C name, e.g. `"fmi2GetReal"`.
    pub fn name(self) -> &'static str {
        use Call::*;
        match self {
            SetDebugLogging => "fmi2SetDebugLogging",
            FreeInstance => "fmi2FreeInstance",
            SetupExperiment => "fmi2SetupExperiment",
            EnterInitializationMode => "fmi2EnterInitializationMode",
            ExitInitializationMode => "fmi2ExitInitializationMode",
            Terminate => "fmi2Terminate",
            Reset => "fmi2Reset",
            GetReal => "fmi2GetReal",
            GetInteger => "fmi2GetInteger",
            GetBoolean => "fmi2GetBoolean",
            GetString => "fmi2GetString",
            SetReal => "fmi2SetReal",
            SetInteger => "fmi2SetInteger",
            SetBoolean => "fmi2SetBoolean",
            SetString => "fmi2SetString",
            GetFmuState => "fmi2GetFMUstate",
            SetFmuState => "fmi2SetFMUstate",
            FreeFmuState => "fmi2FreeFMUstate",
            SerializedFmuStateSize => "fmi2SerializedFMUstateSize",
            SerializeFmuState => "fmi2SerializeFMUstate",
            DeSerializeFmuState => "fmi2DeSerializeFMUstate",
            GetDirectionalDerivative => "fmi2GetDirectionalDerivative",
            EnterEventMode => "fmi2EnterEventMode",
            NewDiscreteStates => "fmi2NewDiscreteStates",
            EnterContinuousTimeMode => "fmi2EnterContinuousTimeMode",
            CompletedIntegratorStep => "fmi2CompletedIntegratorStep",
            SetTime => "fmi2SetTime",
            SetContinuousStates => "fmi2SetContinuousStates",
            GetDerivatives => "fmi2GetDerivatives",
            GetEventIndicators => "fmi2GetEventIndicators",
            GetContinuousStates => "fmi2GetContinuousStates",
            GetNominalsOfContinuousStates => "fmi2GetNominalsOfContinuousStates",
            SetRealInputDerivatives => "fmi2SetRealInputDerivatives",
            GetRealOutputDerivatives => "fmi2GetRealOutputDerivatives",
            DoStep => "fmi2DoStep",
            CancelStep => "fmi2CancelStep",
            GetStatus => "fmi2GetStatus",
            GetRealStatus => "fmi2GetRealStatus",
            GetIntegerStatus => "fmi2GetIntegerStatus",
            GetBooleanStatus => "fmi2GetBooleanStatus",
            GetStringStatus => "fmi2GetStringStatus",
        }
    }

    fn interface(self) -> Interface {
        use Call::*;
        match self {
            EnterEventMode
            | NewDiscreteStates
            | EnterContinuousTimeMode
            | CompletedIntegratorStep
            | SetTime
            | SetContinuousStates
            | GetDerivatives
            | GetEventIndicators
            | GetContinuousStates
            | GetNominalsOfContinuousStates => Interface::ModelExchange,
            SetRealInputDerivatives
            | GetRealOutputDerivatives
            | DoStep
            | CancelStep
            | GetStatus
            | GetRealStatus
            | GetIntegerStatus
            | GetBooleanStatus
            | GetStringStatus => Interface::CoSimulation,
            _ => Interface::Both,
        }
    }

    /// Whether an instance of `kind` in `phase` may take this call (the standard's
    /// state-machine tables: FMI 2.0.4, sections 3.2.3 and 4.2.4). The state-saving
    /// functions are allowed everywhere, as they only ever answer "not supported".
    pub fn allowed(self, kind: FmuKind, phase: Phase) -> bool {
        use Call::*;
        use Phase::*;
        match (self.interface(), kind) {
            (Interface::ModelExchange, FmuKind::CoSimulation)
            | (Interface::CoSimulation, FmuKind::ModelExchange) => return false,
            _ => {}
        }
        // Reading results: wherever a state exists or is being initialised.
        let readable = matches!(
            phase,
            InitializationMode
                | EventMode
                | ContinuousTimeMode
                | StepComplete
                | StepFailed
                | Terminated
                | Error
        );
        match self {
            SetDebugLogging | FreeInstance | Reset => true,
            GetFmuState
            | SetFmuState
            | FreeFmuState
            | SerializedFmuStateSize
            | SerializeFmuState
            | DeSerializeFmuState
            | GetDirectionalDerivative => true,
            SetupExperiment | EnterInitializationMode => phase == Instantiated,
            ExitInitializationMode => phase == InitializationMode,
            Terminate => matches!(
                phase,
                EventMode | ContinuousTimeMode | StepComplete | StepFailed
            ),
            GetReal | GetInteger | GetBoolean | GetString => readable,
            SetReal | SetInteger | SetBoolean | SetString => matches!(
                phase,
                Instantiated | InitializationMode | EventMode | ContinuousTimeMode | StepComplete
            ),
            EnterEventMode => matches!(phase, EventMode | ContinuousTimeMode),
            NewDiscreteStates | EnterContinuousTimeMode => phase == EventMode,
            CompletedIntegratorStep | SetContinuousStates => phase == ContinuousTimeMode,
            SetTime => matches!(phase, EventMode | ContinuousTimeMode),
            GetDerivatives
            | GetEventIndicators
            | GetContinuousStates
            | GetNominalsOfContinuousStates => readable,
            SetRealInputDerivatives => {
                matches!(phase, Instantiated | InitializationMode | StepComplete)
            }
            GetRealOutputDerivatives => {
                matches!(phase, StepComplete | StepFailed | Terminated | Error)
            }
            DoStep => phase == StepComplete,
            CancelStep => false,
            GetStatus | GetRealStatus | GetIntegerStatus | GetBooleanStatus | GetStringStatus => {
                matches!(phase, StepComplete | StepFailed | Terminated)
            }
        }
    }
}

#[cfg(test)]
mod should {
    use super::*;

    #[test]
    fn refuse_model_exchange_calls_on_a_co_simulation_instance_and_back() {
        assert!(!Call::DoStep.allowed(FmuKind::ModelExchange, Phase::EventMode));
        assert!(!Call::DoStep.allowed(FmuKind::ModelExchange, Phase::StepComplete));
        assert!(Call::DoStep.allowed(FmuKind::CoSimulation, Phase::StepComplete));
        assert!(!Call::GetDerivatives.allowed(FmuKind::CoSimulation, Phase::StepComplete));
    }

    #[test]
    fn refuse_derivatives_before_initialisation() {
        assert!(!Call::GetDerivatives.allowed(FmuKind::ModelExchange, Phase::Instantiated));
        assert!(Call::GetDerivatives.allowed(FmuKind::ModelExchange, Phase::ContinuousTimeMode));
    }

    #[test]
    fn allow_continuous_states_to_be_set_only_in_continuous_time_mode() {
        for phase in [
            Phase::Instantiated,
            Phase::InitializationMode,
            Phase::EventMode,
            Phase::Terminated,
            Phase::Error,
        ] {
            assert!(!Call::SetContinuousStates.allowed(FmuKind::ModelExchange, phase));
        }
        assert!(
            Call::SetContinuousStates.allowed(FmuKind::ModelExchange, Phase::ContinuousTimeMode)
        );
    }
}
