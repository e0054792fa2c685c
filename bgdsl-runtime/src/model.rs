//! The contract between generated (or hand-written) models and the solvers.

use crate::event::{EventAction, EventInfo, ModeInfo};
use crate::graph::CausalGraph;
use crate::scalar::Scalar;

/// A system of ordinary differential equations `dx/dt = f(t, x)` with named states and
/// named outputs `y = g(t, x)`.
///
/// `bond_graph!` implements this trait for every model it generates; it can also be
/// implemented by hand. The derivative and output functions are generic over the scalar
/// type so that the same code is evaluated on `f64` and on dual numbers.
///
/// Slices passed to [`Model::derivatives`] and [`Model::outputs`] have exactly
/// [`Model::N_STATES`] and [`Model::N_OUTPUTS`] elements; the solvers guarantee it and an
/// implementation may panic otherwise.
pub trait Model {
    /// The model's parameters (for a generated model: a struct with one `f64` field per
    /// `param`, `Default` from the declared values).
    type Params: Clone + core::fmt::Debug + Default;

    /// The model's name as declared.
    const NAME: &'static str;
    /// State names in the order of the state vector, e.g. `"spring.q"`. Storage in
    /// derivative causality ([`Model::DEPENDENT_STORAGE`]) has no state.
    const STATE_NAMES: &'static [&'static str];
    /// Output names in the order of the output vector.
    const OUTPUT_NAMES: &'static [&'static str];
    /// Length of the state vector.
    const N_STATES: usize = Self::STATE_NAMES.len();
    /// Length of the output vector.
    const N_OUTPUTS: usize = Self::OUTPUT_NAMES.len();
    /// The states in the order of the state vector (one entry per number, named as in
    /// [`Model::STATE_NAMES`]), with their units and documentation; empty for a model
    /// that does not describe them.
    const STATES: &'static [SignalInfo] = &[];
    /// The outputs in the order of the output vector (one entry per number, named as in
    /// [`Model::OUTPUT_NAMES`]), with their units and documentation; empty for a model
    /// that does not describe them.
    const OUTPUTS: &'static [SignalInfo] = &[];
    /// The parameters in declaration order, with their units and documentation (empty
    /// for a model that does not describe them).
    const PARAMETERS: &'static [ParameterInfo] = &[];
    /// How many numbers the parameters hold in all: the sum of their
    /// [`ParameterInfo::len`].
    const N_PARAMETER_VALUES: usize = 0;

    /// Whether [`Model::derivatives`] and [`Model::outputs`] read every parameter and
    /// input through [`Scalar::parameter`] and [`Scalar::input`] and keep their tangents
    /// everywhere (in the parameter expressions the model computes once, too), so that
    /// a scalar type with [`Scalar::PARAMETER_TANGENTS`] gives exact derivatives with
    /// respect to them. `bond_graph!` says `true` unless a parameter expression calls
    /// something not generic over the scalar type (a user's `f64` function); the
    /// default `false` makes analyses fall back to finite differences and say so.
    const EXACT_PARAMETER_DERIVATIVES: bool = false;

    /// The parameters the model evaluates with.
    fn params(&self) -> &Self::Params;

    /// Writes every parameter's numbers into `out` (length
    /// [`Model::N_PARAMETER_VALUES`]) in the order of [`Model::PARAMETERS`]: vectors
    /// component by component, matrices row by row. For hosts that address parameters
    /// by index (an FMU's value references).
    fn parameter_values(&self, out: &mut [f64]) {
        let _ = out;
    }

    /// Sets every parameter from `values`, laid out as [`Model::parameter_values`]
    /// writes them.
    fn set_parameter_values(&mut self, values: &[f64]) {
        let _ = values;
    }

    /// Writes the declared initial conditions (which may depend on the parameters) into
    /// `x0`.
    fn initial_state(&self, x0: &mut [f64]);

    /// Writes `dx/dt` at time `t` and state `x` into `dx`.
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]);

    /// Writes the outputs at time `t` and state `x` into `y`.
    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]);

    /// The structure of the Jacobian ∂(dx/dt)/∂x: for each state derivative (row), the
    /// states it can depend on, in increasing order. `None` means dense. Generated
    /// models give the exact structural pattern, which the stiff solver uses to
    /// compress Jacobian evaluation (columns that share no row are evaluated together).
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = None;

    /// A hand-written Jacobian ∂(dx/dt)/∂x at `(t, x)`, written row-major into `jac`
    /// (`jac[i * n + j]` = ∂ẋᵢ/∂xⱼ, every entry). Return `true` when written; the
    /// default returns `false`, and the solver then differentiates
    /// [`Model::derivatives`] exactly by forward-mode automatic differentiation.
    ///
    /// Dense storage costs `n²`: the stiff solvers look for this Jacobian (by calling it
    /// once at set-up) only in models of at most 512 states
    /// (`bgdsl_runtime::DENSE_HAND_WRITTEN_MAX`); larger models should write
    /// [`Model::jacobian_sparse`]. Without a declared pattern
    /// ([`Model::JACOBIAN_SPARSITY`]) the stiff solvers detect its non-zeros (at the
    /// initial state and two nearby states at set-up, then in every Jacobian of a run,
    /// growing the pattern if a new one appears) and factor it as sparse all the same.
    fn jacobian(&self, t: f64, x: &[f64], jac: &mut [f64]) -> bool {
        let _ = (t, x, jac);
        false
    }

    /// A hand-written Jacobian ∂(dx/dt)/∂x at `(t, x)`, sparse: the values of the
    /// entries of the declared pattern ([`Model::JACOBIAN_SPARSITY`], which it needs)
    /// in its order, row by row (`values[k]` is the `k`-th entry of the rows laid end to
    /// end). Return `true` when written; the default returns `false`.
    ///
    /// The stiff solvers prefer it to [`Model::jacobian`]: it needs no `n × n`
    /// storage, so a large model's Jacobian costs memory and time linear in its
    /// non-zeros.
    fn jacobian_sparse(&self, t: f64, x: &[f64], values: &mut [f64]) -> bool {
        let _ = (t, x, values);
        false
    }

    /// The solver a run uses when the caller names none. Bond-graph models of mechanisms
    /// are stiff by construction (stiff compliant joints stand in for constraints), so
    /// the default is Radau IIA of order 5 ([`Solver::stiff`](crate::Solver::stiff)),
    /// which is also correct, if not the cheapest, on non-stiff models: among the stiff
    /// methods it was the fastest at equal accuracy on models of every size measured
    /// (4 to 10,000 states), except small ones at loose tolerances (`docs/solvers.md`).
    /// A model that knows better overrides this. (Only with the `std` feature, which
    /// the solvers it names need.)
    #[cfg(feature = "std")]
    fn default_solver(&self) -> crate::solver::Solver {
        crate::solver::Solver::stiff()
    }

    /// The model's energy account at `(t, x)`, from its bond graph: the energy in its
    /// storage elements, the power its sources deliver and the power its resistors
    /// dissipate. For a generated model `d(stored)/dt = input − dissipated` holds
    /// exactly; `None` for models that do not say.
    fn power_balance<T: Scalar>(&self, t: f64, x: &[T]) -> Option<PowerBalance<T>> {
        let _ = (t, x);
        None
    }

    /// The causal bond graph the model was generated from, if it has one.
    fn causal_graph(&self) -> Option<&'static CausalGraph> {
        None
    }

    /// Checks what the compiler could not: for a generated model, that each inverse a
    /// two-port's law gives (`MTF frame = M, inverse = X;`) is the inverse of its
    /// modulus at `(t, x)`, to [`ModelError::INVERSE_TOLERANCE`]. A run checks its
    /// starting point ([`Simulation`](crate::Simulation), hence the `models` program
    /// and each [`Stepper`](crate::Stepper) advance; an FMU on leaving
    /// initialisation); a debug build also checks each inverse the equations compute
    /// with at every evaluation of the derivatives in `f64`, and panics there. The
    /// default accepts everything.
    ///
    /// # Errors
    ///
    /// The first two-port whose inverse is wrong, with the residual ‖M X − I‖.
    fn check(&self, t: f64, x: &[f64]) -> Result<(), ModelError> {
        let _ = (t, x);
        Ok(())
    }

    /// The storage elements in derivative causality (`#[allow(derivative_causality)]`),
    /// by name: they hold no state (they are not in [`Model::STATE_NAMES`]); their
    /// co-energy variable follows from the independent states through the junction
    /// structure, and their effort (or flow) is its time derivative along the motion.
    /// Empty for a model without any.
    const DEPENDENT_STORAGE: &'static [&'static str] = &[];

    /// The algebraic loops the model solves at each evaluation
    /// (`#[allow(algebraic_loops)]`), each as the names of the elements on it. Empty for
    /// a model without any.
    const ALGEBRAIC_LOOPS: &'static [&'static [&'static str]] = &[];

    /// Why the last evaluation failed, if it did: a model that solves implicit
    /// unknowns at each evaluation (an algebraic loop, the constraints of dependent
    /// storage) writes NaN into the derivatives (or outputs) when the solve fails, and
    /// says why here: [`ModelError::UnsolvedLoop`] or
    /// [`ModelError::SingularConstraint`], with the elements, the time and the
    /// residual. The solvers ask this when they meet a non-finite derivative and end
    /// the run with [`SolverError::InvalidModel`](crate::SolverError::InvalidModel)
    /// carrying it, rather than a step-size underflow; an FMU returns `fmi2Error` with
    /// its text. A later evaluation whose solve succeeds forgets the failure. The
    /// default (a model whose evaluations cannot fail this way) is `None`.
    fn evaluation_error(&self) -> Option<ModelError> {
        None
    }

    /// The model's events, in the order simultaneous ones are handled (see
    /// [`crate::event`]). Empty for a model without any.
    const EVENTS: &'static [EventInfo] = &[];

    /// The rigid bodies whose pose the state holds, in declaration order: for a generated
    /// model, one per instance of the standard library's `RigidBody` (a model's own
    /// `submodel RigidBody` shadows it and gives none). Empty for a model without any.
    /// An animation reads each body's orientation and position from the state.
    const BODIES: &'static [BodyInfo] = &[];

    /// The discrete modes, in declaration order: the last `MODES.len()` entries of the
    /// state vector, whose derivatives are exactly 0 (so every integrator holds them
    /// constant between events; only [`Model::apply_event`] changes them).
    const MODES: &'static [ModeInfo] = &[];

    /// Writes `g_i(t, x)` for every event `i` into `g` (length `EVENTS.len()`): event `i`
    /// fires when `g_i` crosses zero in [`EventInfo::direction`]. The default (no
    /// events) writes nothing.
    fn event_indicators(&self, t: f64, x: &[f64], g: &mut [f64]) {
        let _ = (t, x, g);
    }

    /// Applies event `index`'s action at time `t` to `x`: the state just before the
    /// event, rewritten in place to the state after it (reinit of states, switch of
    /// modes). Every right-hand side reads the values before the event (simultaneous
    /// assignment). Returns whether the run goes on or stops there.
    fn apply_event(&self, index: usize, t: f64, x: &mut [f64]) -> EventAction {
        let _ = (index, t, x);
        EventAction::Continue
    }
}

