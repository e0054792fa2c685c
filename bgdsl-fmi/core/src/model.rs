//! What an FMU instance needs of a model, as an object-safe trait ([`FmuModel`]), and
//! its implementation for every generated model ([`Exportable`]).
//!
//! One shared library serves several models, chosen at run time by the GUID the
//! importer passes to `fmi2Instantiate`; an instance holds its model as a
//! `Box<dyn FmuModel>`. The trait works on flat `f64` slices whose lengths the
//! instance checks against [`Sizes`] before every call, so the generated code's length
//! assertions never fire.

use bgdsl_runtime::{
    EventAction, EventInfo, EventRecord, ModeInfo, Model, Solver, Stepper, WithInputs,
};

/// A model's rule for its parameters, applied to the whole flat parameter vector (in
/// [`Model::parameter_values`] order) that an `fmi2SetReal` would leave: `Err` with a
/// message naming the parameter and the rule refuses the call, which then changes
/// nothing.
pub type ParameterCheck = fn(&[f64]) -> Result<(), String>;

/// The default [`ParameterCheck`]: finite numbers only, which the instance checks for
/// every value it is given, so nothing is left to check here.
pub fn finite_only(_values: &[f64]) -> Result<(), String> {
    Ok(())
}

/// The models an FMU can be made of: every model `bond_graph!` generates (they
/// implement [`WithInputs`] and [`Default`], the defaults being the declared values).
pub trait Exportable: WithInputs + Default + 'static {}

impl<M: WithInputs + Default + 'static> Exportable for M {}

/// How many numbers of each kind a model has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sizes {
    /// States, the discrete modes included (they are the last [`Sizes::modes`]).
    pub states: usize,
    /// Discrete modes ([`Model::MODES`]): the last states, constant between events.
    pub modes: usize,
    /// Event indicators ([`Model::EVENTS`]).
    pub events: usize,
    /// Outputs.
    pub outputs: usize,
    /// Parameter values, vectors and matrices flattened.
    pub parameters: usize,
    /// Inputs.
    pub inputs: usize,
}

impl Sizes {
    /// The sizes of model `M`.
    pub fn of<M: WithInputs>() -> Self {
        Sizes {
            states: M::N_STATES,
            modes: M::MODES.len(),
            events: M::EVENTS.len(),
            outputs: M::N_OUTPUTS,
            parameters: M::N_PARAMETER_VALUES,
            inputs: M::INPUTS.len(),
        }
    }

    /// The continuous states, the states less the modes: what a Model Exchange
    /// importer integrates (and the state derivatives the FMU declares).
    pub fn continuous(&self) -> usize {
        self.states - self.modes
    }
}

