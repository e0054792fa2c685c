//! Stage 4: from the causal graph to equations in computation order.
//!
//! Each element contributes the assignments its causality dictates (a C in integral
//! causality computes its bond's effort from its state, a 1-junction whose flow comes in
//! on bond s computes s's effort as the signed sum of the others, ...). The assignments
//! are then ordered so that each is computed after what it reads; a cycle is an
//! algebraic loop and is reported with the elements on it, unless the model allows it
//! or it runs through dependent storage: then [`crate::implicit`] tears it.

use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};

use syn::Expr;

use crate::causality::Causality;
use crate::errors::Errors;
use crate::ir::{BondId, ElementId, ElementKind, Graph, Law, Shape};
use crate::rewrite::{rewrite, Rewritten, Scope};
use crate::signals::{Signal, Term};

/// A state of the model: the integral of a storage element's input.
pub struct State {
    /// `mass.p` for a storage element's state, the name of a kinematic state.
    pub name: String,
    /// The storage element, if it is one's state.
    pub element: Option<ElementId>,
    /// The kinematic state's index in [`Graph::kinematics`], if it is one.
    pub kinematic: Option<usize>,
    /// The mode's index in [`Graph::modes`], if it is one (its derivative is 0).
    pub mode: Option<usize>,
    /// Its shape: the bond's dimension for storage, the declared one otherwise.
    pub shape: Shape,
    /// What its time derivative equals.
    pub derivative: Derivative,
}

/// The time derivative of a state.
pub enum Derivative {
    /// A storage element integrates a bond variable.
    Term(Term),
    /// A kinematic state's `der` expression.
    Expr(Rewritten),
}

/// How a linear coefficient k acts on the variable it scales.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `k v`
    Apply,
    /// `kᵀ v` (a transformer's effort relation)
    ApplyTranspose,
    /// `k⁻¹ v`
    Solve,
    /// `k⁻ᵀ v`
    SolveTranspose,
}

/// The right-hand side of one assignment.
pub enum Rhs {
    /// A law written by the user, evaluated with the element's own variables bound.
    Law {
        /// Whether the law's value enters negated (a bond against the port's direction).
        negate: bool,
        /// `let q = <term>;` and the like, before the expression.
        bindings: Vec<(&'static str, Term)>,
        /// The rewritten expression.
        expr: Expr,
    },
    /// A sum of signed terms (junction equations; one term is a copy).
    Sum(Vec<Term>),
    /// One component of a multibond variable (a splitter's scalar side).
    Component {
        /// The multibond variable.
        of: Signal,
        /// Which component.
        index: usize,
    },
    /// A multibond variable made of scalar ones, in component order (a splitter's
    /// multibond side).
    Assemble(Vec<Signal>),
    /// A linear law or a two-port: the coefficient applied to a variable (for a scalar
    /// bond, multiplied or divided).
    Scaled {
        /// The variable scaled.
        term: Term,
        /// The rewritten coefficient expression.
        modulus: Expr,
        /// How the coefficient acts.
        op: Op,
    },
    /// Dependent storage's returned variable: the time derivative of its energy
    /// variable along the motion (see [`crate::implicit`]); `Equations::dependent[index]`.
    Dependent(usize),
}

/// One assignment `defines = rhs`.
pub struct Equation {
    /// The variable it computes.
    pub defines: Signal,
    /// The element it comes from.
    pub element: ElementId,
    /// How it is computed.
    pub rhs: Rhs,
    /// Every signal it reads.
    pub deps: Vec<Signal>,
}

/// A two-port whose law gives the inverse of its modulus: checked on numbers, since
/// the compiler cannot tell whether it is one.
pub struct InverseCheck {
    /// The TF or GY.
    pub element: ElementId,
    /// Its modulus, rewritten.
    pub modulus: Expr,
    /// The inverse its law gives, rewritten.
    pub inverse: Expr,
    /// The dimension of its bonds (the modulus is a number or a square matrix).
    pub dimension: usize,
    /// Whether the equations compute with the inverse (causality runs the two-port
    /// backwards on a multibond); if not, it is checked before a run only.
    pub used: bool,
}

/// Everything the code generator needs to write the model's functions.
pub struct Equations {
    /// The two-ports whose given inverse is checked.
    pub inverses: Vec<InverseCheck>,
    /// States in order of the state vector (storage elements in declaration order).
    pub states: Vec<State>,
    /// Assignments in an order where each comes after what it reads.
    pub ordered: Vec<Equation>,
    /// The outputs' rewritten expressions, in declaration order.
    pub outputs: Vec<Rewritten>,
    /// Storage in derivative causality, in declaration order.
    pub dependent: Vec<crate::implicit::Dependent>,
    /// The unknowns solved at every evaluation (empty for an explicit model).
    pub implicit: crate::implicit::System,
    /// The events' indicators and actions, in declaration order.
    pub events: Vec<crate::events::EventCode>,
}

impl Equations {
    /// For each state derivative, the states it depends on (sorted): the structural
    /// sparsity of the Jacobian, followed through every assignment.
    pub fn jacobian_sparsity(&self) -> Vec<Vec<usize>> {
        let offsets = self.offsets();
        let blocks = self.state_dependencies();
        let mut rows = Vec::new();
        for (i, state) in self.states.iter().enumerate() {
            let columns: Vec<usize> = blocks[i]
                .iter()
                .flat_map(|&j| offsets[j]..offsets[j] + self.states[j].shape.len())
                .collect();
            rows.extend(std::iter::repeat_n(columns, state.shape.len()));
        }
        rows
    }

