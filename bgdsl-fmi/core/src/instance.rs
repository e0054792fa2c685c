//! An FMU instance: the model, where it is in the FMI state machine, and what every FMI
//! call does to it, in safe Rust over slices. The FFI layer ([`crate::ffi`]) turns the
//! C arguments into those slices and checks the call against the state machine first.
//!
//! A call either succeeds, or is *refused* before it changes anything (wrong arguments,
//! a variable that cannot be set now: [`CallError::Refused`]), or *fails* part-way
//! ([`CallError::Failed`]: the instance goes to [`Phase::Error`]). A Co-Simulation step
//! whose solver fails is reported as `fmi2Discard` and leaves the instance at the start
//! of the step, in [`Phase::StepFailed`].
//!
//! # Events
//!
//! Model Exchange: the importer integrates and watches the event indicators
//! (`fmi2GetEventIndicators`, one per [`Model::EVENTS`](bgdsl_runtime::Model::EVENTS))
//! for a change of sign, locates it and enters Event Mode. `fmi2NewDiscreteStates` then
//! compares each indicator with its value at the *reference point*, the last point the
//! FMU accepted (initialisation's end, the last `fmi2NewDiscreteStates`, the last
//! `fmi2CompletedIntegratorStep` that found no crossing), and applies the action of every
//! event whose indicator crossed in its direction ([`Direction::fires`], the runtime's
//! rule), in index order. An importer's event in the other direction (FMI indicators have
//! none) changes nothing but the reference. The discrete modes are the FMU's: the
//! importer integrates the continuous states only ([`crate::variables`]).
//!
//! Co-Simulation: the model's own [`Stepper`](bgdsl_runtime::Stepper) locates and
//! handles the events inside each `fmi2DoStep`; a `stop` action ends the step at the
//! event with `fmi2Discard` and `fmi2Terminated` true, as the standard has a slave end
//! a run early.

#[cfg(doc)]
use bgdsl_runtime::Direction;
use bgdsl_runtime::EventAction;

use crate::description::ModelDescription;
use crate::fmi2::{EventInfo, FmuKind, Status, StatusKind, ValueReference, FALSE, TRUE};
use crate::logger::{Category, Logger};
use crate::machine::{Call, Phase};
use crate::model::{FmuModel, Sizes, Stopped};
use crate::variables::{role_of, Role};

/// Why a call did not succeed. The message says what was wrong and what was expected;
/// the FFI layer logs it, prefixed with the function's name, and returns `fmi2Error`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CallError {
    /// Refused before anything changed: the instance is as it was.
    Refused(String),
    /// Failed part-way: the instance is now in [`Phase::Error`].
    Failed(String),
}

impl CallError {
    /// The message.
    pub fn message(&self) -> &str {
        match self {
            CallError::Refused(m) | CallError::Failed(m) => m,
        }
    }
}

/// What a call returns: a status (`fmi2OK`, or `fmi2Discard` for a failed step) or why
/// it did not succeed.
pub type CallResult = Result<Status, CallError>;

fn refuse<T>(message: impl Into<String>) -> Result<T, CallError> {
    Err(CallError::Refused(message.into()))
}

/// Two communication points closer than this (relative to the larger of 1 and the
/// time) are the same: an importer that computes `t0 + n h` and one that adds `h` up
/// differ by rounding only.
const TIME_MATCH: f64 = 1e-9;

