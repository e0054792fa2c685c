//! Part of the equations stage: what SCAP alone cannot order, made into one implicit
//! system solved at every evaluation.
//!
//! - Dependent storage (a C or I in derivative causality, allowed with
//!   `#[allow(derivative_causality)]`) has no state. Its energy variable E (p = m f for
//!   an I, q = k⁻¹ e for a C) is a function of the states and time, computed by the
//!   equations its received variable reads (its *closure*); what it returns is d/dt E,
//!   the eps part of E evaluated on `Tangent` numbers carrying the state derivatives.
//!   Its equation therefore reads the derivatives of the states E reads.
//! - Equations that still cannot be ordered form cycles: through dependent storage
//!   (a constraint: the derivative of an independent momentum, for a mechanism) or
//!   among resistors and junctions (an algebraic loop, allowed with
//!   `#[allow(algebraic_loops)]`). Each cycle is *torn*: a signal on it is read as an
//!   unknown z_k before it is computed, and the residual z_k − (its computed value) is
//!   solved by Newton's method (one step when every equation on the cycles is linear
//!   in the unknowns).

use std::collections::{BTreeMap, BTreeSet};

use syn::Expr;

use crate::causality::{Causality, ElementCausality};
use crate::equations::{cycle_elements, sequence, Derivative, Equation, Rhs, State};
use crate::errors::Errors;
use crate::ir::Lint;
use crate::ir::{ElementId, ElementKind, Graph, Shape};
use crate::signals::Signal;

/// A storage element in derivative causality.
pub struct Dependent {
    /// The C or I.
    pub element: ElementId,
    /// The variable it receives from the junction structure: its bond's flow (I) or
    /// effort (C).
    pub receives: Signal,
    /// The variable it returns: d/dt of its energy variable (effort for an I, flow for
    /// a C).
    pub returns: Signal,
    /// Whether its bond points away from it (its port variables are the bond's negated
    /// flow).
    pub negate: bool,
    /// Its coefficient (inertia or stiffness), rewritten.
    pub modulus: Expr,
    /// The signals the coefficient reads.
    pub modulus_deps: Vec<Signal>,
    /// The shape of its bond.
    pub shape: Shape,
    /// The equations (indices into `Equations::ordered`, in order) that compute what E
    /// reads.
    pub closure: Vec<usize>,
    /// The states E reads (sorted).
    pub states: Vec<usize>,
}

/// A signal read as an unknown before it is computed.
pub struct Tear {
    /// The signal.
    pub signal: Signal,
    /// Its shape.
    pub shape: Shape,
    /// Where its components start in z.
    pub offset: usize,
    /// Its cycle group (index into [`System::groups`]).
    pub group: usize,
}

/// A strongly connected set of equations that needed tearing.
pub struct Group {
    /// The elements of its equations, in declaration order.
    pub elements: Vec<ElementId>,
    /// The dependent storage on it (empty for an algebraic loop).
    pub dependent: Vec<ElementId>,
    /// The allowance that permits it, for an algebraic loop.
    pub allowance: Option<usize>,
}

impl Group {
    /// Whether it is an algebraic loop rather than a constraint through dependent
    /// storage.
    pub fn is_loop(&self) -> bool {
        self.dependent.is_empty()
    }
}

/// The implicit part of a model.
#[derive(Default)]
pub struct System {
    /// The torn signals in the order of z.
    pub tears: Vec<Tear>,
    /// The cycle groups.
    pub groups: Vec<Group>,
    /// Whether every equation on the cycles is linear in the unknowns.
    pub linear: bool,
}

impl System {
    /// K: the number of scalar unknowns.
    pub fn size(&self) -> usize {
        self.tears.iter().map(|t| t.shape.len()).sum()
    }
}

/// The message for an explicit law on dependent storage.
pub fn explicit_law_message(graph: &Graph, id: ElementId) -> String {
    let (variable, form) = match graph.element(id).kind {
        ElementKind::I => ("p = m f", "`I name = m;` (m a number, vector or matrix, possibly modulated by states, parameters and t)"),
        _ => ("q = e / k", "`C name = k;` (k a number, vector or matrix, possibly modulated by states, parameters and t)"),
    };
    format!(
        "{} takes derivative causality (dependent storage), which needs a linear law ({variable}) \
         to compute its energy variable from what it receives; an explicit law cannot be \
         inverted\nhelp: write it as {form}, or give it a compliant connection so that it keeps \
         integral causality",
        graph.describe(id)
    )
}

