//! Stage 3: sequential causality assignment (SCAP, Karnopp & Rosenberg).
//!
//! Order: sources, then storage elements one at a time in integral causality, then
//! resistors whose law gives only one form (their causality is as fixed as a source's),
//! then the other resistors, then whatever bonds are left; after each choice the
//! consequences are propagated through junctions, transformers and gyrators. The first
//! three are requirements, and propagation only derives their necessary consequences,
//! so a clash among them is a real mistake. The last two are free choices: they are
//! searched depth first with backtracking (preferred option first, so the result is
//! the textbook one whenever that works), which finds an assignment whenever one
//! exists, where plain greedy SCAP can paint itself into a corner. Every stroke remembers
//! which choice forced it (its root) and through which bond, so a conflict names both
//! parties and a derivative causality names the path that forced it.
//!
//! A requirement that leads to a conflict is rolled back, so each reported mistake is
//! independent of the others.

use std::collections::VecDeque;

use crate::ir::{BondId, ElementId, ElementKind, Graph};

/// What each element ended up with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementCausality {
    /// Storage integrating its input.
    Integral,
    /// Resistor computing effort from flow.
    Resistance,
    /// Resistor computing flow from effort.
    Conductance,
    /// Sources, junctions, TF and GY: nothing to choose.
    Fixed,
    /// Storage whose input is fixed by the rest of the graph (allowed with
    /// `#[allow(derivative_causality)]`): dependent storage, without a state.
    Derivative,
}

/// The result of causality assignment.
#[derive(Debug)]
pub struct Causality {
    /// For each bond, the element at its causal-stroke end: the element the effort acts
    /// on, which answers with the flow.
    pub stroke_at: Vec<ElementId>,
    /// For each element, its causality.
    pub element: Vec<ElementCausality>,
    /// The storage elements in derivative causality, in declaration order, each with
    /// the allowance (its index in the model's allowances) that permits it.
    pub dependent: Vec<(ElementId, usize)>,
}

/// A mistake SCAP found, as data; [`render`] turns it into a message.
#[derive(Debug, PartialEq, Eq)]
pub enum CausalityError {
    /// `second` needs a causality that `first` has already imposed the other way.
    Conflict {
        /// The element whose requirement could not be met.
        second: ElementId,
        /// The element whose earlier choice fixed it.
        first: ElementId,
        /// The junction or two-port where the two meet, if not on `second`'s bond.
        at: Option<ElementId>,
        /// How each party's causality reached the meeting place: `first`'s route and
        /// `second`'s, each from the element to the meeting place, both ends included.
        routes: [Vec<ElementId>; 2],
        /// At a junction: whether two bonds set its common variable (`Some(true)`) or
        /// none can (`Some(false)`).
        twice: Option<bool>,
    },
    /// A storage element pushed into derivative causality.
    Derivative {
        /// The storage element.
        element: ElementId,
        /// The elements from the one that forced it to it, both ends included.
        path: Vec<ElementId>,
    },
    /// A resistor whose causality needs the form of its law that is not given.
    MissingForm {
        /// The resistor.
        element: ElementId,
        /// Whether it must compute its flow (`f = ...e...`) rather than its effort.
        needs_flow_form: bool,
        /// The element whose choice fixed it.
        forced_by: ElementId,
        /// The elements from `forced_by` to the resistor, both ends included.
        path: Vec<ElementId>,
    },
    /// A junction that ends with no bond, or two, setting its common variable: an
    /// internal invariant, which no input reaches. A successful search has set every
    /// bond, and the junction rule ran on the last bond set at each junction with all
    /// its bonds already set, where it accepts exactly one setter and rejects (and
    /// undoes) anything else; bonds from an element to itself are refused in
    /// `resolve.rs`. Kept as a spanned error so that a bug here never panics.
    Junction {
        /// The junction.
        junction: ElementId,
        /// How many bonds set its common variable.
        setters: usize,
    },
}

#[derive(Clone, Copy, Debug)]
struct Stroke {
    at: ElementId,
    /// The element whose choice this stroke follows from.
    root: ElementId,
    /// The stroke that triggered this one, and the element that propagated it.
    cause: Option<(BondId, ElementId)>,
}

