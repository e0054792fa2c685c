//! The FMU's variables and their value references.
//!
//! Every variable is an FMI `Real`. They are numbered in consecutive blocks, and a
//! variable's value reference is its position in that list, counted from 0 (so its
//! `ScalarVariable` index in `modelDescription.xml`, counted from 1, is its value
//! reference plus one):
//!
//! | block | name | causality | variability |
//! |---|---|---|---|
//! | states | `spring.q` | `local` (initial `exact`, settable before initialisation ends) | `continuous` |
//! | modes, the last states | `stuck` | `local` (initial `exact`, settable before initialisation ends) | `discrete` |
//! | state derivatives (not of the modes) | `der(spring.q)` | `local` | `continuous` |
//! | outputs | `x` | `output` | `continuous` |
//! | parameters, flattened | `k`, `l1[1]`, `l1[2]`, `l1[3]` | `parameter` | `tunable` |
//! | inputs | `torque` | `input` (with a start value) | `continuous` |
//!
//! Every variable carries the unit and description the model declares
//! ([`Model::STATES`](bgdsl_runtime::Model::STATES), `OUTPUTS`, `PARAMETERS`, `INPUTS`);
//! a state derivative's unit is its state's per second (`m/s` for `m`).
//!
//! A discrete mode ([`Model::MODES`](bgdsl_runtime::Model::MODES)) is a state of the
//! model whose derivative is exactly 0; the FMU declares it as the discrete variable it
//! is (`variability="discrete"`, no derivative), keeps it, and changes it only in an
//! event's action. So Model Exchange's continuous states, the `nx` of
//! `fmi2GetContinuousStates` and `fmi2GetDerivatives`, are the states less the modes:
//! the importer never integrates a mode, and its integrator's finite-difference
//! Jacobian never perturbs one (a bool mode nudged from 0 would read as true). A mode is
//! a `Real` like every variable: 0 or 1 for a bool, an integer value for an `i64`.
//!
//! A state's start value is the model's initial state at the default parameters. An
//! importer may set it (`fmi2SetReal` in Instantiated or Initialization Mode, as
//! `initial="exact"` allows); a state it does not set starts where the model's declared
//! initial conditions put it for the parameters as set (so a changed geometry still
//! assembles).
//!
//! A parameter of several numbers (`param l1: [f64; 3]`) becomes one variable per
//! number, indexed from 1 as the structured naming convention has it (`l1[1]` is
//! `l1[0]` in Rust); a matrix is numbered row by row, the order of
//! [`Model::parameter_values`](bgdsl_runtime::Model::parameter_values).

use bgdsl_runtime::WithInputs;

use crate::fmi2::ValueReference;
use crate::model::Sizes;

/// What a variable is to the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// The `i`-th state.
    State(usize),
    /// The derivative of the `i`-th state.
    Derivative(usize),
    /// The `i`-th output.
    Output(usize),
    /// The `i`-th parameter value (flattened).
    Parameter(usize),
    /// The `i`-th input.
    Input(usize),
}

impl Role {
    /// The kind of variable, for messages: "state", "output", ...
    pub fn kind(self) -> &'static str {
        match self {
            Role::State(_) => "state",
            Role::Derivative(_) => "state derivative",
            Role::Output(_) => "output",
            Role::Parameter(_) => "parameter",
            Role::Input(_) => "input",
        }
    }
}

/// One FMI variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    /// Its name in `modelDescription.xml`.
    pub name: String,
    /// Its value reference (also its position in [`Variables::all`]).
    pub value_reference: ValueReference,
    /// What it is.
    pub role: Role,
    /// Its unit as declared, empty when none was (a state derivative's: its state's
    /// unit per second, `m/s` for `m`).
    pub unit: String,
    /// Its description (a parameter's or input's doc comment), possibly empty.
    pub description: String,
    /// Its start value: the default of a parameter or input, the initial state (at the
    /// default parameters) of a state; `None` for the rest, which the FMU calculates.
    pub start: Option<f64>,
}

/// The variables of one model, in value-reference order.
#[derive(Clone, Debug, PartialEq)]
pub struct Variables {
    sizes: Sizes,
    all: Vec<Variable>,
}