/// `init` on dependent storage is an error: it has no state.
pub fn check_inits(graph: &Graph, causality: &Causality, errors: &mut Errors) {
    for init in &graph.inits {
        if causality.element[init.element.0] == ElementCausality::Derivative {
            let var = if graph.element(init.element).kind == ElementKind::I {
                "momentum"
            } else {
                "displacement"
            };
            errors.at(
                init.span,
                format!(
                    "{} is dependent storage (derivative causality): it has no state, its {var} \
                     follows from the states of the elements it is rigidly tied to, so it cannot \
                     be initialised\nhelp: remove this `init`; set the initial state of the \
                     independent element it follows instead",
                    graph.describe(init.element)
                ),
            );
        }
    }
}

fn defined_by(equations: &[Equation]) -> BTreeMap<Signal, usize> {
    equations
        .iter()
        .enumerate()
        .map(|(i, eq)| (eq.defines, i))
        .collect()
}

/// The equations E of `dependent` reads, transitively (indices), and the states.
fn closure(equations: &[Equation], dependent: &Dependent) -> (BTreeSet<usize>, BTreeSet<usize>) {
    let defined = defined_by(equations);
    let mut seen = BTreeSet::new();
    let mut states = BTreeSet::new();
    let mut stack: Vec<Signal> = vec![dependent.receives];
    stack.extend(&dependent.modulus_deps);
    while let Some(signal) = stack.pop() {
        if let Signal::State(i) = signal {
            states.insert(i);
            continue;
        }
        if let Some(&i) = defined.get(&signal) {
            if seen.insert(i) {
                stack.extend(&equations[i].deps);
            }
        }
    }
    (seen, states)
}

/// Gives each dependent equation its dependencies: the derivatives of the states its E
/// reads (and those states, for the Jacobian pattern). Refuses an E that reads a
/// dependent variable (a higher-index problem).
pub fn link_dependent(
    graph: &Graph,
    states: &[State],
    equations: &mut [Equation],
    dependent: &mut [Dependent],
) -> syn::Result<()> {
    let mut errors = Errors::default();
    for d in dependent.iter_mut() {
        let (members, read) = closure(equations, d);
        let through: Vec<ElementId> = members
            .iter()
            .filter(|&&i| matches!(equations[i].rhs, Rhs::Dependent(_)))
            .map(|&i| equations[i].element)
            .collect();
        if let Some(&other) = through.first() {
            errors.at(
                graph.element(d.element).name.span(),
                format!(
                    "{} is dependent storage whose energy variable would need what {} returns \
                     (a derivative of a derivative: a higher-index problem, which bgdsl does not \
                     solve)\nhelp: give one of them a compliant connection (a stiff C on a \
                     0-junction between them) so that it keeps integral causality",
                    graph.describe(d.element),
                    graph.describe(other)
                ),
            );
            continue;
        }
        d.states = read.into_iter().collect();
        let mut deps = Vec::new();
        for &j in &d.states {
            match &states[j].derivative {
                Derivative::Term(term) => deps.push(term.signal),
                Derivative::Expr(der) => deps.extend(&der.deps),
            }
            deps.push(Signal::State(j));
        }
        deps.dedup();
        if let Some(eq) = equations
            .iter_mut()
            .find(|eq| eq.defines == d.returns && matches!(eq.rhs, Rhs::Dependent(_)))
        {
            eq.deps = deps;
        }
    }
    errors.finish()
}