/// Assigns causality to every bond, or reports every independent mistake.
pub fn assign(graph: &Graph) -> Result<Causality, Vec<CausalityError>> {
    let mut scap = Scap {
        graph,
        strokes: vec![None; graph.bonds.len()],
        queue: VecDeque::new(),
        trail: Vec::new(),
        errors: Vec::new(),
        dependent: Vec::new(),
    };
    let of_kind = |kinds: &[ElementKind]| -> Vec<ElementId> {
        graph
            .element_ids()
            .filter(|&id| kinds.contains(&graph.element(id).kind))
            .collect()
    };
    for id in of_kind(&[ElementKind::Se, ElementKind::Sf]) {
        scap.choose_one_port(id);
    }
    for id in of_kind(&[ElementKind::C, ElementKind::I]) {
        scap.choose_one_port(id);
    }
    let (free, one_form): (Vec<ElementId>, Vec<ElementId>) = of_kind(&[ElementKind::R])
        .into_iter()
        .partition(|&id| scap.is_free(id));
    for id in one_form {
        scap.choose_one_port(id);
    }
    if scap.errors.is_empty() {
        // Free decisions: linear resistors, then bonds that nothing has fixed.
        let mut decisions: Vec<Decision> = free
            .iter()
            .map(|&id| {
                let bond = graph.element(id).bonds[0];
                let wanted = preferred_stroke(graph, id, bond);
                let other = if wanted == id {
                    graph.bond(bond).other(id)
                } else {
                    id
                };
                Decision {
                    bond,
                    options: [wanted, other],
                    root: id,
                }
            })
            .collect();
        decisions.extend(graph.bond_ids().map(|bond| {
            let b = graph.bond(bond);
            Decision {
                bond,
                options: [b.to, b.from],
                root: b.to,
            }
        }));
        let mut budget = SEARCH_BUDGET;
        if let Err(clash) = scap.decide(&decisions, &mut budget) {
            let root = decisions
                .iter()
                .find(|d| scap.strokes[d.bond.0].is_none())
                .map_or(clash.first, |d| d.root);
            scap.report(root, clash);
        }
    }
    scap.finish()
}

/// The stroke a one-port prefers, before anything is propagated.
fn preferred_stroke(graph: &Graph, id: ElementId, bond: BondId) -> ElementId {
    let element = graph.element(id);
    let other = graph.bond(bond).other(id);
    match element.kind {
        // Imposes its effort: the other end receives it.
        ElementKind::Se | ElementKind::C => other,
        // Imposes its flow: it receives the effort.
        ElementKind::Sf | ElementKind::I => id,
        ElementKind::R if element.law.has_effort_form() => other,
        _ => id,
    }
}

/// A free choice: a bond whose stroke may go to either option, the first preferred.
#[derive(Clone, Copy)]
struct Decision {
    bond: BondId,
    options: [ElementId; 2],
    /// The element blamed if no option works.
    root: ElementId,
}

/// How many free options the search may try before giving up: far more than any
/// hand-written graph needs, small enough that a pathological one fails fast.
const SEARCH_BUDGET: usize = 100_000;

struct Scap<'g> {
    graph: &'g Graph,
    strokes: Vec<Option<Stroke>>,
    queue: VecDeque<BondId>,
    /// Every bond assigned, in order, so a choice can be undone back to a checkpoint.
    trail: Vec<BondId>,
    errors: Vec<CausalityError>,
    /// Storage elements allowed into derivative causality, with their allowance.
    dependent: Vec<(ElementId, usize)>,
}

/// Two requirements met at `at`: the one already there came from `first`.
struct Clash {
    first: ElementId,
    at: Option<ElementId>,
    /// The routes of `first`'s and of the new requirement's causality to `at`.
    routes: [Vec<ElementId>; 2],
    /// See [`CausalityError::Conflict::twice`].
    twice: Option<bool>,
}

