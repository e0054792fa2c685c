//! Events and modes (stages 2 and 4): a `mode` is a discrete state, stored after the
//! continuous states with derivative exactly 0; a `when` block is an event, fired when
//! its condition's indicator g = lhs − rhs (or `crossing(g)`) crosses zero, whose
//! actions rewrite states and modes. Here they are resolved (names, what may be
//! assigned) and rewritten for code generation ([`crate::event_code`]).

use std::collections::BTreeSet;

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{Expr, Ident};

use crate::errors::Errors;
use crate::event_syntax::{ActionSyntax, WhenDecl};
use crate::ir::{ElementId, ElementKind, Graph, Shape};
use crate::rewrite::{rewrite, Scope};

pub use crate::event_syntax::ModeKind;

/// A discrete mode.
pub struct Mode {
    /// Its name.
    pub name: Ident,
    /// Its value type.
    pub kind: ModeKind,
    /// The initial value, an expression in parameters.
    pub init: Expr,
    /// Its doc comment, if any.
    pub doc: Option<String>,
}

/// Which way an indicator must cross zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// `a > b`: g = a − b rises through zero.
    Rising,
    /// `a < b`: g = a − b falls through zero.
    Falling,
    /// `crossing(g)`: either way.
    Both,
}

/// A `when` block, resolved.
pub struct Event {
    /// Its name (a label, or `when_k`).
    pub name: Ident,
    /// Its doc comment ("" without one).
    pub doc: String,
    /// The direction its indicator fires in.
    pub direction: Direction,
    /// The indicator's left side (or `crossing`'s argument).
    pub lhs: Expr,
    /// The right side of a comparison.
    pub rhs: Option<Expr>,
    /// The actions.
    pub actions: Vec<Action>,
}

/// One action, resolved.
pub enum Action {
    /// `reinit target = value;`
    Reinit {
        /// The state.
        target: Target,
        /// The new value.
        value: Expr,
    },
    /// `mode = value;`
    Switch {
        /// The mode's index in [`Graph::modes`].
        mode: usize,
        /// The new value.
        value: Expr,
    },
    /// `stop;`
    Stop,
    /// `if cond { then } else { otherwise }`
    If {
        /// The condition.
        cond: Expr,
        /// Actions when it holds.
        then: Vec<Action>,
        /// Actions otherwise.
        otherwise: Vec<Action>,
    },
}

/// What a `reinit` writes.
pub enum Target {
    /// A C's `q` or an I's `p`; where it is named.
    Storage(ElementId, Span),
    /// A kinematic state (index in [`Graph::kinematics`]).
    Kinematic(usize),
}

/// Resolves the `when` blocks of a model whose declarations are known (modes among
/// them), reporting what an action cannot assign and conditions that are not
/// comparisons.
pub fn resolve(graph: &mut Graph, whens: Vec<WhenDecl>, errors: &mut Errors) {
    let mut unknown_assignment = false;
    for (k, when) in whens.into_iter().enumerate() {
        let name = when
            .label
            .clone()
            .unwrap_or_else(|| Ident::new(&format!("when_{}", k + 1), when.span));
        let doc = crate::codegen::doc_text(&when.attrs).unwrap_or_default();
        if when.actions.is_empty() {
            errors.at(
                when.body,
                format!(
                    "event `{}` has no action: a `when` does something when it fires\n\
                     help: give it an action (`reinit ball.p = ..;`, `mode = ..;`, `stop;`) or remove it",
                    crate::flatten::display(&name.to_string())
                ),
            );
        }
        let actions = actions(graph, when.actions, errors, &mut unknown_assignment);
        let Some((direction, lhs, rhs)) = condition(when.condition, errors) else {
            continue;
        };
        graph.events.push(Event {
            name,
            doc,
            direction,
            lhs,
            rhs,
            actions,
        });
    }
    // An assignment that named no mode was reported; "never switched" would follow it.
    if !unknown_assignment {
        check_modes_switched(graph, errors);
    }
}

