//! Rewrites the user's law and output expressions for the generated code: references
//! to signals (`spring.e`, `v.f`, `b3.e`, `mass.p`) become the variables holding them
//! and are recorded as dependencies; numeric literals become values of the scalar type,
//! so `0.5 * k * q.powi(3)` type-checks for `f64` and dual numbers alike.
//!
//! The rules for literals: every float literal is converted; an integer literal is
//! converted where it is an operand of an arithmetic or comparison operator (`2 * q`),
//! and left alone elsewhere (`q.powi(3)`).

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
    /// The element's own variables bound for this expression (`q`, `f`, ...).
    pub own: &'a [&'static str],
    /// What the expression belongs to, for messages ("the law of C `spring`").
    pub context: String,
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
    let bond = |i: usize| el.bonds[i];
    // One-ports: power positive into passive elements, out of sources.
    let port_negated = || {
        let b = graph.bond(bond(0));
        let inward = b.points_into(element);
        match el.kind {
            ElementKind::Se | ElementKind::Sf => inward,
            _ => !inward,
        }
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
    term.ok_or_else(|| {
        let available = match el.kind {
            ElementKind::C => "e, f, q",
            ElementKind::I => "e, f, p",
            ElementKind::Se | ElementKind::Sf | ElementKind::R => "e, f",
            ElementKind::Zero => "e (its common effort; name a bond `a -[b]-> c` to read a flow)",
            ElementKind::One => "f (its common flow; name a bond `a -[b]-> c` to read an effort)",
            ElementKind::Tf | ElementKind::Gy => "e1, f1, e2, f2",
        };
        format!(
            "{} has no signal `{member}`; it has {available}",
            graph.describe(element)
        )
    })
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

/// `<__T as Scalar>::from_f64(value)` at the literal's span.
pub fn scalar_literal(lit: &LitFloat) -> Expr {
    let span = lit.span();
    Expr::Verbatim(quote_spanned!(span=> <__T as ::bgdsl_runtime::Scalar>::from_f64(#lit)))
}

struct Rewriter<'s, 'e> {
    scope: &'s Scope<'s>,
    errors: &'e mut crate::errors::Errors,
    deps: Vec<Signal>,
}

impl Rewriter<'_, '_> {
    fn lookup(&self, name: &Ident) -> Option<Lookup> {
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
                if let Some(name) = as_ident(expr).cloned() {
                    let word = name.to_string();
                    if let Some(Lookup::Element(id)) = self.lookup(&name) {
                        let what = self.scope.graph.describe(id);
                        self.errors.at(
                            name.span(),
                            format!("{what} is an element, not a value: read one of its signals, e.g. `{name}.e`"),
                        );
                    } else if ["e", "f", "q", "p"].contains(&word.as_str())
                        && !self.scope.own.contains(&word.as_str())
                    {
                        let own = if self.scope.own.is_empty() {
                            "none: refer to signals by element, e.g. `spring.q`".to_string()
                        } else {
                            self.scope.own.join(", ")
                        };
                        self.errors.at(
                            name.span(),
                            format!(
                                "`{word}` is not available in {}; its own variables are {own}",
                                self.scope.context
                            ),
                        );
                    }
                }
            }
            Expr::Macro(_) => {}
            _ => syn::visit_mut::visit_expr_mut(self, expr),
        }
    }
}