impl Scap<'_> {
    fn choose_one_port(&mut self, id: ElementId) {
        let Some(&bond) = self.graph.element(id).bonds.first() else {
            return;
        };
        let wanted = preferred_stroke(self.graph, id, bond);
        match self.strokes[bond.0] {
            None => self.choose(bond, wanted, id),
            Some(stroke) if stroke.at == wanted => {}
            // A resistor takes either causality its law can compute.
            Some(stroke)
                if self.graph.element(id).kind == ElementKind::R
                    && self.resistor_accepts(id, stroke.at) => {}
            Some(stroke) => {
                let kind = self.graph.element(id).kind;
                if matches!(kind, ElementKind::C | ElementKind::I) {
                    let allowed =
                        self.graph
                            .allowance(crate::ir::Lint::DerivativeCausality, &[id], &[bond]);
                    if let Some(allowance) = allowed {
                        self.dependent.push((id, allowance));
                        return;
                    }
                }
                let error = match kind {
                    ElementKind::C | ElementKind::I => CausalityError::Derivative {
                        element: id,
                        path: self.path_to(bond, id),
                    },
                    ElementKind::R => CausalityError::MissingForm {
                        element: id,
                        needs_flow_form: stroke.at == id,
                        forced_by: stroke.root,
                        path: self.path_to(bond, id),
                    },
                    _ => {
                        // At a junction: the source wanted to set its common variable
                        // (and another bond does), or not to (and no other bond can).
                        let other = self.graph.bond(bond).other(id);
                        let twice = matches!(
                            self.graph.element(other).kind,
                            ElementKind::Zero | ElementKind::One
                        )
                        .then(|| self.sets_common(other, wanted));
                        CausalityError::Conflict {
                            second: id,
                            first: stroke.root,
                            at: None,
                            routes: [self.path_to(bond, other), vec![id, other]],
                            twice,
                        }
                    }
                };
                self.errors.push(error);
            }
        }
    }

    fn resistor_accepts(&self, id: ElementId, stroke_at: ElementId) -> bool {
        let law = &self.graph.element(id).law;
        if stroke_at == id {
            law.has_flow_form()
        } else {
            law.has_effort_form()
        }
    }

    /// A linear resistor can take either causality.
    fn is_free(&self, id: ElementId) -> bool {
        let element = self.graph.element(id);
        element.kind == ElementKind::R && matches!(element.law, crate::ir::Law::Linear(_))
    }

    /// Makes a required choice and propagates it; on a clash, undoes it and reports.
    fn choose(&mut self, bond: BondId, at: ElementId, root: ElementId) {
        if let Err(clash) = self.try_choose(bond, at, root) {
            self.report(root, clash);
        }
    }

    /// Depth-first search over the free decisions still open, each option propagated
    /// before the next decision; undoes its own choices when it fails.
    fn decide(&mut self, decisions: &[Decision], budget: &mut usize) -> Result<(), Clash> {
        let Some(&Decision {
            bond,
            options,
            root,
        }) = decisions.iter().find(|d| self.strokes[d.bond.0].is_none())
        else {
            return Ok(());
        };
        let mut first_clash = None;
        for at in options {
            if *budget == 0 {
                break;
            }
            *budget -= 1;
            let checkpoint = self.trail.len();
            let outcome = self.try_choose(bond, at, root).and_then(|()| {
                let deeper = self.decide(decisions, budget);
                if deeper.is_err() {
                    self.rollback(checkpoint);
                }
                deeper
            });
            match outcome {
                Ok(()) => return Ok(()),
                Err(clash) => {
                    first_clash.get_or_insert(clash);
                }
            }
        }
        Err(first_clash.unwrap_or(Clash {
            first: root,
            at: None,
            routes: [Vec::new(), Vec::new()],
            twice: None,
        }))
    }

    fn report(&mut self, root: ElementId, clash: Clash) {
        self.errors.push(CausalityError::Conflict {
            second: root,
            first: clash.first,
            at: clash.at,
            routes: clash.routes,
            twice: clash.twice,
        });
    }

    /// Sets a stroke and propagates it; on a clash, undoes everything it set.
    fn try_choose(&mut self, bond: BondId, at: ElementId, root: ElementId) -> Result<(), Clash> {
        let checkpoint = self.trail.len();
        self.queue.clear();
        self.set(bond, at, root, None);
        let result = self.propagate();
        if result.is_err() {
            self.rollback(checkpoint);
        }
        result
    }

    fn rollback(&mut self, checkpoint: usize) {
        for undone in self.trail.drain(checkpoint..) {
            self.strokes[undone.0] = None;
        }
    }

    fn set(
        &mut self,
        bond: BondId,
        at: ElementId,
        root: ElementId,
        cause: Option<(BondId, ElementId)>,
    ) {
        self.strokes[bond.0] = Some(Stroke { at, root, cause });
        self.trail.push(bond);
        self.queue.push_back(bond);
    }

    fn propagate(&mut self) -> Result<(), Clash> {
        while let Some(bond) = self.queue.pop_front() {
            let b = self.graph.bond(bond);
            for end in [b.from, b.to] {
                match self.graph.element(end).kind {
                    ElementKind::Zero | ElementKind::One => self.junction_rule(end, bond)?,
                    ElementKind::Tf | ElementKind::Gy => self.two_port_rule(end, bond)?,
                    ElementKind::Split => self.splitter_rule(end, bond)?,
                    _ => {}
                }
            }
        }
        Ok(())
    }

    /// Whether `bond` sets the common variable of `junction`: the effort of a
    /// 0-junction comes in on the bond whose stroke is at the junction; the flow of a
    /// 1-junction comes in on the bond whose stroke is at the other end.
    fn sets_common(&self, junction: ElementId, stroke_at: ElementId) -> bool {
        let at_junction = stroke_at == junction;
        match self.graph.element(junction).kind {
            ElementKind::Zero => at_junction,
            _ => !at_junction,
        }
    }

    fn junction_rule(&mut self, junction: ElementId, trigger: BondId) -> Result<(), Clash> {
        let bonds = &self.graph.element(junction).bonds;
        let mut setters = Vec::new();
        let mut free = Vec::new();
        for &bond in bonds {
            match self.strokes[bond.0] {
                Some(stroke) if self.sets_common(junction, stroke.at) => {
                    setters.push((bond, stroke))
                }
                Some(_) => {}
                None => free.push(bond),
            }
        }
        let root = self.strokes[trigger.0].map_or(junction, |s| s.root);
        let cause = Some((trigger, junction));
        match (setters.len(), free.len()) {
            (0, 0) => Err(Clash {
                first: root,
                at: Some(junction),
                routes: [Vec::new(), self.path_to(trigger, junction)],
                twice: Some(false),
            }),
            (0, 1) => {
                // The last free bond must set the common variable.
                let bond = free[0];
                let other = self.graph.bond(bond).other(junction);
                let at = if self.sets_common(junction, junction) {
                    junction
                } else {
                    other
                };
                self.set(bond, at, root, cause);
                Ok(())
            }
            (0, _) => Ok(()),
            (1, _) => {
                for bond in free {
                    let other = self.graph.bond(bond).other(junction);
                    let at = if self.sets_common(junction, junction) {
                        other
                    } else {
                        junction
                    };
                    self.set(bond, at, root, cause);
                }
                Ok(())
            }
            _ => {
                let (first_bond, first) = setters
                    .iter()
                    .map(|&(bond, s)| (bond, s.root))
                    .find(|&(_, r)| r != root)
                    .unwrap_or((setters[0].0, setters[0].1.root));
                // The new requirement's own setter, else the bond that brought it.
                let second_bond = setters
                    .iter()
                    .map(|&(bond, _)| bond)
                    .find(|&bond| bond != first_bond)
                    .unwrap_or(trigger);
                Err(Clash {
                    first,
                    at: Some(junction),
                    routes: [
                        self.path_to(first_bond, junction),
                        self.path_to(second_bond, junction),
                    ],
                    twice: Some(true),
                })
            }
        }
    }

    fn two_port_rule(&mut self, two_port: ElementId, trigger: BondId) -> Result<(), Clash> {
        let element = self.graph.element(two_port);
        let (port1, port2) = (element.bonds[0], element.bonds[1]);
        let gyrator = element.kind == ElementKind::Gy;
        // A TF passes effort through (exactly one port receives effort), a GY turns it
        // into flow (both ports receive effort, or neither).
        let partner_at = |stroke_at: ElementId, partner: BondId| {
            let receives = stroke_at == two_port;
            let partner_receives = if gyrator { receives } else { !receives };
            if partner_receives {
                two_port
            } else {
                self.graph.bond(partner).other(two_port)
            }
        };
        let (this, partner) = if trigger == port1 {
            (port1, port2)
        } else {
            (port2, port1)
        };
        let Some(stroke) = self.strokes[this.0] else {
            return Ok(());
        };
        let wanted = partner_at(stroke.at, partner);
        match self.strokes[partner.0] {
            None => {
                self.set(partner, wanted, stroke.root, Some((this, two_port)));
                Ok(())
            }
            Some(existing) if existing.at == wanted => Ok(()),
            Some(existing) => Err(Clash {
                first: if existing.root != stroke.root {
                    existing.root
                } else {
                    stroke.root
                },
                at: Some(two_port),
                routes: [
                    self.path_to(partner, two_port),
                    self.path_to(this, two_port),
                ],
                twice: None,
            }),
        }
    }

    /// A splitter passes effort through every component the same way: its multibond
    /// brings effort in exactly when its components carry it out. (Only the splitters
    /// in front of whole-vector elements reach this stage; see [`crate::split`].)
    fn splitter_rule(&mut self, splitter: ElementId, trigger: BondId) -> Result<(), Clash> {
        let bonds = &self.graph.element(splitter).bonds;
        let Some(stroke) = self.strokes[trigger.0] else {
            return Ok(());
        };
        let whole = bonds[0];
        let receives_whole = if trigger == whole {
            stroke.at == splitter
        } else {
            // A component bringing effort in means the multibond carries it out.
            stroke.at != splitter
        };
        let cause = Some((trigger, splitter));
        for (port, &bond) in bonds.iter().enumerate() {
            let receives = if port == 0 {
                receives_whole
            } else {
                !receives_whole
            };
            let wanted = if receives {
                splitter
            } else {
                self.graph.bond(bond).other(splitter)
            };
            match self.strokes[bond.0] {
                None => self.set(bond, wanted, stroke.root, cause),
                Some(existing) if existing.at == wanted => {}
                Some(existing) => {
                    return Err(Clash {
                        first: if existing.root != stroke.root {
                            existing.root
                        } else {
                            stroke.root
                        },
                        at: Some(splitter),
                        routes: [
                            self.path_to(bond, splitter),
                            self.path_to(trigger, splitter),
                        ],
                        twice: None,
                    })
                }
            }
        }
        Ok(())
    }

    /// The elements from the choice that fixed `bond` to `target`.
    fn path_to(&self, bond: BondId, target: ElementId) -> Vec<ElementId> {
        let mut path = vec![target];
        let mut current = self.strokes[bond.0];
        while let Some(stroke) = current {
            match stroke.cause {
                Some((parent, via)) => {
                    if path.last() != Some(&via) {
                        path.push(via);
                    }
                    current = self.strokes[parent.0];
                }
                None => {
                    if path.last() != Some(&stroke.root) {
                        path.push(stroke.root);
                    }
                    break;
                }
            }
        }
        path.reverse();
        path
    }

    fn finish(mut self) -> Result<Causality, Vec<CausalityError>> {
        let graph = self.graph;
        if self.errors.is_empty() {
            for junction in graph.element_ids() {
                let element = graph.element(junction);
                // An unused submodel port has no bonds and nothing to set.
                if !matches!(element.kind, ElementKind::Zero | ElementKind::One)
                    || element.bonds.is_empty()
                {
                    continue;
                }
                let setters = graph
                    .element(junction)
                    .bonds
                    .iter()
                    .filter(|b| self.strokes[b.0].is_some_and(|s| self.sets_common(junction, s.at)))
                    .count();
                if setters != 1 {
                    self.errors
                        .push(CausalityError::Junction { junction, setters });
                }
            }
        }
        if !self.errors.is_empty() {
            return Err(self.errors);
        }
        let stroke_at: Vec<ElementId> = self
            .strokes
            .iter()
            .map(|s| s.map_or(ElementId(0), |s| s.at))
            .collect();
        let element = graph
            .element_ids()
            .map(|id| match graph.element(id).kind {
                ElementKind::C | ElementKind::I if self.dependent.iter().any(|&(d, _)| d == id) => {
                    ElementCausality::Derivative
                }
                ElementKind::C | ElementKind::I => ElementCausality::Integral,
                ElementKind::R => {
                    let bond = graph.element(id).bonds[0];
                    if stroke_at[bond.0] == id {
                        ElementCausality::Conductance
                    } else {
                        ElementCausality::Resistance
                    }
                }
                _ => ElementCausality::Fixed,
            })
            .collect();
        Ok(Causality {
            stroke_at,
            element,
            dependent: self.dependent,
        })
    }
}

