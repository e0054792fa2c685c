//! Stage 2: from syntax to the graph IR. Resolves names and checks the structure:
//! duplicates, unknown names, laws that do not fit their element, the number and
//! direction of each element's bonds, initial conditions.

use std::collections::BTreeMap;

use syn::Ident;

use crate::allow::{take_lints, Placement};
use crate::errors::Errors;
use crate::ir::{
    AllowScope, Allowance, Bond, BondId, Element, ElementId, ElementKind, Graph, Init, Law, Output,
    Param,
};
use crate::syntax::{LawSyntax, ModelDef, Stmt};

/// Names a law may use for the element's own variables; parameters may not take them.
pub const RESERVED_NAMES: [&str; 5] = ["t", "e", "f", "q", "p"];

/// Builds the graph of one model, or reports every structural mistake found.
pub fn resolve(mut model: ModelDef) -> syn::Result<Graph> {
    let mut errors = Errors::default();
    for error in model.errors {
        errors.push(error);
    }
    let model_lints = take_lints(&mut model.attrs, Placement::Model, &mut errors);
    let mut resolver = Resolver {
        errors,
        names: BTreeMap::new(),
        poisoned: model.poisoned.iter().map(|n| n.to_string()).collect(),
        graph: Graph {
            attrs: model.attrs,
            vis: model.vis,
            name: model.name,
            params: Vec::new(),
            elements: Vec::new(),
            bonds: Vec::new(),
            inits: Vec::new(),
            outputs: Vec::new(),
            kinematics: Vec::new(),
            bond_dims: Vec::new(),
            dissolved: Vec::new(),
            storage: Vec::new(),
            allowances: model_lints
                .into_iter()
                .map(|(lint, span)| Allowance {
                    lint,
                    span,
                    scope: AllowScope::Model,
                })
                .collect(),
            modes: Vec::new(),
            events: Vec::new(),
            bodies: std::mem::take(&mut model.bodies),
        },
        components: Vec::new(),
    };
    // Declarations first, so that bonds may name elements declared after them.
    let mut chains = Vec::new();
    let mut inits = Vec::new();
    let mut states = Vec::new();
    let mut ders = Vec::new();
    let mut whens = Vec::new();
    for stmt in model.stmts {
        match stmt {
            Stmt::Param(param) => resolver.declare_param(param),
            Stmt::Element(element) => resolver.declare_element(element),
            Stmt::Output(output) => resolver.declare_output(output),
            Stmt::Bonds(chain) => chains.push(chain),
            Stmt::Init(init) => inits.push(init),
            Stmt::State(state) => states.push(state),
            Stmt::Der(der) => ders.push(der),
            Stmt::Mode(mode) => resolver.declare_mode(mode),
            Stmt::When(when) => {
                if let Some(label) = &when.label {
                    resolver.claim(label, Named::Event);
                }
                whens.push(when);
            }
        }
    }
    resolver.declare_states(states, ders);
    if resolver.graph.elements.is_empty()
        && resolver.errors.is_empty()
        && resolver.poisoned.is_empty()
    {
        let name = &resolver.graph.name;
        resolver.errors.at(
            name.span(),
            format!(
                "model `{name}` has no elements: a bond graph needs elements joined by bonds\n\
                 help: declare elements and bond them, e.g. `Se push = 1.0; R load = 2.0; push -> load;`"
            ),
        );
    }
    for chain in chains {
        resolver.connect(chain);
    }
    // A statement that did not parse or a name that did not resolve leaves elements
    // with bonds missing: counting them then would only report follow-on errors.
    if resolver.errors.is_empty() {
        resolver.order_splitter_ports();
        resolver.check_ports();
    }
    for init in inits {
        resolver.initial_condition(init);
    }
    crate::events::resolve(&mut resolver.graph, whens, &mut resolver.errors);
    resolver.lint_expressions();
    if resolver.errors.is_empty() {
        crate::dims::infer(&mut resolver.graph, &mut resolver.errors);
    }
    if resolver.errors.is_empty() {
        crate::split::dissolve(&mut resolver.graph, &mut resolver.errors);
    }
    resolver.errors.finish()?;
    Ok(resolver.graph)
}

/// What a name in the model's namespace refers to.
#[derive(Clone, Copy)]
enum Named {
    Param,
    Element(ElementId),
    Bond,
    State,
    Mode,
    Event,
}

struct Resolver {
    errors: Errors,
    /// Parameters, elements and bond labels share one namespace: a law says `k` for a
    /// parameter and `spring.e` for an element's effort.
    names: BTreeMap<String, (Named, Ident)>,
    /// Names whose declaration failed or was duplicated: references to them would only
    /// produce follow-on errors, so they are passed over quietly.
    poisoned: std::collections::BTreeSet<String>,
    graph: Graph,
    /// Bonds attached to a splitter, with the component they were written at (`s.0`;
    /// `None` for the multibond) and where.
    components: Vec<(ElementId, Option<usize>, BondId, proc_macro2::Span)>,
}