/// What [`Model::check`] finds wrong with a model at a state.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ModelError {
    /// A two-port's law gives an inverse of its modulus that is not one:
    /// ‖M X − I‖ (Frobenius norm) exceeds [`ModelError::INVERSE_TOLERANCE`].
    WrongInverse {
        /// The element, as the model names it (`joint.to_frame`).
        element: &'static str,
        /// The time of the state checked.
        t: f64,
        /// ‖M X − I‖.
        residual: f64,
    },
    /// The implicit unknowns of an algebraic loop (`#[allow(algebraic_loops)]`) could
    /// not be solved: Newton's method did not converge from the previous solution, or
    /// the loop's equations gave a non-finite value.
    UnsolvedLoop {
        /// The elements on the loop, comma-separated, as the model names them
        /// (`d1, d2, j`).
        members: &'static str,
        /// The time of the evaluation.
        t: f64,
        /// The residual of the worst-converged unknown (NaN or infinite when the
        /// equations gave a non-finite value).
        residual: f64,
    },
    /// The constraints of dependent storage (`#[allow(derivative_causality)]`) or of an
    /// algebraic loop are singular: the Jacobian of their residual has no inverse, so
    /// the unknowns are not determined (a redundant constraint, or a mechanism at a
    /// dead point where its mass matrix is singular).
    SingularConstraint {
        /// The elements constrained, comma-separated, as the model names them
        /// (`mass2, rod`).
        members: &'static str,
        /// The time of the evaluation.
        t: f64,
    },
}

