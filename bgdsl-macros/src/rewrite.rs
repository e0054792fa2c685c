//! Rewrites the user's law and output expressions for the generated code: references
//! to signals (`spring.e`, `v.f`, `b3.e`, `mass.p`) become the variables holding them
//! and are recorded as dependencies; numeric literals become values of the scalar type,
//! so `0.5 * k * q.powi(3)` type-checks for `f64` and dual numbers alike.
//!
//! The rules for literals: every float literal is converted; an integer literal is
//! converted where it is an operand of an arithmetic or comparison operator (`2 * q`),
//! and left alone elsewhere (`q.powi(3)`).

use std::collections::BTreeSet;

use proc_macro2::Span;
use quote::quote_spanned;
use syn::spanned::Spanned;
use syn::visit_mut::VisitMut;
use syn::{Expr, ExprLit, Ident, Lit, LitFloat, Member};

use crate::ir::{ElementId, ElementKind, Graph};
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
    let mut rewriter = Rewriter {
        scope,
        errors,
        deps: Vec::new(),
        locals: local_names(expr),
    };
    let mut expr = expr.clone();
    rewriter.visit_expr_mut(&mut expr);
    Rewritten {
        expr,
        deps: rewriter.deps,
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
pub enum Named {
    /// An element: its kind and how messages name it.
    Element(ElementKind, String),
    /// A bond label.
    Bond,
}

/// Checks the names an expression uses, before any causality is known: signals the
/// element has, elements not used as values, and own variables that exist here.
pub fn lint(
    expr: &Expr,
    lookup: &dyn Fn(&Ident) -> Option<Named>,
    own: &[&str],
    context: &str,
    errors: &mut crate::errors::Errors,
) {
    let mut linter = Linter {
        lookup,
        own,
        context,
        errors,
        locals: local_names(expr),
    };
    syn::visit::Visit::visit_expr(&mut linter, expr);
}

struct Linter<'a> {
    lookup: &'a dyn Fn(&Ident) -> Option<Named>,
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
        (self.lookup)(name)
    }
}

/// Names the expression binds itself (`let` patterns, closure parameters, match and
/// `if let` bindings). They shadow elements, parameters and own variables, as in Rust;
/// scoping is taken as the whole expression, which only errs towards leaving a name to
/// rustc to resolve.
fn local_names(expr: &Expr) -> BTreeSet<String> {
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
                    None => {}
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

impl VisitMut for Rewriter<'_, '_> {
    fn visit_expr_mut(&mut self, expr: &mut Expr) {
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
                if numeric {
                    int_to_float(&mut binary.left);
                    int_to_float(&mut binary.right);
                }
                syn::visit_mut::visit_expr_binary_mut(self, binary);
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
