//! Part of code generation: the model's energy account, from the graph itself.
//!
//! - Stored energy: each C and I element's law integrated from zero to its state along
//!   the straight path, `E = ∫₀¹ φ(s x) · x ds`: `½ x · φ(x)` for linear and
//!   modulated-linear laws (½ q·K q, ½ p·M⁻¹ p, the paper's ½ h·(R J Rᵀ)⁻¹ h), by
//!   5-point Gauss–Legendre quadrature for a written law (exact for polynomial laws up
//!   to degree 9).
//! - Input power: `e · f` at each source's port (positive when it delivers).
//! - Dissipated power: `e · f` at each resistor's port.

use std::collections::BTreeMap;

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::Ident;

use crate::equations::{Equations, Op, Rhs};
use crate::ir::{ElementId, ElementKind, Graph, Shape};
use crate::signals::Signal;

/// Gauss–Legendre nodes and weights on [0, 1] (5 points; Abramowitz & Stegun 25.4.30,
/// mapped from [-1, 1]).
const GAUSS_LEGENDRE_5: [(f64, f64); 5] = [
    (0.046_910_077_030_668, 0.118_463_442_528_094_5),
    (0.230_765_344_947_158_5, 0.239_314_335_249_683_2),
    (0.5, 0.284_444_444_444_444_4),
    (0.769_234_655_052_841_5, 0.239_314_335_249_683_2),
    (0.953_089_922_969_332, 0.118_463_442_528_094_5),
];