impl ModelError {
    /// The largest ‖M X − I‖ accepted. A wrong inverse is off by order one (by about
    /// 1.4 times the angle between two rotations taken for each other); an inverse
    /// that is exact only on the states a model reaches (the transpose of a rotation
    /// matrix held in a state) is off by how far a state strays from them: the
    /// integration error (measured up to 3.4e-4 in a run of the flagship made to
    /// fail), a finite-difference step (about 1e-5 of the state's scale), below this.
    pub const INVERSE_TOLERANCE: f64 = 1e-3;
}

impl core::fmt::Display for ModelError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ModelError::WrongInverse {
                element,
                t,
                residual,
            } => write!(
                f,
                "at t = {t}, the inverse given for the modulus of `{element}` is not its \
                 inverse: ‖M X − I‖ = {residual:e} (at most {:e} accepted); correct the \
                 `inverse = ...` of its law",
                ModelError::INVERSE_TOLERANCE
            ),
            ModelError::UnsolvedLoop {
                members,
                t,
                residual,
            } if !residual.is_finite() => write!(
                f,
                "at t = {t} s, the algebraic loop through {members} evaluated to \
                 {residual}: its equations are undefined at the state reached (a law \
                 out of its domain, e.g. exp overflowing, or a division by zero)"
            ),
            ModelError::UnsolvedLoop {
                members,
                t,
                residual,
            } => write!(
                f,
                "the algebraic loop through {members} did not converge at t = {t} s \
                 (residual {residual:.1e}): Newton's method from the previous solution \
                 failed; the loop's laws may have several solutions or none there, or \
                 change too fast (a step discontinuity); smoothen the laws, or break the \
                 loop with a small storage element"
            ),
            ModelError::SingularConstraint { members, t } => write!(
                f,
                "the constraints on {members} are singular at t = {t} s: a redundant \
                 constraint or a dead-point configuration (the mass matrix is singular); \
                 remove the redundant constraint, or make one joint compliant (a stiff C) \
                 so that the constraint can be violated slightly"
            ),
        }
    }
}

