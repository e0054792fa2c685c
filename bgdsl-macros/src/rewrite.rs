//! Rewrites the user's law and output expressions for the generated code: references
//! to signals (`spring.e`, `v.f`, `b3.e`, `mass.p`) become the variables holding them
//! and are recorded as dependencies; numeric literals become values of the scalar type,
//! so `0.5 * k * q.powi(3)` type-checks for `f64` and dual numbers alike.
//!
//! The rules for literals: every float literal is converted; an integer literal is
//! converted where it is an operand of an arithmetic or comparison operator (`2 * q`),
//! and left alone elsewhere (`q.powi(3)`).

use std::collections::{BTreeMap, BTreeSet};

use proc_macro2::Span;
use quote::quote_spanned;
use syn::spanned::Spanned;
use syn::visit_mut::VisitMut;
use syn::{Expr, ExprLit, Ident, Lit, LitFloat, Member};

use crate::ir::{ElementId, ElementKind, Graph, Shape};
use crate::signals::{Signal, Term};

/// What an expression may refer to besides parameters and `t`.
pub struct Scope<'a> {
    /// The model.
    pub graph: &'a Graph,
    /// The state index of each storage element.
    pub state_of: &'a [Option<usize>],
    /// The state index of each kinematic state.
    pub kinematic_state: &'a [usize],
}

/// The rewritten expression and the signals it reads.
pub struct Rewritten {
    /// The expression, ready to splice.
    pub expr: Expr,
    /// Signals it depends on, in order of first appearance.
    pub deps: Vec<Signal>,
}

/// Rewrites `expr` in `scope`, reporting unknown signals into `errors`.
pub fn rewrite(expr: &Expr, scope: &Scope, errors: &mut crate::errors::Errors) -> Rewritten {
    let locals = local_names(expr);
    let mut expr = expr.clone();
    crate::components::normalise(
        &mut expr,
        &Env {
            scope,
            locals: &locals,
        },
        errors,
    );
    let mut rewriter = Rewriter {
        scope,
        errors,
        deps: Vec::new(),
        locals,
        numeric: true,
        hoisting: true,
    };
    rewriter.visit_expr_mut(&mut expr);
    Rewritten {
        expr,
        deps: rewriter.deps,
    }
}

/// Names as an expression sees them: the model's, shadowed by its own local bindings.
pub struct Env<'a> {
    /// The model.
    pub scope: &'a Scope<'a>,
    /// The expression's local bindings.
    pub locals: &'a BTreeSet<String>,
}

impl Env<'_> {
    /// What a bare name is, for [`crate::hoist::class`].
    fn leaf(&self, name: &Ident) -> crate::hoist::Leaf {
        use crate::hoist::Leaf;
        let word = name.to_string();
        let graph = self.scope.graph;
        if self.locals.contains(&word) || ["e", "f", "q", "p"].contains(&word.as_str()) {
            return Leaf::Varying;
        }
        if word == "t" {
            // Dependent storage differentiates its energy variable along time too: an
            // expression in `t` must carry that derivative, not be a per-call constant.
            let differentiated = graph
                .allowances
                .iter()
                .any(|a| a.lint == crate::ir::Lint::DerivativeCausality);
            return if differentiated {
                Leaf::Varying
            } else {
                Leaf::Timed
            };
        }
        if let Some(param) = graph.params.iter().find(|p| p.name == *name) {
            return if param.input {
                Leaf::Timed
            } else {
                Leaf::Parameter
            };
        }
        let known = graph.kinematics.iter().any(|k| k.name == *name)
            || graph.modes.iter().any(|m| m.name == *name)
            || graph
                .element_ids()
                .any(|id| graph.element(id).name == *name)
            || graph.bonds.iter().any(|b| b.label.as_ref() == Some(name));
        if known {
            Leaf::Varying
        } else {
            Leaf::Other
        }
    }

    /// The shape of a signal.
    pub fn signal_shape(&self, signal: Signal) -> Shape {
        let graph = self.scope.graph;
        match signal {
            Signal::Effort(b) | Signal::Flow(b) => Shape::of_dimension(graph.bond_dims[b.0]),
            Signal::State(i) => {
                if let Some(k) = self.scope.kinematic_state.iter().position(|&s| s == i) {
                    return graph.kinematics[k].shape;
                }
                let element = self.scope.state_of.iter().position(|&s| s == Some(i));
                element
                    .and_then(|e| graph.elements[e].bonds.first())
                    .map_or(Shape::Scalar, |b| Shape::of_dimension(graph.bond_dims[b.0]))
            }
        }
    }
}