/// The mistakes worth reporting: a redundant constraint is found once from each rigid
/// side it over-determines (each storage element's requirement meets the same two
/// connections), so only the first report of one set of connections is kept.
pub fn independent<'e>(graph: &Graph, errors: &'e [CausalityError]) -> Vec<&'e CausalityError> {
    let mut seen: Vec<Vec<ElementId>> = Vec::new();
    errors
        .iter()
        .filter(|error| {
            let CausalityError::Conflict {
                second,
                first,
                at,
                routes,
                twice,
            } = error
            else {
                return true;
            };
            let redundant = (first == second || *twice == Some(true))
                && redundant_constraint(graph, *second, *first, *at, routes).is_some();
            if !redundant {
                return true;
            }
            let mut connections: Vec<ElementId> = routes
                .iter()
                .flatten()
                .copied()
                .filter(|&id| !matches!(graph.element(id).kind, ElementKind::C | ElementKind::I))
                .collect();
            connections.sort();
            connections.dedup();
            if seen.contains(&connections) {
                return false;
            }
            seen.push(connections);
            true
        })
        .collect()
}

/// Where derivative causality is allowed, a conflict that remains is a redundant
/// constraint: two rigid connections fixing one junction's variable. The message names
/// the elements on both routes.
fn redundant_constraint(
    graph: &Graph,
    second: ElementId,
    first: ElementId,
    meeting: Option<ElementId>,
    routes: &[Vec<ElementId>; 2],
) -> Option<String> {
    let mut involved: Vec<ElementId> = routes.iter().flatten().copied().collect();
    involved.extend([first, second]);
    involved.sort();
    involved.dedup();
    graph.allowance(crate::ir::Lint::DerivativeCausality, &involved, &[])?;
    let junction = meeting
        .filter(|&j| matches!(graph.element(j).kind, ElementKind::Zero | ElementKind::One))?;
    let common = if graph.element(junction).kind == ElementKind::Zero {
        "effort"
    } else {
        "flow"
    };
    let named: Vec<String> = involved
        .iter()
        .filter(|&&id| !matches!(graph.element(id).kind, ElementKind::Zero | ElementKind::One))
        .map(|&id| graph.describe(id))
        .collect();
    let connections: Vec<String> = involved
        .iter()
        .filter(|&&id| matches!(graph.element(id).kind, ElementKind::Tf | ElementKind::Gy))
        .map(|&id| graph.describe(id))
        .collect();
    let which = if connections.is_empty() {
        String::new()
    } else {
        format!(" (here: {})", connections.join(" or "))
    };
    Some(format!(
        "redundant constraint at {}: {} fix its {common} twice (routes: {} and {}); even with \
         derivative causality allowed, the rigid connections here over-determine the motion\n\
         help: remove one of the connections{which}, or make one compliant: a 0-junction with \
         a stiff `C joint = k;` (k a stiffness, {STIFFNESS}) and an R for damping",
        graph.describe(junction),
        named.join(", "),
        route(graph, &routes[0]),
        route(graph, &routes[1]),
    ))
}