impl core::error::Error for ModelError {}

/// What a model says about one of its parameters (see [`Model::PARAMETERS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParameterInfo {
    /// The name, as the parameter struct's field and in scenario files.
    pub name: &'static str,
    /// The unit as declared (`param m = 1.0 in "kg";`), empty when none was.
    pub unit: &'static str,
    /// The parameter's doc comment, empty when it has none.
    pub doc: &'static str,
    /// How many numbers it holds: 1 for a scalar, 3 for `[f64; 3]`, 9 for a 3×3 matrix.
    pub len: usize,
}

/// What a model says about one number of its state or output vector (see
/// [`Model::STATES`] and [`Model::OUTPUTS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SignalInfo {
    /// The name, as in [`Model::STATE_NAMES`] or [`Model::OUTPUT_NAMES`]: `spring.q`,
    /// `F_x`.
    pub name: &'static str,
    /// The unit as declared (`output x = spring.q in "m";`, `C spring = k, q in "m";`),
    /// empty when the model does not say; never a guess.
    pub unit: &'static str,
    /// Its documentation (the doc comment of the output, of the `state`, or of the
    /// element whose state it is), empty when there is none.
    pub doc: &'static str,
}

/// Where a rigid body's pose lies in a model's state vector (see [`Model::BODIES`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BodyInfo {
    /// The body's name: the instance's path as the model's names show it, `crank`, or
    /// `arm.upper` for a body inside an instance `arm`.
    pub name: &'static str,
    /// The state index of its orientation's `R_11`: the rotation matrix (body frame to
    /// frame 0) is the 9 states from there, column by column (`R_11, R_21, R_31, R_12,
    /// …`), as [`Model::STATE_NAMES`] lists them.
    pub orientation: usize,
    /// The state index of its centre of mass's `r_x` in frame 0: `r_x, r_y, r_z` from
    /// there, in metres.
    pub position: usize,
}