/// A condition's direction and sides, or an error at it.
fn condition(expr: Expr, errors: &mut Errors) -> Option<(Direction, Expr, Option<Expr>)> {
    use syn::BinOp::*;
    match expr {
        Expr::Paren(inner) => condition(*inner.expr, errors),
        Expr::Binary(binary) => {
            let direction = match binary.op {
                Lt(_) | Le(_) => Direction::Falling,
                Gt(_) | Ge(_) => Direction::Rising,
                Eq(_) | Ne(_) => {
                    errors.at(
                        binary.op.span(),
                        "an event fires when a value crosses a level, and real numbers are \
                         almost never exactly equal: `==` and `!=` are no conditions\n\
                         help: write `x > level` (rising), `x < level` (falling) or \
                         `crossing(x - level)` (either way)",
                    );
                    return None;
                }
                And(_) | Or(_) => {
                    errors.at(
                        binary.op.span(),
                        "a `when` condition is one comparison: `&&` and `||` combine none\n\
                         help: fire on one comparison and test the other with `if` in the actions",
                    );
                    return None;
                }
                _ => return not_a_comparison(&Expr::Binary(binary), errors),
            };
            Some((direction, *binary.left, Some(*binary.right)))
        }
        Expr::Call(call) if matches!(&*call.func, Expr::Path(p) if p.path.is_ident("crossing")) => {
            if call.args.len() != 1 {
                errors.at(
                    call.span(),
                    "`crossing` takes one value: `crossing(x)` fires when x crosses zero either way",
                );
                return None;
            }
            let arg = call.args.into_iter().next()?;
            Some((Direction::Both, arg, None))
        }
        other => not_a_comparison(&other, errors),
    }
}

fn not_a_comparison<T>(expr: &Expr, errors: &mut Errors) -> Option<T> {
    errors.at(
        expr.span(),
        "a `when` condition is a comparison or a crossing: `a < b` fires when a − b falls \
         through zero, `a > b` when it rises through zero, `crossing(x)` when x crosses zero \
         either way",
    );
    None
}

/// The actions resolved; `unknown` is set when an assignment names no mode.
fn actions(
    graph: &Graph,
    written: Vec<ActionSyntax>,
    errors: &mut Errors,
    unknown: &mut bool,
) -> Vec<Action> {
    written
        .into_iter()
        .filter_map(|action| match action {
            ActionSyntax::Reinit {
                target,
                member,
                value,
            } => reinit_target(graph, &target, member.as_ref(), errors)
                .map(|target| Action::Reinit { target, value }),
            ActionSyntax::Assign { target, value } => {
                let mode = switched_mode(graph, &target, errors);
                *unknown |= mode.is_none();
                mode.map(|mode| Action::Switch { mode, value })
            }
            ActionSyntax::Stop => Some(Action::Stop),
            ActionSyntax::If {
                cond,
                then,
                otherwise,
            } => Some(Action::If {
                cond,
                then: actions(graph, then, errors, unknown),
                otherwise: actions(graph, otherwise, errors, unknown),
            }),
        })
        .collect()
}

const STATES: &str = "a C's `q`, an I's `p` or a kinematic `state`";