    /// For each state, the states its derivative reads (sorted), followed through every
    /// assignment.
    pub fn state_dependencies(&self) -> Vec<Vec<usize>> {
        let mut reads: BTreeMap<Signal, Vec<usize>> = BTreeMap::new();
        let states_of = |signal: Signal, reads: &BTreeMap<Signal, Vec<usize>>| match signal {
            Signal::State(i) => vec![i],
            other => reads.get(&other).cloned().unwrap_or_default(),
        };
        let union = |deps: &[Signal], reads: &BTreeMap<Signal, Vec<usize>>| {
            let mut states: Vec<usize> = deps.iter().flat_map(|&d| states_of(d, reads)).collect();
            states.sort_unstable();
            states.dedup();
            states
        };
        // Torn unknowns are read before they are computed: repeat until nothing grows
        // (one pass for a model without them).
        loop {
            let mut grew = false;
            for eq in &self.ordered {
                let states = union(&eq.deps, &reads);
                if reads.get(&eq.defines) != Some(&states) {
                    grew = true;
                    reads.insert(eq.defines, states);
                }
            }
            if !grew || self.implicit.tears.is_empty() {
                break;
            }
        }
        self.states
            .iter()
            .map(|s| match &s.derivative {
                Derivative::Term(term) => states_of(term.signal, &reads),
                Derivative::Expr(expr) => union(&expr.deps, &reads),
            })
            .collect()
    }

    /// Where each state starts in the state vector.
    pub fn offsets(&self) -> Vec<usize> {
        self.states
            .iter()
            .scan(0, |next, state| {
                let at = *next;
                *next += state.shape.len();
                Some(at)
            })
            .collect()
    }