/// Orders the equations, tearing every cycle the model allows; refuses one it does not.
pub fn tear(
    graph: &Graph,
    causality: &Causality,
    states: &[State],
    equations: Vec<Equation>,
    dependent: &[Dependent],
) -> syn::Result<(Vec<Equation>, System)> {
    let mut torn: Vec<Signal> = Vec::new();
    let mut tear_group: Vec<usize> = Vec::new();
    let mut group_members: Vec<BTreeSet<usize>> = Vec::new();
    let mut groups: Vec<Group> = Vec::new();
    let order = loop {
        let cycle = match sequence(&equations, &torn) {
            Ok(order) => break order,
            Err(cycle) => cycle,
        };
        let elements = cycle_elements(&equations, &cycle);
        let on_it: Vec<ElementId> = cycle
            .iter()
            .filter_map(|&i| match equations[i].rhs {
                Rhs::Dependent(k) => Some(dependent[k].element),
                _ => None,
            })
            .collect();
        let allowance = if on_it.is_empty() {
            let bonds: Vec<crate::ir::BondId> = cycle
                .iter()
                .filter_map(|&i| match equations[i].defines {
                    Signal::Effort(b) | Signal::Flow(b) => Some(b),
                    Signal::State(_) => None,
                })
                .collect();
            match graph.allowance(Lint::AlgebraicLoops, &elements, &bonds) {
                Some(a) => Some(a),
                None => return Err(crate::equations::algebraic_loop(graph, &elements)),
            }
        } else {
            None
        };
        let choice = choose_tear(graph, states, &equations, &cycle, dependent);
        torn.push(equations[choice].defines);
        let cycle_set: BTreeSet<usize> = cycle.iter().copied().collect();
        let group = match group_members
            .iter()
            .position(|g| !g.is_disjoint(&cycle_set))
        {
            Some(g) => {
                group_members[g].extend(cycle_set);
                let all: Vec<usize> = group_members[g].iter().copied().collect();
                groups[g].elements = cycle_elements(&equations, &all);
                for e in on_it {
                    if !groups[g].dependent.contains(&e) {
                        groups[g].dependent.push(e);
                    }
                }
                if groups[g].allowance.is_none() && groups[g].dependent.is_empty() {
                    groups[g].allowance = allowance;
                }
                g
            }
            None => {
                group_members.push(cycle_set);
                groups.push(Group {
                    elements,
                    dependent: on_it,
                    allowance,
                });
                groups.len() - 1
            }
        };
        tear_group.push(group);
    };
    check_unused(graph, causality, &groups)?;
    let ordered = crate::equations::arrange(equations, order);
    let mut offset = 0;
    let tears: Vec<Tear> = torn
        .iter()
        .zip(&tear_group)
        .map(|(&signal, &group)| {
            let shape = match signal {
                Signal::Effort(b) | Signal::Flow(b) => Shape::of_dimension(graph.bond_dims[b.0]),
                Signal::State(i) => states[i].shape,
            };
            let tear = Tear {
                signal,
                shape,
                offset,
                group,
            };
            offset += shape.len();
            tear
        })
        .collect();
    let linear = is_linear(states, &ordered, &torn, dependent);
    Ok((
        ordered,
        System {
            tears,
            groups,
            linear,
        },
    ))
}

/// The signal to tear on a cycle: the derivative of a state that dependent storage
/// reads, else a resistor's output, else the signal most equations on the cycle read.
fn choose_tear(
    graph: &Graph,
    states: &[State],
    equations: &[Equation],
    cycle: &[usize],
    dependent: &[Dependent],
) -> usize {
    let rates: Vec<Signal> = cycle
        .iter()
        .filter_map(|&i| match equations[i].rhs {
            Rhs::Dependent(k) => Some(k),
            _ => None,
        })
        .flat_map(|k| dependent[k].states.iter())
        .filter_map(|&j| match &states[j].derivative {
            Derivative::Term(term) => Some(term.signal),
            Derivative::Expr(_) => None,
        })
        .collect();
    if let Some(&i) = cycle
        .iter()
        .find(|&&i| rates.contains(&equations[i].defines))
    {
        return i;
    }
    if let Some(&i) = cycle
        .iter()
        .find(|&&i| graph.element(equations[i].element).kind == ElementKind::R)
    {
        return i;
    }
    let readers = |i: usize| {
        cycle
            .iter()
            .filter(|&&r| equations[r].deps.contains(&equations[i].defines))
            .count()
    };
    cycle
        .iter()
        .copied()
        .max_by_key(|&i| (readers(i), std::cmp::Reverse(i)))
        .unwrap_or(cycle[0])
}

/// Whether every equation that reads an unknown (directly or not) is linear in it.
fn is_linear(
    states: &[State],
    ordered: &[Equation],
    torn: &[Signal],
    dependent: &[Dependent],
) -> bool {
    let mut varying: BTreeSet<Signal> = torn.iter().copied().collect();
    // Torn signals are read before they are computed: two passes reach every reader.
    for _ in 0..2 {
        for eq in ordered {
            if eq.deps.iter().any(|d| varying.contains(d)) {
                varying.insert(eq.defines);
            }
        }
    }
    ordered.iter().all(|eq| {
        let reads = |s: &Signal| varying.contains(s);
        match &eq.rhs {
            Rhs::Sum(_) | Rhs::Component { .. } | Rhs::Assemble(_) => true,
            Rhs::Law { .. } => !eq.deps.iter().any(reads),
            Rhs::Scaled { term, .. } => !eq.deps.iter().filter(|&&d| d != term.signal).any(reads),
            Rhs::Dependent(k) => {
                dependent[*k]
                    .states
                    .iter()
                    .all(|&j| match &states[j].derivative {
                        Derivative::Term(_) => true,
                        Derivative::Expr(der) => !der.deps.iter().any(reads),
                    })
            }
        }
    })
}

