//! Parameter expressions: which parts of a law, output or `der` expression depend only
//! on parameters and constants, so that they are computed once in `f64` instead of on
//! every call in the model's scalar type (a dual number when the solver wants a
//! Jacobian).
//!
//! Each sub-expression has a [`Class`]: *constant* (literals, parameters, constants
//! such as `core::f64::consts::PI` or a user's `MY_CONST`, and calls of functions and
//! methods on those), *timed* (also reads `t` or an input: constant within one
//! evaluation), or *varying* (reads a state, a signal, an element's own variable or a
//! local binding). The rewriter replaces each maximal non-varying sub-expression in a
//! position that holds a number by a [`marker`]: the `f64` expression with its class
//! and, when [`crate::shapes`] can tell, its shape. Code generation ([`crate::derived`])
//! gathers the markers: a constant one of known shape becomes a field of the model's
//! derived-value cache, computed when the parameters change; any other is computed in
//! `f64` at the start of each evaluation. Either is then lifted into the scalar type.
//!
//! Conservative by construction: whatever is not recognised stays varying, which is how
//! every expression was evaluated before (in the scalar type).

use proc_macro2::{Delimiter, Group, Ident, Literal, Span, TokenStream, TokenTree};
use quote::{quote, quote_spanned, ToTokens};
use syn::spanned::Spanned;
use syn::visit::Visit;
use syn::visit_mut::VisitMut;
use syn::{BinOp, Expr, ExprLit, Lit, LitFloat, UnOp};

use crate::ir::Shape;

/// How an expression depends on what changes during a run (ordered: the class of a
/// compound expression is the greatest of its parts').
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Class {
    /// Parameters and constants only: the same until a parameter changes.
    Constant,
    /// Also time or inputs: the same within one evaluation.
    Timed,
    /// Reads a state, a signal, an own variable or a local binding.
    Varying,
}

/// What a bare name in an expression is, as classification needs it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Leaf {
    /// A parameter (a field of the parameter struct).
    Parameter,
    /// `t` or an input.
    Timed,
    /// A state, element, bond label, own variable or local binding.
    Varying,
    /// Not a name of the model: a constant or item of the user's scope.
    Other,
}

/// The class of `expr`, given what its bare names are.
pub fn class(expr: &Expr, leaf: &dyn Fn(&Ident) -> Leaf) -> Class {
    let mut classifier = Classifier {
        leaf,
        class: Class::Constant,
    };
    classifier.visit_expr(expr);
    classifier.class
}

struct Classifier<'a> {
    leaf: &'a dyn Fn(&Ident) -> Leaf,
    class: Class,
}

impl Classifier<'_> {
    fn at_least(&mut self, class: Class) {
        self.class = self.class.max(class);
    }
}

/// Whether tokens name the model's scalar type or `Self`: such an expression is
/// evaluated in the scalar type.
fn mentions_scalar(tokens: TokenStream) -> bool {
    tokens.into_iter().any(|tree| match tree {
        TokenTree::Ident(ident) => ident == "Scalar" || ident == "Self" || ident == "self",
        TokenTree::Group(group) => mentions_scalar(group.stream()),
        _ => false,
    })
}

impl<'ast> Visit<'ast> for Classifier<'_> {
    fn visit_expr_path(&mut self, path: &'ast syn::ExprPath) {
        if path.qself.is_some() || mentions_scalar(path.to_token_stream()) {
            return self.at_least(Class::Varying);
        }
        let Some(ident) = path.path.get_ident() else {
            // `core::f64::consts::PI`, `my_crate::LIMIT`.
            return;
        };
        let class = match (self.leaf)(ident) {
            Leaf::Parameter => Class::Constant,
            Leaf::Timed => Class::Timed,
            Leaf::Varying => Class::Varying,
            // By Rust's naming convention a constant is UPPER_CASE (or a unit struct);
            // a lowercase name the model does not know is left to rustc.
            Leaf::Other if ident.to_string().starts_with(char::is_uppercase) => Class::Constant,
            Leaf::Other => Class::Varying,
        };
        self.at_least(class);
    }

    fn visit_expr_call(&mut self, call: &'ast syn::ExprCall) {
        match &*call.func {
            // A function: its name is not a value.
            Expr::Path(func) => {
                if func.qself.is_some() || mentions_scalar(func.to_token_stream()) {
                    self.at_least(Class::Varying);
                }
            }
            other => self.visit_expr(other),
        }
        for arg in &call.args {
            self.visit_expr(arg);
        }
    }

    fn visit_expr_method_call(&mut self, call: &'ast syn::ExprMethodCall) {
        if let Some(turbofish) = &call.turbofish {
            if mentions_scalar(turbofish.to_token_stream()) {
                self.at_least(Class::Varying);
            }
        }
        self.visit_expr(&call.receiver);
        for arg in &call.args {
            self.visit_expr(arg);
        }
    }

    fn visit_type(&mut self, ty: &'ast syn::Type) {
        if mentions_scalar(ty.to_token_stream()) {
            self.at_least(Class::Varying);
        }
    }

    fn visit_expr_macro(&mut self, _: &'ast syn::ExprMacro) {
        self.at_least(Class::Varying);
    }

    fn visit_expr_closure(&mut self, _: &'ast syn::ExprClosure) {
        self.at_least(Class::Varying);
    }

    fn visit_expr(&mut self, expr: &'ast Expr) {
        match expr {
            Expr::Verbatim(_) => self.at_least(Class::Varying),
            _ => syn::visit::visit_expr(self, expr),
        }
    }
}