/// One instance of a model, as `fmi2Instantiate` made it.
pub struct Instance {
    kind: FmuKind,
    phase: Phase,
    logger: Logger,
    description: ModelDescription,
    sizes: Sizes,
    model: Box<dyn FmuModel>,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    tolerance: Option<f64>,
    /// The state: the initial state (following the parameters, but for the entries
    /// the importer set) until initialisation ends, then the importer's (Model
    /// Exchange) or the solver's (Co-Simulation).
    x: Vec<f64>,
    /// The initial states the importer set with `fmi2SetReal` before initialisation
    /// ended; the others follow the parameters.
    x_start: Vec<Option<f64>>,
    dx: Vec<f64>,
    y: Vec<f64>,
    p: Vec<f64>,
    u: Vec<f64>,
    /// Co-Simulation: what the last `fmi2DoStep` returned.
    last_step: Status,
    /// The event indicators at the current time and state, as last evaluated.
    g: Vec<f64>,
    /// Model Exchange: the event indicators at the reference point a crossing is
    /// measured from (see the module's documentation).
    g_reference: Vec<f64>,
    /// The event whose `stop` action ended the run, and when: Model Exchange's
    /// `terminateSimulation`, Co-Simulation's `fmi2Terminated`.
    stopped: Option<(&'static str, f64)>,
}

impl core::fmt::Debug for Instance {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Instance")
            .field("model", &self.description.model_name)
            .field("kind", &self.kind)
            .field("phase", &self.phase)
            .field("time", &self.time)
            .field("x", &self.x)
            .finish_non_exhaustive()
    }
}

impl Instance {
    /// A fresh instance of `model` (described by `description`), in
    /// [`Phase::Instantiated`].
    pub fn new(
        kind: FmuKind,
        logger: Logger,
        description: ModelDescription,
        model: Box<dyn FmuModel>,
    ) -> Self {
        let sizes = model.sizes();
        Instance {
            kind,
            phase: Phase::Instantiated,
            logger,
            description,
            sizes,
            model,
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            tolerance: None,
            x: vec![0.0; sizes.states],
            x_start: vec![None; sizes.states],
            dx: vec![0.0; sizes.states],
            y: vec![0.0; sizes.outputs],
            p: vec![0.0; sizes.parameters],
            u: vec![0.0; sizes.inputs],
            last_step: Status::Ok,
            g: vec![0.0; sizes.events],
            g_reference: vec![0.0; sizes.events],
            stopped: None,
        }
    }

    /// Which interface the instance serves.
    pub fn kind(&self) -> FmuKind {
        self.kind
    }

    /// Where the instance is in the state machine.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The current time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The model's description (name, variables, GUID).
    pub fn description(&self) -> &ModelDescription {
        &self.description
    }

    /// Sends a message to the importer's logger (if it wants it).
    pub fn log(&self, status: Status, message: &str) {
        self.logger.log(status, message);
    }

    /// Logs a call that succeeded, with its arguments, in category `logCalls`
    /// (formatting only when that category is on). A call that fails is logged once,
    /// as an error, by the FFI layer instead.
    pub fn trace(&self, call: Call, args: impl FnOnce() -> String) {
        if self.logger.wants(Category::Calls) {
            self.logger
                .log(Status::Ok, &format!("{}({})", call.name(), args()));
        }
    }

    /// Puts the instance in [`Phase::Error`] (a failure part-way, or a panic).
    pub fn enter_error(&mut self) {
        self.phase = Phase::Error;
    }

    /// Whether the state machine allows `call` now; if not, why.
    pub fn check(&self, call: Call) -> Result<(), CallError> {
        if call.allowed(self.kind, self.phase) {
            return Ok(());
        }
        let other = match self.kind {
            FmuKind::ModelExchange => FmuKind::CoSimulation,
            FmuKind::CoSimulation => FmuKind::ModelExchange,
        };
        let allowed_in_other_kind = ALL_PHASES.iter().any(|&p| call.allowed(other, p));
        let allowed_in_this_kind = ALL_PHASES.iter().any(|&p| call.allowed(self.kind, p));
        if allowed_in_other_kind && !allowed_in_this_kind {
            return refuse(format!(
                "{} is a {} function, but this instance was instantiated for {}",
                call.name(),
                other.name(),
                self.kind.name()
            ));
        }
        let phases: Vec<_> = ALL_PHASES
            .iter()
            .filter(|&&p| call.allowed(self.kind, p))
            .map(|p| p.name())
            .collect();
        let allowed = if phases.is_empty() {
            "is never allowed here".to_string()
        } else {
            format!("is allowed in {} only", phases.join(", "))
        };
        refuse(format!(
            "{} is not allowed now: the instance is in {}; the call {allowed}",
            call.name(),
            self.phase.name()
        ))
    }