fn reinit_target(
    graph: &Graph,
    target: &Ident,
    member: Option<&Ident>,
    errors: &mut Errors,
) -> Option<Target> {
    let shown = crate::flatten::display(&target.to_string());
    let element = graph
        .element_ids()
        .find(|&id| graph.element(id).name == *target);
    let message = match (element, member) {
        (Some(id), Some(member)) => {
            let kind = graph.element(id).kind;
            let state = match kind {
                ElementKind::C => Some("q"),
                ElementKind::I => Some("p"),
                _ => None,
            };
            match state {
                Some(state) if member == state => return Some(Target::Storage(id, target.span())),
                Some(state) => format!(
                    "`{shown}.{member}` is not a state: it is computed from the states at every \
                     instant, and `reinit` changes a state\nhelp: reinit the state of {}, \
                     `{shown}.{state}`",
                    graph.describe(id)
                ),
                None => format!(
                    "{} has no state: `reinit` changes {STATES}",
                    graph.describe(id)
                ),
            }
        }
        (Some(id), None) => {
            let state = match graph.element(id).kind {
                ElementKind::C => "q",
                ElementKind::I => "p",
                _ => {
                    let message = format!(
                        "{} has no state: `reinit` changes {STATES}",
                        graph.describe(id)
                    );
                    errors.at(target.span(), message);
                    return None;
                }
            };
            format!(
                "{} is an element, not a state: write `reinit {shown}.{state} = ..;`",
                graph.describe(id)
            )
        }
        (None, _) => {
            if let Some(k) = graph.kinematics.iter().position(|k| k.name == *target) {
                if member.is_none() {
                    return Some(Target::Kinematic(k));
                }
                format!("reinit the whole state `{shown}`: `reinit {shown} = ..;`")
            } else if graph.modes.iter().any(|m| m.name == *target) {
                format!(
                    "`{shown}` is a mode, not a state: assign a mode with `{shown} = ..;` (no `reinit`)"
                )
            } else if graph.params.iter().any(|p| p.name == *target) {
                format!(
                    "`{shown}` is a parameter, not a state: a parameter is fixed for a run, and \
                     `reinit` changes {STATES}\nhelp: to switch a value at events, declare it \
                     as a mode: `mode {shown}: f64 = ..;` and assign it with `{shown} = ..;`"
                )
            } else if graph.bonds.iter().any(|b| b.label.as_ref() == Some(target)) {
                format!("bond `{shown}` is no state: `reinit` changes {STATES}")
            } else {
                let mut known: Vec<String> = graph
                    .kinematics
                    .iter()
                    .map(|k| k.name.to_string())
                    .collect();
                known.extend(graph.element_ids().filter_map(|id| {
                    let e = graph.element(id);
                    matches!(e.kind, ElementKind::C | ElementKind::I).then(|| e.name.to_string())
                }));
                format!(
                    "unknown state `{shown}`: `reinit` changes {STATES}{}",
                    did_you_mean(target, &known)
                )
            }
        }
    };
    errors.at(target.span(), message);
    None
}

/// `\nhelp: did you mean `x`?` for a name one or two edits from `name`.
fn did_you_mean(name: &Ident, known: &[String]) -> String {
    let written = crate::flatten::display(&name.to_string());
    known
        .iter()
        .map(|k| crate::flatten::display(k))
        .map(|k| (crate::resolve::edit_distance(&written, &k), k))
        .filter(|(d, k)| *d <= 2.min(k.chars().count().saturating_sub(1).max(1)))
        .min()
        .map(|(_, k)| format!("\nhelp: did you mean `{k}`?"))
        .unwrap_or_default()
}