/// Whether an expression of this form is worth hoisting (and yields a number, vector
/// or matrix when its parts do). Literals and bare parameters are not: they are bound
/// in the scalar type already.
pub fn hoistable(expr: &Expr) -> bool {
    match expr {
        Expr::Paren(inner) => hoistable(&inner.expr),
        Expr::Group(inner) => hoistable(&inner.expr),
        Expr::Binary(binary) => matches!(
            binary.op,
            BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Div(_) | BinOp::Rem(_)
        ),
        Expr::Unary(unary) => matches!(unary.op, UnOp::Neg(_)),
        Expr::Call(_) | Expr::MethodCall(_) | Expr::Field(_) | Expr::Index(_) => true,
        // A constant: a path, or an UPPER_CASE name (a bare parameter is bound already).
        Expr::Path(path) => path.path.get_ident().is_none_or(|ident| {
            ident.to_string().starts_with(char::is_uppercase) && path.path.segments.len() == 1
        }),
        _ => false,
    }
}

/// Where a hoisted expression is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    /// In the model's derived-value cache, when the parameters change.
    Cached,
    /// At the start of every evaluation.
    PerCall,
}

/// The name of the marker macro code generation replaces.
pub const MARKER: &str = "__bgdsl_hoisted";

/// The marker for a hoisted expression: `__bgdsl_hoisted! { kind shape ; expr ;
/// scalar }`, with the expression in its `f64` form and, when it has one that carries
/// parameter tangents ([`tangent_safe`]), in its scalar-type form (empty otherwise).
/// Code generation replaces every marker by the lifted value (see
/// [`crate::derived`]), or by the scalar form for a scalar type that seeds parameters.
pub fn marker(kind: Kind, shape: Option<Shape>, expr: &Expr, scalar_form: Option<&Expr>) -> Expr {
    let span = expr.span();
    let kind = match kind {
        Kind::Cached => quote!(cached),
        Kind::PerCall => quote!(per_call),
    };
    let shape = match shape {
        Some(Shape::Scalar) => quote!(scalar),
        Some(Shape::Vector(n)) => {
            let n = Literal::usize_unsuffixed(n);
            quote!(vector #n)
        }
        Some(Shape::Matrix(r, c)) => {
            let (r, c) = (Literal::usize_unsuffixed(r), Literal::usize_unsuffixed(c));
            quote!(matrix #r #c)
        }
        None => quote!(unknown),
    };
    let mut f64_form = expr.clone();
    FloatOperands.visit_expr_mut(&mut f64_form);
    let name = Ident::new(MARKER, span);
    let body = Group::new(
        Delimiter::Brace,
        quote!(#kind #shape ; #f64_form ; #scalar_form),
    );
    Expr::Verbatim(quote_spanned!(span=> #name ! #body))
}

/// Integer literals as operands of arithmetic or comparison become float literals, so
/// `2 * k` is `2.0 * k` in `f64` as it is in the scalar type.
struct FloatOperands;

fn int_to_float_literal(expr: &mut Expr) {
    if let Expr::Lit(ExprLit {
        lit: Lit::Int(int),
        attrs,
    }) = expr
    {
        if int.suffix().is_empty() {
            let float = LitFloat::new(&format!("{}.0", int.base10_digits()), int.span());
            *expr = Expr::Lit(ExprLit {
                lit: Lit::Float(float),
                attrs: attrs.clone(),
            });
        }
    }
}

impl VisitMut for FloatOperands {
    fn visit_expr_binary_mut(&mut self, binary: &mut syn::ExprBinary) {
        if !matches!(binary.op, BinOp::And(_) | BinOp::Or(_)) {
            int_to_float_literal(&mut binary.left);
            int_to_float_literal(&mut binary.right);
        }
        syn::visit_mut::visit_expr_binary_mut(self, binary);
    }
}

/// The methods of [`bgdsl_runtime::Scalar`] a number's parameter expression may call
/// and still be evaluated in the scalar type.
const SCALAR_TRAIT_METHODS: &[&str] = &[
    "sqrt", "cbrt", "exp", "ln", "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh",
    "cosh", "tanh", "abs", "signum", "powi", "powf", "min", "max", "recip",
];

/// The runtime's helpers (generic over the scalar type) a parameter expression may call.
const GENERIC_HELPERS: &[&str] = &["vec3", "box_inertia", "diag3", "skew", "rot_z", "identity3"];

/// Whether a hoisted expression is also valid in the scalar type, so that a scalar type
/// that seeds parameter tangents can evaluate it instead of lifting its `f64` value:
/// it reads only parameters, inputs and `t`, and calls only what is generic over the
/// scalar type (arithmetic of numbers, vectors and matrices the way nalgebra defines it
/// for any scalar, the methods of `Scalar`, the runtime's helpers). Conservative: a
/// user's function or constant, or an `f64` method `Scalar` lacks, is not.
pub fn tangent_safe(
    expr: &Expr,
    leaf: &dyn Fn(&Ident) -> Leaf,
    shape: &dyn Fn(&Expr) -> Option<Shape>,
) -> bool {
    let safe = |e: &Expr| tangent_safe(e, leaf, shape);
    let operand = |e: &Expr| {
        matches!(
            e,
            Expr::Lit(ExprLit {
                lit: Lit::Int(_),
                ..
            })
        ) || safe(e)
    };
    let number = |e: &Expr| shape(e) == Some(Shape::Scalar);
    match expr {
        Expr::Lit(ExprLit { lit, .. }) => matches!(lit, Lit::Float(_)),
        Expr::Paren(inner) => safe(&inner.expr),
        Expr::Group(inner) => safe(&inner.expr),
        Expr::Path(path) => {
            path.qself.is_none()
                && (float_constant(&path.path)
                    || path
                        .path
                        .get_ident()
                        .is_some_and(|name| matches!(leaf(name), Leaf::Parameter | Leaf::Timed)))
        }
        Expr::Unary(unary) => matches!(unary.op, UnOp::Neg(_)) && safe(&unary.expr),
        Expr::Binary(binary) => {
            let (left, right) = (&*binary.left, &*binary.right);
            let parts = operand(left) && operand(right);
            match binary.op {
                BinOp::Add(_) | BinOp::Sub(_) => parts,
                // nalgebra multiplies a matrix by a scalar on the right only.
                BinOp::Mul(_) => parts && (number(right) || !number(left)),
                BinOp::Div(_) => parts && number(right),
                _ => false,
            }
        }
        Expr::MethodCall(call) => {
            let method = call.method.to_string();
            let args = if method == "powi" {
                call.args.iter().all(|a| {
                    matches!(
                        a,
                        Expr::Lit(ExprLit {
                            lit: Lit::Int(_),
                            ..
                        })
                    )
                })
            } else {
                call.args.iter().all(safe)
            };
            let known = if number(&call.receiver) {
                SCALAR_TRAIT_METHODS.contains(&method.as_str())
            } else {
                ["component_mul", "component_div", "transpose"].contains(&method.as_str())
            };
            call.turbofish.is_none() && known && safe(&call.receiver) && args
        }
        Expr::Call(call) => {
            let Expr::Path(func) = &*call.func else {
                return false;
            };
            // `vec3` or `::bgdsl_runtime::multibond::vec3` (as the standard library
            // writes it).
            let words: Vec<String> = func
                .path
                .segments
                .iter()
                .map(|s| s.ident.to_string())
                .collect();
            let helper = match words.as_slice() {
                [name] => Some(name),
                [runtime, multibond, name]
                    if runtime == "bgdsl_runtime" && multibond == "multibond" =>
                {
                    Some(name)
                }
                _ => None,
            };
            func.qself.is_none()
                && helper.is_some_and(|name| GENERIC_HELPERS.contains(&name.as_str()))
                && call.args.iter().all(safe)
        }
        // A component of a vector or matrix: `l1.x`, `R0.m12`.
        Expr::Field(field) => {
            matches!(&field.member, syn::Member::Named(m)
                if crate::shapes::component(&m.to_string()).is_some())
                && safe(&field.base)
        }
        Expr::Reference(reference) => reference.mutability.is_none() && safe(&reference.expr),
        _ => false,
    }
}

/// Whether `path` is one of the standard library's `f64` constants:
/// `core::f64::consts::PI`, `std::f64::consts::TAU`, with or without a leading `::`.
fn float_constant(path: &syn::Path) -> bool {
    let words: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
    matches!(words.as_slice(), [krate, f64, consts, _]
        if (krate == "core" || krate == "std") && f64 == "f64" && consts == "consts")
}

/// Writes the standard library's `f64` constants as values of the scalar type, for a
/// hoisted expression's scalar form (the rewriter leaves paths it does not know alone).
pub struct ConstantsInScalar;

impl VisitMut for ConstantsInScalar {
    fn visit_expr_mut(&mut self, expr: &mut Expr) {
        match expr {
            Expr::Path(path) if path.qself.is_none() && float_constant(&path.path) => {
                let span = path.span();
                *expr = Expr::Verbatim(
                    quote_spanned!(span=> <Scalar as ::bgdsl_runtime::Scalar>::from_f64(#path)),
                );
            }
            _ => syn::visit_mut::visit_expr_mut(self, expr),
        }
    }
}

/// `left * right` for a `left` known to be a matrix, as the runtime's product written
/// out entry by entry (`MatMul::mat_mul`): nalgebra's generic product is several
/// times slower on dual numbers (see `bgdsl_runtime::multibond::mat_mul`).
pub fn matrix_product(left: &Expr, right: &Expr) -> Expr {
    let span = left.span();
    Expr::Verbatim(quote_spanned!(span=>
        ::bgdsl_runtime::multibond::MatMul::mat_mul(#left, #right)))
}

/// A span for generated names the user's text cannot reach.
pub fn hidden_span(at: Span) -> Span {
    Span::mixed_site().located_at(at)
}

#[cfg(test)]
mod should {
    use super::*;

    fn class_of(text: &str) -> Class {
        let leaf = |name: &Ident| match name.to_string().as_str() {
            "k" | "m" | "freq" => Leaf::Parameter,
            "t" | "u" => Leaf::Timed,
            "q" | "spring" | "local" => Leaf::Varying,
            _ => Leaf::Other,
        };
        class(&syn::parse_str(text).unwrap(), &leaf)
    }

    #[test]
    fn classify_parameters_time_and_states() {
        assert_eq!(class_of("(k / m).sqrt()"), Class::Constant);
        assert_eq!(class_of("box_inertia(m, k, 2.0, 3.0)"), Class::Constant);
        assert_eq!(
            class_of("core::f64::consts::PI * MY_CONST"),
            Class::Constant
        );
        assert_eq!(
            class_of("(2.0 * core::f64::consts::PI * freq * t).sin()"),
            Class::Timed
        );
        assert_eq!(class_of("k * u"), Class::Timed);
        assert_eq!(class_of("k * q"), Class::Varying);
        assert_eq!(class_of("spring.e * k"), Class::Varying);
        assert_eq!(class_of("unknown_lowercase * k"), Class::Varying);
        assert_eq!(class_of("<Scalar as Trait>::from_f64(k)"), Class::Varying);
        assert_eq!(class_of("Scalar::from_f64(k)"), Class::Varying);
        assert_eq!(class_of("k.into::<Scalar>()"), Class::Varying);
        assert_eq!(class_of("(|x: f64| x * k)(m)"), Class::Varying);
    }

    #[test]
    fn hoist_only_what_computes_a_value() {
        let hoistable_text = |text: &str| hoistable(&syn::parse_str(text).unwrap());
        assert!(hoistable_text("2.0 * k"));
        assert!(hoistable_text("(k).sqrt()"));
        assert!(hoistable_text("core::f64::consts::PI"));
        assert!(!hoistable_text("k"));
        assert!(!hoistable_text("2.0"));
        assert!(!hoistable_text("k > 2.0"));
        assert!(!hoistable_text("if k > 0.0 { k } else { m }"));
    }

    #[test]
    fn write_integer_operands_as_floats_in_the_f64_form() {
        let expr: Expr = syn::parse_str("2 * k + k.powi(3)").unwrap();
        let tokens = marker(Kind::Cached, Some(Shape::Scalar), &expr, None).to_token_stream();
        let text = tokens.to_string();
        assert!(text.contains("2.0 * k"), "{text}");
        assert!(text.contains("powi (3)"), "{text}");
        assert!(
            text.starts_with("__bgdsl_hoisted ! { cached scalar ;"),
            "{text}"
        );
    }
}