impl Resolver {
    fn claim(&mut self, name: &Ident, what: Named) -> bool {
        let key = name.to_string();
        if let Some((earlier, first)) = self.names.get(&key) {
            let evented = [what, *earlier]
                .iter()
                .any(|n| matches!(n, Named::Mode | Named::Event));
            let names = if evented {
                "parameters, elements, junctions, states, modes, event labels and bond labels"
            } else {
                "parameters, elements, junctions, states and bond labels"
            };
            self.poisoned.insert(key.clone());
            self.errors.with_note(
                name.span(),
                format!(
                    "the name `{name}` is declared twice\n\
                     help: rename one of them: {names} share one namespace"
                ),
                first.span(),
                format!("`{name}` is first declared here"),
            );
            return false;
        }
        self.names.insert(key, (what, name.clone()));
        true
    }

    fn declare_param(&mut self, param: crate::syntax::ParamDecl) {
        if param.input && param.shape != crate::ir::Shape::Scalar {
            self.errors.at(
                param.name.span(),
                format!(
                    "input `{}` must be a number (`input {} = 0.0;`): a host sets inputs one \
                     value at a time; declare one input per component",
                    param.name, param.name
                ),
            );
            self.poisoned.insert(param.name.to_string());
            return;
        }
        if RESERVED_NAMES.contains(&param.name.to_string().as_str()) {
            self.errors.at(
                param.name.span(),
                format!(
                    "`{}` cannot be a parameter's name: `t` is time and `e`, `f`, `q`, `p` \
                     are an element's own variables in its law",
                    param.name
                ),
            );
            self.poisoned.insert(param.name.to_string());
            return;
        }
        if self.claim(&param.name, Named::Param) {
            self.graph.params.push(Param {
                attrs: param.attrs,
                name: param.name,
                shape: param.shape,
                default: param.default,
                unit: param.unit,
                input: param.input,
            });
        }
    }

    fn declare_element(&mut self, mut decl: crate::syntax::ElementDecl) {
        let id = ElementId(self.graph.elements.len());
        let lints = take_lints(
            &mut decl.attrs,
            Placement::Statement("an element"),
            &mut self.errors,
        );
        if !self.claim(&decl.name, Named::Element(id)) {
            return;
        }
        self.allow(lints, AllowScope::Element(id));
        let law = self.check_law(
            decl.kind.written(decl.modulated),
            decl.kind,
            &decl.name,
            decl.law,
        );
        if decl.inverse.is_some() && !matches!(decl.kind, ElementKind::Tf | ElementKind::Gy) {
            self.errors
                .at(decl.name.span(), "only a TF or GY takes an `inverse = ...`");
        }
        let doc = crate::codegen::doc_text(&decl.attrs);
        let unit = match (decl.kind, decl.state_unit) {
            (_, None) => None,
            (ElementKind::C, Some((var, unit))) if var == "q" => Some(unit),
            (ElementKind::I, Some((var, unit))) if var == "p" => Some(unit),
            (kind @ (ElementKind::C | ElementKind::I), Some((var, _))) => {
                let state = if kind == ElementKind::C { "q" } else { "p" };
                self.errors.at(
                    var.span(),
                    format!(
                        "the state of {} `{}` is `{state}`, not `{var}`: write `, {state} in \"unit\"`",
                        kind.word(),
                        crate::flatten::display(&decl.name.to_string()),
                    ),
                );
                None
            }
            (kind, Some((var, _))) => {
                self.errors.at(
                    var.span(),
                    format!(
                        "{} `{}` has no state to give a unit: only C (`, q in \"m\"`) and I \
                         (`, p in \"kg·m/s\"`) elements have one",
                        kind.written(decl.modulated),
                        crate::flatten::display(&decl.name.to_string()),
                    ),
                );
                None
            }
        };
        if unit.is_some() || (doc.is_some() && matches!(decl.kind, ElementKind::C | ElementKind::I))
        {
            self.graph.storage.push(crate::ir::StorageNote {
                element: id,
                unit,
                doc,
            });
        }
        self.graph.elements.push(Element {
            name: decl.name,
            kind: decl.kind,
            modulated: decl.modulated,
            law,
            dimension: decl.dimension,
            inverse: decl.inverse,
            bonds: Vec::new(),
        });
    }

    fn declare_mode(&mut self, mode: crate::event_syntax::ModeDecl) {
        if self.claim(&mode.name, Named::Mode) {
            self.graph.modes.push(crate::events::Mode {
                doc: crate::codegen::doc_text(&mode.attrs),
                name: mode.name,
                kind: mode.kind,
                init: mode.init,
            });
        }
    }