fn switched_mode(graph: &Graph, target: &Ident, errors: &mut Errors) -> Option<usize> {
    if let Some(m) = graph.modes.iter().position(|m| m.name == *target) {
        return Some(m);
    }
    let shown = crate::flatten::display(&target.to_string());
    let message = if graph.kinematics.iter().any(|k| k.name == *target) {
        format!("`{shown}` is a state, not a mode: write `reinit {shown} = ..;`")
    } else if graph.params.iter().any(|p| p.name == *target) {
        format!(
            "`{shown}` is a parameter, fixed for a run: an action assigns a mode\nhelp: to \
             switch it at events, declare it as a mode: `mode {shown}: f64 = ..;`"
        )
    } else {
        let known: Vec<String> = graph.modes.iter().map(|m| m.name.to_string()).collect();
        let list = if known.is_empty() {
            "the model has none: declare one with `mode name: bool = false;`".to_string()
        } else {
            format!(
                "the modes are: {}",
                known
                    .iter()
                    .map(|k| crate::flatten::display(k))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        format!(
            "unknown mode `{shown}`: `name = value;` in a `when` assigns a mode; {list}{}",
            did_you_mean(target, &known)
        )
    };
    errors.at(target.span(), message);
    None
}

/// A mode that laws read but no action switches is a parameter in disguise.
fn check_modes_switched(graph: &Graph, errors: &mut Errors) {
    let mut switched = BTreeSet::new();
    for event in &graph.events {
        collect_switched(&event.actions, &mut switched);
    }
    let mut read = BTreeSet::new();
    for expr in expressions(graph) {
        collect_names(expr, &mut read);
    }
    for (i, mode) in graph.modes.iter().enumerate() {
        if !switched.contains(&i) && read.contains(&mode.name.to_string()) {
            let shown = crate::flatten::display(&mode.name.to_string());
            errors.at(
                mode.name.span(),
                format!(
                    "mode `{shown}` is read but never switched: no `when` assigns it, so it \
                     keeps its initial value\nhelp: make it a parameter (`param {shown} = ..;`), \
                     or switch it in a `when` (`{shown} = ..;`)"
                ),
            );
        }
    }
}

fn collect_switched(actions: &[Action], switched: &mut BTreeSet<usize>) {
    for action in actions {
        match action {
            Action::Switch { mode, .. } => {
                switched.insert(*mode);
            }
            Action::If {
                then, otherwise, ..
            } => {
                collect_switched(then, switched);
                collect_switched(otherwise, switched);
            }
            Action::Reinit { .. } | Action::Stop => {}
        }
    }
}

/// Every expression of the model that runs during a simulation.
fn expressions(graph: &Graph) -> Vec<&Expr> {
    let mut all = Vec::new();
    for element in &graph.elements {
        match &element.law {
            crate::ir::Law::Linear(expr) => all.push(expr),
            crate::ir::Law::Forms { effort, flow } => all.extend(effort.iter().chain(flow)),
            crate::ir::Law::None => {}
        }
        all.extend(&element.inverse);
    }
    all.extend(graph.outputs.iter().map(|o| &o.expr));
    all.extend(graph.kinematics.iter().map(|k| &k.der));
    for event in &graph.events {
        all.push(&event.lhs);
        all.extend(&event.rhs);
        action_expressions(&event.actions, &mut all);
    }
    all
}

fn action_expressions<'a>(actions: &'a [Action], all: &mut Vec<&'a Expr>) {
    for action in actions {
        match action {
            Action::Reinit { value, .. } | Action::Switch { value, .. } => all.push(value),
            Action::If {
                cond,
                then,
                otherwise,
            } => {
                all.push(cond);
                action_expressions(then, all);
                action_expressions(otherwise, all);
            }
            Action::Stop => {}
        }
    }
}

fn collect_names(expr: &Expr, names: &mut BTreeSet<String>) {
    struct Names<'a>(&'a mut BTreeSet<String>);
    impl<'ast> syn::visit::Visit<'ast> for Names<'_> {
        fn visit_expr_path(&mut self, path: &'ast syn::ExprPath) {
            if let Some(ident) = path.path.get_ident() {
                self.0.insert(ident.to_string());
            }
        }
    }
    syn::visit::Visit::visit_expr(&mut Names(names), expr);
}

/// Checks the names the events' expressions use, with the model's other expressions.
pub fn lint(graph: &Graph, vocabulary: &crate::rewrite::Vocabulary, errors: &mut Errors) {
    for event in &graph.events {
        let name = crate::flatten::display(&event.name.to_string());
        let context = format!("the condition of event `{name}`");
        crate::rewrite::lint(&event.lhs, vocabulary, &[], &context, errors);
        if let Some(rhs) = &event.rhs {
            crate::rewrite::lint(rhs, vocabulary, &[], &context, errors);
        }
        let context = format!("the actions of event `{name}`");
        let mut all = Vec::new();
        action_expressions(&event.actions, &mut all);
        for expr in all {
            crate::rewrite::lint(expr, vocabulary, &[], &context, errors);
        }
    }
    for mode in &graph.modes {
        let context = format!(
            "the initial value of mode `{}`",
            crate::flatten::display(&mode.name.to_string())
        );
        crate::rewrite::lint(&mode.init, vocabulary, &[], &context, errors);
    }
}

/// An event ready for code generation: its indicator and its actions in the terms of
/// the generated code.
pub struct EventCode {
    /// g(t, x), rewritten.
    pub indicator: Expr,
    /// The actions, rewritten.
    pub actions: Vec<ActionCode>,
}