    /// The shape of a signal: a bond's dimension, or a state's shape.
    pub fn shape_of(&self, graph: &Graph, signal: Signal) -> Shape {
        match signal {
            Signal::Effort(b) | Signal::Flow(b) => Shape::of_dimension(graph.bond_dims[b.0]),
            Signal::State(i) => self.states[i].shape,
        }
    }
}

/// Derives and orders the equations, or reports algebraic loops and bad references.
pub fn derive(graph: &Graph, causality: &Causality) -> syn::Result<Equations> {
    let mut errors = Errors::default();
    let mut state_of = vec![None; graph.elements.len()];
    let mut states = Vec::new();
    for id in graph.element_ids() {
        let element = graph.element(id);
        let var = match element.kind {
            ElementKind::C => "q",
            ElementKind::I => "p",
            _ => continue,
        };
        if causality.element[id.0] == crate::causality::ElementCausality::Derivative {
            continue;
        }
        let bond = element.bonds[0];
        let negate = !graph.bond(bond).points_into(id);
        let derivative = match element.kind {
            ElementKind::C => Term::signed(negate, Signal::Flow(bond)),
            _ => Term::plus(Signal::Effort(bond)),
        };
        state_of[id.0] = Some(states.len());
        states.push(State {
            name: format!(
                "{}.{var}",
                crate::flatten::display(&element.name.to_string())
            ),
            element: Some(id),
            kinematic: None,
            mode: None,
            shape: Shape::of_dimension(graph.bond_dims[bond.0]),
            derivative: Derivative::Term(derivative),
        });
    }
    let kinematic_state: Vec<usize> =
        (states.len()..states.len() + graph.kinematics.len()).collect();
    for (k, kinematic) in graph.kinematics.iter().enumerate() {
        let scope = Scope {
            graph,
            state_of: &state_of,
            kinematic_state: &kinematic_state,
        };
        let der = rewrite(&kinematic.der, &scope, &mut errors);
        states.push(State {
            name: crate::flatten::display(&kinematic.name.to_string()),
            element: None,
            kinematic: Some(k),
            mode: None,
            shape: kinematic.shape,
            derivative: Derivative::Expr(der),
        });
    }
    // Modes last: constant between events, so their derivative is exactly 0.
    let mode_state: Vec<usize> = (states.len()..states.len() + graph.modes.len()).collect();
    for (m, mode) in graph.modes.iter().enumerate() {
        let zero = crate::rewrite::scalar_literal(&syn::LitFloat::new("0.0", mode.name.span()));
        states.push(State {
            name: crate::flatten::display(&mode.name.to_string()),
            element: None,
            kinematic: None,
            mode: Some(m),
            shape: Shape::Scalar,
            derivative: Derivative::Expr(Rewritten {
                expr: zero,
                deps: Vec::new(),
            }),
        });
    }
    let events = crate::events::derive(
        graph,
        &Scope {
            graph,
            state_of: &state_of,
            kinematic_state: &kinematic_state,
        },
        &mode_state,
        &mut errors,
    );
    let mut builder = Builder {
        graph,
        causality,
        state_of: &state_of,
        kinematic_state: &kinematic_state,
        errors: &mut errors,
        equations: Vec::new(),
        inverses: Vec::new(),
        dependent: Vec::new(),
    };
    for id in graph.element_ids() {
        builder.element(id);
    }
    let mut equations = builder.equations;
    let inverses = builder.inverses;
    let dependent = builder.dependent;
    crate::implicit::check_inits(graph, causality, &mut errors);
    let outputs = graph
        .outputs
        .iter()
        .map(|output| {
            let scope = Scope {
                graph,
                state_of: &state_of,
                kinematic_state: &kinematic_state,
            };
            rewrite(&output.expr, &scope, &mut errors)
        })
        .collect();
    errors.finish()?;
    if dependent.is_empty() && graph.allowances.is_empty() {
        let ordered = order(graph, equations)?;
        return Ok(Equations {
            inverses,
            states,
            ordered,
            outputs,
            dependent,
            implicit: crate::implicit::System::default(),
            events,
        });
    }
    let mut dependent = dependent;
    crate::implicit::link_dependent(graph, &states, &mut equations, &mut dependent)?;
    let (ordered, implicit) =
        crate::implicit::tear(graph, causality, &states, equations, &dependent)?;
    crate::implicit::finish_dependent(graph, &ordered, &implicit, &mut dependent)?;
    Ok(Equations {
        inverses,
        states,
        ordered,
        outputs,
        dependent,
        implicit,
        events,
    })
}

struct Builder<'a> {
    graph: &'a Graph,
    causality: &'a Causality,
    state_of: &'a [Option<usize>],
    kinematic_state: &'a [usize],
    errors: &'a mut Errors,
    equations: Vec<Equation>,
    inverses: Vec<InverseCheck>,
    dependent: Vec<crate::implicit::Dependent>,
}