/// The body of `Model::power_balance`, after the evaluation body has computed every
/// signal.
pub fn account(graph: &Graph, equations: &Equations) -> TokenStream {
    let scalar = quote!(<Scalar as ::bgdsl_runtime::Scalar>);
    let zero = quote!(#scalar::from_f64(0.0));
    let mut sums = [vec![zero.clone()], vec![zero.clone()], vec![zero]];
    for (bucket, term) in terms(graph, equations) {
        sums[bucket].push(term);
    }
    let [stored, input, dissipated] = sums;
    quote! {
        ::core::option::Option::Some(::bgdsl_runtime::PowerBalance {
            stored: #(#stored)+*,
            input: #(#input)+*,
            dissipated: #(#dissipated)+*,
        })
    }
}

/// The terms of the energy account, each with its bucket: 0 stored energy, 1 input
/// power, 2 dissipated power.
pub fn terms(graph: &Graph, equations: &Equations) -> Vec<(usize, TokenStream)> {
    let mut terms = Vec::new();
    // Each equation by what it defines and its element: one lookup per state.
    let defining: BTreeMap<(Signal, ElementId), usize> = equations
        .ordered
        .iter()
        .enumerate()
        .rev()
        .map(|(i, eq)| ((eq.defines, eq.element), i))
        .collect();
    for (index, state) in equations.states.iter().enumerate() {
        let Some(element) = state.element else {
            continue;
        };
        let x = Signal::State(index).ident(Span::call_site());
        let Some(law) = storage_law(graph, equations, &defining, element, index) else {
            continue;
        };
        terms.push((0, law.energy(state.shape, &x)));
    }
    terms.extend(
        crate::staged::dependent_energy(graph, equations)
            .into_iter()
            .map(|term| (0, term)),
    );
    for id in graph.element_ids() {
        let element = graph.element(id);
        let bucket = match element.kind {
            ElementKind::Se | ElementKind::Sf => 1,
            ElementKind::R => 2,
            _ => continue,
        };
        let bond = element.bonds[0];
        let (e, f) = (
            Signal::Effort(bond).ident(Span::call_site()),
            Signal::Flow(bond).ident(Span::call_site()),
        );
        let shape = Shape::of_dimension(graph.bond_dims[bond.0]);
        let product = dot(shape, &quote!(#e), &quote!(#f));
        // Port power: into a resistor, out of a source.
        let along_port = graph.bond(bond).points_into(id) == (element.kind == ElementKind::R);
        terms.push((
            bucket,
            if along_port {
                product
            } else {
                quote!((-#product))
            },
        ));
    }
    terms
}

/// `a · b` for numbers or vectors.
fn dot(shape: Shape, a: &TokenStream, b: &TokenStream) -> TokenStream {
    match shape {
        Shape::Scalar => quote!((#a * #b)),
        _ => quote!((#a).dot(&#b)),
    }
}

/// A storage element's law φ, as the equations stage wrote it (C: e = φ(q); I: f =
/// φ(p)), without the sign a bond against the port's direction adds.
enum Law<'a> {
    /// A law written by the user: the variable it binds, its type and its expression.
    Written {
        var: Ident,
        ty: TokenStream,
        expr: &'a syn::Expr,
    },
    /// A linear law `k x` or `k⁻¹ x` (a modulus that may depend on other signals).
    Linear { modulus: &'a syn::Expr, op: Op },
}

impl Law<'_> {
    /// The stored energy at state `x`, `∫₀¹ φ(s x) · x ds`: `½ x · φ(x)` for a linear
    /// law (exact: φ(s x) = s φ(x)), else 5-point Gauss–Legendre quadrature of a closure
    /// over the law, so that its text appears once.
    fn energy(&self, shape: Shape, x: &Ident) -> TokenStream {
        let scalar = quote!(<Scalar as ::bgdsl_runtime::Scalar>);
        match self {
            Law::Linear { modulus, op } => {
                let at = quote!(#x);
                let value = match (shape, op) {
                    (Shape::Scalar, Op::Apply | Op::ApplyTranspose) => quote!((#at * (#modulus))),
                    (Shape::Scalar, _) => quote!((#at / (#modulus))),
                    (shape, op) => {
                        crate::codegen::linear_op(shape, *op, modulus, at, Span::call_site())
                    }
                };
                let product = dot(shape, &value, &quote!(#x));
                quote!((#scalar::from_f64(0.5) * #product))
            }
            Law::Written { var, ty, expr } => {
                let nodes = GAUSS_LEGENDRE_5.iter().map(|(node, _)| node);
                let weights = GAUSS_LEGENDRE_5.iter().map(|(_, weight)| weight);
                let at = quote!(#x * #scalar::from_f64(__nodes[__i]));
                let product = dot(shape, &quote!(__law(#at)), &quote!(#x));
                // A `while` over indices: a scope without the prelude has no iterators.
                quote!({
                    let __law = |#var: #ty| #expr;
                    let (__nodes, __weights) = ([#(#nodes),*], [#(#weights),*]);
                    let mut __sum = #scalar::from_f64(0.0);
                    let mut __i = 0;
                    while __i < 5 {
                        __sum += #scalar::from_f64(__weights[__i]) * #product;
                        __i += 1;
                    }
                    __sum
                })
            }
        }
    }
}

/// A storage element's law φ (see [`Law`]), found among the equations.
fn storage_law<'a>(
    graph: &Graph,
    equations: &'a Equations,
    defining: &BTreeMap<(Signal, ElementId), usize>,
    element: ElementId,
    state: usize,
) -> Option<Law<'a>> {
    let bond = graph.element(element).bonds[0];
    let defines = match graph.element(element).kind {
        ElementKind::C => Signal::Effort(bond),
        _ => Signal::Flow(bond),
    };
    let equation = &equations.ordered[*defining.get(&(defines, element))?];
    let shape = equations.states[state].shape;
    match &equation.rhs {
        Rhs::Law { bindings, expr, .. } => Some(Law::Written {
            var: Ident::new(bindings.first()?.0, Span::call_site()),
            ty: crate::codegen::value_type(shape, &quote!(Scalar)),
            expr,
        }),
        Rhs::Scaled { modulus, op, .. } => Some(Law::Linear { modulus, op: *op }),
        Rhs::Sum(_) | Rhs::Component { .. } | Rhs::Assemble(_) | Rhs::Dependent(_) => None,
    }
}