/// An action in the terms of the generated code.
pub enum ActionCode {
    /// Writes `value` into state `state` (converted from a mode's type).
    Write {
        /// The state's index in `Equations::states`.
        state: usize,
        /// The value.
        value: Expr,
        /// The mode's type, for a mode.
        mode: Option<ModeKind>,
    },
    /// Ends the run.
    Stop,
    /// A branch.
    If {
        /// The condition.
        cond: Expr,
        /// Actions when it holds.
        then: Vec<ActionCode>,
        /// Actions otherwise.
        otherwise: Vec<ActionCode>,
    },
}

/// Rewrites every event's indicator and actions; `mode_state[m]` is mode m's state.
pub fn derive(
    graph: &Graph,
    scope: &Scope,
    mode_state: &[usize],
    errors: &mut Errors,
) -> Vec<EventCode> {
    graph
        .events
        .iter()
        .map(|event| {
            check_scalar(&event.lhs, scope, errors);
            let lhs = rewrite(&event.lhs, scope, errors).expr;
            let indicator = match &event.rhs {
                Some(rhs) => {
                    check_scalar(rhs, scope, errors);
                    let rhs = rewrite(rhs, scope, errors).expr;
                    syn::parse_quote!((#lhs) - (#rhs))
                }
                None => lhs,
            };
            EventCode {
                indicator,
                actions: action_code(graph, &event.actions, scope, mode_state, errors),
            }
        })
        .collect()
}

fn action_code(
    graph: &Graph,
    actions: &[Action],
    scope: &Scope,
    mode_state: &[usize],
    errors: &mut Errors,
) -> Vec<ActionCode> {
    actions
        .iter()
        .filter_map(|action| match action {
            Action::Reinit { target, value } => {
                let state = match target {
                    Target::Kinematic(k) => scope.kinematic_state[*k],
                    Target::Storage(id, span) => match scope.state_of[id.0] {
                        Some(state) => state,
                        None => {
                            errors.at(
                                *span,
                                format!(
                                    "{} is dependent storage (derivative causality): it has no \
                                     state to reinit; its momentum or displacement follows the \
                                     states it depends on\nhelp: reinit the independent state \
                                     it is rigidly connected to",
                                    graph.describe(*id)
                                ),
                            );
                            return None;
                        }
                    },
                };
                Some(ActionCode::Write {
                    state,
                    value: rewrite(value, scope, errors).expr,
                    mode: None,
                })
            }
            Action::Switch { mode, value } => Some(ActionCode::Write {
                state: mode_state[*mode],
                value: rewrite(value, scope, errors).expr,
                mode: Some(graph.modes[*mode].kind),
            }),
            Action::Stop => Some(ActionCode::Stop),
            Action::If {
                cond,
                then,
                otherwise,
            } => Some(ActionCode::If {
                cond: rewrite(cond, scope, errors).expr,
                then: action_code(graph, then, scope, mode_state, errors),
                otherwise: action_code(graph, otherwise, scope, mode_state, errors),
            }),
        })
        .collect()
}

/// A condition's side must be a number.
fn check_scalar(expr: &Expr, scope: &Scope, errors: &mut Errors) {
    let locals = crate::rewrite::local_names(expr);
    let env = crate::rewrite::Env {
        scope,
        locals: &locals,
    };
    match crate::shapes::shape(expr, &env) {
        Some(Shape::Vector(n)) => errors.at(
            expr.span(),
            format!(
                "a `when` condition compares numbers, and this is a {n}-vector\nhelp: compare \
                 one component (`.x`, `[1]`) or a number made of it (`.norm()`, `.dot(n)`)"
            ),
        ),
        Some(Shape::Matrix(r, c)) => errors.at(
            expr.span(),
            format!(
                "a `when` condition compares numbers, and this is a {r}×{c} matrix\nhelp: \
                 compare one entry (`[(0, 1)]`) or a number made of it"
            ),
        ),
        _ => {}
    }
}