impl crate::shapes::ShapeEnv for Env<'_> {
    fn name(&self, name: &Ident) -> Option<Shape> {
        let word = name.to_string();
        if self.locals.contains(&word) {
            return None;
        }
        crate::value_shape::Declared(self.scope.graph).name(name)
    }

    fn signal(&self, base: &Ident, member: &Ident) -> Option<Shape> {
        if self.locals.contains(&base.to_string()) {
            return None;
        }
        let graph = self.scope.graph;
        if let Some(id) = graph
            .element_ids()
            .find(|&id| graph.element(id).name == *base)
        {
            if let Some(dissolved) = graph.dissolved(id) {
                return Some(Shape::Vector(dissolved.components.len()));
            }
            let term = element_signal(graph, self.scope.state_of, id, &member.to_string()).ok()?;
            return Some(self.signal_shape(term.signal));
        }
        let bond = graph
            .bond_ids()
            .find(|&b| graph.bond(b).label.as_ref() == Some(base))?;
        Some(Shape::of_dimension(graph.bond_dims[bond.0]))
    }
}

/// The signal `element.member` names, as a term of the element's own sign convention.
pub fn element_signal(
    graph: &Graph,
    state_of: &[Option<usize>],
    element: ElementId,
    member: &str,
) -> Result<Term, String> {
    let el = graph.element(element);
    if graph.dissolved(element).is_some() {
        // Its common variable is assembled by the rewriter; it has nothing else.
        return Err(no_such_signal(&graph.describe(element), el.kind, member));
    }
    let bond = |i: usize| el.bonds[i];
    // Passive one-ports: power positive into the element. A source's variables are its
    // bond's, counted along the half arrow (so an Sf's `f` is always its value).
    let port_negated = || match el.kind {
        ElementKind::Se | ElementKind::Sf => false,
        _ => !graph.bond(bond(0)).points_into(element),
    };
    let term = match (el.kind, member) {
        (ElementKind::C, "q") | (ElementKind::I, "p") if state_of[element.0].is_none() => {
            let (variable, law, other) = if el.kind == ElementKind::I {
                ("momentum", "p = m f", "f")
            } else {
                ("displacement", "q = e / k", "e")
            };
            return Err(format!(
                "{} is dependent storage (derivative causality): it has no state `{member}`\n\
                 help: its {variable} is its law applied to what it receives ({law}): write \
                 it with `{}.{other}`",
                graph.describe(element),
                crate::flatten::display(&el.name.to_string()),
            ));
        }
        (ElementKind::C, "q") | (ElementKind::I, "p") => {
            state_of[element.0].map(|i| Term::plus(Signal::State(i)))
        }
        (
            ElementKind::Se | ElementKind::Sf | ElementKind::C | ElementKind::I | ElementKind::R,
            "e",
        ) => Some(Term::plus(Signal::Effort(bond(0)))),
        (
            ElementKind::Se | ElementKind::Sf | ElementKind::C | ElementKind::I | ElementKind::R,
            "f",
        ) => Some(Term::signed(port_negated(), Signal::Flow(bond(0)))),
        (ElementKind::Zero, "e") => Some(Term::plus(Signal::Effort(bond(0)))),
        (ElementKind::One, "f") => Some(Term::plus(Signal::Flow(bond(0)))),
        (ElementKind::Tf | ElementKind::Gy, "e1") => Some(Term::plus(Signal::Effort(bond(0)))),
        (ElementKind::Tf | ElementKind::Gy, "f1") => Some(Term::plus(Signal::Flow(bond(0)))),
        (ElementKind::Tf | ElementKind::Gy, "e2") => Some(Term::plus(Signal::Effort(bond(1)))),
        (ElementKind::Tf | ElementKind::Gy, "f2") => Some(Term::plus(Signal::Flow(bond(1)))),
        _ => None,
    };
    term.ok_or_else(|| no_such_signal(&graph.describe(element), el.kind, member))
}