/// When `first` sits on one component of a split multibond and the conflict meets on
/// another, the whole-vector elements the split junctions meet (which alone carry an
/// influence across components), named for the message.
fn crossed_components(
    graph: &Graph,
    first: ElementId,
    meeting: Option<ElementId>,
) -> Option<String> {
    let component = |j: ElementId| {
        graph
            .dissolved
            .iter()
            .find_map(|d| d.components.iter().position(|&c| c == j))
    };
    let attached = graph
        .element(first)
        .bonds
        .first()
        .map(|&b| graph.bond(b).other(first))?;
    let (from, at) = (component(attached)?, component(meeting?)?);
    if from == at {
        return None;
    }
    // The splitters the split stage inserted: their first bond is the whole multibond.
    let whole: Vec<String> = graph
        .element_ids()
        .filter(|&id| graph.element(id).kind == ElementKind::Split && graph.dissolved(id).is_none())
        .filter_map(|id| {
            let bond = *graph.element(id).bonds.first()?;
            Some(graph.describe(graph.bond(bond).other(id)))
        })
        .collect();
    (!whole.is_empty()).then(|| whole.join(", "))
}

/// What a C's number means, for every help that suggests writing `C name = k;`
/// (the same reading as the missing-law message in `resolve.rs`).
const STIFFNESS: &str = "e = k q";

