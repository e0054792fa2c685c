//! Stepping a model from a host program: a controller under test, a digital twin fed
//! by measurements, a co-simulation master. The host owns the loop; the [`Stepper`]
//! integrates to each time it is asked for, with the inputs the host set, and hands
//! back the outputs.

use serde::{Deserialize, Serialize};

use crate::error::{NonFiniteKind, SampleTimeProblem, SolverError};
use crate::event::{EventOptions, EventRecord};
use crate::model::{Model, WithInputs};
use crate::record::{EventLog, Recorder};
use crate::solver::{Simulation, Solver, Stats};

/// A model, its solver's workspace and where the integration stands.
///
/// Every [`Stepper::advance_to`] starts the method afresh from the current state (the
/// first step size chosen anew, the Jacobian evaluated anew), so a jump in the inputs
/// between calls never reaches into the step-size history or a stale Jacobian. All
/// memory is taken when the stepper is made: advancing allocates nothing.
///
/// A model's events ([`crate::event`]) are handled inside each advance as in a
/// [`Simulation`] run and listed in [`Stepper::events`]; a stop action ends the advance
/// at the event ([`Stepper::time`] says where). Events the host causes by changing
/// inputs between advances are the host's to handle (see [`Stepper::events`]).
///
/// ```
/// use bgdsl_runtime::{bond_graph, Solver, Stepper};
///
/// bond_graph! {
///     /// A mass pushed by a force the host sets.
///     pub model Pushed {
///         input force = 0.0 in "N";
///         I mass = 2.0;
///         MSe push = force;
///         push -> mass;
///         output speed = mass.f;
///     }
/// }
///
/// let mut stepper = Stepper::new(Pushed::default(), Solver::from_name("dopri5")?)?;
/// let outputs = stepper.advance_with(1.0, PushedInputs { force: 4.0 })?;
/// assert!((outputs[0] - 2.0).abs() < 1e-12); // v = F t / m
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Stepper<M: Model + 'static> {
    simulation: Simulation<'static, M>,
    t: f64,
    x: Vec<f64>,
    y: Vec<f64>,
    events: EventLog,
    /// The last advance ended where the stepper stands, so the next continues its
    /// events (false at the start, after `set_state`, `restore` or a failed advance).
    continuing: bool,
}

/// The events a stepper keeps per advance unless told otherwise
/// ([`Stepper::set_event_capacity`]).
const DEFAULT_EVENT_CAPACITY: usize = 64;

impl<M: Model + 'static> core::fmt::Debug for Stepper<M> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Stepper")
            .field("model", &M::NAME)
            .field("t", &self.t)
            .field("x", &self.x)
            .finish_non_exhaustive()
    }
}

/// Where a stepper stood: plain data, to save and restore (or send elsewhere).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// The model's name ([`Model::NAME`]), checked on restore.
    pub model: String,
    /// The time.
    pub t: f64,
    /// The state, in the order of [`Model::STATE_NAMES`].
    pub state: Vec<f64>,
}

/// A snapshot that does not fit the stepper it is restored into.
#[derive(Clone, Debug, PartialEq)]
pub enum SnapshotError {
    /// It was taken of another model.
    OtherModel {
        /// The snapshot's model.
        found: String,
        /// The stepper's model.
        expected: &'static str,
    },
    /// Its state has the wrong length, or a value that is not finite.
    BadState {
        /// What is wrong.
        reason: String,
    },
}

impl core::fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SnapshotError::OtherModel { found, expected } => write!(
                f,
                "the snapshot is of model `{found}`, but this stepper runs `{expected}`"
            ),
            SnapshotError::BadState { reason } => write!(f, "the snapshot's state {reason}"),
        }
    }
}

impl std::error::Error for SnapshotError {}