    // ----- common functions ---------------------------------------------------------

    /// `fmi2SetDebugLogging`.
    pub fn set_debug_logging(&mut self, logging_on: bool, categories: &[String]) -> CallResult {
        self.logger
            .set_debug_logging(logging_on, categories)
            .map_err(CallError::Refused)?;
        Ok(Status::Ok)
    }

    /// `fmi2SetupExperiment`: the start time, and optionally the stop time and the
    /// relative tolerance for Co-Simulation's solver.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> CallResult {
        if !start.is_finite() {
            return refuse(format!("startTime = {start} is not finite"));
        }
        if let Some(stop) = stop {
            if !(stop.is_finite() && stop >= start) {
                return refuse(format!(
                    "stopTime = {stop} is not a finite time >= startTime = {start}"
                ));
            }
        }
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return refuse(format!("tolerance = {tol} is not a positive number"));
            }
        }
        self.tolerance = tolerance;
        self.start_time = start;
        self.stop_time = stop;
        self.time = start;
        Ok(Status::Ok)
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode(&mut self) -> CallResult {
        self.time = self.start_time;
        self.phase = Phase::InitializationMode;
        Ok(Status::Ok)
    }

    /// `fmi2ExitInitializationMode`: the state is fixed (each state the importer set,
    /// the declared initial conditions for the parameters as set for the others); Model
    /// Exchange goes to Event Mode, Co-Simulation starts its solver.
    pub fn exit_initialization_mode(&mut self) -> CallResult {
        self.refresh_state();
        if let Some(i) = self.x.iter().position(|v| !v.is_finite()) {
            return refuse(format!(
                "the initial state {} = {} is not finite (check the parameters)",
                self.variable_name(Role::State(i)),
                self.x[i]
            ));
        }
        if let Err(message) = self.model.check_state(self.time, &self.x) {
            return refuse(message);
        }
        match self.kind {
            FmuKind::ModelExchange => {
                // No event at the start: the indicators there are the first reference.
                self.evaluate_indicators()?;
                self.g_reference.copy_from_slice(&self.g);
                self.phase = Phase::EventMode;
            }
            FmuKind::CoSimulation => {
                self.model
                    .start_stepping(self.time, &self.x, self.tolerance)
                    .map_err(CallError::Failed)?;
                self.phase = Phase::StepComplete;
            }
        }
        Ok(Status::Ok)
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> CallResult {
        self.phase = Phase::Terminated;
        Ok(Status::Ok)
    }

    /// `fmi2Reset`: back to [`Phase::Instantiated`] with the default parameters,
    /// inputs and initial states. The logging settings stay.
    pub fn reset(&mut self) -> CallResult {
        self.model.reset();
        self.x_start.fill(None);
        self.phase = Phase::Instantiated;
        self.time = 0.0;
        self.start_time = 0.0;
        self.stop_time = None;
        self.tolerance = None;
        self.last_step = Status::Ok;
        self.stopped = None;
        Ok(Status::Ok)
    }

    // ----- variables ----------------------------------------------------------------

    /// `fmi2GetReal`: `values[k]` gets the variable with value reference `vrs[k]`.
    /// Outputs and derivatives are evaluated at the current time and state; the call is
    /// refused (nothing written) when the model cannot evaluate them there and says why
    /// ([`FmuModel::evaluation_error`]).
    pub fn get_real(&mut self, vrs: &[ValueReference], values: &mut [f64]) -> CallResult {
        self.check_lengths("vr", vrs.len(), "value", values.len())?;
        let roles = self.roles(vrs)?;
        let needs = |f: fn(&Role) -> bool| roles.iter().any(f);
        if needs(|r| matches!(r, Role::State(_) | Role::Derivative(_) | Role::Output(_))) {
            self.refresh_state();
        }
        if needs(|r| matches!(r, Role::Derivative(_))) {
            self.model.derivatives(self.time, &self.x, &mut self.dx);
            self.evaluated(&self.dx, "derivatives")?;
        }
        if needs(|r| matches!(r, Role::Output(_))) {
            self.model.outputs(self.time, &self.x, &mut self.y);
            self.evaluated(&self.y, "outputs")?;
        }
        if needs(|r| matches!(r, Role::Parameter(_))) {
            self.model.parameter_values(&mut self.p);
        }
        if needs(|r| matches!(r, Role::Input(_))) {
            self.model.input_values(&mut self.u);
        }
        for (value, role) in values.iter_mut().zip(&roles) {
            *value = match *role {
                Role::State(i) => self.x[i],
                Role::Derivative(i) => self.dx[i],
                Role::Output(i) => self.y[i],
                Role::Parameter(i) => self.p[i],
                Role::Input(i) => self.u[i],
            };
        }
        Ok(Status::Ok)
    }

    /// `fmi2SetReal`: parameters (before initialisation ends; then in Event Mode or
    /// between Co-Simulation steps), inputs (whenever `fmi2SetReal` is allowed) and the
    /// initial states (before initialisation ends: they are `initial="exact"`).
    /// Derivatives and outputs are computed, not set. Every value is checked before
    /// any is set, and the parameters as they would be then against the model's rule
    /// ([`FmuModel::check_parameter_values`]).
    pub fn set_real(&mut self, vrs: &[ValueReference], values: &[f64]) -> CallResult {
        self.check_lengths("vr", vrs.len(), "value", values.len())?;
        let roles = self.roles(vrs)?;
        for ((&vr, role), &value) in vrs.iter().zip(&roles).zip(values) {
            let name = self.variable_name(*role);
            match role {
                Role::Derivative(_) | Role::Output(_) => {
                    return refuse(format!(
                        "{name} (value reference {vr}) is {} {}: only parameters, inputs and \
                         initial states can be set",
                        if role.kind().starts_with('o') {
                            "an"
                        } else {
                            "a"
                        },
                        role.kind()
                    ));
                }
                Role::State(_) if self.phase.is_initialised() => {
                    return refuse(format!(
                        "state {name} (value reference {vr}) can be set before initialisation \
                         ends only (it is initial=\"exact\"); afterwards the state is the \
                         integration's{}",
                        match self.kind {
                            FmuKind::ModelExchange => " (fmi2SetContinuousStates sets it)",
                            FmuKind::CoSimulation => "",
                        }
                    ));
                }
                Role::Parameter(_) if self.phase == Phase::ContinuousTimeMode => {
                    return refuse(format!(
                        "parameter {name} can be changed in Event Mode only, not in \
                         Continuous-Time Mode (call fmi2EnterEventMode first)"
                    ));
                }
                _ => {}
            }
            if !value.is_finite() {
                return refuse(format!("{name} = {value} is not finite"));
            }
        }
        let touches = |f: fn(&Role) -> bool| roles.iter().any(f);
        if touches(|r| matches!(r, Role::Parameter(_))) {
            let mut p = vec![0.0; self.sizes.parameters];
            self.model.parameter_values(&mut p);
            for (role, &value) in roles.iter().zip(values) {
                if let Role::Parameter(i) = *role {
                    p[i] = value;
                }
            }
            self.model.check_parameter_values(&p).map_err(|rule| {
                CallError::Refused(format!("{rule}; the parameters are left as they were"))
            })?;
            self.model.set_parameter_values(&p);
            self.p = p;
        }
        if touches(|r| matches!(r, Role::Input(_))) {
            self.model.input_values(&mut self.u);
        }
        for (role, &value) in roles.iter().zip(values) {
            match *role {
                Role::Input(i) => self.u[i] = value,
                Role::State(i) => self.x_start[i] = Some(value),
                _ => {}
            }
        }
        if touches(|r| matches!(r, Role::Input(_))) {
            self.model.set_input_values(&self.u);
        }
        Ok(Status::Ok)
    }

    /// `fmi2Get/SetInteger`, `Boolean`, `String`: the models have only `Real`
    /// variables, so any value reference is unknown (an empty list is fine).
    pub fn no_variables_of_type(&self, type_name: &str, vrs: &[ValueReference]) -> CallResult {
        match vrs.first() {
            None => Ok(Status::Ok),
            Some(vr) => refuse(format!(
                "value reference {vr} is not an {type_name} variable: {} has Real variables only",
                self.description.model_name
            )),
        }
    }

    // ----- Model Exchange -----------------------------------------------------------

    /// `fmi2EnterEventMode`.
    pub fn enter_event_mode(&mut self) -> CallResult {
        self.phase = Phase::EventMode;
        Ok(Status::Ok)
    }

    /// `fmi2NewDiscreteStates`: applies the action of every event whose indicator
    /// crossed zero in its direction since the reference point, in index order, each
    /// to the state the previous one left; the indicators at the state after become the
    /// reference. `eventInfo` says whether the continuous states changed (the importer
    /// then reads them) and whether a `stop` action asks the importer to end the run.
    /// One call settles it: no event fires from the state after an event (the runtime's
    /// rule), so `newDiscreteStatesNeeded` is false.
    pub fn new_discrete_states(&mut self, info: &mut EventInfo) -> CallResult {
        self.evaluate_indicators()?;
        let events = self.model.events();
        let mut x = self.x.clone();
        let mut stop = None;
        for (i, event) in events.iter().enumerate() {
            if !event.direction.fires(self.g_reference[i], self.g[i]) {
                continue;
            }
            let before = self.logger.wants(Category::Events).then(|| x.clone());
            let action = self.model.apply_event(i, self.time, &mut x);
            if action == EventAction::Stop {
                stop = Some((event.name, self.time));
            }
            if let Some(before) = before {
                self.log_event(event.name, self.time, &before, &x, action);
            }
        }
        if let Some(k) = x.iter().position(|v| !v.is_finite()) {
            return Err(CallError::Failed(format!(
                "after the events at t = {}, {} = {} is not finite",
                self.time,
                self.variable_name(Role::State(k)),
                x[k]
            )));
        }
        let n = self.sizes.continuous();
        let changed = x[..n]
            .iter()
            .zip(&self.x[..n])
            .any(|(a, b)| a.to_bits() != b.to_bits());
        self.x = x;
        if let Err(error) = self.evaluate_indicators() {
            return Err(CallError::Failed(error.message().to_string()));
        }
        self.g_reference.copy_from_slice(&self.g);
        self.stopped = self.stopped.or(stop);
        *info = EventInfo {
            terminate_simulation: if self.stopped.is_some() { TRUE } else { FALSE },
            values_of_continuous_states_changed: if changed { TRUE } else { FALSE },
            ..EventInfo::QUIET
        };
        Ok(Status::Ok)
    }

    /// `fmi2EnterContinuousTimeMode`; refused once an event's `stop` action asked to end
    /// the run (`terminateSimulation`: the importer calls `fmi2Terminate`).
    pub fn enter_continuous_time_mode(&mut self) -> CallResult {
        if let Some((event, t)) = self.stopped {
            return refuse(format!(
                "the event {event} stopped {} at t = {t} (terminateSimulation): call \
                 fmi2Terminate",
                self.description.model_name
            ));
        }
        self.phase = Phase::ContinuousTimeMode;
        Ok(Status::Ok)
    }

    /// `fmi2CompletedIntegratorStep`: the step's end becomes the reference point, unless
    /// an indicator crossed in its event's direction since the last one (an importer
    /// that does not locate events): then the FMU asks for Event Mode
    /// (`enterEventMode`) and keeps the reference, so that `fmi2NewDiscreteStates`
    /// handles the event there. Returns `(enterEventMode, terminateSimulation)`.
    pub fn completed_integrator_step(&mut self) -> Result<(bool, bool), CallError> {
        self.evaluate_indicators()?;
        let events = self.model.events();
        let pending = events
            .iter()
            .enumerate()
            .any(|(i, e)| e.direction.fires(self.g_reference[i], self.g[i]));
        if !pending {
            self.g_reference.copy_from_slice(&self.g);
        }
        Ok((pending, self.stopped.is_some()))
    }

    /// `fmi2SetTime`.
    pub fn set_time(&mut self, t: f64) -> CallResult {
        if !t.is_finite() {
            return refuse(format!("time = {t} is not finite"));
        }
        self.time = t;
        Ok(Status::Ok)
    }

    /// `fmi2SetContinuousStates`: the continuous states (the modes are the FMU's,
    /// changed at events only).
    pub fn set_continuous_states(&mut self, x: &[f64]) -> CallResult {
        self.check_state_count("nx", x.len())?;
        self.x[..x.len()].copy_from_slice(x);
        Ok(Status::Ok)
    }

    /// `fmi2GetDerivatives`: `dx/dt` at the current time and state; refused (nothing
    /// written) when the model cannot evaluate them there and says why
    /// ([`FmuModel::evaluation_error`]: an algebraic loop that did not converge).
    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> CallResult {
        self.check_state_count("nx", dx.len())?;
        self.refresh_state();
        self.model.derivatives(self.time, &self.x, &mut self.dx);
        self.evaluated(&self.dx, "derivatives")?;
        dx.copy_from_slice(&self.dx[..dx.len()]);
        Ok(Status::Ok)
    }

    /// Whether `values` the model just evaluated (its `what`) are usable: when one is
    /// not finite because the evaluation failed and the model says why
    /// ([`FmuModel::evaluation_error`]), the call is refused with that message, and
    /// nothing is handed to the importer (which may try another state or time: the
    /// instance is unchanged).
    fn evaluated(&self, values: &[f64], what: &str) -> Result<(), CallError> {
        if values.iter().all(|v| v.is_finite()) {
            return Ok(());
        }
        match self.model.evaluation_error() {
            Some(reason) => refuse(format!(
                "the {what} of {} cannot be evaluated at t = {}: {reason}",
                self.description.model_name, self.time
            )),
            None => Ok(()),
        }
    }

    /// `fmi2GetEventIndicators`: g of every event at the current time and state
    /// ([`FmuModel::event_indicators`]); refused (nothing written) when the model cannot
    /// evaluate them there and says why.
    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> CallResult {
        if z.len() != self.sizes.events {
            return refuse(format!(
                "ni = {}, but {} has {} event indicators (numberOfEventIndicators)",
                z.len(),
                self.description.model_name,
                self.sizes.events
            ));
        }
        self.evaluate_indicators()?;
        z.copy_from_slice(&self.g);
        Ok(Status::Ok)
    }

    /// Evaluates the event indicators at the current time and state into `self.g`.
    fn evaluate_indicators(&mut self) -> Result<(), CallError> {
        if self.g.is_empty() {
            return Ok(());
        }
        self.refresh_state();
        self.model.event_indicators(self.time, &self.x, &mut self.g);
        self.evaluated(&self.g, "event indicators")
    }

    /// Logs an event the FMU handled, in category `logEvents`.
    fn log_event(&self, name: &str, t: f64, before: &[f64], after: &[f64], action: EventAction) {
        let changes: Vec<String> = before
            .iter()
            .zip(after)
            .enumerate()
            .filter(|(_, (a, b))| a.to_bits() != b.to_bits())
            .map(|(k, (a, b))| format!("{} {a} -> {b}", self.variable_name(Role::State(k))))
            .collect();
        let what = if changes.is_empty() {
            "no state changed".to_string()
        } else {
            changes.join(", ")
        };
        let stop = if action == EventAction::Stop {
            "; stop"
        } else {
            ""
        };
        self.logger.log_in(
            Category::Events,
            Status::Ok,
            &format!("event {name} at t = {t}: {what}{stop}"),
        );
    }

    /// `fmi2GetContinuousStates`.
    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> CallResult {
        self.check_state_count("nx", x.len())?;
        self.refresh_state();
        x.copy_from_slice(&self.x[..x.len()]);
        Ok(Status::Ok)
    }

    /// `fmi2GetNominalsOfContinuousStates`: 1 for every continuous state (the models
    /// declare no scales).
    pub fn get_nominals_of_continuous_states(&mut self, nominals: &mut [f64]) -> CallResult {
        self.check_state_count("nx", nominals.len())?;
        nominals.fill(1.0);
        Ok(Status::Ok)
    }

    // ----- Co-Simulation ------------------------------------------------------------

    /// `fmi2DoStep`: integrates from `t` (which must be where the last step ended, or
    /// the start time) over `h` with the model's own solver and the inputs held.
    pub fn do_step(&mut self, t: f64, h: f64) -> CallResult {
        if !(t.is_finite() && h.is_finite() && h >= 0.0) {
            return refuse(format!(
                "currentCommunicationPoint = {t} and communicationStepSize = {h}: both must \
                 be finite and the step size not negative"
            ));
        }
        if (t - self.time).abs() > TIME_MATCH * self.time.abs().max(t.abs()).max(1.0) {
            return refuse(format!(
                "currentCommunicationPoint = {t}, but the FMU is at t = {}: a step starts \
                 where the previous one ended (or at the start time)",
                self.time
            ));
        }
        let end = t + h;
        if let Some(stop) = self.stop_time {
            if end > stop + TIME_MATCH * stop.abs().max(1.0) {
                return refuse(format!(
                    "the step would end at t = {end}, after the stop time {stop} given to \
                     fmi2SetupExperiment"
                ));
            }
        }
        if h == 0.0 {
            self.last_step = Status::Ok;
            return Ok(Status::Ok);
        }
        let outcome = self.model.advance_to(end, &mut self.x);
        if self.logger.wants(Category::Events) {
            let more = self.model.step_events(&mut |e| {
                self.log_event(e.name, e.t, e.before, e.after, e.action);
            });
            if more > 0 {
                self.logger.log_in(
                    Category::Events,
                    Status::Ok,
                    &format!("and {more} more events in the step from t = {t} to t = {end}"),
                );
            }
        }
        match outcome {
            Ok(None) => {
                self.time = end;
                self.last_step = Status::Ok;
                Ok(Status::Ok)
            }
            Ok(Some(Stopped { event, t: at })) => {
                // The standard's way for a slave to end the run inside a step.
                self.time = at;
                self.stopped = Some((event, at));
                self.phase = Phase::StepFailed;
                self.last_step = Status::Discard;
                self.log(
                    Status::Discard,
                    &format!(
                        "fmi2DoStep: the event {event} stopped {} at t = {at}, inside the step \
                         from t = {t} to t = {end}: fmi2GetBooleanStatus(fmi2Terminated) is \
                         true, fmi2GetRealStatus(fmi2LastSuccessfulTime) is {at}, and the \
                         state is the one after the event; call fmi2Terminate",
                        self.description.model_name
                    ),
                );
                Ok(Status::Discard)
            }
            Err(reason) => {
                self.phase = Phase::StepFailed;
                self.last_step = Status::Discard;
                self.log(
                    Status::Discard,
                    &format!(
                        "fmi2DoStep: the step from t = {t} to t = {end} failed: {reason}. The \
                         FMU stays at t = {} (fmi2GetRealStatus(fmi2LastSuccessfulTime))",
                        self.time
                    ),
                );
                Ok(Status::Discard)
            }
        }
    }

    /// `fmi2GetStatus`: only `fmi2DoStepStatus`, the status of the last step.
    pub fn get_status(&self, kind: StatusKind) -> Result<Status, CallError> {
        match kind {
            StatusKind::DoStepStatus => Ok(self.last_step),
            other => self.status_not_available(other, "fmi2GetStatus"),
        }
    }

    /// `fmi2GetRealStatus`: only `fmi2LastSuccessfulTime`.
    pub fn get_real_status(&self, kind: StatusKind) -> Result<f64, CallError> {
        match kind {
            StatusKind::LastSuccessfulTime => Ok(self.time),
            other => self.status_not_available(other, "fmi2GetRealStatus"),
        }
    }

    /// `fmi2GetBooleanStatus`: only `fmi2Terminated`, true once an event's `stop`
    /// action ended the run inside a step (which returned `fmi2Discard`).
    pub fn get_boolean_status(&self, kind: StatusKind) -> Result<bool, CallError> {
        match kind {
            StatusKind::Terminated => Ok(self.stopped.is_some()),
            other => self.status_not_available(other, "fmi2GetBooleanStatus"),
        }
    }

    fn status_not_available<T>(&self, kind: StatusKind, call: &str) -> Result<T, CallError> {
        refuse(format!(
            "{call} cannot report {kind:?}: steps are never asynchronous (no fmi2Pending), \
             so fmi2GetStatus answers fmi2DoStepStatus, fmi2GetRealStatus \
             fmi2LastSuccessfulTime and fmi2GetBooleanStatus fmi2Terminated"
        ))
    }

    // ----- helpers ------------------------------------------------------------------

    /// Before initialisation ends the state is the initial state for the parameters
    /// as they are now, but for the states the importer set.
    fn refresh_state(&mut self) {
        if !self.phase.is_initialised() {
            self.model.initial_state(&mut self.x);
            for (x, set) in self.x.iter_mut().zip(&self.x_start) {
                if let Some(value) = set {
                    *x = *value;
                }
            }
        }
    }

    fn roles(&self, vrs: &[ValueReference]) -> Result<Vec<Role>, CallError> {
        vrs.iter()
            .map(|&vr| match role_of(self.sizes, vr) {
                Some(role) => Ok(role),
                None => refuse(format!(
                    "value reference {vr} is not a variable of {}: its value references are \
                     0 to {} (see modelDescription.xml)",
                    self.description.model_name,
                    self.description.variables.all().len().saturating_sub(1)
                )),
            })
            .collect()
    }

    fn variable_name(&self, role: Role) -> &str {
        let vr = self.description.variables.value_reference(role);
        self.description
            .variables
            .get(vr)
            .map_or("?", |v| v.name.as_str())
    }

    fn check_lengths(&self, a: &str, na: usize, b: &str, nb: usize) -> Result<(), CallError> {
        if na != nb {
            return refuse(format!("{a} has {na} entries but {b} has {nb}"));
        }
        Ok(())
    }

    fn check_state_count(&self, what: &str, n: usize) -> Result<(), CallError> {
        if n != self.sizes.continuous() {
            let modes = match self.sizes.modes {
                0 => String::new(),
                m => format!(" (and {m} discrete modes, which the FMU keeps)"),
            };
            return refuse(format!(
                "{what} = {n}, but {} has {} continuous states{modes}",
                self.description.model_name,
                self.sizes.continuous()
            ));
        }
        Ok(())
    }
}

const ALL_PHASES: [Phase; 8] = [
    Phase::Instantiated,
    Phase::InitializationMode,
    Phase::EventMode,
    Phase::ContinuousTimeMode,
    Phase::StepComplete,
    Phase::StepFailed,
    Phase::Terminated,
    Phase::Error,
];