/// Turns a causality mistake into a message at the user's text.
pub fn render(graph: &Graph, error: &CausalityError) -> syn::Error {
    let name = |id: ElementId| graph.describe(id);
    let span = |id: ElementId| graph.element(id).name.span();
    match error {
        CausalityError::Conflict {
            second,
            first,
            at,
            routes,
            twice,
        } => render_conflict(graph, *second, *first, *at, routes, *twice),
        CausalityError::Derivative { element, path } => {
            let forced_by = path.first().copied().unwrap_or(*element);
            let kind = graph.element(*element).kind;
            let forcer_kind = graph.element(forced_by).kind;
            // The junction the storage sits on, if the path reaches it through one.
            let junction =
                path.len().checked_sub(2).map(|i| path[i]).filter(|&j| {
                    matches!(graph.element(j).kind, ElementKind::Zero | ElementKind::One)
                });
            let shown =
                |id: ElementId| crate::flatten::display(&graph.element(id).name.to_string());
            let nobody = junction.and_then(|j| match (kind, graph.element(j).kind) {
                (ElementKind::I, ElementKind::Zero) => Some((
                    format!("nothing else sets the effort of {}, so the inertia would have to", name(j)),
                    format!(
                        "bond a compliance (C) or a resistance (R) to `{0}`, which sets its effort: \
                         `C store = k; {0} -> store;` with k a stiffness ({STIFFNESS})",
                        shown(j)
                    ),
                )),
                (ElementKind::C, ElementKind::One) => Some((
                    format!("nothing else sets the flow of {}, so the compliance would have to", name(j)),
                    format!(
                        "bond an inertia (I) or a resistance (R) to `{0}`, which sets its flow: \
                         `I mass = m; {0} -> mass;`",
                        shown(j)
                    ),
                )),
                _ => None,
            });
            let (why, help) = match (kind, forcer_kind) {
                _ if nobody.is_some() => nobody.unwrap_or_default(),
                (ElementKind::I, ElementKind::I) => (
                    "the two inertias are rigidly tied".to_owned(),
                    format!(
                        "put a compliance between them, as mechanism models do with compliant \
                         joints: a 0-junction between the two with `C joint = k;` on it, k a \
                         stiffness ({STIFFNESS}), and an R for damping; or merge them into one I"
                    ),
                ),
                (ElementKind::C, ElementKind::C) => (
                    "the two compliances share one variable".to_owned(),
                    "put a resistance (R) or an inertia (I) between them, or merge them into one C"
                        .to_owned(),
                ),
                (ElementKind::I, _) => (
                    "its flow is fixed from outside".to_owned(),
                    format!(
                        "put a compliance between it and what fixes it: a 0-junction between \
                         them with `C joint = k;` on it, k a stiffness ({STIFFNESS}), and an R \
                         for damping"
                    ),
                ),
                _ => (
                    "its effort is fixed from outside".to_owned(),
                    "put a resistance (R) or an inertia (I) between it and what fixes it"
                        .to_owned(),
                ),
            };
            let meant = if kind == forcer_kind {
                "the rigid connection"
            } else {
                "the constraint"
            };
            let mut e = syn::Error::new(
                span(*element),
                format!(
                    "{} is forced into derivative causality by {} (path: {}); {why}\nhelp: {help}\n\
                     help: if {meant} is meant, allow it: `#[allow(derivative_causality)]` on `{}` \
                     or on the model (it then has no state of its own)",
                    name(*element),
                    name(forced_by),
                    route(graph, path),
                    shown(*element),
                ),
            );
            if forced_by != *element {
                let note = match forcer_kind {
                    ElementKind::Se => format!("note: {} fixes the effort here", name(forced_by)),
                    ElementKind::Sf => format!("note: {} fixes the flow here", name(forced_by)),
                    _ => format!(
                        "note: {} takes integral causality here first",
                        name(forced_by)
                    ),
                };
                e.combine(syn::Error::new(span(forced_by), note));
            }
            e
        }
        CausalityError::MissingForm {
            element,
            needs_flow_form,
            forced_by,
            path,
        } => {
            let el = &graph.element(*element).name;
            let (given, needed) = if *needs_flow_form {
                (
                    "e = φ(f)",
                    format!("its flow from its effort\nhelp: add `f = ...e...` (the same law solved for f) to `R {el} {{ ... }}`"),
                )
            } else {
                (
                    "f = φ(e)",
                    format!("its effort from its flow\nhelp: add `e = ...f...` (the same law solved for e) to `R {el} {{ ... }}`"),
                )
            };
            let mut e = syn::Error::new(
                span(*element),
                format!(
                    "R `{el}` gives its law only as {given}, but its causality (fixed by {}; path: {}) needs {needed}",
                    name(*forced_by),
                    route(graph, path)
                ),
            );
            e.combine(syn::Error::new(
                span(*forced_by),
                format!("note: {} fixes that causality", name(*forced_by)),
            ));
            e
        }
        // Unreachable from any input (see the variant's doc): said as a bug in bgdsl,
        // still at the junction's text, rather than as advice to the user.
        CausalityError::Junction { junction, setters } => {
            syn::Error::new(
                span(*junction),
                format!(
                "internal error in bgdsl's causality assignment: {} ended with {setters} bonds \
                 setting its common {} although every step kept it at one; this is a bug in \
                 bond_graph!, not in your model: please report it with this model",
                name(*junction),
                if graph.element(*junction).kind == ElementKind::Zero { "effort" } else { "flow" }
            ),
            )
        }
    }
}