/// A model behind an FMU instance: evaluation for Model Exchange, integration with the
/// model's own solver for Co-Simulation, and flat access to parameters and inputs.
///
/// Callers pass slices of the lengths in [`FmuModel::sizes`]; implementations may
/// panic otherwise (the FFI layer catches it, but the instance checks first).
pub trait FmuModel {
    /// The lengths of the slices the other methods take.
    fn sizes(&self) -> Sizes;
    /// Writes the initial state (from the current parameters) into `x0`.
    fn initial_state(&self, x0: &mut [f64]);
    /// Writes `dx/dt` at `(t, x)` into `dx`.
    fn derivatives(&self, t: f64, x: &[f64], dx: &mut [f64]);
    /// Writes the outputs at `(t, x)` into `y`.
    fn outputs(&self, t: f64, x: &[f64], y: &mut [f64]);
    /// Why the last evaluation of the derivatives or outputs failed, if it did
    /// ([`Model::evaluation_error`]: an algebraic loop that did not converge, singular
    /// constraints), as the sentence to log. The default: evaluations do not fail so.
    fn evaluation_error(&self) -> Option<String> {
        None
    }
    /// Writes the parameter values into `out`.
    fn parameter_values(&self, out: &mut [f64]);
    /// Sets the parameter values from `values`.
    fn set_parameter_values(&mut self, values: &[f64]);
    /// Whether `values` (every parameter value, flattened) is a set the model accepts:
    /// the model's [`ParameterCheck`].
    ///
    /// # Errors
    ///
    /// The message of the first rule broken, naming the parameter.
    fn check_parameter_values(&self, values: &[f64]) -> Result<(), String>;
    /// The model's own check of a state ([`Model::check`]): an inverse its law gives
    /// that is not one.
    ///
    /// # Errors
    ///
    /// The check's message, naming the element, the time and the residual.
    fn check_state(&self, t: f64, x: &[f64]) -> Result<(), String>;
    /// The model's events ([`Model::EVENTS`]), in the order simultaneous ones are
    /// handled.
    fn events(&self) -> &'static [EventInfo];
    /// The model's discrete modes ([`Model::MODES`]): the last states.
    fn modes(&self) -> &'static [ModeInfo];
    /// Writes the event indicators g at `(t, x)` into `g`
    /// ([`Model::event_indicators`]).
    fn event_indicators(&self, t: f64, x: &[f64], g: &mut [f64]);
    /// Applies event `index`'s action to `x`, the state just before the event,
    /// rewritten to the state after ([`Model::apply_event`]).
    fn apply_event(&self, index: usize, t: f64, x: &mut [f64]) -> EventAction;
    /// Writes the inputs into `out`.
    fn input_values(&self, out: &mut [f64]);
    /// Sets the inputs from `values`.
    fn set_input_values(&mut self, values: &[f64]);
    /// Prepares Co-Simulation from time `t0` and state `x0`: the model's default solver
    /// ([`Model::default_solver`]), its relative tolerance replaced by `tolerance` when
    /// the importer gives one.
    ///
    /// # Errors
    ///
    /// The solver cannot be set up (an invalid tolerance) or `x0` is not finite.
    fn start_stepping(&mut self, t0: f64, x0: &[f64], tolerance: Option<f64>)
        -> Result<(), String>;
    /// Integrates from where the last step ended to time `t` with the inputs held,
    /// handling the events on the way, and writes the state there into `x`; or, when an
    /// event's `stop` action ends the run before `t`, the state after that event, and
    /// returns which event stopped it when. Before [`FmuModel::start_stepping`] this
    /// is an error.
    ///
    /// # Errors
    ///
    /// The solver failed; the integration then stays where it was.
    fn advance_to(&mut self, t: f64, x: &mut [f64]) -> Result<Option<Stopped>, String>;
    /// Shows `visit` each event the last [`FmuModel::advance_to`] handled, in time
    /// order (those the stepper's log had room for: 64 per step), and returns how many
    /// more it handled.
    fn step_events(&self, visit: &mut dyn FnMut(&EventRecord<'_>)) -> usize;
    /// Back to the model as first made: default parameters and inputs, no integration.
    fn reset(&mut self);
}

/// An event whose `stop` action ended a Co-Simulation step early.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stopped {
    /// The event's name ([`EventInfo::name`]).
    pub event: &'static str,
    /// When: where the step ended.
    pub t: f64,
}

/// A generated model and, once Co-Simulation starts, the [`Stepper`] that owns it.
#[derive(Debug)]
pub struct Adapter<M: Model + 'static> {
    holder: Holder<M>,
    check: ParameterCheck,
}

#[derive(Debug)]
enum Holder<M: Model + 'static> {
    /// Before Co-Simulation starts, and always for Model Exchange.
    Model(M),
    /// Co-Simulation: the stepper owns the model.
    Stepping(Box<Stepper<M>>),
}

impl<M: Exportable> Adapter<M> {
    /// The model with its default parameters and inputs, accepting any finite
    /// parameter values ([`finite_only`]).
    pub fn new() -> Self {
        Self::with_check(finite_only)
    }

    /// The model with its default parameters and inputs, and `check` for the values
    /// an importer sets.
    pub fn with_check(check: ParameterCheck) -> Self {
        Adapter {
            holder: Holder::Model(M::default()),
            check,
        }
    }

    /// The model as a trait object, for an FMU instance, with `check` for its
    /// parameters.
    pub fn boxed(check: ParameterCheck) -> Box<dyn FmuModel> {
        Box::new(Self::with_check(check))
    }

    fn model(&self) -> &M {
        match &self.holder {
            Holder::Model(model) => model,
            Holder::Stepping(stepper) => stepper.model(),
        }
    }

    fn model_mut(&mut self) -> &mut M {
        match &mut self.holder {
            Holder::Model(model) => model,
            Holder::Stepping(stepper) => stepper.model_mut(),
        }
    }
}

impl<M: Exportable> Default for Adapter<M> {
    fn default() -> Self {
        Self::new()
    }
}

/// `solver` with its relative tolerance set to `rtol` (adaptive methods; the fixed-step
/// ones have none).
fn with_tolerance(solver: Solver, rtol: f64) -> Solver {
    match solver {
        Solver::DormandPrince(mut o) => {
            o.rtol = rtol;
            Solver::DormandPrince(o)
        }
        Solver::Radau5(mut o) => {
            o.rtol = rtol;
            Solver::Radau5(o)
        }
        Solver::Rodas4(mut o) => {
            o.rtol = rtol;
            Solver::Rodas4(o)
        }
        Solver::Rodas5P(mut o) => {
            o.rtol = rtol;
            Solver::Rodas5P(o)
        }
        other => other,
    }
}