/// The message for `element.member` when the element has no such signal.
fn no_such_signal(described: &str, kind: ElementKind, member: &str) -> String {
    let available = match kind {
        ElementKind::C => "e, f, q",
        ElementKind::I => "e, f, p",
        ElementKind::Se | ElementKind::Sf | ElementKind::R => "e, f",
        ElementKind::Zero => "e (its common effort; name a bond `a -[b]-> c` to read a flow)",
        ElementKind::One => "f (its common flow; name a bond `a -[b]-> c` to read an effort)",
        ElementKind::Tf | ElementKind::Gy => "e1, f1, e2, f2",
        ElementKind::Split => "none of its own (label a bond at it, `a -[b]-> s`, and read `b.e`)",
    };
    format!("{described} has no signal `{member}`; it has {available}")
}

/// The signals each kind of element has.
fn has_signal(kind: ElementKind, member: &str) -> bool {
    match kind {
        ElementKind::C => ["e", "f", "q"].contains(&member),
        ElementKind::I => ["e", "f", "p"].contains(&member),
        ElementKind::Se | ElementKind::Sf | ElementKind::R => ["e", "f"].contains(&member),
        ElementKind::Zero => member == "e",
        ElementKind::One => member == "f",
        ElementKind::Tf | ElementKind::Gy => ["e1", "f1", "e2", "f2"].contains(&member),
        ElementKind::Split => false,
    }
}

/// What a name in an expression refers to, as checking needs it.
#[derive(Clone)]
pub enum Named {
    /// An element: its kind and how messages name it.
    Element(ElementKind, String),
    /// A bond label.
    Bond,
    /// A parameter or input.
    Param,
    /// A kinematic state.
    State,
    /// A discrete mode: a plain value.
    Mode,
}

impl Named {
    /// What kind of name it is, for a did-you-mean.
    fn kind(&self) -> &'static str {
        match self {
            Named::Element(..) => "element",
            Named::Bond => "bond",
            Named::Param => "parameter",
            Named::State => "state",
            Named::Mode => "mode",
        }
    }
}

/// Every name of a model an expression may use.
#[derive(Default)]
pub struct Vocabulary {
    names: Vec<(Ident, Named)>,
    /// Each name's first entry in `names` (lookups in a large model stay O(log n)).
    index: BTreeMap<String, usize>,
    /// Names not to report as unknown (their declaration failed and was reported).
    tolerated: BTreeSet<String>,
}

impl Vocabulary {
    /// Never reports `name` as unknown.
    pub fn tolerate(&mut self, name: &str) {
        self.tolerated.insert(name.to_string());
    }

    /// Adds a name.
    pub fn add(&mut self, name: &Ident, named: Named) {
        self.index
            .entry(name.to_string())
            .or_insert(self.names.len());
        self.names.push((name.clone(), named));
    }

    fn lookup(&self, name: &Ident) -> Option<Named> {
        let at = *self.index.get(&name.to_string())?;
        self.names.get(at).map(|(_, named)| named.clone())
    }