    /// Kinematic states and their derivatives: one `der` for each `state`.
    fn declare_states(
        &mut self,
        states: Vec<crate::syntax::StateDecl>,
        ders: Vec<crate::syntax::DerDecl>,
    ) {
        let mut ders: Vec<Option<crate::syntax::DerDecl>> = ders.into_iter().map(Some).collect();
        for state in states {
            let position = ders
                .iter()
                .position(|d| d.as_ref().is_some_and(|d| d.name == state.name));
            let der = position.and_then(|i| ders[i].take());
            if !self.claim(&state.name, Named::State) {
                continue;
            }
            let Some(der) = der else {
                self.errors.at(
                    state.name.span(),
                    format!(
                        "state `{0}` has no derivative: add `der {0} = ...;`",
                        state.name
                    ),
                );
                continue;
            };
            self.graph.kinematics.push(crate::ir::Kinematic {
                name: state.name,
                shape: state.shape,
                init: state.init,
                der: der.expr,
                unit: state.unit,
                doc: crate::codegen::doc_text(&state.attrs),
            });
        }
        for der in ders.into_iter().flatten() {
            let twice = self.graph.kinematics.iter().any(|k| k.name == der.name);
            let message = if twice {
                format!(
                    "`der {0}` is given twice\nhelp: keep one `der {0} = ...;` and remove the other",
                    der.name
                )
            } else {
                format!(
                    "`der {0}` names no state: declare it with `state {0}: Type = initial;`",
                    der.name
                )
            };
            self.errors.at(der.name.span(), message);
        }
    }

    /// Checks that the law's shape fits the kind; on a mistake records it and returns
    /// a law that keeps later stages quiet.
    fn check_law(&mut self, word: &str, kind: ElementKind, name: &Ident, law: LawSyntax) -> Law {
        use ElementKind::*;
        match (kind, law) {
            (Zero | One | Split, LawSyntax::None) => Law::None,
            (Zero | One | Split, _) => {
                let dimension = if kind == Split { "[n]" } else { "" };
                self.errors.at(
                    name.span(),
                    format!(
                        "{} `{name}` has no law: write `{word}{dimension} {name};`",
                        kind.describe()
                    ),
                );
                Law::None
            }
            (_, LawSyntax::Linear(expr)) => Law::Linear(expr),
            (Se | Sf | Tf | Gy, LawSyntax::Forms(forms)) => {
                let what = if matches!(kind, Se | Sf) {
                    "value"
                } else {
                    "modulus"
                };
                self.errors.at(
                    forms[0].var.span(),
                    format!("the {what} of {word} `{name}` is written `{word} {name} = expr;`"),
                );
                Law::None
            }
            (Se | Sf | Tf | Gy | C | I | R, LawSyntax::None) => {
                let hint = match kind {
                    Se | Sf => format!("`{word} {name} = value;`"),
                    Tf | Gy => format!("`{word} {name} = modulus;`"),
                    C => format!(
                        "`C {name} = k;` with k its stiffness, `e = k q` (a compliance c is \
                         `1.0 / c`), or `C {name} {{ e = ...q... }}`"
                    ),
                    I => format!("`I {name} = inertia;` or `I {name} {{ f = ...p... }}`"),
                    _ => format!("`R {name} = resistance;` or `R {name} {{ e = ...f... }}`"),
                };
                self.errors.at(
                    name.span(),
                    format!("{word} `{name}` needs a constitutive law: {hint}"),
                );
                Law::None
            }
            (C | I | R, LawSyntax::Forms(forms)) => {
                let mut effort = None;
                let mut flow = None;
                for form in forms {
                    let var = form.var.to_string();
                    let allowed = match kind {
                        C => var == "e",
                        I => var == "f",
                        _ => var == "e" || var == "f",
                    };
                    if !allowed {
                        let expected = match kind {
                            C => "a C element's law gives its effort from its displacement: `e = ...q...`",
                            I => "an I element's law gives its flow from its momentum: `f = ...p...`",
                            _ => "an R element's law is `e = ...f...` and/or `f = ...e...`",
                        };
                        self.errors.at(
                            form.var.span(),
                            format!("unexpected `{var} = ...`: {expected}"),
                        );
                        continue;
                    }
                    let slot = if var == "e" { &mut effort } else { &mut flow };
                    if slot.is_some() {
                        self.errors
                            .at(form.var.span(), format!("`{var} = ...` is given twice\nhelp: keep one `{var} = ...` and remove the other"));
                    }
                    *slot = Some(form.expr);
                }
                Law::Forms { effort, flow }
            }
        }
    }

    fn declare_output(&mut self, output: crate::syntax::OutputDecl) {
        if let Some(first) = self.graph.outputs.iter().find(|o| o.name == output.name) {
            let first = first.name.span();
            self.errors.with_note(
                output.name.span(),
                format!(
                    "the output `{}` is declared twice\nhelp: rename one of them, or remove one",
                    output.name
                ),
                first,
                "first declared here",
            );
            return;
        }
        self.graph.outputs.push(Output {
            attrs: output.attrs,
            name: output.name,
            shape: output.shape,
            expr: output.expr,
            unit: output.unit,
        });
    }