impl<M: Exportable> FmuModel for Adapter<M> {
    fn sizes(&self) -> Sizes {
        Sizes::of::<M>()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        self.model().initial_state(x0);
    }

    fn derivatives(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        self.model().derivatives::<f64>(t, x, dx);
    }

    fn outputs(&self, t: f64, x: &[f64], y: &mut [f64]) {
        self.model().outputs::<f64>(t, x, y);
    }

    fn evaluation_error(&self) -> Option<String> {
        self.model()
            .evaluation_error()
            .map(|error| error.to_string())
    }

    fn parameter_values(&self, out: &mut [f64]) {
        self.model().parameter_values(out);
    }

    fn set_parameter_values(&mut self, values: &[f64]) {
        self.model_mut().set_parameter_values(values);
    }

    fn check_parameter_values(&self, values: &[f64]) -> Result<(), String> {
        (self.check)(values)
    }

    fn check_state(&self, t: f64, x: &[f64]) -> Result<(), String> {
        self.model().check(t, x).map_err(|error| error.to_string())
    }

    fn events(&self) -> &'static [EventInfo] {
        M::EVENTS
    }

    fn modes(&self) -> &'static [ModeInfo] {
        M::MODES
    }

    fn event_indicators(&self, t: f64, x: &[f64], g: &mut [f64]) {
        self.model().event_indicators(t, x, g);
    }

    fn apply_event(&self, index: usize, t: f64, x: &mut [f64]) -> EventAction {
        self.model().apply_event(index, t, x)
    }

    fn input_values(&self, out: &mut [f64]) {
        self.model().input_values(out);
    }

    fn set_input_values(&mut self, values: &[f64]) {
        self.model_mut().set_input_values(values);
    }

    fn start_stepping(
        &mut self,
        t0: f64,
        x0: &[f64],
        tolerance: Option<f64>,
    ) -> Result<(), String> {
        // The model moves into the stepper; a default one stands in meanwhile.
        let model = match core::mem::replace(&mut self.holder, Holder::Model(M::default())) {
            Holder::Model(model) => model,
            Holder::Stepping(mut stepper) => {
                let result = stepper.set_state(t0, x0).map_err(|e| e.to_string());
                self.holder = Holder::Stepping(stepper);
                return result;
            }
        };
        let mut solver = model.default_solver();
        if let Some(rtol) = tolerance {
            solver = with_tolerance(solver, rtol);
        }
        // Everything `Stepper::starting_at` checks, checked first, so that a failure
        // gives the model (and the parameters set so far) back.
        let problem = if let Err(e) = solver.validate() {
            Some(format!("cannot start the {} solver: {e}", solver.name()))
        } else {
            x0.iter().position(|v| !v.is_finite()).map(|i| {
                let name = M::STATE_NAMES.get(i).copied().unwrap_or("?");
                format!("the initial state {name} = {} is not finite", x0[i])
            })
        };
        if let Some(problem) = problem {
            self.holder = Holder::Model(model);
            return Err(problem);
        }
        let stepper = Stepper::starting_at(model, solver, t0, x0)
            .map_err(|e| format!("cannot start the {} solver: {e}", solver.name()))?;
        self.holder = Holder::Stepping(Box::new(stepper));
        Ok(())
    }

    fn advance_to(&mut self, t: f64, x: &mut [f64]) -> Result<Option<Stopped>, String> {
        match &mut self.holder {
            Holder::Model(_) => Err("the integration has not been started".to_string()),
            Holder::Stepping(stepper) => {
                stepper.advance_to(t).map_err(|e| e.to_string())?;
                x.copy_from_slice(stepper.state());
                // A stop action ends the advance at its event: before `t`, or at `t`
                // exactly.
                let stop = stepper
                    .events()
                    .iter()
                    .filter(|e| e.action == EventAction::Stop)
                    .last()
                    .map(|e| e.name);
                if stop.is_none() && stepper.time() >= t {
                    return Ok(None);
                }
                Ok(Some(Stopped {
                    event: stop.unwrap_or("(past the events the step's log keeps)"),
                    t: stepper.time(),
                }))
            }
        }
    }

    fn step_events(&self, visit: &mut dyn FnMut(&EventRecord<'_>)) -> usize {
        let Holder::Stepping(stepper) = &self.holder else {
            return 0;
        };
        for event in stepper.events().iter() {
            visit(&event);
        }
        stepper.events().dropped()
    }

    fn reset(&mut self) {
        self.holder = Holder::Model(M::default());
    }
}