/// `push -> v -> motor`: the elements of a path by their names.
fn route(graph: &Graph, path: &[ElementId]) -> String {
    let names: Vec<String> = path
        .iter()
        .map(|&id| crate::flatten::display(&graph.element(id).name.to_string()))
        .collect();
    names.join(" -> ")
}

/// ", through GY `motor`, which turns an effort into a flow" for the gyrators on a path.
fn through_gyrators(graph: &Graph, path: &[ElementId]) -> String {
    let gyrators: Vec<String> = path
        .iter()
        .filter(|&&id| graph.element(id).kind == ElementKind::Gy)
        .map(|&id| graph.describe(id))
        .collect();
    match gyrators.as_slice() {
        [] => String::new(),
        [one] => {
            format!(", through {one}, which turns an effort into a flow and a flow into an effort")
        }
        many => format!(
            ", through {}, which turn efforts into flows and flows into efforts",
            many.join(" and ")
        ),
    }
}

/// The whole path of a conflict: `first`'s route to the meeting place, then on to
/// `second` (its route walked backwards).
fn conflict_path(routes: &[Vec<ElementId>; 2]) -> Vec<ElementId> {
    let mut path = routes[0].clone();
    for &id in routes[1].iter().rev() {
        if path.last() != Some(&id) {
            path.push(id);
        }
    }
    path
}