impl BodyInfo {
    /// The body's orientation at state `x`, column-major (`R_11, R_21, R_31, R_12, …`).
    pub fn orientation_of(&self, x: &[f64]) -> [f64; 9] {
        let mut r = [0.0; 9];
        r.copy_from_slice(&x[self.orientation..self.orientation + 9]);
        r
    }

    /// The body's centre of mass at state `x`, in frame 0.
    pub fn position_of(&self, x: &[f64]) -> [f64; 3] {
        [x[self.position], x[self.position + 1], x[self.position + 2]]
    }
}

/// The unit of entry `index` of `infos`, empty when the model does not describe it: the
/// lookup every consumer of [`Model::STATES`] and [`Model::OUTPUTS`] does.
pub fn unit_of(infos: &[SignalInfo], index: usize) -> &'static str {
    infos.get(index).map_or("", |info| info.unit)
}

/// What a model says about one of its inputs (see [`WithInputs::INPUTS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputInfo {
    /// The name, as the inputs struct's field.
    pub name: &'static str,
    /// The unit as declared (`input torque = 0.0 in "N·m";`), empty when none was.
    pub unit: &'static str,
    /// The input's doc comment, empty when it has none.
    pub doc: &'static str,
}

/// A model whose laws read inputs that the host sets between steps: a voltage from a
/// controller, a measured load. Every model `bond_graph!` generates implements it (with
/// an empty inputs struct when it declares no `input`).
///
/// The inputs are a field of the model: a host that owns the model (or a
/// [`Stepper`](crate::Stepper), which owns it) sets them between calls that integrate,
/// and a solver sees them constant within each call.
pub trait WithInputs: Model {
    /// The inputs, one `f64` field per declared `input`.
    type Inputs: Copy + core::fmt::Debug + Default + PartialEq;
    /// The inputs in declaration order, with units and documentation.
    const INPUTS: &'static [InputInfo];
    /// The inputs now.
    fn inputs(&self) -> Self::Inputs;
    /// Sets the inputs.
    fn set_inputs(&mut self, inputs: Self::Inputs);
    /// Writes the inputs into `out` (one per [`WithInputs::INPUTS`] entry).
    fn input_values(&self, out: &mut [f64]);
    /// Sets the inputs from `values` (one per [`WithInputs::INPUTS`] entry).
    fn set_input_values(&mut self, values: &[f64]);
}

/// A model's energy account at one instant (see [`Model::power_balance`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerBalance<T> {
    /// Energy held by the storage elements (C and I), J: each element's law integrated
    /// from zero to its state.
    pub stored: T,
    /// Power delivered by the sources (Se, Sf), W; negative where a source absorbs.
    pub input: T,
    /// Power dissipated by the resistors (R), W.
    pub dissipated: T,
}

/// A model made from its parameter struct alone, so that a program can build any model
/// of a list from parameters it read (a scenario file, a command line).
///
/// `bond_graph!` implements it for every model it generates (as its `new`); a
/// hand-written model implements it itself.
pub trait FromParams: Model {
    /// The model with these parameters.
    fn from_params(params: Self::Params) -> Self;
}