    fn lookup_element(&mut self, name: &Ident) -> Option<ElementId> {
        if self.poisoned.contains(&name.to_string()) {
            return None;
        }
        match self.names.get(&name.to_string()) {
            Some((Named::Element(id), _)) => Some(*id),
            Some((Named::Param, _)) => {
                self.errors.at(
                    name.span(),
                    format!(
                        "`{name}` is a parameter, not an element: bonds connect elements\n\
                         help: to bring its value into the graph, bond an element whose law \
                         reads it, e.g. a source `Se push = {name};`"
                    ),
                );
                None
            }
            Some((Named::Bond, _)) => {
                self.errors.at(
                    name.span(),
                    format!(
                        "`{name}` is a bond label, not an element: bonds connect elements\n\
                         help: bond one of the elements that the bond `{name}` joins; its label \
                         only names it, so that laws can read `{name}.e` and `{name}.f`"
                    ),
                );
                None
            }
            Some((Named::State, _)) => {
                self.errors.at(
                    name.span(),
                    format!(
                        "`{name}` is a state, not an element: bonds connect elements\n\
                         help: to bring its value into the graph, bond an element whose law \
                         reads it, e.g. a source `Sf drive = {name};`"
                    ),
                );
                None
            }
            Some((Named::Mode | Named::Event, _)) => {
                let what = match self.names.get(&name.to_string()) {
                    Some((Named::Mode, _)) => "a mode",
                    _ => "an event",
                };
                self.errors.at(
                    name.span(),
                    format!("`{name}` is {what}, not an element: bonds connect elements"),
                );
                None
            }
            None => {
                let elements: Vec<String> = self
                    .graph
                    .elements
                    .iter()
                    .map(|e| e.name.to_string())
                    .collect();
                self.errors.at(
                    name.span(),
                    format!(
                        "unknown element `{name}`{}; the model's elements are: {}",
                        suggestion(name, &elements),
                        elements.join(", ")
                    ),
                );
                None
            }
        }
    }

    fn connect(&mut self, mut chain: crate::syntax::BondChain) {
        if let Some(doc) = chain.attrs.iter().find(|a| a.path().is_ident("doc")) {
            self.errors.push(syn::Error::new_spanned(
                doc,
                "attributes and doc comments are not allowed on a bond statement",
            ));
            chain.attrs.retain(|a| !a.path().is_ident("doc"));
        }
        let lints = take_lints(
            &mut chain.attrs,
            Placement::Statement("a bond statement"),
            &mut self.errors,
        );
        let first_bond = self.graph.bonds.len();
        self.connect_links(chain.first, chain.links);
        let bonds = (first_bond..self.graph.bonds.len()).map(BondId).collect();
        self.allow(lints, AllowScope::Bonds(bonds));
    }

    /// Records the lints allowed before a statement, covering `scope`.
    fn allow(&mut self, lints: Vec<(crate::allow::Lint, proc_macro2::Span)>, scope: AllowScope) {
        for (lint, span) in lints {
            self.graph.allowances.push(Allowance {
                lint,
                span,
                scope: scope.clone(),
            });
        }
    }

    fn connect_links(
        &mut self,
        first: crate::syntax::Endpoint,
        links: Vec<(crate::syntax::Arrow, crate::syntax::Endpoint)>,
    ) {
        let mut left = first;
        for (arrow, right) in links {
            let sources: Vec<Option<ElementId>> =
                left.ports().iter().map(|p| self.lookup_port(p)).collect();
            let targets: Vec<Option<ElementId>> =
                right.ports().iter().map(|p| self.lookup_port(p)).collect();
            if sources.len() > 1 && targets.len() > 1 {
                self.errors.at(
                    arrow.span,
                    "an arrow between two groups is ambiguous: connect a group to one element",
                );
            } else if arrow.label.is_some() && sources.len() * targets.len() > 1 {
                self.errors.at(
                    arrow.span,
                    "a label names one bond, but this arrow makes several: label each bond on its own",
                );
            } else {
                let label_ok = match &arrow.label {
                    Some(label) => self.claim(label, Named::Bond),
                    None => true,
                };
                for (from, from_port) in sources.iter().zip(left.ports()) {
                    for (to, to_port) in targets.iter().zip(right.ports()) {
                        let (Some(from), Some(to)) = (*from, *to) else {
                            continue;
                        };
                        if from == to {
                            self.errors.at(
                                to_port.name.span(),
                                format!(
                                    "a bond from `{0}` to itself connects nothing\n\
                                     help: a bond joins two different elements: bond `{0}` to \
                                     the element it exchanges power with, or remove this bond",
                                    from_port.name
                                ),
                            );
                            continue;
                        }
                        let id = BondId(self.graph.bonds.len());
                        self.note_component(from, from_port, id);
                        self.note_component(to, to_port, id);
                        self.graph.bonds.push(Bond {
                            from,
                            to,
                            label: if label_ok { arrow.label.clone() } else { None },
                        });
                        self.graph.elements[from.0].bonds.push(id);
                        self.graph.elements[to.0].bonds.push(id);
                    }
                }
            }
            left = right;
        }
    }