impl Builder<'_> {
    fn stroke_at(&self, bond: BondId) -> ElementId {
        self.causality.stroke_at[bond.0]
    }

    fn push(&mut self, defines: Signal, element: ElementId, rhs: Rhs, extra_deps: Vec<Signal>) {
        let mut deps = extra_deps;
        let mut add = |s: Signal| {
            if !deps.contains(&s) {
                deps.push(s);
            }
        };
        match &rhs {
            Rhs::Law { bindings, .. } => bindings.iter().for_each(|(_, t)| add(t.signal)),
            Rhs::Sum(terms) => terms.iter().for_each(|t| add(t.signal)),
            Rhs::Component { of, .. } => add(*of),
            Rhs::Assemble(parts) => parts.iter().for_each(|&s| add(s)),
            Rhs::Scaled { term, .. } => add(term.signal),
            Rhs::Dependent(_) => {}
        }
        self.equations.push(Equation {
            defines,
            element,
            rhs,
            deps,
        });
    }

    fn rewrite(&mut self, expr: &Expr) -> Rewritten {
        let scope = Scope {
            graph: self.graph,
            state_of: self.state_of,
            kinematic_state: self.kinematic_state,
        };
        rewrite(expr, &scope, self.errors)
    }

    /// A user law in a given form, as an assignment.
    fn law(
        &mut self,
        id: ElementId,
        defines: Signal,
        negate: bool,
        own: &'static str,
        bound: Term,
        expr: &Expr,
    ) {
        let rewritten = self.rewrite(expr);
        let rhs = Rhs::Law {
            negate,
            bindings: vec![(own, bound)],
            expr: rewritten.expr,
        };
        self.push(defines, id, rhs, rewritten.deps);
    }

    fn scaled(&mut self, id: ElementId, defines: Signal, term: Term, modulus: &Expr, op: Op) {
        let rewritten = self.rewrite(modulus);
        let rhs = Rhs::Scaled {
            term,
            modulus: rewritten.expr,
            op,
        };
        self.push(defines, id, rhs, rewritten.deps);
    }

    fn element(&mut self, id: ElementId) {
        let graph = self.graph;
        let element = graph.element(id);
        let bonds = &element.bonds;
        match element.kind {
            ElementKind::Se | ElementKind::Sf => {
                let Law::Linear(value) = &element.law else {
                    return;
                };
                let bond = bonds[0];
                let rewritten = self.rewrite(value);
                // A source sets its bond's effort or flow counted along the half arrow,
                // whichever way the arrow points (an inward bond makes it a sink).
                let defines = if element.kind == ElementKind::Se {
                    Signal::Effort(bond)
                } else {
                    Signal::Flow(bond)
                };
                let rhs = Rhs::Law {
                    negate: false,
                    bindings: Vec::new(),
                    expr: rewritten.expr,
                };
                self.push(defines, id, rhs, rewritten.deps);
            }
            ElementKind::C | ElementKind::I | ElementKind::R => self.passive(id),
            ElementKind::Tf | ElementKind::Gy => {
                let Law::Linear(modulus) = &element.law else {
                    return;
                };
                // A two-port taken apart by a splitter has no bonds of its own.
                let [b1, b2] = bonds[..] else {
                    return;
                };
                let receives_e1 = self.stroke_at(b1) == id;
                let (e1, f1, e2, f2) = (
                    Signal::Effort(b1),
                    Signal::Flow(b1),
                    Signal::Effort(b2),
                    Signal::Flow(b2),
                );
                // TF: e1 = nᵀ e2, f2 = n f1.  GY: e1 = rᵀ f2, e2 = r f1. (For scalar
                // bonds the transposes are the numbers themselves.)
                use Op::*;
                let plan = match (element.kind, receives_e1) {
                    (ElementKind::Tf, true) => [(e2, e1, SolveTranspose), (f1, f2, Solve)],
                    (ElementKind::Tf, false) => [(e1, e2, ApplyTranspose), (f2, f1, Apply)],
                    (_, true) => [(f2, e1, SolveTranspose), (f1, e2, Solve)],
                    (_, false) => [(e1, f2, ApplyTranspose), (e2, f1, Apply)],
                };
                let (n1, n2) = (graph.bond_dims[b1.0], graph.bond_dims[b2.0]);
                // A plain number's inverse is its reciprocal: working backwards divides
                // by it, on a multibond as on a scalar bond.
                let multibond = n1 > 1 && !crate::split::scalar_modulus(graph, modulus);
                let inverts = receives_e1;
                if inverts && n1 != n2 {
                    self.errors
                        .at(element.name.span(), non_square_inverse(graph, id, n1, n2));
                    return;
                }
                if let Some(inverse) = &element.inverse {
                    // Rewritten again for the check: any mistake in them is reported
                    // by the rewriting for the equations.
                    let mut quiet = Errors::default();
                    let scope = Scope {
                        graph,
                        state_of: self.state_of,
                        kinematic_state: self.kinematic_state,
                    };
                    self.inverses.push(InverseCheck {
                        element: id,
                        modulus: rewrite(modulus, &scope, &mut quiet).expr,
                        inverse: rewrite(inverse, &scope, &mut quiet).expr,
                        dimension: n1,
                        used: multibond && inverts,
                    });
                }
                match (&element.inverse, multibond && inverts) {
                    // A matrix modulus is inverted only through the inverse the law gives.
                    (Some(inverse), true) => {
                        for (defines, from, op) in plan {
                            let op = if op == Solve { Apply } else { ApplyTranspose };
                            self.scaled(id, defines, Term::plus(from), inverse, op);
                        }
                    }
                    (None, true) => {
                        let name = &element.name;
                        // Backwards a TF computes port 2's effort, a GY its flow; a
                        // compliance (TF) or an inertia (GY) at port 2 turns it forwards.
                        let (keyword, computed, turns_round) = match element.kind {
                            ElementKind::Tf => ("MTF", "port 2's effort", "a compliance"),
                            _ => ("MGY", "port 2's flow", "an inertia"),
                        };
                        self.errors.at(
                            name.span(),
                            format!(
                                "{} would need the inverse of its modulus: its causality has it \
                                 receive the effort on port 1, so it must compute {computed} and \
                                 port 1's flow backwards; a matrix modulus has no inverse unless the \
                                 law gives one (a skew-symmetric one, like a lever arm's, has none; \
                                 a modulus the compiler can see is a plain number is divided by)\n\
                                 help: give it as `{keyword} {name} = M, inverse = ...;`, or change the \
                                 causality around it (e.g. {turns_round} at port 2)",
                                graph.describe(id)
                            ),
                        );
                    }
                    _ => {
                        for (defines, from, op) in plan {
                            self.scaled(id, defines, Term::plus(from), modulus, op);
                        }
                    }
                }
            }
            ElementKind::Zero | ElementKind::One => self.junction(id),
            ElementKind::Split => self.splitter(id),
        }
    }

    /// A splitter copies each component across: effort from the side that brings it,
    /// flow back the other way.
    fn splitter(&mut self, id: ElementId) {
        let bonds = &self.graph.element(id).bonds;
        let Some((&whole, parts)) = bonds.split_first() else {
            return;
        };
        type Variable = fn(BondId) -> Signal;
        // Effort in on the multibond: each component's effort is read from it, and its
        // flow is made of theirs; otherwise the other way round.
        let (read, made): (Variable, Variable) = if self.stroke_at(whole) == id {
            (Signal::Effort, Signal::Flow)
        } else {
            (Signal::Flow, Signal::Effort)
        };
        for (index, &part) in parts.iter().enumerate() {
            let rhs = Rhs::Component {
                of: read(whole),
                index,
            };
            self.push(read(part), id, rhs, Vec::new());
        }
        let rhs = Rhs::Assemble(parts.iter().map(|&b| made(b)).collect());
        self.push(made(whole), id, rhs, Vec::new());
    }

    fn passive(&mut self, id: ElementId) {
        let element = self.graph.element(id);
        let bond = element.bonds[0];
        // Port flow = bond flow when the half arrow points in, its negative otherwise.
        let negate = !self.graph.bond(bond).points_into(id);
        let (e, f) = (Signal::Effort(bond), Signal::Flow(bond));
        let state = self.state_of[id.0].map(Signal::State);
        if self.causality.element[id.0] == crate::causality::ElementCausality::Derivative {
            let (receives, returns) = if element.kind == ElementKind::I {
                (f, e)
            } else {
                (e, f)
            };
            let Law::Linear(coefficient) = &element.law else {
                self.errors.at(
                    element.name.span(),
                    crate::implicit::explicit_law_message(self.graph, id),
                );
                return;
            };
            let modulus = self.rewrite(coefficient);
            let index = self.dependent.len();
            self.dependent.push(crate::implicit::Dependent {
                element: id,
                receives,
                returns,
                negate,
                modulus: modulus.expr,
                modulus_deps: modulus.deps,
                shape: Shape::of_dimension(self.graph.bond_dims[bond.0]),
                closure: Vec::new(),
                states: Vec::new(),
            });
            self.push(returns, id, Rhs::Dependent(index), Vec::new());
            return;
        }
        match (element.kind, &element.law, state) {
            (ElementKind::C, Law::Linear(k), Some(q)) => {
                self.scaled(id, e, Term::plus(q), k, Op::Apply)
            }
            (
                ElementKind::C,
                Law::Forms {
                    effort: Some(law), ..
                },
                Some(q),
            ) => self.law(id, e, false, "q", Term::plus(q), law),
            (ElementKind::I, Law::Linear(m), Some(p)) => {
                self.scaled(id, f, Term::signed(negate, p), m, Op::Solve)
            }
            (
                ElementKind::I,
                Law::Forms {
                    flow: Some(law), ..
                },
                Some(p),
            ) => self.law(id, f, negate, "p", Term::plus(p), law),
            (ElementKind::R, law, _) => {
                let resistance = self.stroke_at(bond) != id;
                match (law, resistance) {
                    (Law::Linear(c), true) => {
                        self.scaled(id, e, Term::signed(negate, f), c, Op::Apply)
                    }
                    (Law::Linear(c), false) => {
                        self.scaled(id, f, Term::signed(negate, e), c, Op::Solve)
                    }
                    (
                        Law::Forms {
                            effort: Some(law), ..
                        },
                        true,
                    ) => self.law(id, e, false, "f", Term::signed(negate, f), law),
                    (
                        Law::Forms {
                            flow: Some(law), ..
                        },
                        false,
                    ) => self.law(id, f, negate, "e", Term::plus(e), law),
                    // The missing form was reported by causality assignment.
                    _ => {}
                }
            }
            _ => {}
        }
    }

    fn junction(&mut self, id: ElementId) {
        let graph = self.graph;
        let bonds = &graph.element(id).bonds;
        let zero = graph.element(id).kind == ElementKind::Zero;
        // The bond that brings in the common variable: effort at a 0, flow at a 1.
        let Some(&setter) = bonds.iter().find(|&&b| (self.stroke_at(b) == id) == zero) else {
            return;
        };
        type Variable = fn(BondId) -> Signal;
        let (common, summed): (Variable, Variable) = if zero {
            (Signal::Effort, Signal::Flow)
        } else {
            (Signal::Flow, Signal::Effort)
        };
        let inward = |b: BondId| graph.bond(b).points_into(id);
        let mut terms = Vec::new();
        for &bond in bonds.iter().filter(|&&b| b != setter) {
            self.push(
                common(bond),
                id,
                Rhs::Sum(vec![Term::plus(common(setter))]),
                Vec::new(),
            );
            // Σ in = Σ out, solved for the setter's summed variable.
            terms.push(Term::signed(inward(bond) == inward(setter), summed(bond)));
        }
        self.push(summed(setter), id, Rhs::Sum(terms), Vec::new());
    }
}