impl Variables {
    /// The variables of model `M`, its default parameter and input values as start
    /// values.
    pub fn of<M: WithInputs + Default>() -> Self {
        let sizes = Sizes::of::<M>();
        let defaults = M::default();
        let mut parameter_starts = vec![0.0; sizes.parameters];
        defaults.parameter_values(&mut parameter_starts);
        let mut input_starts = vec![0.0; sizes.inputs];
        defaults.input_values(&mut input_starts);
        let mut state_starts = vec![0.0; sizes.states];
        defaults.initial_state(&mut state_starts);

        let mut all = Vec::new();
        let mut push = |name: String, role, unit, description: &str, start| {
            all.push(Variable {
                name,
                value_reference: 0, // numbered below
                role,
                unit,
                description: description.trim().to_string(),
                start,
            })
        };
        // Units and descriptions as the model declares them (`Model::STATES`,
        // `Model::OUTPUTS`); a derivative's unit is its state's per second.
        let described = |infos: &'static [bgdsl_runtime::SignalInfo], i: usize| {
            infos.get(i).map_or(("", ""), |info| (info.unit, info.doc))
        };
        let continuous = sizes.continuous();
        for (i, name) in M::STATE_NAMES.iter().enumerate() {
            let (unit, doc) = described(M::STATES, i);
            let doc = match i.checked_sub(continuous).and_then(|m| M::MODES.get(m)) {
                Some(mode) => mode_description(mode),
                None => doc.to_string(),
            };
            push(
                name.to_string(),
                Role::State(i),
                unit.to_string(),
                &doc,
                Some(state_starts[i]),
            );
        }
        for (i, name) in M::STATE_NAMES.iter().enumerate().take(continuous) {
            let (unit, _) = described(M::STATES, i);
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!("{unit}/s")
            };
            let doc = format!("time derivative of {name}");
            push(
                format!("der({name})"),
                Role::Derivative(i),
                unit,
                &doc,
                None,
            );
        }
        for (i, name) in M::OUTPUT_NAMES.iter().enumerate() {
            let (unit, doc) = described(M::OUTPUTS, i);
            push(
                name.to_string(),
                Role::Output(i),
                unit.to_string(),
                doc,
                None,
            );
        }
        let described: usize = M::PARAMETERS.iter().map(|info| info.len).sum();
        if described == sizes.parameters {
            let mut flat = 0;
            for info in M::PARAMETERS {
                for k in 0..info.len {
                    let name = if info.len == 1 {
                        info.name.to_string()
                    } else {
                        format!("{}[{}]", info.name, k + 1)
                    };
                    let start = parameter_starts[flat];
                    push(
                        name,
                        Role::Parameter(flat),
                        info.unit.to_string(),
                        info.doc,
                        Some(start),
                    );
                    flat += 1;
                }
            }
        } else {
            // A hand-written model whose `PARAMETERS` do not describe its values:
            // number them.
            for (i, start) in parameter_starts.iter().enumerate() {
                let name = format!("parameter[{}]", i + 1);
                push(name, Role::Parameter(i), String::new(), "", Some(*start));
            }
        }
        for (i, info) in M::INPUTS.iter().enumerate() {
            let start = input_starts[i];
            push(
                info.name.to_string(),
                Role::Input(i),
                info.unit.to_string(),
                info.doc,
                Some(start),
            );
        }
        make_names_unique(&mut all);
        for (i, variable) in all.iter_mut().enumerate() {
            variable.value_reference = i as ValueReference;
        }
        Variables { sizes, all }
    }

    /// How many numbers of each kind the model has.
    pub fn sizes(&self) -> Sizes {
        self.sizes
    }

    /// Every variable, in value-reference order.
    pub fn all(&self) -> &[Variable] {
        &self.all
    }

    /// The variable with value reference `vr`, if there is one.
    pub fn get(&self, vr: ValueReference) -> Option<&Variable> {
        self.all.get(usize::try_from(vr).ok()?)
    }

    /// The variable called `name`, if there is one.
    pub fn find(&self, name: &str) -> Option<&Variable> {
        self.all.iter().find(|v| v.name == name)
    }

    /// The value reference of a role.
    pub fn value_reference(&self, role: Role) -> ValueReference {
        let s = self.sizes;
        let position = match role {
            Role::State(i) => i,
            Role::Derivative(i) => s.states + i,
            Role::Output(i) => s.states + s.continuous() + i,
            Role::Parameter(i) => s.states + s.continuous() + s.outputs + i,
            Role::Input(i) => s.states + s.continuous() + s.outputs + s.parameters + i,
        };
        position as ValueReference
    }
}

/// The role of value reference `vr` in a model of these sizes, `None` for a value
/// reference that names no variable. The instance uses this on every `fmi2GetReal`, so
/// it is arithmetic, not a lookup.
pub fn role_of(sizes: Sizes, vr: ValueReference) -> Option<Role> {
    let at = usize::try_from(vr).ok()?;
    let derivatives = sizes.states;
    let outputs = derivatives + sizes.continuous();
    let parameters = outputs + sizes.outputs;
    let inputs = parameters + sizes.parameters;
    let end = inputs + sizes.inputs;
    Some(if at < derivatives {
        Role::State(at)
    } else if at < outputs {
        Role::Derivative(at - derivatives)
    } else if at < parameters {
        Role::Output(at - outputs)
    } else if at < inputs {
        Role::Parameter(at - parameters)
    } else if at < end {
        Role::Input(at - inputs)
    } else {
        return None;
    })
}

/// A mode's description: its doc comment and what its value means.
fn mode_description(mode: &bgdsl_runtime::ModeInfo) -> String {
    let kind = match mode.kind {
        bgdsl_runtime::ModeKind::Bool => "discrete mode, bool: 0 false, 1 true",
        bgdsl_runtime::ModeKind::Integer => "discrete mode, an integer",
        bgdsl_runtime::ModeKind::Real => "discrete mode",
    };
    let doc = mode.doc.trim();
    if doc.is_empty() {
        format!("({kind})")
    } else {
        format!("{doc} ({kind})")
    }
}