    /// ``; help: did you mean the parameter `force`?`` for the nearest name one or two
    /// edits away (as the user writes it: `crank.tip` for an instance's part).
    fn suggestion(&self, name: &Ident) -> String {
        let written = crate::flatten::display(&name.to_string());
        let candidates: Vec<String> = self
            .names
            .iter()
            .map(|(known, _)| crate::flatten::display(&known.to_string()))
            .collect();
        let best = candidates
            .iter()
            .zip(&self.names)
            .map(|(k, (_, named))| (crate::resolve::edit_distance(&written, k), k, named.kind()))
            .filter(|(d, k, _)| *d <= 2.min(k.chars().count().saturating_sub(1).max(1)))
            .min_by_key(|(d, _, _)| *d);
        match best {
            Some((_, known, kind)) => format!("\nhelp: did you mean the {kind} `{known}`?"),
            None => String::new(),
        }
    }
}

/// Checks the names an expression uses, before any causality is known: signals the
/// element has, elements not used as values, own variables that exist here, and names
/// the model does not have (see [`Linter`]).
pub fn lint(
    expr: &Expr,
    vocabulary: &Vocabulary,
    own: &[&str],
    context: &str,
    errors: &mut crate::errors::Errors,
) {
    let mut linter = Linter {
        vocabulary,
        own,
        context,
        errors,
        locals: local_names(expr),
    };
    syn::visit::Visit::visit_expr(&mut linter, expr);
}

/// The name checks of [`lint`].
///
/// A bare lowercase name that the expression does not bind itself (`let`, closure
/// parameters, patterns), that is not `t`, an own variable, nor in call position
/// (`my_function(k)`: a function of the user's scope), must be a name of the model:
/// otherwise it is an "unknown name" error at the name, with the nearest model name as
/// a did-you-mean. Paths (`core::f64::consts::PI`), method and field names, and names
/// that start with an upper-case letter (constants, unit structs and enum variants of
/// the user's scope, by Rust's naming convention) are left to rustc.
struct Linter<'a> {
    vocabulary: &'a Vocabulary,
    own: &'a [&'a str],
    context: &'a str,
    errors: &'a mut crate::errors::Errors,
    locals: BTreeSet<String>,
}

impl Linter<'_> {
    fn lookup(&self, name: &Ident) -> Option<Named> {
        if self.locals.contains(&name.to_string()) {
            return None;
        }
        self.vocabulary.lookup(name)
    }

    /// Reports `name` if it must be a model name and is not one.
    fn check_known(&mut self, name: &Ident) {
        let word = name.to_string();
        let word = word.strip_prefix("r#").unwrap_or(&word);
        let must_be_known = word.starts_with(|c: char| c.is_lowercase() || c == '_')
            && word != "t"
            && word != "self"
            && !self.locals.contains(word)
            && !self.vocabulary.tolerated.contains(word)
            && !["e", "f", "q", "p"].contains(&word);
        if must_be_known && self.lookup(name).is_none() {
            let shown = crate::flatten::display(word);
            self.errors.at(
                name.span(),
                format!(
                    "unknown name `{shown}` in {}: the model has no parameter, element, bond \
                     or state of that name{}",
                    self.context,
                    self.vocabulary.suggestion(name)
                ),
            );
        }
    }
}

/// Names the expression binds itself (`let` patterns, closure parameters, match and
/// `if let` bindings). They shadow elements, parameters and own variables, as in Rust;
/// scoping is taken as the whole expression, which only errs towards leaving a name to
/// rustc to resolve.
pub fn local_names(expr: &Expr) -> BTreeSet<String> {
    struct Collector(BTreeSet<String>);
    impl<'ast> syn::visit::Visit<'ast> for Collector {
        fn visit_pat_ident(&mut self, pat: &'ast syn::PatIdent) {
            self.0.insert(pat.ident.to_string());
            syn::visit::visit_pat_ident(self, pat);
        }
    }
    let mut collector = Collector(BTreeSet::new());
    syn::visit::Visit::visit_expr(&mut collector, expr);
    collector.0
}