/// A two-port between bonds of different dimensions whose causality would need its
/// modulus inverted: an n₂×n₁ matrix with n₁ ≠ n₂ has no inverse.
fn non_square_inverse(graph: &Graph, id: ElementId, n1: usize, n2: usize) -> String {
    let element = graph.element(id);
    let bonds = &element.bonds;
    let meets = |port: usize| graph.describe(graph.bond(bonds[port]).other(id));
    let size = |n: usize| match n {
        1 => "scalar".to_string(),
        n => format!("{n}-dimensional"),
    };
    format!(
        "{} joins a {} bond at port 1 (from {}) to a {} bond at port 2 (to {}), so its modulus \
         is a {n2}×{n1} matrix, which has no inverse; but its causality has it receive the \
         effort on port 1, so it would have to compute port 2's effort and port 1's flow \
         backwards{}\n\
         help: let port 2's side set the effort (a storage element or resistor there, not \
         a source of effort at port 1); to push a 3-D junction along `n` with a scalar \
         force, bond the junction to port 1 and the force to port 2 through the transposed \
         modulus (`MTF proj = n.transpose();`: f2 = nᵀ v, e1 = n F)",
        graph.describe(id),
        size(n1),
        meets(0),
        size(n2),
        meets(1),
        if element.inverse.is_some() {
            " (an `inverse = ...` cannot help: only a square modulus has one)"
        } else {
            ""
        },
    )
}