/// Gives a name that an earlier variable already has a suffix `_2`, `_3`, ... (the
/// first that is free), so that every name is unique as FMI requires. Generated models
/// keep parameters, states and outputs apart, so this is a guard, not a feature.
fn make_names_unique(all: &mut [Variable]) {
    let mut seen = std::collections::BTreeSet::new();
    for variable in all.iter_mut() {
        if !seen.contains(&variable.name) {
            seen.insert(variable.name.clone());
            continue;
        }
        let mut n = 2;
        while seen.contains(&format!("{}_{n}", variable.name)) {
            n += 1;
        }
        variable.name = format!("{}_{n}", variable.name);
        seen.insert(variable.name.clone());
    }
}

/// Whether `name` follows FMI 2.0's structured naming convention (section 2.2.9):
/// identifiers of letters, digits and `_` not starting with a digit, joined by `.`,
/// each optionally followed by `[i,j,...]`; or `der(name)`. Quoted names (`'a b'`) are
/// not produced here and so not accepted.
pub fn is_structured_name(name: &str) -> bool {
    let inner = match name.strip_prefix("der(").and_then(|r| r.strip_suffix(')')) {
        Some(inner) => inner,
        None => name,
    };
    !inner.is_empty() && inner.split('.').all(is_indexed_identifier)
}

fn is_indexed_identifier(part: &str) -> bool {
    let (base, indices) = match part.find('[') {
        Some(at) => (&part[..at], Some(&part[at..])),
        None => (part, None),
    };
    let mut chars = base.chars();
    let starts_well = matches!(chars.next(), Some(c) if c == '_' || c.is_ascii_alphabetic());
    let rest_well = chars.all(|c| c == '_' || c.is_ascii_alphanumeric());
    let indices_well = match indices {
        None => true,
        Some(text) => text
            .strip_prefix('[')
            .and_then(|t| t.strip_suffix(']'))
            .is_some_and(|list| {
                list.split(',')
                    .all(|i| !i.is_empty() && i.chars().all(|c| c.is_ascii_digit()))
            }),
    };
    starts_well && rest_well && indices_well
}

#[cfg(test)]
mod should {
    use super::*;

    #[test]
    fn number_the_blocks_one_after_another() {
        let sizes = Sizes {
            states: 2,
            outputs: 3,
            parameters: 4,
            inputs: 1,
            ..Sizes::default()
        };
        let roles: Vec<_> = (0..12).map(|vr| role_of(sizes, vr)).collect();
        assert_eq!(roles[0], Some(Role::State(0)));
        assert_eq!(roles[3], Some(Role::Derivative(1)));
        assert_eq!(roles[4], Some(Role::Output(0)));
        assert_eq!(roles[7], Some(Role::Parameter(0)));
        assert_eq!(roles[10], Some(Role::Parameter(3)));
        assert_eq!(roles[11], Some(Role::Input(0)));
        assert_eq!(role_of(sizes, 12), None);
        assert_eq!(role_of(sizes, u32::MAX), None);
    }

    #[test]
    fn give_no_derivative_to_a_mode() {
        // Three states, the last a mode: derivatives of the first two only.
        let sizes = Sizes {
            states: 3,
            modes: 1,
            outputs: 1,
            ..Sizes::default()
        };
        let roles: Vec<_> = (0..6).map(|vr| role_of(sizes, vr)).collect();
        assert_eq!(roles[2], Some(Role::State(2)));
        assert_eq!(roles[3], Some(Role::Derivative(0)));
        assert_eq!(roles[4], Some(Role::Derivative(1)));
        assert_eq!(roles[5], Some(Role::Output(0)));
        assert_eq!(role_of(sizes, 6), None);
    }

    #[test]
    fn accept_the_names_bond_graph_models_have() {
        for name in [
            "spring.q",
            "der(spring.q)",
            "l1[3]",
            "crank.R_11",
            "_x",
            "a.b[1,2].c",
        ] {
            assert!(is_structured_name(name), "{name}");
        }
    }

    #[test]
    fn reject_names_outside_the_structured_convention() {
        for name in ["", "1x", "a..b", "a[]", "a[x]", "der(x", "a b", "x.", "ü"] {
            assert!(!is_structured_name(name), "{name}");
        }
    }

    #[test]
    fn suffix_a_repeated_name() {
        let variable = |name: &str| Variable {
            name: name.to_string(),
            value_reference: 0,
            role: Role::Output(0),
            unit: String::new(),
            description: String::new(),
            start: None,
        };
        let mut all = vec![variable("x"), variable("x_2"), variable("x"), variable("x")];
        make_names_unique(&mut all);
        let names: Vec<_> = all.iter().map(|v| v.name.as_str()).collect();
        assert_eq!(names, ["x", "x_2", "x_3", "x_4"]);
    }
}