/// An allowance nothing uses is an error, so a stale opt-in never hides anything.
fn check_unused(graph: &Graph, causality: &Causality, groups: &[Group]) -> syn::Result<()> {
    let mut errors = Errors::default();
    for (index, allowance) in graph.allowances.iter().enumerate() {
        let used = causality.dependent.iter().any(|&(_, a)| a == index)
            || groups.iter().any(|g| g.allowance == Some(index));
        if used {
            continue;
        }
        let what = match allowance.lint {
            Lint::DerivativeCausality => {
                "no storage element it covers takes derivative causality (each keeps its own state)"
            }
            Lint::AlgebraicLoops => "no algebraic loop runs through what it covers",
        };
        let earlier = graph
            .allowances
            .iter()
            .take(index)
            .any(|a| a.lint == allowance.lint);
        let also = if earlier {
            " (or an allowance written earlier already covers it)"
        } else {
            ""
        };
        errors.at(
            allowance.span,
            format!(
                "`{}` is not needed: {what}{also}\nhelp: remove it, so that a stale opt-in never \
                 hides a mistake",
                allowance.lint.name()
            ),
        );
    }
    errors.finish()
}

/// Places the closure of each dependent element in the final order, and refuses an E
/// that reads an unknown of an algebraic loop.
pub fn finish_dependent(
    graph: &Graph,
    ordered: &[Equation],
    system: &System,
    dependent: &mut [Dependent],
) -> syn::Result<()> {
    let mut errors = Errors::default();
    for d in dependent.iter_mut() {
        let (members, _) = closure(ordered, d);
        if let Some(tear) = system
            .tears
            .iter()
            .find(|t| members.iter().any(|&i| ordered[i].defines == t.signal))
        {
            let group = &system.groups[tear.group];
            let names: Vec<String> = group.elements.iter().map(|&e| graph.describe(e)).collect();
            errors.at(
                graph.element(d.element).name.span(),
                format!(
                    "{} is dependent storage whose energy variable reads a variable of an \
                     algebraic loop ({}): it must be a function of the states and time alone \
                     (a higher-index problem otherwise)\nhelp: break the loop with a storage \
                     element, or give the storage a compliant connection",
                    graph.describe(d.element),
                    names.join(", ")
                ),
            );
        }
        d.closure = members.into_iter().collect();
    }
    errors.finish()
}

#[cfg(test)]
mod should {
    use crate::equations::Equations;

    fn derive(text: &str) -> syn::Result<Equations> {
        let file: crate::syntax::File = syn::parse_str(text).unwrap();
        let graph = crate::resolve::resolve(file.models.into_iter().next().unwrap()).unwrap();
        let causality = crate::causality::assign(&graph)
            .map_err(|errors| crate::causality::render(&graph, &errors[0]))?;
        crate::equations::derive(&graph, &causality)
    }