/// Orders the equations so each follows what it reads (Kahn's algorithm, always
/// taking the earliest-declared ready equation, so the order is deterministic).
fn order(graph: &Graph, equations: Vec<Equation>) -> syn::Result<Vec<Equation>> {
    match sequence(&equations, &[]) {
        Ok(sequence) => Ok(arrange(equations, sequence)),
        Err(cycle) => Err(algebraic_loop(graph, &cycle_elements(&equations, &cycle))),
    }
}

/// The equations in the order `sequence` gives (indices into `equations`).
pub fn arrange(equations: Vec<Equation>, sequence: Vec<usize>) -> Vec<Equation> {
    let mut slots: Vec<Option<Equation>> = equations.into_iter().map(Some).collect();
    sequence
        .into_iter()
        .filter_map(|i| slots[i].take())
        .collect()
}

/// An order of the equations in which each follows what it reads, reading the `torn`
/// signals as given (Kahn's algorithm, always taking the earliest-declared ready
/// equation, so the order is deterministic); or one strongly connected set of
/// equations that cannot be ordered (indices).
pub fn sequence(equations: &[Equation], torn: &[Signal]) -> Result<Vec<usize>, Vec<usize>> {
    let defined_by: BTreeMap<Signal, usize> = equations
        .iter()
        .enumerate()
        .filter(|(_, eq)| !torn.contains(&eq.defines))
        .map(|(i, eq)| (eq.defines, i))
        .collect();
    let producers = |eq: &Equation| -> Vec<usize> {
        eq.deps
            .iter()
            .filter_map(|d| defined_by.get(d).copied())
            .collect()
    };
    let mut waiting_on: Vec<usize> = equations.iter().map(|eq| producers(eq).len()).collect();
    let mut readers: Vec<Vec<usize>> = vec![Vec::new(); equations.len()];
    for (i, eq) in equations.iter().enumerate() {
        for producer in producers(eq) {
            readers[producer].push(i);
        }
    }
    let mut ready: BinaryHeap<Reverse<usize>> = (0..equations.len())
        .filter(|&i| waiting_on[i] == 0)
        .map(Reverse)
        .collect();
    let mut sequence = Vec::with_capacity(equations.len());
    while let Some(Reverse(i)) = ready.pop() {
        sequence.push(i);
        for &reader in &readers[i] {
            waiting_on[reader] -= 1;
            if waiting_on[reader] == 0 {
                ready.push(Reverse(reader));
            }
        }
    }
    if sequence.len() < equations.len() {
        return Err(find_cycle(equations, &waiting_on, &defined_by));
    }
    Ok(sequence)
}