impl<'ast> syn::visit::Visit<'ast> for Linter<'_> {
    fn visit_expr(&mut self, expr: &'ast Expr) {
        match expr {
            Expr::Field(field) => {
                if let (Some(base), Member::Named(member)) = (as_ident(&field.base), &field.member)
                {
                    let word = member.to_string();
                    match self.lookup(base) {
                        Some(Named::Element(kind, described)) => {
                            if !has_signal(kind, &word) {
                                self.errors
                                    .at(member.span(), no_such_signal(&described, kind, &word));
                            }
                            return;
                        }
                        Some(Named::Param) | Some(Named::State) | Some(Named::Mode) => {}
                        Some(Named::Bond) => {
                            if word != "e" && word != "f" {
                                self.errors.at(
                                    member.span(),
                                    format!(
                                        "bond `{base}` has no signal `{word}`; a bond has e and f"
                                    ),
                                );
                            }
                            return;
                        }
                        None => {}
                    }
                }
                syn::visit::visit_expr_field(self, field);
            }
            Expr::Call(call) => {
                // A function's name is not a value.
                if !matches!(&*call.func, Expr::Path(_)) {
                    self.visit_expr(&call.func);
                }
                for arg in &call.args {
                    self.visit_expr(arg);
                }
            }
            Expr::Path(_) => {
                let Some(name) = as_ident(expr) else { return };
                let word = name.to_string();
                match self.lookup(name) {
                    Some(Named::Element(_, described)) => self.errors.at(
                        name.span(),
                        format!("{described} is an element, not a value: read one of its signals, e.g. `{name}.e`"),
                    ),
                    Some(Named::Bond) => self.errors.at(
                        name.span(),
                        format!("bond `{name}` is not a value: read `{name}.e` or `{name}.f`"),
                    ),
                    Some(Named::Param) | Some(Named::State) | Some(Named::Mode) => {}
                    None if ["e", "f", "q", "p"].contains(&word.as_str()) && !self.own.contains(&word.as_str()) && !self.locals.contains(&word) => {
                        let own = if self.own.is_empty() {
                            "none: refer to signals by element, e.g. `spring.q`".to_string()
                        } else {
                            self.own.join(", ")
                        };
                        self.errors.at(
                            name.span(),
                            format!("`{word}` is not available in {}; its own variables are {own}", self.context),
                        );
                    }
                    None => self.check_known(name),
                }
            }
            Expr::Macro(_) => {}
            _ => syn::visit::visit_expr(self, expr),
        }
    }
}

