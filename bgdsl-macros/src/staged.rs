//! Part of code generation: the staged evaluation of a model with dependent storage or
//! allowed algebraic loops (see [`crate::implicit`]).
//!
//! For K unknowns the model gets, as inherent methods generic over the scalar:
//! - `__energy_<k>(t, x)`: dependent storage k's energy variable E(x, t), by the
//!   equations its received variable reads;
//! - `__residual(t, x, z)`: the whole evaluation with the torn signals read from z
//!   first, returning z − (their computed values);
//! - `__solve(t, x)`: Newton on `__residual` over `DualN<K>` (x constant) from the
//!   remembered guess, then the implicit-function step on the caller's scalar
//!   (`Solution::refine`), so derivatives flow through the solve exactly (skipped for
//!   a linear system on `f64`, whose one step is the solution already); `None` after
//!   recording a failure.
//!
//! `derivatives`, `outputs`, `power_balance` and `check` call `__solve` first and then
//! evaluate with the unknowns bound to `__z`.

use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote, quote_spanned};

use crate::codegen::{assignment, linear_op, prelude, value_type};
use crate::equations::{Derivative, Equations, Op};
use crate::ir::{ElementKind, Graph, Shape};
use crate::rewrite::term_tokens;
use crate::signals::{Signal, Term};

/// Whether the model needs any of this (dependent storage or unknowns).
pub fn needed(equations: &Equations) -> bool {
    !equations.dependent.is_empty() || !equations.implicit.tears.is_empty()
}