/// The elements of a set of equations, sorted, without repeats.
pub fn cycle_elements(equations: &[Equation], cycle: &[usize]) -> Vec<ElementId> {
    let mut elements: Vec<ElementId> = cycle.iter().map(|&i| equations[i].element).collect();
    elements.sort();
    elements.dedup();
    elements
}

/// One algebraic loop: the strongly connected set of equations (among those that could
/// not be ordered) around a cycle, as indices into `equations`.
pub fn find_cycle(
    equations: &[Equation],
    waiting_on: &[usize],
    defined_by: &BTreeMap<Signal, usize>,
) -> Vec<usize> {
    let stuck = |i: usize| waiting_on[i] > 0;
    let producers = |i: usize| -> Vec<usize> {
        equations[i]
            .deps
            .iter()
            .filter_map(|d| defined_by.get(d).copied())
            .filter(|&p| stuck(p))
            .collect()
    };
    // Walking producers from any stuck equation must meet a cycle: every stuck
    // equation waits on another stuck one.
    let Some(mut current) = (0..equations.len()).find(|&i| stuck(i)) else {
        return Vec::new();
    };
    let mut seen = vec![false; equations.len()];
    while !seen[current] {
        seen[current] = true;
        match producers(current).first() {
            Some(&next) => current = next,
            None => break,
        }
    }
    let reach = |start: usize, step: &dyn Fn(usize) -> Vec<usize>| {
        let mut reached = vec![false; equations.len()];
        let mut stack = vec![start];
        while let Some(i) = stack.pop() {
            if !std::mem::replace(&mut reached[i], true) {
                stack.extend(step(i));
            }
        }
        reached
    };
    let upstream = reach(current, &producers);
    let readers = |i: usize| -> Vec<usize> {
        (0..equations.len())
            .filter(|&r| stuck(r) && producers(r).contains(&i))
            .collect()
    };
    let downstream = reach(current, &readers);
    (0..equations.len())
        .filter(|&i| upstream[i] && downstream[i])
        .collect()
}

/// The message for an algebraic loop the model does not allow.
pub fn algebraic_loop(graph: &Graph, cycle: &[ElementId]) -> syn::Error {
    let names: Vec<String> = cycle.iter().map(|&id| graph.describe(id)).collect();
    // Point at a resistor on the loop if there is one: that is what the user can change.
    let blamed = cycle
        .iter()
        .find(|&&id| graph.element(id).kind == ElementKind::R)
        .or(cycle.first());
    let span = blamed.map_or_else(|| graph.name.span(), |&id| graph.element(id).name.span());
    syn::Error::new(
        span,
        format!(
            "algebraic loop: {} compute each other's variables at the same instant, so there is \
             no order to evaluate them in\n\
             help: break the loop with a storage element (a small C or I where the physics has \
             one), or combine the resistors on the loop into one R\n\
             help: if the loop is meant, allow it: `#[allow(algebraic_loops)]` on {} or on the \
             model (it is then solved at every evaluation)",
            names.join(", "),
            blamed.map_or_else(
                || "an element on it".to_owned(),
                |&id| {
                    format!(
                        "`{}`",
                        crate::flatten::display(&graph.element(id).name.to_string())
                    )
                }
            ),
        ),
    )
}

#[cfg(test)]
mod should {
    use super::*;

    fn term(derivative: &Derivative) -> Term {
        match derivative {
            Derivative::Term(term) => *term,
            Derivative::Expr(_) => panic!("a storage state integrates a term"),
        }
    }

    fn derive_text(text: &str) -> (Graph, syn::Result<Equations>) {
        let file: crate::syntax::File = syn::parse_str(text).unwrap();
        let graph = crate::resolve::resolve(file.models.into_iter().next().unwrap()).unwrap();
        let causality = crate::causality::assign(&graph).unwrap();
        let equations = derive(&graph, &causality);
        (graph, equations)
    }

    /// `e3`, `f0`, `x1`: a compact name for each computed signal, in order.
    fn order_of(equations: &Equations) -> Vec<String> {
        equations
            .ordered
            .iter()
            .map(|eq| match eq.defines {
                Signal::Effort(b) => format!("e{}", b.0),
                Signal::Flow(b) => format!("f{}", b.0),
                Signal::State(i) => format!("x{i}"),
            })
            .collect()
    }