/// The tokens of a term: `__e3` or `(-__f2)`.
pub fn term_tokens(term: Term, span: Span) -> proc_macro2::TokenStream {
    let ident = term.signal.ident(span);
    if term.negate {
        quote_spanned!(span=> (-#ident))
    } else {
        quote_spanned!(span=> #ident)
    }
}

/// `<Scalar as Scalar>::from_f64(value)` at the literal's span.
pub fn scalar_literal(lit: &LitFloat) -> Expr {
    let span = lit.span();
    Expr::Verbatim(quote_spanned!(span=> <Scalar as ::bgdsl_runtime::Scalar>::from_f64(#lit)))
}

struct Rewriter<'s, 'e> {
    scope: &'s Scope<'s>,
    errors: &'e mut crate::errors::Errors,
    deps: Vec<Signal>,
    locals: BTreeSet<String>,
    /// Whether the expression being visited stands where a number goes (an operand,
    /// an argument, a branch's value), so a parameter expression there may be hoisted.
    numeric: bool,
    /// Whether parameter expressions are hoisted (not while writing a hoisted
    /// expression's own scalar form).
    hoisting: bool,
}

impl Rewriter<'_, '_> {
    fn lookup(&self, name: &Ident) -> Option<Lookup> {
        if self.locals.contains(&name.to_string()) {
            return None;
        }
        let graph = self.scope.graph;
        if let Some(id) = graph
            .element_ids()
            .find(|&id| graph.element(id).name == *name)
        {
            return Some(Lookup::Element(id));
        }
        graph
            .bond_ids()
            .find(|&b| graph.bond(b).label.as_ref() == Some(name))
            .map(Lookup::Bond)
    }

    fn signal(&mut self, base: &Ident, member: &Ident) -> Option<Term> {
        let member_name = member.to_string();
        let result = match self.lookup(base)? {
            Lookup::Element(id) => {
                element_signal(self.scope.graph, self.scope.state_of, id, &member_name)
            }
            Lookup::Bond(b) => match member_name.as_str() {
                "e" => Ok(Term::plus(Signal::Effort(b))),
                "f" => Ok(Term::plus(Signal::Flow(b))),
                _ => Err(format!(
                    "bond `{base}` has no signal `{member}`; a bond has e and f"
                )),
            },
        };
        match result {
            Ok(term) => {
                if !self.deps.contains(&term.signal) {
                    self.deps.push(term.signal);
                }
                Some(term)
            }
            Err(message) => {
                self.errors.at(member.span(), message);
                None
            }
        }
    }
}

/// `SVector::from([c0, c1, ...])`: a vector made of its components' signals.
fn assemble_tokens(parts: &[Term], span: Span) -> proc_macro2::TokenStream {
    let n = parts.len();
    let parts = parts.iter().map(|&part| term_tokens(part, span));
    quote_spanned!(span=> ::bgdsl_runtime::multibond::SVector::<Scalar, #n>::from([#(#parts),*]))
}

impl Rewriter<'_, '_> {
    /// The common variable of a junction a splitter took apart, or a port variable of a
    /// two-port it took apart: made of its scalar components' variables.
    fn assembled(&mut self, base: &Ident, member: &Ident) -> Option<Vec<Term>> {
        let Some(Lookup::Element(id)) = self.lookup(base) else {
            return None;
        };
        let graph = self.scope.graph;
        let dissolved = graph.dissolved(id)?;
        let kind = graph.element(id).kind;
        type Variable = fn(crate::ir::BondId) -> Signal;
        // Which port of each component, and which of its variables.
        let (port, signal): (usize, Variable) = match (kind, member.to_string().as_str()) {
            (ElementKind::Zero, "e") => (0, Signal::Effort),
            (ElementKind::One, "f") => (0, Signal::Flow),
            (ElementKind::Tf | ElementKind::Gy, "e1") => (0, Signal::Effort),
            (ElementKind::Tf | ElementKind::Gy, "f1") => (0, Signal::Flow),
            (ElementKind::Tf | ElementKind::Gy, "e2") => (1, Signal::Effort),
            (ElementKind::Tf | ElementKind::Gy, "f2") => (1, Signal::Flow),
            _ => return None,
        };
        let parts: Vec<Term> = dissolved
            .components
            .iter()
            .filter_map(|&c| {
                graph
                    .element(c)
                    .bonds
                    .get(port)
                    .map(|&b| Term::plus(signal(b)))
            })
            .collect();
        for part in &parts {
            if !self.deps.contains(&part.signal) {
                self.deps.push(part.signal);
            }
        }
        Some(parts)
    }
}

impl Rewriter<'_, '_> {
    /// Whether `expr` is an integer made of `i64` modes: a mode, or arithmetic, a
    /// parenthesis or a negation with one among its operands (`gear * 2 + 1`).
    fn is_integer(&self, expr: &Expr) -> bool {
        use syn::BinOp::*;
        match expr {
            Expr::Paren(inner) => self.is_integer(&inner.expr),
            Expr::Group(inner) => self.is_integer(&inner.expr),
            Expr::Unary(unary) => {
                matches!(unary.op, syn::UnOp::Neg(_)) && self.is_integer(&unary.expr)
            }
            Expr::Binary(binary) => {
                matches!(binary.op, Add(_) | Sub(_) | Mul(_) | Div(_) | Rem(_))
                    && (self.is_integer(&binary.left) || self.is_integer(&binary.right))
            }
            _ => as_ident(expr).is_some_and(|name| {
                !self.locals.contains(&name.to_string())
                    && self
                        .scope
                        .graph
                        .modes
                        .iter()
                        .any(|m| m.name == *name && m.kind == crate::events::ModeKind::Integer)
            }),
        }
    }
}

enum Lookup {
    Element(ElementId),
    Bond(crate::ir::BondId),
}

fn as_ident(expr: &Expr) -> Option<&Ident> {
    match expr {
        Expr::Path(path) if path.qself.is_none() && path.attrs.is_empty() => path.path.get_ident(),
        _ => None,
    }
}

fn int_to_float(expr: &mut Expr) {
    if let Expr::Lit(ExprLit {
        lit: Lit::Int(int), ..
    }) = expr
    {
        if int.suffix().is_empty() {
            let float = LitFloat::new(&format!("{}.0", int.base10_digits()), int.span());
            *expr = scalar_literal(&float);
        }
    }
}

impl Rewriter<'_, '_> {
    /// Whether `expr` (not yet rewritten) is known to be a matrix.
    fn is_matrix(&self, expr: &Expr) -> bool {
        let env = Env {
            scope: self.scope,
            locals: &self.locals,
        };
        matches!(crate::shapes::shape(expr, &env), Some(Shape::Matrix(..)))
    }

    /// Replaces `expr` by a hoisting marker if it is a parameter expression worth
    /// hoisting where a number goes (see [`crate::hoist`]).
    fn hoisted(&mut self, expr: &mut Expr) -> bool {
        use crate::hoist::{class, hoistable, marker, Class, Kind};
        if !self.hoisting || !self.numeric || !hoistable(expr) {
            return false;
        }
        let env = Env {
            scope: self.scope,
            locals: &self.locals,
        };
        // A bare parameter is bound in the scalar type already.
        if let Expr::Path(path) = expr {
            if path
                .path
                .get_ident()
                .is_some_and(|name| env.leaf(name) != crate::hoist::Leaf::Other)
            {
                return false;
            }
        }
        let kind = match class(expr, &|name| env.leaf(name)) {
            Class::Varying => return false,
            Class::Timed => Kind::PerCall,
            Class::Constant => Kind::Cached,
        };
        let shape = crate::shapes::shape(expr, &env);
        let kind = if shape.is_some() { kind } else { Kind::PerCall };
        let safe = shape.is_some()
            && crate::hoist::tangent_safe(expr, &|name| env.leaf(name), &|e| {
                crate::shapes::shape(e, &env)
            });
        // The same expression in the scalar type, for parameter tangents.
        let scalar_form = safe.then(|| {
            let mut scalar = expr.clone();
            syn::visit_mut::VisitMut::visit_expr_mut(
                &mut crate::hoist::ConstantsInScalar,
                &mut scalar,
            );
            self.hoisting = false;
            self.visit_expr_mut(&mut scalar);
            self.hoisting = true;
            scalar
        });
        *expr = marker(kind, shape, expr, scalar_form.as_ref());
        true
    }

    /// Visits `expr` standing where a number goes (`numeric`) or not.
    fn visit_at(&mut self, expr: &mut Expr, numeric: bool) {
        let outer = std::mem::replace(&mut self.numeric, numeric);
        self.visit_expr_mut(expr);
        self.numeric = outer;
    }
}

impl VisitMut for Rewriter<'_, '_> {
    fn visit_expr_mut(&mut self, expr: &mut Expr) {
        if self.hoisted(expr) {
            return;
        }
        let outer = self.numeric;
        self.numeric = true;
        self.visit_children(expr);
        self.numeric = outer;
    }
}

impl Rewriter<'_, '_> {
    fn visit_children(&mut self, expr: &mut Expr) {
        match expr {
            Expr::Field(field) => {
                if let (Some(base), Member::Named(member)) = (as_ident(&field.base), &field.member)
                {
                    let (base, member) = (base.clone(), member.clone());
                    if let Some(parts) = self.assembled(&base, &member) {
                        *expr = Expr::Verbatim(assemble_tokens(&parts, field.span()));
                        return;
                    }
                    if self.lookup(&base).is_some() {
                        if let Some(term) = self.signal(&base, &member) {
                            *expr = Expr::Verbatim(term_tokens(term, field.span()));
                        }
                        return;
                    }
                }
                syn::visit_mut::visit_expr_field_mut(self, field);
            }
            Expr::Lit(ExprLit {
                lit: Lit::Float(float),
                ..
            }) => {
                let float = float.clone();
                *expr = scalar_literal(&float);
            }
            Expr::Binary(binary) => {
                use syn::BinOp::*;
                let numeric = matches!(
                    binary.op,
                    Add(_)
                        | Sub(_)
                        | Mul(_)
                        | Div(_)
                        | Rem(_)
                        | Lt(_)
                        | Le(_)
                        | Gt(_)
                        | Ge(_)
                        | Eq(_)
                        | Ne(_)
                        | AddAssign(_)
                        | SubAssign(_)
                        | MulAssign(_)
                        | DivAssign(_)
                );
                // Arithmetic on an `i64` mode keeps its integers as written.
                let integer = [&*binary.left, &*binary.right]
                    .iter()
                    .any(|side| self.is_integer(side));
                if numeric && !integer {
                    int_to_float(&mut binary.left);
                    int_to_float(&mut binary.right);
                }
                let matrix_product = matches!(binary.op, Mul(_)) && self.is_matrix(&binary.left);
                self.visit_at(&mut binary.left, numeric);
                self.visit_at(&mut binary.right, numeric);
                if matrix_product {
                    *expr = crate::hoist::matrix_product(&binary.left, &binary.right);
                }
            }
            Expr::Unary(unary) => {
                let numeric = matches!(unary.op, syn::UnOp::Neg(_));
                self.visit_at(&mut unary.expr, numeric);
            }
            Expr::If(branch) => {
                self.visit_at(&mut branch.cond, false);
                syn::visit_mut::visit_block_mut(self, &mut branch.then_branch);
                if let Some((_, otherwise)) = &mut branch.else_branch {
                    self.visit_at(otherwise, true);
                }
            }
            Expr::Match(choice) => {
                self.visit_at(&mut choice.expr, false);
                for arm in &mut choice.arms {
                    if let Some((_, guard)) = &mut arm.guard {
                        self.visit_at(guard, false);
                    }
                    self.visit_at(&mut arm.body, true);
                }
            }
            Expr::Index(index) => {
                self.visit_at(&mut index.expr, true);
                self.visit_at(&mut index.index, false);
            }
            Expr::Cast(cast) => self.visit_at(&mut cast.expr, false),
            Expr::Let(binding) => self.visit_at(&mut binding.expr, false),
            Expr::MethodCall(call) => {
                self.visit_at(&mut call.receiver, true);
                // `powi` takes an integer.
                let numeric = call.method != "powi";
                for arg in &mut call.args {
                    self.visit_at(arg, numeric);
                }
            }
            Expr::Call(call) => {
                // A function's name is not a value.
                if !matches!(&*call.func, Expr::Path(_)) {
                    self.visit_at(&mut call.func, false);
                }
                for arg in &mut call.args {
                    self.visit_at(arg, true);
                }
            }
            Expr::Path(_) => {
                let Some(name) = as_ident(expr).cloned() else {
                    return;
                };
                if self.locals.contains(&name.to_string()) {
                    return;
                }
                let graph = self.scope.graph;
                if let Some(k) = graph.kinematics.iter().position(|k| k.name == name) {
                    let signal = Signal::State(self.scope.kinematic_state[k]);
                    if !self.deps.contains(&signal) {
                        self.deps.push(signal);
                    }
                    *expr = Expr::Verbatim(term_tokens(Term::plus(signal), name.span()));
                }
            }
            Expr::Macro(_) => {}
            _ => syn::visit_mut::visit_expr_mut(self, expr),
        }
    }
}