    const GEAR: &str = "#[allow(derivative_causality)] model G { Se s = 1.0; I a = 0.2; I b = 0.05;
        1 w1; 1 w2; TF g = 3.0; s -> w1 -> a; w1 -> g -> w2 -> b; }";

    #[test]
    fn tear_the_independent_momentum_rate_of_a_gear_and_call_it_linear() {
        let eqs = derive(GEAR).unwrap();
        assert_eq!(eqs.states.len(), 1);
        assert_eq!(eqs.dependent.len(), 1);
        assert_eq!(eqs.dependent[0].states, [0]);
        assert_eq!(eqs.implicit.size(), 1);
        // The torn signal is what ṗ_a integrates: the effort on a's bond (bond 1).
        assert_eq!(
            eqs.implicit.tears[0].signal,
            crate::signals::Signal::Effort(crate::ir::BondId(1))
        );
        assert!(eqs.implicit.linear);
        assert!(!eqs.implicit.groups[0].is_loop());
    }

    #[test]
    fn take_the_allowance_from_a_bond_statement_or_an_element() {
        let on_bond = derive(
            "model G { Se s = 1.0; I a = 0.2; I b = 0.05; 1 w1; 1 w2; TF g = 3.0;
             s -> w1 -> a; #[allow(derivative_causality)] w1 -> g -> w2 -> b; }",
        )
        .unwrap();
        assert_eq!(on_bond.dependent.len(), 1);
        let on_element = derive(
            "model G { Se s = 1.0; I a = 0.2; #[allow(derivative_causality)] I b = 0.05;
             1 w1; 1 w2; TF g = 3.0; s -> w1 -> a; w1 -> g -> w2 -> b; }",
        )
        .unwrap();
        assert_eq!(on_element.dependent.len(), 1);
        // On the other inertia, which keeps its state, it covers nothing.
        let elsewhere = derive(
            "model G { Se s = 1.0; #[allow(derivative_causality)] I a = 0.2; I b = 0.05;
             1 w1; 1 w2; TF g = 3.0; s -> w1 -> a; w1 -> g -> w2 -> b; }",
        )
        .err()
        .unwrap()
        .to_string();
        assert!(elsewhere.contains("derivative causality"), "{elsewhere}");
    }

    #[test]
    fn need_no_unknown_when_a_flow_source_drives_the_storage() {
        let eqs = derive(
            "#[allow(derivative_causality)] model M { Sf s = t; I m = 2.0; 1 v; s -> v -> m; }",
        )
        .unwrap();
        assert_eq!((eqs.states.len(), eqs.dependent.len()), (0, 1));
        assert_eq!(eqs.implicit.size(), 0);
    }

    #[test]
    fn tear_a_resistor_output_and_classify_the_loop_by_its_laws() {
        let linear = derive(
            "#[allow(algebraic_loops)] model M { I m = 1.0; R a = 2.0; R b = 3.0; 1 v; 0 j;
             v -> m; v -> j -> { a, b }; }",
        )
        .unwrap();
        assert_eq!(linear.implicit.size(), 1);
        assert!(linear.implicit.groups[0].is_loop());
        assert!(linear.implicit.linear);
        let quadratic = derive(
            "#[allow(algebraic_loops)] model M { I m = 1.0; R a { e = 2.0 * f * f.abs() };
             R b = 3.0; 1 v; 0 j; v -> m; v -> j -> { a, b }; }",
        )
        .unwrap();
        assert_eq!(quadratic.implicit.size(), 1);
        assert!(!quadratic.implicit.linear);
    }

    #[test]
    fn refuse_an_allowance_nothing_uses() {
        let message = derive(
            "#[allow(algebraic_loops)] model M { Se s = 1.0; I m = 1.0; 1 v; s -> v -> m; }",
        )
        .err()
        .unwrap()
        .to_string();
        assert!(
            message.contains("is not needed") && message.contains("remove it"),
            "{message}"
        );
    }

    #[test]
    fn call_a_conflict_between_rigid_connections_a_redundant_constraint() {
        let message = derive(
            "#[allow(derivative_causality)] model M { Se s = 1.0; I a = 0.2; I b = 0.05;
             1 w1; 1 w2; TF g = 3.0; TF h = 3.0; s -> w1 -> a; w1 -> g -> w2 -> b;
             w1 -> h -> w2; }",
        )
        .err()
        .unwrap()
        .to_string();
        assert!(
            message.starts_with("redundant constraint at 1-junction `w2`"),
            "{message}"
        );
        for name in ["TF `g`", "TF `h`", "I `a`"] {
            assert!(message.contains(name), "{message}");
        }
    }

    #[test]
    fn say_that_dependent_storage_has_no_state_to_read() {
        let text = GEAR.replace(
            "w1 -> g -> w2 -> b;",
            "w1 -> g -> w2 -> b; output pb = b.p;",
        );
        let message = derive(&text).err().unwrap().to_string();
        assert!(
            message.contains("has no state `p`") && message.contains("`b.f`"),
            "{message}"
        );
    }

    #[test]
    fn refuse_an_init_on_dependent_storage() {
        let text = GEAR.replace("w1 -> g -> w2 -> b;", "w1 -> g -> w2 -> b; init b.p = 1.0;");
        let message = derive(&text).err().unwrap().to_string();
        assert!(message.contains("has no state"), "{message}");
    }
}