    #[test]
    fn compute_the_junction_sum_after_every_effort_it_reads() {
        // Bonds: 0 push->v, 1 v->mass, 2 v->spring, 3 v->damper. The mass sets v's flow,
        // so the damper's effort needs the flow copied from the mass first, and the
        // mass's effort (the sum) comes last.
        let (_, eqs) = derive_text(
            "model M { Se push = 1.0; I mass = 1.0; C spring = 1.0; R damper = 1.0; 1 v;
                       push -> v -> { mass, spring, damper }; }",
        );
        let eqs = eqs.unwrap();
        let order = order_of(&eqs);
        let at = |s: &str| order.iter().position(|o| o == s).unwrap();
        assert!(at("f1") < at("f3") && at("f3") < at("e3"));
        assert!(at("e0") < at("e1") && at("e2") < at("e1") && at("e3") < at("e1"));
        assert_eq!(order.len(), 8);
        // The mass's momentum integrates its effort; the spring's position its flow.
        assert_eq!(
            term(&eqs.states[0].derivative),
            Term::plus(Signal::Effort(BondId(1)))
        );
        assert_eq!(
            term(&eqs.states[1].derivative),
            Term::plus(Signal::Flow(BondId(2)))
        );
    }

    #[test]
    fn sum_with_signs_from_the_half_arrows() {
        // Bond 0 points into v, bond 1 out of it, bond 2 (the mass, setting the flow)
        // out of it: e2 = e0 - e1.
        let (_, eqs) = derive_text(
            "model M { Se s = 1.0; C c = 1.0; I m = 1.0; 1 v; s -> v; v -> c; v -> m; }",
        );
        let eqs = eqs.unwrap();
        let sum = eqs
            .ordered
            .iter()
            .find(|eq| eq.defines == Signal::Effort(BondId(2)))
            .unwrap();
        let Rhs::Sum(terms) = &sum.rhs else {
            panic!("a junction sum")
        };
        assert_eq!(
            terms,
            &[
                Term::signed(false, Signal::Effort(BondId(0))),
                Term::signed(true, Signal::Effort(BondId(1)))
            ]
        );
    }

    #[test]
    fn negate_the_port_flow_of_a_storage_element_whose_bond_points_away() {
        let (_, eqs) = derive_text(
            "model M { Se s = 1.0; C c = 1.0; 1 v; s -> v; c -> v; I m = 1.0; v -> m; }",
        );
        let eqs = eqs.unwrap();
        let c = eqs.states.iter().find(|s| s.name.ends_with(".q")).unwrap();
        assert_eq!(
            term(&c.derivative),
            Term::signed(true, Signal::Flow(BondId(1)))
        );
    }

    #[test]
    fn invert_a_linear_resistor_in_conductance_causality() {
        let (_, eqs) = derive_text("model M { Se s = 1.0; R r = 2.0; C c = 1.0; I m = 1.0; 0 j; 1 k; s -> k -> { m, j }; j -> { r, c }; }");
        let eqs = eqs.unwrap();
        let r = eqs
            .ordered
            .iter()
            .find(|eq| eq.defines == Signal::Flow(BondId(3)))
            .unwrap();
        assert!(matches!(r.rhs, Rhs::Scaled { op: Op::Solve, .. }));
    }

    #[test]
    fn record_the_signals_a_modulated_law_reads() {
        let (_, eqs) = derive_text(
            "model M { Se s = -2.0 * m.f; I m = 1.0; 1 v; s -> v -> m; output y = s.e + t; }",
        );
        let eqs = eqs.unwrap();
        let source = eqs
            .ordered
            .iter()
            .find(|eq| eq.defines == Signal::Effort(BondId(0)))
            .unwrap();
        assert_eq!(source.deps, [Signal::Flow(BondId(1))]);
        assert_eq!(eqs.outputs[0].deps, [Signal::Effort(BondId(0))]);
    }

    #[test]
    fn name_the_elements_on_an_algebraic_loop() {
        let (_, eqs) =
            derive_text("model M { Se s = 1.0; R a = 1.0; R b = 2.0; 1 v; s -> v -> { a, b }; }");
        let message = eqs.err().unwrap().to_string();
        assert!(message.starts_with("algebraic loop: "), "{message}");
        for name in ["R `a`", "R `b`", "1-junction `v`"] {
            assert!(message.contains(name), "{message}");
        }
    }

    #[test]
    fn follow_dependencies_through_junctions_into_the_jacobian_pattern() {
        // Two masses coupled by a spring; the second also has a damper to ground. States:
        // 0 a.p, 1 k.q, 2 b.p. ṗa = -k q; q̇ = va - vb; ṗb = k q - c vb.
        let (_, eqs) = derive_text(
            "model M { I a = 1.0; C k = 1.0; I b = 1.0; R c = 1.0; 1 va; 0 s; 1 vb;
                       va -> a; va -> s -> k; s -> vb -> { b, c }; }",
        );
        assert_eq!(
            eqs.unwrap().state_dependencies(),
            [vec![1], vec![0, 2], vec![1, 2]]
        );
    }
}