    /// An element named as a bond's end; `s.0` must name a splitter.
    fn lookup_port(&mut self, port: &crate::syntax::Port) -> Option<ElementId> {
        let id = self.lookup_element(&port.name)?;
        let kind = self.graph.element(id).kind;
        match &port.component {
            Some(index) if kind != ElementKind::Split => {
                self.errors.at(
                    index.span(),
                    format!(
                        "`{}.{index}` names a component, but {} is not a splitter; \
                         only a `Split[n]` element has components",
                        port.name,
                        self.graph.describe(id)
                    ),
                );
                None
            }
            _ => Some(id),
        }
    }

    /// Remembers a bond at a splitter, with the component it was written at.
    fn note_component(&mut self, element: ElementId, port: &crate::syntax::Port, bond: BondId) {
        if self.graph.element(element).kind != ElementKind::Split {
            return;
        }
        let component = match &port.component {
            Some(index) => match index.base10_parse::<usize>() {
                Ok(i) => Some(i),
                Err(error) => {
                    self.errors.push(error);
                    return;
                }
            },
            None => None,
        };
        let span = port
            .component
            .as_ref()
            .map_or(port.name.span(), |index| index.span());
        self.components.push((element, component, bond, span));
    }

    /// Puts each splitter's bonds in port order: the multibond, then the components
    /// `s.0`, `s.1`, ...; reports a splitter without a dimension, without its multibond
    /// or with a component missing, repeated or out of range.
    fn order_splitter_ports(&mut self) {
        for index in 0..self.graph.elements.len() {
            let id = ElementId(index);
            let element = &self.graph.elements[index];
            if element.kind != ElementKind::Split {
                continue;
            }
            let name = element.name.clone();
            let shown = crate::flatten::display(&name.to_string());
            let Some((n, _)) = element.dimension else {
                self.errors.at(
                    name.span(),
                    format!("splitter `{shown}` needs its dimension: `Split[3] {shown};`"),
                );
                continue;
            };
            let at_this: Vec<(Option<usize>, BondId, proc_macro2::Span)> = self
                .components
                .iter()
                .filter(|c| c.0 == id)
                .map(|&(_, component, bond, span)| (component, bond, span))
                .collect();
            let whole: Vec<&(Option<usize>, BondId, proc_macro2::Span)> =
                at_this.iter().filter(|c| c.0.is_none()).collect();
            let mut ports = vec![None; n + 1];
            match whole.as_slice() {
                [] => self.errors.at(
                    name.span(),
                    format!(
                        "splitter `{shown}` has no multibond: connect the {n}-dimensional side \
                         to `{shown}` itself (`... -> {shown}`) and the components to `{shown}.0` .. `{shown}.{}`",
                        n - 1
                    ),
                ),
                [(_, bond, _)] => ports[0] = Some(*bond),
                [_, second, ..] => self.errors.at(
                    second.2,
                    format!(
                        "splitter `{shown}` has one multibond; name a component for the others: `{shown}.0` .. `{shown}.{}`",
                        n - 1
                    ),
                ),
            }
            for &(component, bond, span) in &at_this {
                let Some(i) = component else { continue };
                if i >= n {
                    self.errors.at(
                        span,
                        format!(
                            "splitter `{shown}` has components 0 to {}; there is no component {i}",
                            n - 1
                        ),
                    );
                } else if ports[i + 1].is_some() {
                    self.errors.at(
                        span,
                        format!(
                            "component {i} of splitter `{shown}` is connected twice; a component \
                             carries one scalar bond\n\
                             help: join the two bonds at one junction and bond the junction to \
                             `{shown}.{i}` once (a 1-junction when they share its flow, a 0-junction \
                             when they share its effort), or bond this one to a free component"
                        ),
                    );
                } else {
                    ports[i + 1] = Some(bond);
                }
            }
            let missing: Vec<String> = (0..n)
                .filter(|&i| ports[i + 1].is_none())
                .map(|i| format!("`{shown}.{i}`"))
                .collect();
            if !missing.is_empty() {
                self.errors.at(
                    name.span(),
                    format!(
                        "splitter `{shown}` leaves {} unconnected: every component needs its scalar bond",
                        missing.join(", ")
                    ),
                );
            }
            if let Some(ordered) = ports.into_iter().collect::<Option<Vec<BondId>>>() {
                self.graph.elements[index].bonds = ordered;
            }
        }
    }

