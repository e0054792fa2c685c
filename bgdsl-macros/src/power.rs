//! Part of code generation: the model's energy account, from the graph itself.
//!
//! - Stored energy: each C and I element's law integrated from zero to its state along
//!   the straight path, `E = ∫₀¹ φ(s x) · x ds`, by 5-point Gauss–Legendre quadrature:
//!   exact for linear and modulated-linear laws (½ q·K q, ½ p·M⁻¹ p, the paper's
//!   ½ h·(R J Rᵀ)⁻¹ h) and for polynomial laws up to degree 9.
//! - Input power: `e · f` at each source's port (positive when it delivers).
//! - Dissipated power: `e · f` at each resistor's port.

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::Ident;

use crate::equations::{Equations, Op, Rhs};
use crate::ir::{ElementKind, Graph, Shape};
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
    let mut stored = vec![zero.clone()];
    let mut input = vec![zero.clone()];
    let mut dissipated = vec![zero];
    for (index, state) in equations.states.iter().enumerate() {
        let Some(element) = state.element else {
            continue;
        };
        let x = Signal::State(index).ident(Span::call_site());
        let Some(law) = storage_law(graph, equations, element, index) else {
            continue;
        };
        let terms = GAUSS_LEGENDRE_5.iter().map(|&(node, weight)| {
            let at = quote!((#x * #scalar::from_f64(#node)));
            let value = law(&at);
            let product = dot(state.shape, &value, &quote!(#x));
            quote!(#scalar::from_f64(#weight) * #product)
        });
        stored.push(quote!((#(#terms)+*)));
    }
    stored.extend(crate::staged::dependent_energy(graph, equations));
    for id in graph.element_ids() {
        let element = graph.element(id);
        let bucket = match element.kind {
            ElementKind::Se | ElementKind::Sf => &mut input,
            ElementKind::R => &mut dissipated,
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
        bucket.push(if along_port {
            product
        } else {
            quote!((-#product))
        });
    }
    quote! {
        ::core::option::Option::Some(::bgdsl_runtime::PowerBalance {
            stored: #(#stored)+*,
            input: #(#input)+*,
            dissipated: #(#dissipated)+*,
        })
    }
}

/// `a · b` for numbers or vectors.
fn dot(shape: Shape, a: &TokenStream, b: &TokenStream) -> TokenStream {
    match shape {
        Shape::Scalar => quote!((#a * #b)),
        _ => quote!((#a).dot(&#b)),
    }
}

type Law<'a> = Box<dyn Fn(&TokenStream) -> TokenStream + 'a>;

/// A storage element's law φ as a function of (the tokens of) a value of its state:
/// C: e = φ(q); I: f = φ(p), as the equations stage wrote it, without the sign a bond
/// against the port's direction adds.
fn storage_law<'a>(
    graph: &Graph,
    equations: &'a Equations,
    element: crate::ir::ElementId,
    state: usize,
) -> Option<Law<'a>> {
    let bond = graph.element(element).bonds[0];
    let defines = match graph.element(element).kind {
        ElementKind::C => Signal::Effort(bond),
        _ => Signal::Flow(bond),
    };
    let equation = equations
        .ordered
        .iter()
        .find(|eq| eq.defines == defines && eq.element == element)?;
    let shape = equations.states[state].shape;
    match &equation.rhs {
        Rhs::Law { bindings, expr, .. } => {
            let var = Ident::new(bindings.first()?.0, Span::call_site());
            let ty = match shape {
                Shape::Scalar => quote!(Scalar),
                Shape::Vector(n) => quote!(::bgdsl_runtime::multibond::SVector<Scalar, #n>),
                Shape::Matrix(r, c) => quote!(::bgdsl_runtime::multibond::SMatrix<Scalar, #r, #c>),
            };
            Some(Box::new(
                move |at: &TokenStream| quote!({ let #var: #ty = #at; #expr }),
            ))
        }
        Rhs::Scaled { modulus, op, .. } => {
            let op = *op;
            Some(Box::new(move |at: &TokenStream| match (shape, op) {
                (Shape::Scalar, Op::Apply | Op::ApplyTranspose) => quote!((#at * (#modulus))),
                (Shape::Scalar, _) => quote!((#at / (#modulus))),
                (shape, op) => {
                    crate::codegen::linear_op(shape, op, modulus, at.clone(), Span::call_site())
                }
            }))
        }
        Rhs::Sum(_) | Rhs::Component { .. } | Rhs::Assemble(_) | Rhs::Dependent(_) => None,
    }
}