impl<M: Model + 'static> Stepper<M> {
    /// A stepper for `model` with `solver`, at `t = 0` in the model's initial state.
    ///
    /// # Errors
    ///
    /// The solver's options are invalid.
    pub fn new(model: M, solver: Solver) -> Result<Self, SolverError> {
        let mut x0 = vec![0.0; M::N_STATES];
        model.initial_state(&mut x0);
        Self::starting_at(model, solver, 0.0, &x0)
    }

    /// A stepper for `model` with `solver`, at time `t0` in state `x0`.
    ///
    /// # Errors
    ///
    /// The solver's options are invalid, or `x0` does not have
    /// [`Model::N_STATES`] finite values.
    pub fn starting_at(model: M, solver: Solver, t0: f64, x0: &[f64]) -> Result<Self, SolverError> {
        let simulation = Simulation::owning(model, solver)?;
        let mut stepper = Stepper {
            simulation,
            t: t0,
            x: vec![0.0; M::N_STATES],
            y: vec![0.0; M::N_OUTPUTS],
            events: EventLog::bounded(M::N_STATES, DEFAULT_EVENT_CAPACITY),
            continuing: false,
        };
        stepper.set_state(t0, x0)?;
        Ok(stepper)
    }

    /// Integrates from the current time to `t` (with the inputs as they are now) and
    /// returns the outputs there, in the order of [`Model::OUTPUT_NAMES`]. Asking for
    /// the current time only evaluates the outputs. The events inside the interval are
    /// handled and listed in [`Stepper::events`]; an event that stops the run ends the
    /// advance at its time, with the outputs there (after the event).
    ///
    /// # Errors
    ///
    /// `t` lies before the current time, or the solver fails (for a model that could
    /// not evaluate, e.g. an algebraic loop that did not converge:
    /// [`SolverError::InvalidModel`] with [`Model::evaluation_error`]); the stepper then
    /// stays where it was before the call.
    pub fn advance_to(&mut self, t: f64) -> Result<&[f64], SolverError> {
        if !t.is_finite() || t < self.t {
            let problem = if t.is_finite() {
                SampleTimeProblem::BeforeStart { t0: self.t }
            } else {
                SampleTimeProblem::NotFinite
            };
            return Err(SolverError::InvalidSampleTimes {
                index: 0,
                t,
                problem,
            });
        }
        self.events.clear();
        if t == self.t {
            self.refresh_outputs(t)?;
            return Ok(&self.y);
        }
        let mut recorder = Keep {
            outputs: &mut self.y,
            events: &mut self.events,
            stopped: false,
        };
        if core::mem::take(&mut self.continuing) {
            self.simulation.continue_events();
        }
        self.simulation.run(self.t, &self.x, &[t], &mut recorder)?;
        self.continuing = true;
        let stopped = recorder.stopped;
        self.x.copy_from_slice(self.simulation.state());
        // A stop action ends the advance at the event's time, before `t`.
        self.t = if stopped { self.simulation.time() } else { t };
        Ok(&self.y)
    }

    /// The events of the last [`Stepper::advance_to`], in time order, with the state on
    /// both sides of each; kept in room reserved up front
    /// ([`Stepper::set_event_capacity`], 64 by default), beyond which they are only
    /// counted ([`EventLog::dropped`]).
    ///
    /// An advance continues the events of the one before: an event that fired at its
    /// very end (a stop, a bounce) is armed as it would be within one run, and the
    /// chattering rule counts on. Events the host causes itself by changing inputs or
    /// parameters between advances (a set point stepped across a switching threshold)
    /// are the host's to handle: the indicators' references are taken again, with the
    /// model as it now stands, at the start of every advance, so such a crossing does
    /// not fire. [`Stepper::set_state`] and [`Stepper::restore`] start the events
    /// afresh (no event at the new point).
    pub fn events(&self) -> &EventLog {
        &self.events
    }

    /// Reserves room for `capacity` events per advance (allocates; advancing does not).
    pub fn set_event_capacity(&mut self, capacity: usize) {
        self.events = EventLog::bounded(M::N_STATES, capacity);
    }

    /// Sets how advances locate events and when they give up on chattering ones.
    ///
    /// # Errors
    ///
    /// An option is out of range ([`SolverError::InvalidOptions`]).
    pub fn set_event_options(&mut self, options: EventOptions) -> Result<(), SolverError> {
        self.simulation.set_event_options(options)
    }

    /// Gives every state its own absolute tolerance for later advances, as
    /// [`Simulation::set_atol`] (whose errors it returns).
    pub fn set_atol(&mut self, atol: &[f64]) -> Result<(), SolverError> {
        self.simulation.set_atol(atol)
    }

    /// Keeps the states `states` non-negative in later advances, as
    /// [`Simulation::set_non_negative`] (whose errors it returns).
    pub fn set_non_negative(&mut self, states: &[usize]) -> Result<(), SolverError> {
        self.simulation.set_non_negative(states)
    }

    /// The current time.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The current state, in the order of [`Model::STATE_NAMES`].
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// The outputs at the current time and state (as of the last call that moved or
    /// set them; [`Stepper::advance_to`] the current time to re-evaluate after
    /// changing the model).
    pub fn outputs(&self) -> &[f64] {
        &self.y
    }

    /// Moves the integration to time `t` and state `x` (a restart, an estimator's
    /// correction).
    ///
    /// # Errors
    ///
    /// `x` does not have [`Model::N_STATES`] values, or one is not finite, or the
    /// model cannot evaluate its outputs there ([`SolverError::InvalidModel`] with
    /// [`Model::evaluation_error`]); the stepper then stays where it was.
    pub fn set_state(&mut self, t: f64, x: &[f64]) -> Result<(), SolverError> {
        if x.len() != M::N_STATES {
            return Err(SolverError::StateLengthMismatch {
                model: M::NAME,
                expected: M::N_STATES,
                found: x.len(),
            });
        }
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFiniteState {
                t,
                state: M::STATE_NAMES.get(index).copied().unwrap_or("?"),
                value: x[index],
                kind: NonFiniteKind::State,
            });
        }
        let model = self.simulation.model();
        model.outputs::<f64>(t, x, &mut self.y);
        if let Err(error) = outputs_evaluated(model, &self.y) {
            // Put the outputs of the point the stepper stays at back.
            model.outputs::<f64>(self.t, &self.x, &mut self.y);
            return Err(error);
        }
        self.t = t;
        self.x.copy_from_slice(x);
        self.continuing = false;
        Ok(())
    }

    /// The model, to read its parameters and inputs.
    pub fn model(&self) -> &M {
        self.simulation.model()
    }

    /// The model, to change its parameters or inputs before the next
    /// [`Stepper::advance_to`].
    pub fn model_mut(&mut self) -> &mut M {
        match self.simulation.model_mut() {
            Some(model) => model,
            // A stepper's simulation always owns its model (`Simulation::owning`).
            None => unreachable!("a stepper owns its model"),
        }
    }

    /// The solver's counters for the last call that integrated.
    pub fn stats(&self) -> Stats {
        self.simulation.stats()
    }

    /// Where the stepper stands, as plain data.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            model: M::NAME.to_string(),
            t: self.t,
            state: self.x.clone(),
        }
    }

    /// Returns the stepper to a snapshot taken of the same model.
    ///
    /// # Errors
    ///
    /// The snapshot is of another model or its state does not fit; the stepper is
    /// then unchanged.
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<(), SnapshotError> {
        if snapshot.model != M::NAME {
            return Err(SnapshotError::OtherModel {
                found: snapshot.model.clone(),
                expected: M::NAME,
            });
        }
        self.set_state(snapshot.t, &snapshot.state)
            .map_err(|error| SnapshotError::BadState {
                reason: match error {
                    SolverError::StateLengthMismatch {
                        expected, found, ..
                    } => {
                        format!("has {found} values, but the model has {expected} states")
                    }
                    other => format!("is not usable: {other}"),
                },
            })
    }

    /// Evaluates the outputs at the current point. Fails with the model's own error
    /// when that evaluation failed ([`Model::evaluation_error`]).
    fn refresh_outputs(&mut self, t: f64) -> Result<(), SolverError> {
        let model = self.simulation.model();
        model.outputs::<f64>(t, &self.x, &mut self.y);
        outputs_evaluated(model, &self.y)
    }
}