    /// Each kind has a fixed number of ports; TF and GY pass power through, so their
    /// port 1 points in and port 2 points out.
    fn check_ports(&mut self) {
        for index in 0..self.graph.elements.len() {
            let id = ElementId(index);
            let element = &self.graph.elements[index];
            let name = &element.name;
            let count = element.bonds.len();
            let what = self.graph.describe(id);
            // A submodel's junction is a port: the model may leave it unused, or join
            // only the submodel's own bond to it (a free rotation, say).
            let port = element.name.to_string().contains(crate::flatten::SEPARATOR)
                && matches!(element.kind, ElementKind::Zero | ElementKind::One);
            let shown = crate::flatten::display(&name.to_string());
            let message = match element.kind {
                _ if port => None,
                _ if count == 0 => Some(format!(
                    "{what} is not connected to anything\n\
                     help: bond it to the graph (`{name} -> ...` or `... -> {name}`), or remove it"
                )),
                ElementKind::Zero | ElementKind::One if count < 2 => {
                    let bond = self.graph.bond(element.bonds[0]);
                    let other = self.graph.describe(bond.other(id));
                    Some(format!(
                        "{what} has only one bond; a junction joins two or more bonds\n\
                         help: bond the other elements that share its {} to it \
                         (`{name} -> {{ a, b }}`), or remove the junction and bond {other} where it belongs",
                        if element.kind == ElementKind::Zero { "effort" } else { "flow" }
                    ))
                }
                ElementKind::Zero | ElementKind::One | ElementKind::Split => None,
                ElementKind::Tf | ElementKind::Gy if count < 2 => Some(format!(
                    "{what} has {count} bond, but a two-port takes exactly 2 (one in, one out)\n\
                     help: give it a bond in, port 1 (`... -> {name}`), and a bond out, port 2 (`{name} -> ...`)"
                )),
                ElementKind::Tf | ElementKind::Gy if count != 2 => Some(format!(
                    "{what} has {count} bonds, but a two-port takes exactly 2 (one in, one out)\n\
                     help: join the bonds of one side at a junction and bond the junction to `{shown}`: \
                     `1 j; {{ a, b }} -> j -> {name};`"
                )),
                ElementKind::Tf | ElementKind::Gy => {
                    let [a, b] = [element.bonds[0], element.bonds[1]];
                    let into = |bond: BondId| self.graph.bonds[bond.0].points_into(id);
                    match (into(a), into(b)) {
                        (true, false) => None,
                        (false, true) => {
                            self.graph.elements[index].bonds.swap(0, 1);
                            None
                        }
                        (true, true) => Some(format!(
                            "both bonds of {what} point into it; a two-port passes power through: one bond in (port 1), one out (port 2)\n\
                             help: turn one of the arrows round, so that power comes in on one bond and leaves on the other: `a -> {shown} -> b;`"
                        )),
                        (false, false) => Some(format!(
                            "both bonds of {what} point out of it; a two-port passes power through: one bond in (port 1), one out (port 2)\n\
                             help: turn one of the arrows round, so that power comes in on one bond and leaves on the other: `a -> {shown} -> b;`"
                        )),
                    }
                }
                _ if count != 1 => Some(format!(
                    "{what} has {count} bonds, but a one-port takes exactly 1\n\
                     help: bond it to one junction that joins the others: `1 j; {name} -> j -> {{ a, b }};` \
                     (a 1-junction when they share its flow, a 0-junction when they share its effort)"
                )),
                _ => None,
            };
            if let Some(message) = message {
                let span = self.graph.elements[index].name.span();
                self.errors.at(span, message);
            }
        }
    }

    fn initial_condition(&mut self, init: crate::syntax::InitDecl) {
        let Some(id) = self.lookup_element(&init.element) else {
            return;
        };
        let element = self.graph.element(id);
        let expected = match element.kind {
            ElementKind::C => "q",
            ElementKind::I => "p",
            _ => {
                let what = self.graph.describe(id);
                self.errors.at(
                    init.element.span(),
                    format!(
                        "{what} has no state; only C (`.q`) and I (`.p`) elements take initial conditions\n\
                         help: remove this `init`, or give it to the C or I whose state it means"
                    ),
                );
                return;
            }
        };
        if init.var != expected {
            let what = self.graph.describe(id);
            self.errors.at(
                init.var.span(),
                format!("{what} has the state `{expected}`, not `{}`: write `init {}.{expected} = ...;`", init.var, init.element),
            );
            return;
        }
        if let Some(first) = self.graph.inits.iter().find(|i| i.element == id) {
            let first = first.span;
            self.errors.with_note(
                init.element.span(),
                format!(
                    "`{}.{expected}` is given an initial value twice\n\
                     help: keep one `init {}.{expected} = ...;` and remove the other",
                    init.element, init.element
                ),
                first,
                "first given here",
            );
            return;
        }
        self.graph.inits.push(Init {
            element: id,
            span: init.element.span(),
            value: init.value,
        });
    }
}