/// The message of a causal conflict: where, between whom, along which path, and how
/// to mend it, in the terms of the junction where it happens.
fn render_conflict(
    graph: &Graph,
    second: ElementId,
    first: ElementId,
    at: Option<ElementId>,
    routes: &[Vec<ElementId>; 2],
    twice: Option<bool>,
) -> syn::Error {
    let name = |id: ElementId| graph.describe(id);
    let span = |id: ElementId| graph.element(id).name.span();
    // Where the two meet: the junction named by propagation, else the element at the
    // other end of the second one's bond.
    let meeting = at.or_else(|| {
        let element = graph.element(second);
        element.bonds.first().map(|&b| graph.bond(b).other(second))
    });
    let place = meeting.map_or(String::new(), |j| format!(" at {}", name(j)));
    let path = conflict_path(routes);
    let shown_path = if path.len() > 1 {
        format!(
            " (path: {}{})",
            route(graph, &path),
            through_gyrators(graph, &path)
        )
    } else {
        String::new()
    };
    let what = match graph.element(second).kind {
        ElementKind::Se => "effort",
        ElementKind::Sf => "flow",
        _ => "causality",
    };
    if first == second || twice == Some(true) {
        if let Some(message) = redundant_constraint(graph, second, first, meeting, routes) {
            return syn::Error::new(span(second), message);
        }
    }
    if first == second {
        // The requirement clashed with its own consequences, met by two routes.
        let split =
            meeting.is_some_and(|j| graph.dissolved.iter().any(|d| d.components.contains(&j)));
        let why = if split {
            "its consequences arrive there by two routes that disagree: the junctions a \
             splitter takes apart get their components' causalities one by one, but an \
             element acting on the whole vector (a C, I or R[n] with one law, a source, a \
             TF or GY whose modulus may be a matrix) takes one causality for all its \
             components\n\
             help: write that element as scalar elements behind a splitter (a TF or GY \
             whose modulus is a plain number, such as `TF lever = n;` with an f64 `n`, is \
             taken apart by component)"
        } else {
            "its consequences come back around a loop of junctions, TFs and GYs with the \
             opposite causality\n\
             help: break the loop with a storage (C or I) or a resistive (R) element on it"
        };
        // The routes from the element to where they meet (a splitter's are left out:
        // they run through the scalar junctions it was taken apart into).
        let routes_shown = match routes {
            _ if split => String::new(),
            [a, b] if a.len() > 1 && b.len() > 1 => format!(
                " (routes: {} and {}{})",
                route(graph, a),
                route(graph, b),
                through_gyrators(graph, &path)
            ),
            [_, b] if b.len() > 1 => {
                format!(" (path: {}{})", route(graph, b), through_gyrators(graph, b))
            }
            _ => String::new(),
        };
        return syn::Error::new(
            span(second),
            format!(
                "causal conflict{place}: {} cannot impose its {what}{routes_shown}: {why}",
                name(second)
            ),
        );
    }
    if let Some(whole) = crossed_components(graph, first, meeting) {
        let mut e = syn::Error::new(
            span(second),
            format!(
                "causal conflict{place}: {} cannot impose its {what}, because {} already fixes \
                 it; {} acts on another component of the split multibond and reaches this one \
                 only through {whole}, which acts on the whole vector and so takes one causality \
                 for all its components (a C, I or R[n] with one law, a source, or a TF or GY \
                 whose modulus may be a matrix: only a plain-number modulus is taken apart by \
                 component)\n\
                 help: write that element as scalar elements behind a splitter",
                name(second),
                name(first),
                name(first)
            ),
        );
        e.combine(syn::Error::new(
            span(first),
            format!("note: {} fixes it here", name(first)),
        ));
        return e;
    }
    let junction =
        meeting.filter(|&j| matches!(graph.element(j).kind, ElementKind::Zero | ElementKind::One));
    let message = match (junction, twice) {
        (Some(j), Some(twice)) => {
            let zero = graph.element(j).kind == ElementKind::Zero;
            let (common, kind) = if zero { ("effort", "0-junction") } else { ("flow", "1-junction") };
            if twice {
                let buffer = if zero {
                    "a resistance (R) or an inertia (I) between one of them and the junction (on a 1-junction)".to_owned()
                } else {
                    format!("a compliance (`C joint = k;` with k a stiffness, {STIFFNESS}) or a resistance (R) between one of them and the junction (on a 0-junction)")
                };
                format!(
                    "causal conflict{place}: {} and {} both set its {common}{shown_path}; a {kind} \
                     takes its {common} from exactly one of its bonds\n\
                     help: remove one of them, or put {buffer}",
                    name(first),
                    name(second)
                )
            } else {
                let (setters, example, imposed) = if zero {
                    ("a compliance (C) or a resistance (R)", "C store = k;", "flows")
                } else {
                    ("an inertia (I) or a resistance (R)", "I mass = m;", "efforts")
                };
                let shown = crate::flatten::display(&graph.element(j).name.to_string());
                let stiffness = if zero {
                    format!(" with k a stiffness ({STIFFNESS})")
                } else {
                    String::new()
                };
                format!(
                    "causal conflict{place}: nothing sets its {common}{shown_path}: {} and {} both \
                     impose {imposed} on it, and a {kind} needs one bond that sets its {common}\n\
                     help: bond {setters} to `{shown}`, which sets its {common}: `{example} {shown} -> {};`{stiffness}",
                    name(first),
                    name(second),
                    example.split_whitespace().nth(1).unwrap_or_default()
                )
            }
        }
        _ => format!(
            "causal conflict{place}: {} cannot impose its {what}, because {} already fixes it{shown_path}\n\
             help: remove one of them, or put a storage or resistive element between them",
            name(second),
            name(first)
        ),
    };
    let mut e = syn::Error::new(span(second), message);
    e.combine(syn::Error::new(
        span(first),
        format!("note: {} fixes it here", name(first)),
    ));
    e
}

#[cfg(test)]
mod proptests;
#[cfg(test)]
mod tests;