/// `let <torn signal> = <from __z>;` for every unknown, before the equations.
pub fn unknowns(equations: &Equations) -> TokenStream {
    let binds = equations.implicit.tears.iter().map(|tear| {
        let ident = tear.signal.ident(Span::call_site());
        let offset = tear.offset;
        match tear.shape {
            Shape::Scalar => quote!(let #ident: Scalar = __z[#offset];),
            shape => {
                let n = shape.len();
                quote!(let #ident: ::bgdsl_runtime::multibond::SVector<Scalar, #n> =
                    ::bgdsl_runtime::multibond::SVector::<Scalar, #n>::from_fn(|__i, _| __z[#offset + __i]);)
            }
        }
    });
    quote!(#(#binds)*)
}

fn energy_fn_ident(index: usize) -> proc_macro2::Ident {
    format_ident!("__energy_{}", index)
}

/// What dependent storage `index` returns: the eps part of E on `Tangent` numbers whose
/// eps parts are the state derivatives (and 1 for time).
pub fn dependent_rate(equations: &Equations, index: usize, span: Span) -> TokenStream {
    let d = &equations.dependent[index];
    let rt = quote!(::bgdsl_runtime);
    let tangent = quote!(#rt::Tangent::<Scalar>);
    let zero = quote!(<Scalar as #rt::Scalar>::from_f64(0.0));
    let mut entries = Vec::new();
    for (j, (state, offset)) in equations.states.iter().zip(equations.offsets()).enumerate() {
        let rate = d.states.contains(&j).then(|| match &state.derivative {
            Derivative::Term(term) => term_tokens(*term, span),
            Derivative::Expr(der) => {
                let expr = &der.expr;
                quote!((#expr))
            }
        });
        for c in 0..state.shape.len() {
            let at = offset + c;
            let eps = match (&rate, state.shape) {
                (None, _) => zero.clone(),
                (Some(rate), Shape::Scalar) => rate.clone(),
                (Some(rate), _) => quote!((#rate)[#c]),
            };
            entries.push(quote!(#tangent::new(__x[#at], #eps)));
        }
    }
    let energy = energy_fn_ident(index);
    let n_states = entries.len();
    let sign = (d.negate && is_compliance(d)).then(|| quote!(-));
    let eps = match d.shape {
        Shape::Scalar => quote!(#sign __energy.eps),
        _ => quote!(#sign __energy.map(|__c| __c.eps)),
    };
    quote_spanned! {span=> {
        let __xt: [#rt::Tangent<Scalar>; #n_states] = [#(#entries),*];
        let __energy = self.#energy::<#rt::Tangent<Scalar>>(
            #tangent::new(t, <Scalar as #rt::Scalar>::from_f64(1.0)),
            &__xt,
        );
        #eps
    }}
}

fn is_compliance(d: &crate::implicit::Dependent) -> bool {
    matches!(d.receives, Signal::Effort(_))
}

/// E of dependent storage `index` in terms of its received variable: p = ±m f (I),
/// q = k⁻¹ e (C).
fn energy_value(d: &crate::implicit::Dependent) -> TokenStream {
    let span = Span::call_site();
    let modulus = &d.modulus;
    if is_compliance(d) {
        let e = term_tokens(Term::plus(d.receives), span);
        match d.shape {
            Shape::Scalar => quote!(#e / (#modulus)),
            shape => linear_op(shape, Op::Solve, modulus, e, span),
        }
    } else {
        let f = term_tokens(Term::signed(d.negate, d.receives), span);
        match d.shape {
            Shape::Scalar => quote!(#f * (#modulus)),
            shape => linear_op(shape, Op::Apply, modulus, f, span),
        }
    }
}

/// The inherent methods of a model with dependent storage or unknowns.
pub fn methods(
    graph: &Graph,
    equations: &Equations,
    derived: &crate::derived::Derived,
) -> TokenStream {
    if !needed(equations) {
        return TokenStream::new();
    }
    let rt = quote!(::bgdsl_runtime);
    let prelude = prelude(graph, equations, derived);
    let energies = equations.dependent.iter().enumerate().map(|(k, d)| {
        let ident = energy_fn_ident(k);
        let ty = value_type(d.shape, &quote!(Scalar));
        let closure = d
            .closure
            .iter()
            .map(|&i| assignment(graph, equations, &equations.ordered[i]));
        let value = energy_value(d);
        let doc = format!(
            "The energy variable of dependent storage `{}` at a state and time.",
            crate::flatten::display(&graph.element(d.element).name.to_string())
        );
        quote! {
            #[doc = #doc]
            #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
            #[inline]
            fn #ident<Scalar: #rt::Scalar>(&self, t: Scalar, __x: &[Scalar]) -> #ty {
                #prelude
                #(#closure)*
                #value
            }
        }
    });
    let k = equations.implicit.size();
    let solve = (k > 0).then(|| {
        let n_states: usize = equations.states.iter().map(|s| s.shape.len()).sum();
        let body = crate::codegen::evaluation_body(graph, equations, derived);
        let residuals = equations.implicit.tears.iter().flat_map(|tear| {
            let ident = tear.signal.ident(Span::call_site());
            let offset = tear.offset;
            let shape = tear.shape;
            (0..shape.len()).map(move |c| match shape {
                Shape::Scalar => quote!(__z[#offset] - #ident),
                _ => {
                    let at = offset + c;
                    quote!(__z[#at] - #ident[#c])
                }
            })
        });
        let linear = equations.implicit.linear;
        quote! {
            /// The residual of the unknowns: z − their values computed with z.
            #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
            #[inline]
            fn __residual<Scalar: #rt::Scalar>(&self, __t: ::core::primitive::f64, __x: &[Scalar], __z: &[Scalar; #k]) -> [Scalar; #k] {
                #body
                [#(#residuals),*]
            }

            /// The unknowns at a state: Newton in `f64` from the remembered guess, then
            /// one implicit-function step on `Scalar`; `None` after recording a failure.
            #[allow(unused_variables, clippy::all)]
            fn __solve<Scalar: #rt::Scalar>(&self, __t: ::core::primitive::f64, __x: &[Scalar]) -> ::core::option::Option<[Scalar; #k]> {
                let __xc: [#rt::DualN<#k>; #n_states] = ::core::array::from_fn(|__i| {
                    <#rt::DualN<#k> as #rt::Scalar>::from_f64(#rt::Scalar::to_f64(__x[__i]))
                });
                let __solved = #rt::implicit::solve::<#k>(self.__implicit.guess(), #linear, |__zd, __r| {
                    *__r = self.__residual::<#rt::DualN<#k>>(__t, &__xc, __zd);
                });
                match __solved {
                    ::core::result::Result::Ok(__solution) => {
                        self.__implicit.remember(&__solution.z);
                        let __zs: [Scalar; #k] = __solution.z.map(<Scalar as #rt::Scalar>::from_f64);
                        // On plain numbers a linear system's one step is already the
                        // solution to rounding: the implicit-function step would only
                        // repeat the whole evaluation to carry tangents there are none of.
                        if #linear && ::core::any::TypeId::of::<Scalar>() == ::core::any::TypeId::of::<::core::primitive::f64>() {
                            return ::core::option::Option::Some(__zs);
                        }
                        let __r = self.__residual::<Scalar>(__t, __x, &__zs);
                        ::core::option::Option::Some(__solution.refine(&__r))
                    }
                    ::core::result::Result::Err(mut __failure) => {
                        __failure.t = __t;
                        self.__implicit.record(__failure);
                        ::core::option::Option::None
                    }
                }
            }
        }
    });
    quote! {
        #(#energies)*
        #solve
    }
}

/// `let __z = <solved>;` at the top of an evaluation, with what to do on failure.
pub fn solve_first(equations: &Equations, on_failure: TokenStream) -> TokenStream {
    if equations.implicit.size() == 0 {
        return TokenStream::new();
    }
    quote! {
        let __z = match self.__solve::<Scalar>(__t, __x) {
            ::core::option::Option::Some(__z) => __z,
            ::core::option::Option::None => { #on_failure }
        };
    }
}

/// Fills `target` with NaN and returns: a failed solve is never passed on as numbers.
pub fn fill_nan(target: &str) -> TokenStream {
    let target = proc_macro2::Ident::new(target, Span::call_site());
    quote! {
        for __v in #target.iter_mut() {
            *__v = <Scalar as ::bgdsl_runtime::Scalar>::from_f64(::core::primitive::f64::NAN);
        }
        return;
    }
}

/// The field, its initial value, and the `Model` items of an implicit model.
pub struct ModelParts {
    /// `__implicit: ImplicitMemory<K>,` (empty for K = 0).
    pub field: TokenStream,
    /// Its value in `new`.
    pub value: TokenStream,
    /// `DEPENDENT_STORAGE`, `ALGEBRAIC_LOOPS`, `evaluation_error`.
    pub items: TokenStream,
}

/// See [`ModelParts`].
pub fn model_parts(graph: &Graph, equations: &Equations) -> ModelParts {
    if !needed(equations) {
        return ModelParts {
            field: TokenStream::new(),
            value: TokenStream::new(),
            items: TokenStream::new(),
        };
    }
    let rt = quote!(::bgdsl_runtime);
    let shown =
        |id: crate::ir::ElementId| crate::flatten::display(&graph.element(id).name.to_string());
    let dependent: Vec<String> = equations
        .dependent
        .iter()
        .map(|d| shown(d.element))
        .collect();
    let loops = equations
        .implicit
        .groups
        .iter()
        .filter(|g| g.is_loop())
        .map(|g| {
            let names = g.elements.iter().map(|&e| shown(e));
            quote!(&[#(#names),*])
        });
    let k = equations.implicit.size();
    let (field, value, error) = if k == 0 {
        (TokenStream::new(), TokenStream::new(), TokenStream::new())
    } else {
        // For each scalar unknown, the names a failure report gives.
        let members = equations.implicit.tears.iter().flat_map(|tear| {
            let group = &equations.implicit.groups[tear.group];
            let names: Vec<String> = if group.is_loop() {
                group.elements.iter().map(|&e| shown(e)).collect()
            } else {
                group.dependent.iter().map(|&e| shown(e)).collect()
            };
            std::iter::repeat_n(names.join(", "), tear.shape.len())
        });
        (
            quote! {
                /// The unknowns of the last solve (the next one's guess) and its failure.
                __implicit: #rt::implicit::ImplicitMemory<#k>,
            },
            quote!(__implicit: #rt::implicit::ImplicitMemory::new(),),
            quote! {
                fn evaluation_error(&self) -> ::core::option::Option<#rt::ModelError> {
                    const MEMBERS: [&'static ::core::primitive::str; #k] = [#(#members),*];
                    let __failure = self.__implicit.failure()?;
                    let members = MEMBERS[__failure.unknown.min(#k - 1)];
                    ::core::option::Option::Some(match __failure.kind {
                        #rt::implicit::FailureKind::Singular => #rt::ModelError::SingularConstraint {
                            members,
                            t: __failure.t,
                        },
                        _ => #rt::ModelError::UnsolvedLoop {
                            members,
                            t: __failure.t,
                            residual: __failure.residual,
                        },
                    })
                }
            },
        )
    };
    let items = quote! {
        const DEPENDENT_STORAGE: &'static [&'static ::core::primitive::str] = &[#(#dependent),*];
        const ALGEBRAIC_LOOPS: &'static [&'static [&'static ::core::primitive::str]] = &[#(#loops),*];
        #error
    };
    ModelParts {
        field,
        value,
        items,
    }
}

/// Dependent storage's stored energy for the power account: ½ p·f (I), ½ q·e (C).
pub fn dependent_energy(graph: &Graph, equations: &Equations) -> Vec<TokenStream> {
    let rt = quote!(::bgdsl_runtime);
    equations
        .dependent
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let energy = energy_fn_ident(k);
            let port = if graph.element(d.element).kind == ElementKind::I {
                term_tokens(Term::signed(d.negate, d.receives), Span::call_site())
            } else {
                term_tokens(Term::plus(d.receives), Span::call_site())
            };
            let product = match d.shape {
                Shape::Scalar => quote!((self.#energy::<Scalar>(t, __x) * #port)),
                _ => quote!((self.#energy::<Scalar>(t, __x).dot(&#port))),
            };
            quote!((<Scalar as #rt::Scalar>::from_f64(0.5) * #product))
        })
        .collect()
}