impl Resolver {
    /// Checks the names every law and output uses (see [`crate::rewrite::lint`]), so
    /// such mistakes are reported together with the structural ones.
    fn lint_expressions(&mut self) {
        use crate::rewrite::{lint, Named as Target, Vocabulary};
        let graph = &self.graph;
        let mut lookup = Vocabulary::default();
        for id in graph.element_ids() {
            let element = graph.element(id);
            lookup.add(
                &element.name,
                Target::Element(element.kind, graph.describe(id)),
            );
        }
        for label in graph.bonds.iter().filter_map(|b| b.label.as_ref()) {
            lookup.add(label, Target::Bond);
        }
        for param in &graph.params {
            lookup.add(&param.name, Target::Param);
        }
        for state in &graph.kinematics {
            lookup.add(&state.name, Target::State);
        }
        for mode in &graph.modes {
            lookup.add(&mode.name, Target::Mode);
        }
        // Names whose declaration failed were reported (or were declared but left out
        // of the graph for a reported reason): they are not unknown.
        for name in self.poisoned.iter().chain(self.names.keys()) {
            lookup.tolerate(name);
        }
        for param in &graph.params {
            let context = format!("the default of parameter `{}`", param.name);
            lint(&param.default, &lookup, &[], &context, &mut self.errors);
        }
        for init in &graph.inits {
            let context = "an initial condition".to_string();
            lint(&init.value, &lookup, &[], &context, &mut self.errors);
        }
        for state in &graph.kinematics {
            let context = format!("the initial value of state `{}`", state.name);
            lint(&state.init, &lookup, &[], &context, &mut self.errors);
        }
        for id in graph.element_ids() {
            let element = graph.element(id);
            let context = format!("the law of {}", graph.describe(id));
            match &element.law {
                Law::Linear(expr) => lint(expr, &lookup, &[], &context, &mut self.errors),
                Law::Forms { effort, flow } => {
                    let (effort_own, flow_own): (&[&str], &[&str]) = match element.kind {
                        ElementKind::C => (&["q"], &[]),
                        ElementKind::I => (&[], &["p"]),
                        _ => (&["f"], &["e"]),
                    };
                    if let Some(expr) = effort {
                        lint(expr, &lookup, effort_own, &context, &mut self.errors);
                    }
                    if let Some(expr) = flow {
                        lint(expr, &lookup, flow_own, &context, &mut self.errors);
                    }
                }
                Law::None => {}
            }
        }
        for output in &graph.outputs {
            let context = format!("the output `{}`", output.name);
            lint(&output.expr, &lookup, &[], &context, &mut self.errors);
        }
        for state in &graph.kinematics {
            let context = format!("the derivative of state `{}`", state.name);
            lint(&state.der, &lookup, &[], &context, &mut self.errors);
        }
        crate::events::lint(graph, &lookup, &mut self.errors);
        crate::components::normalise_initial_values(&mut self.graph, &mut self.errors);
    }
}

/// ` (did you mean `spring`?)` when a known name is one or two edits away.
pub fn suggestion(name: &Ident, known: &[String]) -> String {
    let name = name.to_string();
    known
        .iter()
        .map(|k| (edit_distance(&name, k), k))
        .filter(|(d, _)| *d <= 2)
        .min()
        .map(|(_, k)| format!(" (did you mean `{k}`?)"))
        .unwrap_or_default()
}

/// The Levenshtein distance between `a` and `b`.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != *cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod should {
    use super::*;

    fn resolve_text(text: &str) -> syn::Result<Graph> {
        let file: crate::syntax::File = syn::parse_str(text)?;
        resolve(file.models.into_iter().next().unwrap())
    }

    fn messages(text: &str) -> Vec<String> {
        match resolve_text(text) {
            Ok(_) => Vec::new(),
            Err(e) => e.into_iter().map(|e| e.to_string()).collect(),
        }
    }

    #[test]
    fn expand_fan_out_into_one_bond_each() {
        let g =
            resolve_text("model M { Se s = 1.0; 1 v; C c = 1.0; I i = 1.0; s -> v -> { c, i }; }")
                .unwrap();
        assert_eq!(g.bonds.len(), 3);
        assert_eq!(g.bond(BondId(2)).from, ElementId(1));
        assert_eq!(g.bond(BondId(2)).to, ElementId(3));
        assert_eq!(
            g.element(ElementId(1)).bonds,
            [BondId(0), BondId(1), BondId(2)]
        );
    }

    #[test]
    fn put_the_inward_bond_of_a_transformer_first() {
        let g =
            resolve_text("model M { Se s = 1.0; TF t = 2.0; R r = 1.0; t -> r; s -> t; }").unwrap();
        let tf = g.element(ElementId(1));
        assert!(g.bond(tf.bonds[0]).points_into(ElementId(1)));
    }

    #[test]
    fn report_every_naming_mistake_at_once() {
        let m = messages(
            "model M { param k = 1.0; C k = 2.0; Se s = 1.0; R r = 1.0; 1 v; s -> v -> r; v -> rr;
                       output y = s.x; output z = 2.0 * r; }",
        );
        assert_eq!(m.len(), 5, "{m:?}");
        assert!(m[0].contains("declared twice"));
        assert!(m[2].starts_with("unknown element `rr` (did you mean `r`?)"));
        assert_eq!(m[3], "Se `s` has no signal `x`; it has e, f");
        assert!(m[4].starts_with("R `r` is an element, not a value"));
    }

    #[test]
    fn report_every_port_mistake_at_once() {
        let m = messages(
            "model M { Se s = 1.0; Se s2 = 1.0; R r = 1.0; TF t = 1.0; s2 -> t; r -> t; }",
        );
        assert_eq!(m.len(), 2, "{m:?}");
        assert!(m[0].contains("Se `s` is not connected"));
        assert!(m[1].contains("both bonds of TF `t` point into it"));
    }

    #[test]
    fn stay_quiet_about_names_whose_declaration_failed() {
        // `1 v = 3.0` keeps v; `C c = ;` poisons c; the duplicate `k` is poisoned too.
        let m = messages("model M { param k = 1.0; Se k = 1.0; 1 v = 3.0; C c = ; Sf s = 1.0; s -> v -> { c, k }; }");
        assert_eq!(m.len(), 4, "{m:?}");
        assert!(m[0].starts_with("a 1-junction has no constitutive law"));
        assert!(
            m[1].starts_with("expected an expression") || m[1].starts_with("unexpected end"),
            "{m:?}"
        );
        assert!(m[2].contains("declared twice"));
    }

    #[test]
    fn let_locals_in_a_law_shadow_elements_and_own_variables() {
        let m = messages(
            "model M { Sf src = 1.0; C spring = 1.0; src -> spring;
                       output y = { let spring = 2.0; let q = 3.0; spring * q * t }; }",
        );
        assert!(m.is_empty(), "{m:?}");
    }

    #[test]
    fn reject_a_law_in_the_wrong_variable() {
        let m = messages("model M { C c { f = q }; Se s = 1.0; s -> c; }");
        assert_eq!(m, ["unexpected `f = ...`: a C element's law gives its effort from its displacement: `e = ...q...`"]);
    }

    #[test]
    fn reject_reserved_parameter_names() {
        let m = messages("model M { param q = 1.0; Se s = 1.0; C c = 1.0; s -> c; }");
        assert!(m[0].starts_with("`q` cannot be a parameter's name"));
    }

    #[test]
    fn check_initial_conditions_name_a_state() {
        let m =
            messages("model M { Se s = 1.0; C c = 1.0; s -> c; init c.p = 1.0; init s.q = 0.0; }");
        assert_eq!(m.len(), 2, "{m:?}");
        assert!(m[0].contains("has the state `q`, not `p`"));
        assert!(m[1].contains("has no state"));
    }
}