impl<M: WithInputs + 'static> Stepper<M> {
    /// Sets the inputs the next [`Stepper::advance_to`] holds.
    pub fn set_inputs(&mut self, inputs: M::Inputs) {
        self.model_mut().set_inputs(inputs);
    }

    /// Sets the inputs and integrates to `t` with them held: one period of a host's
    /// loop. Returns the outputs at `t`.
    ///
    /// # Errors
    ///
    /// As [`Stepper::advance_to`].
    pub fn advance_with(&mut self, t: f64, inputs: M::Inputs) -> Result<&[f64], SolverError> {
        self.set_inputs(inputs);
        self.advance_to(t)
    }
}

/// What an advance keeps of its run: the outputs at its end and its events.
struct Keep<'a> {
    outputs: &'a mut [f64],
    events: &'a mut EventLog,
    stopped: bool,
}

impl Recorder for Keep<'_> {
    fn record(&mut self, _t: f64, _x: &[f64], y: &[f64]) {
        self.outputs.copy_from_slice(y);
    }

    fn event(&mut self, record: &EventRecord<'_>) {
        self.events.push(record);
        self.stopped |= record.action == crate::event::EventAction::Stop;
    }
}

/// The model's own error ([`Model::evaluation_error`]) if outputs `y` it just evaluated
/// are not finite because the evaluation failed.
fn outputs_evaluated<M: Model>(model: &M, y: &[f64]) -> Result<(), SolverError> {
    match model.evaluation_error() {
        Some(cause) if y.iter().any(|v| !v.is_finite()) => Err(SolverError::InvalidModel(cause)),
        _ => Ok(()),
    }
}