#[cfg(test)]
mod tests {
    use crate::allow::Lint;
    use crate::ir::{BondId, ElementId, Graph};

    fn resolved(text: &str) -> syn::Result<Graph> {
        let file: crate::syntax::File = syn::parse_str(text).unwrap();
        super::resolve(file.models.into_iter().next().unwrap())
    }

    fn id(graph: &Graph, name: &str) -> ElementId {
        graph
            .element_ids()
            .find(|&i| graph.element(i).name == name)
            .unwrap()
    }

    #[test]
    fn record_where_each_lint_is_allowed() {
        let graph = resolved(
            "#[allow(algebraic_loops)] model M {
                 Se push = 1.0; I m1 = 1.0; I m2 = 2.0;
                 #[allow(derivative_causality)] 1 v;
                 /// a damper
                 R d = 1.0;
                 push -> v -> m1;
                 #[allow(derivative_causality)] v -> { m2, d };
             }",
        )
        .unwrap();
        let (m1, m2, v) = (id(&graph, "m1"), id(&graph, "m2"), id(&graph, "v"));
        let bond_to_m2 = graph.bond_ids().find(|&b| graph.bond(b).to == m2).unwrap();
        let bond_to_m1 = graph.bond_ids().find(|&b| graph.bond(b).to == m1).unwrap();
        assert_eq!(graph.allowances.len(), 3);
        assert_eq!(graph.allowance(Lint::AlgebraicLoops, &[], &[]), Some(0));
        assert_eq!(
            graph.allowance(Lint::DerivativeCausality, &[v], &[]),
            Some(1)
        );
        assert_eq!(
            graph.allowance(Lint::DerivativeCausality, &[m2], &[bond_to_m2]),
            Some(2)
        );
        assert_eq!(
            graph.allowance(Lint::DerivativeCausality, &[m1], &[bond_to_m1]),
            None
        );
        assert_eq!(
            graph.allowance(Lint::DerivativeCausality, &[], &[BondId(99)]),
            None
        );
        // The model's own attributes keep nothing of ours.
        assert!(graph.attrs.is_empty());
    }

    #[test]
    fn keep_the_old_message_for_a_doc_comment_on_a_bond_statement() {
        let error = resolved("model M { Se a = 1.0; R b = 1.0; /// no\n a -> b; }")
            .err()
            .unwrap();
        assert_eq!(
            error.to_string(),
            "attributes and doc comments are not allowed on a bond statement"
        );
    }

    #[test]
    fn reject_a_misspelt_lint_on_an_element() {
        let error = resolved("model M { Se a = 1.0; #[allow(algebraic_loop)] R b = 1.0; a -> b; }")
            .err()
            .unwrap();
        assert!(
            error.to_string().contains("did you mean `algebraic_loops`"),
            "{error}"
        );
    }
}
