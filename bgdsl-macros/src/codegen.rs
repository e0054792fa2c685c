//! Stage 5: Rust code for a model: the parameter struct, typed state and output
//! structs, the causal-graph description and the `Model` implementation whose
//! functions are straight-line code in the order the equations stage chose.
//!
//! Every path is absolute (`::core::...`, `::bgdsl_runtime::...`) so the expansion
//! compiles in any scope; user expressions keep their spans so type errors land on
//! the user's text.

use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote, quote_spanned, ToTokens};
use syn::{Expr, ExprLit, Ident, Lit, LitFloat, Visibility};

use crate::causality::{Causality, ElementCausality};
use crate::equations::{Derivative, Equations, Op, Rhs};
use crate::ir::{ElementKind, Graph, Shape};
use crate::rewrite::term_tokens;
use crate::signals::{Signal, Term};

/// The generated items of a model that compiled.
pub fn generate(graph: &Graph, causality: &Causality, equations: &Equations) -> TokenStream {
    let vis = &graph.vis;
    let name = &graph.name;
    let params: Vec<ParamDecl> = graph
        .params
        .iter()
        .map(|p| ParamDecl {
            attrs: &p.attrs,
            name: &p.name,
            shape: p.shape,
            default: &p.default,
            unit: p.unit.as_ref(),
            input: p.input,
        })
        .collect();
    let params_ident = params_ident(name);
    let derived = collect_derived(equations);
    let refresh = derived
        .has_cache()
        .then(|| quote!(self.__derived = Self::__derive(&self.params);));
    let host = host_interface(vis, name, &params, refresh);
    let params_struct = params_struct(vis, name, &params);
    let state_names: Vec<String> = equations
        .states
        .iter()
        .flat_map(|s| component_names(&s.name, s.shape))
        .collect();
    let output_shapes = output_shapes(graph, equations);
    let output_names: Vec<String> = graph
        .outputs
        .iter()
        .zip(&output_shapes)
        .flat_map(|(o, &shape)| {
            component_names(&crate::flatten::display(&o.name.to_string()), shape)
        })
        .collect();
    let bodies = bodies_const(graph, &state_names);
    let n_states = state_names.len();
    let n_outputs = output_names.len();
    let units = crate::units::check(graph, equations);
    let signal_infos = |names: &[String], described: Vec<&crate::units::Described>| {
        let entries = names.iter().zip(described).map(|(name, d)| {
            let (unit, doc) = (&d.unit, &d.doc);
            quote!(__S { name: #name, unit: #unit, doc: #doc })
        });
        quote!({
            use ::bgdsl_runtime::SignalInfo as __S;
            &[#(#entries),*]
        })
    };
    let state_infos = signal_infos(
        &state_names,
        equations
            .states
            .iter()
            .zip(&units.states)
            .flat_map(|(s, d)| std::iter::repeat_n(d, s.shape.len()))
            .collect(),
    );
    let output_infos = signal_infos(
        &output_names,
        output_shapes
            .iter()
            .zip(&units.outputs)
            .flat_map(|(shape, d)| std::iter::repeat_n(d, shape.len()))
            .collect(),
    );
    let unit_warnings = &units.warnings;
    // `loop.q` → `loop_q`; an output `type` → `r#type`.
    let field = |n: &String| crate::keywords::rust_ident(&n.replace('.', "_"), Span::call_site());
    let state_fields: Vec<Ident> = state_names.iter().map(field).collect();
    let state_docs: Vec<String> = state_names.iter().map(|n| format!("`{n}`")).collect();
    let output_fields: Vec<Ident> = output_names.iter().map(field).collect();
    let state_struct = format_ident!("{}State", name);
    let outputs_struct = format_ident!("{}Outputs", name);
    let record_struct_state = record_struct(
        vis,
        &state_struct,
        &format!("The state of [`{name}`], by name."),
        &state_fields,
        &state_docs,
    );
    let output_docs: Vec<String> = graph
        .outputs
        .iter()
        .zip(&output_shapes)
        .flat_map(|(o, &shape)| {
            let doc = doc_text(&o.attrs).unwrap_or_else(|| format!("Output `{}`.", o.name));
            std::iter::repeat_n(doc, shape.len())
        })
        .collect();
    let record_struct_outputs = record_struct(
        vis,
        &outputs_struct,
        &format!("The outputs of [`{name}`], by name."),
        &output_fields,
        &output_docs,
    );
    let graph_const = graph_description(graph, causality, equations);
    let body = evaluation_body(graph, equations, &derived);
    let event_items = crate::event_code::model_items(graph, equations, &body);
    let check_body = {
        let solve =
            crate::staged::solve_first(equations, quote!(return ::core::result::Result::Ok(());));
        quote!(#solve #body)
    };
    let (check_inverses, debug_inverses) = inverse_checks(graph, equations, &check_body);
    let power = crate::power::account(graph, equations);
    let solve_dx = crate::staged::solve_first(equations, crate::staged::fill_nan("__dx"));
    let solve_y = crate::staged::solve_first(equations, crate::staged::fill_nan("__y"));
    let solve_power =
        crate::staged::solve_first(equations, quote!(return ::core::option::Option::None;));
    let staged_methods = crate::staged::methods(graph, equations, &derived);
    let exact_tangents = derived.exact_tangents(graph);
    let crate::staged::ModelParts {
        field: implicit_field,
        value: implicit_value,
        items: implicit_items,
    } = crate::staged::model_parts(graph, equations);
    let scalar = quote!(Scalar);
    let state_offsets = equations.offsets();
    let dx = Ident::new("__dx", Span::call_site());
    let derivatives: Vec<TokenStream> = equations
        .states
        .iter()
        .zip(&state_offsets)
        .map(|(s, &offset)| {
            let value = match &s.derivative {
                Derivative::Term(term) => term_tokens(*term, Span::call_site()),
                Derivative::Expr(der) => der.expr.to_token_stream(),
            };
            write_value(s.shape, value, &dx, offset, &scalar)
        })
        .collect();
    let y = Ident::new("__y", Span::call_site());
    let mut output_offset = 0;
    let outputs: Vec<TokenStream> = equations
        .outputs
        .iter()
        .zip(&output_shapes)
        .map(|(o, &shape)| {
            let write = write_value(shape, o.expr.to_token_stream(), &y, output_offset, &scalar);
            output_offset += shape.len();
            write
        })
        .collect();
    // A large model's evaluation is split into chunk methods the three share.
    let (chunk_methods, derivatives_body, outputs_body, power_body) =
        if crate::chunks::applies(equations, &body) {
            let chunked = crate::chunks::split(
                graph,
                equations,
                &derived,
                crate::power::terms(graph, equations),
            );
            (
                chunked.methods,
                chunked.derivatives,
                chunked.outputs,
                chunked.power,
            )
        } else {
            (
                TokenStream::new(),
                quote!(#solve_dx #body #debug_inverses #(#derivatives)*),
                quote!(#solve_y #body #(#outputs)*),
                quote!(#solve_power #body #power),
            )
        };
    let initial = initial_state(graph, equations);
    let sparsity = equations
        .jacobian_sparsity()
        .into_iter()
        .map(|row| quote!(&[#(#row),*]));
    let params_f64 = bind_params(graph, &quote!(::core::primitive::f64));
    let model_doc = if graph.attrs.iter().any(|a| a.path().is_ident("doc")) {
        quote!()
    } else {
        let text = format!("The bond-graph model `{name}`.");
        quote!(#[doc = #text])
    };
    let attrs = &graph.attrs;
    let name_str = name.to_string();
    let HostInterface {
        inputs_struct,
        inputs_ident,
        parameter_infos,
        model_items,
        with_inputs,
    } = host;
    // The derived-value cache, when the model has parameter expressions to keep.
    // The memory of an implicit model's solve is no part of its value.
    let (partial_eq_derive, partial_eq_impl) = if implicit_field.is_empty() {
        (quote!(::core::cmp::PartialEq), quote!())
    } else {
        (
            quote!(),
            quote! {
                impl ::core::cmp::PartialEq for #name {
                    fn eq(&self, other: &Self) -> ::core::primitive::bool {
                        self.params == other.params && self.inputs == other.inputs
                    }
                }
            },
        )
    };
    let (derived_field, derived_value, derive_fn, default_derive, default_impl) =
        if derived.has_cache() {
            let cache_type = crate::derived::Derived::cache_type(name);
            let cache_struct = derived.cache_struct(name, &params_ident);
            (
                quote! {
                    /// The model's parameter expressions, computed from `params` (see
                    /// `__derive`).
                    __derived: #cache_type,
                },
                quote!(__derived: Self::__derive(&params),),
                derived.derive_fn(graph, name, &params_ident),
                quote!(),
                quote! {
                    #cache_struct

                    impl ::core::default::Default for #name {
                        fn default() -> Self {
                            Self::new(::core::default::Default::default())
                        }
                    }
                },
            )
        } else {
            (
                quote!(),
                quote!(),
                quote!(),
                quote!(::core::default::Default,),
                quote!(),
            )
        };
    let tokens = quote! {
        #unit_warnings
        #params_struct
        #inputs_struct

        #(#attrs)*
        #model_doc
        #[derive(::core::clone::Clone, ::core::fmt::Debug, #default_derive #partial_eq_derive)]
        #vis struct #name {
            /// The parameters the model evaluates with.
            pub params: #params_ident,
            /// The inputs, set by the host between steps.
            pub inputs: #inputs_ident,
            #derived_field
            #implicit_field
        }

        #default_impl
        #partial_eq_impl

        impl #name {
            /// The number of states.
            pub const N_STATES: ::core::primitive::usize = #n_states;
            /// The number of outputs.
            pub const N_OUTPUTS: ::core::primitive::usize = #n_outputs;
            #graph_const

            /// The model with the given parameters.
            pub fn new(params: #params_ident) -> Self {
                Self {
                    #derived_value
                    params,
                    inputs: ::core::default::Default::default(),
                    #implicit_value
                }
            }

            #derive_fn
            #staged_methods
        }

        #chunk_methods

        impl ::bgdsl_runtime::FromParams for #name {
            fn from_params(params: #params_ident) -> Self {
                Self::new(params)
            }
        }

        #record_struct_state
        #record_struct_outputs

        #[automatically_derived]
        impl ::bgdsl_runtime::Model for #name {
            type Params = #params_ident;
            const NAME: &'static ::core::primitive::str = #name_str;
            const STATE_NAMES: &'static [&'static ::core::primitive::str] = &[#(#state_names),*];
            const OUTPUT_NAMES: &'static [&'static ::core::primitive::str] = &[#(#output_names),*];
            const STATES: &'static [::bgdsl_runtime::SignalInfo] = #state_infos;
            const OUTPUTS: &'static [::bgdsl_runtime::SignalInfo] = #output_infos;
            const PARAMETERS: &'static [::bgdsl_runtime::ParameterInfo] = #parameter_infos;
            #bodies
            #model_items
            const EXACT_PARAMETER_DERIVATIVES: ::core::primitive::bool = #exact_tangents;
            #implicit_items
            const JACOBIAN_SPARSITY: ::core::option::Option<&'static [&'static [::core::primitive::usize]]> =
                ::core::option::Option::Some(&[#(#sparsity),*]);

            fn params(&self) -> &#params_ident {
                &self.params
            }

            #[allow(unused_variables, non_snake_case, clippy::all)]
            fn initial_state(&self, __x0: &mut [::core::primitive::f64]) {
                ::core::assert_eq!(__x0.len(), #n_states, "state vector length");
                #[allow(unused_imports)]
                use ::bgdsl_runtime::Scalar as _;
                #params_f64
                #initial
            }

            #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
            #[inline]
            fn derivatives<Scalar: ::bgdsl_runtime::Scalar>(&self, __t: ::core::primitive::f64, __x: &[Scalar], __dx: &mut [Scalar]) {
                ::core::assert_eq!(__x.len(), #n_states, "state vector length");
                ::core::assert_eq!(__dx.len(), #n_states, "derivative vector length");
                #derivatives_body
            }

            #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
            fn outputs<Scalar: ::bgdsl_runtime::Scalar>(&self, __t: ::core::primitive::f64, __x: &[Scalar], __y: &mut [Scalar]) {
                ::core::assert_eq!(__x.len(), #n_states, "state vector length");
                ::core::assert_eq!(__y.len(), #n_outputs, "output vector length");
                #outputs_body
            }

            #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
            fn power_balance<Scalar: ::bgdsl_runtime::Scalar>(
                &self,
                __t: ::core::primitive::f64,
                __x: &[Scalar],
            ) -> ::core::option::Option<::bgdsl_runtime::PowerBalance<Scalar>> {
                ::core::assert_eq!(__x.len(), #n_states, "state vector length");
                #power_body
            }

            fn causal_graph(&self) -> ::core::option::Option<&'static ::bgdsl_runtime::CausalGraph> {
                ::core::option::Option::Some(&Self::GRAPH)
            }

            #check_inverses
            #event_items
        }

        #with_inputs
    };
    derived.replace(tokens)
}

/// The parameter expressions hoisted out of every law, modulus, `der` and output.
fn collect_derived(equations: &Equations) -> crate::derived::Derived {
    let laws = equations.ordered.iter().filter_map(|eq| match &eq.rhs {
        Rhs::Law { expr, .. } => Some(expr.to_token_stream()),
        Rhs::Scaled { modulus, .. } => Some(modulus.to_token_stream()),
        _ => None,
    });
    let ders = equations.states.iter().filter_map(|s| match &s.derivative {
        Derivative::Expr(der) => Some(der.expr.to_token_stream()),
        Derivative::Term(_) => None,
    });
    let outputs = equations.outputs.iter().map(|o| o.expr.to_token_stream());
    let dependent = equations
        .dependent
        .iter()
        .map(|d| d.modulus.to_token_stream());
    // A given inverse and its modulus are evaluated again by `Model::check`.
    let inverses = equations.inverses.iter().flat_map(|check| {
        [
            check.modulus.to_token_stream(),
            check.inverse.to_token_stream(),
        ]
    });
    crate::derived::Derived::collect(
        laws.chain(ders)
            .chain(outputs)
            .chain(dependent)
            .chain(inverses)
            .chain(crate::event_code::expressions(equations)),
    )
}

/// What the macro emits for a model with mistakes: its items with the right names
/// (the parameter struct with its real fields, `new`, `GRAPH`, the state and output
/// records, the `Model` implementation), so the user's other code that names them does
/// not drown in follow-on errors.
pub fn stub(model: &crate::syntax::ModelDef) -> TokenStream {
    let vis = &model.vis;
    let name = &model.name;
    let params_ident = params_ident(name);
    let name_str = name.to_string();
    let mut seen = std::collections::BTreeSet::new();
    let params: Vec<ParamDecl> = model
        .stmts
        .iter()
        .filter_map(|stmt| match stmt {
            // An input that is not a number was reported; leaving it out of the stub
            // spares a follow-on type error.
            crate::syntax::Stmt::Param(p) if p.input && p.shape != Shape::Scalar => None,
            crate::syntax::Stmt::Param(p) if seen.insert(p.name.to_string()) => Some(ParamDecl {
                attrs: &p.attrs,
                name: &p.name,
                shape: p.shape,
                default: &p.default,
                unit: p.unit.as_ref(),
                input: p.input,
            }),
            _ => None,
        })
        .collect();
    let host = host_interface(vis, name, &params, None);
    let params_struct = params_struct(vis, name, &params);
    let no_fields: &[Ident] = &[];
    let state = record_struct(
        vis,
        &format_ident!("{}State", name),
        "The state.",
        no_fields,
        &[],
    );
    let outputs = record_struct(
        vis,
        &format_ident!("{}Outputs", name),
        "The outputs.",
        no_fields,
        &[],
    );
    let HostInterface {
        inputs_struct,
        inputs_ident,
        parameter_infos,
        model_items,
        with_inputs,
    } = host;
    quote! {
        #params_struct
        #inputs_struct
        #state
        #outputs

        /// The model (it has errors: see the compiler's messages).
        #[derive(::core::clone::Clone, ::core::fmt::Debug, ::core::default::Default, ::core::cmp::PartialEq)]
        #vis struct #name {
            /// The parameters.
            pub params: #params_ident,
            /// The inputs.
            pub inputs: #inputs_ident,
        }

        impl #name {
            /// The number of states.
            pub const N_STATES: ::core::primitive::usize = 0;
            /// The number of outputs.
            pub const N_OUTPUTS: ::core::primitive::usize = 0;
            /// The causal bond graph.
            pub const GRAPH: ::bgdsl_runtime::CausalGraph =
                ::bgdsl_runtime::CausalGraph { model: #name_str, elements: &[], bonds: &[], loops: &[] };
            /// The model with the given parameters.
            pub fn new(params: #params_ident) -> Self {
                Self {
                    params,
                    inputs: ::core::default::Default::default(),
                }
            }
        }

        impl ::bgdsl_runtime::FromParams for #name {
            fn from_params(params: #params_ident) -> Self {
                Self::new(params)
            }
        }

        impl ::bgdsl_runtime::Model for #name {
            type Params = #params_ident;
            const NAME: &'static ::core::primitive::str = #name_str;
            const STATE_NAMES: &'static [&'static ::core::primitive::str] = &[];
            const OUTPUT_NAMES: &'static [&'static ::core::primitive::str] = &[];
            const PARAMETERS: &'static [::bgdsl_runtime::ParameterInfo] = #parameter_infos;
            #model_items
            fn params(&self) -> &#params_ident {
                &self.params
            }
            fn initial_state(&self, _: &mut [::core::primitive::f64]) {}
            fn derivatives<Scalar: ::bgdsl_runtime::Scalar>(&self, _: ::core::primitive::f64, _: &[Scalar], _: &mut [Scalar]) {}
            fn outputs<Scalar: ::bgdsl_runtime::Scalar>(&self, _: ::core::primitive::f64, _: &[Scalar], _: &mut [Scalar]) {}
        }

        #with_inputs
    }
}

fn params_ident(name: &Ident) -> Ident {
    format_ident!("{}Params", name)
}

/// The text of the doc comments among `attrs`, lines joined, if there are any.
pub fn doc_text(attrs: &[syn::Attribute]) -> Option<String> {
    let lines: Vec<String> = attrs
        .iter()
        .filter(|a| a.path().is_ident("doc"))
        .filter_map(|a| match &a.meta {
            syn::Meta::NameValue(nv) => match &nv.value {
                Expr::Lit(ExprLit {
                    lit: Lit::Str(s), ..
                }) => Some(s.value().trim().to_string()),
                _ => None,
            },
            _ => None,
        })
        .collect();
    (!lines.is_empty()).then(|| lines.join("\n"))
}

/// A parameter default in `f64`: a bare integer literal is read as a float.
fn f64_expr(expr: &Expr) -> TokenStream {
    match expr {
        Expr::Lit(ExprLit {
            lit: Lit::Int(int), ..
        }) if int.suffix().is_empty() => {
            let float = LitFloat::new(&format!("{}.0", int.base10_digits()), int.span());
            quote!(#float)
        }
        other => quote!(#other),
    }
}

/// A parameter as code generation needs it (from the IR, or from syntax for a stub).
pub struct ParamDecl<'a> {
    /// Doc comments and attributes.
    pub attrs: &'a [syn::Attribute],
    /// The name.
    pub name: &'a Ident,
    /// Its shape.
    pub shape: Shape,
    /// The default value.
    pub default: &'a Expr,
    /// The declared unit.
    pub unit: Option<&'a syn::LitStr>,
    /// Declared `input`.
    pub input: bool,
}

/// What a host program sees of a model's parameters and inputs.
struct HostInterface {
    /// `FooInputs` and its `Default`.
    inputs_struct: TokenStream,
    /// `FooInputs`.
    inputs_ident: Ident,
    /// The value of `Model::PARAMETERS`.
    parameter_infos: TokenStream,
    /// `N_PARAMETER_VALUES` and the flat parameter access of `Model`.
    model_items: TokenStream,
    /// The `WithInputs` implementation.
    with_inputs: TokenStream,
}

/// `refresh` recomputes what the model derives from its parameters, after
/// `set_parameter_values` wrote them.
fn host_interface(
    vis: &Visibility,
    model: &Ident,
    declared: &[ParamDecl],
    refresh: Option<TokenStream>,
) -> HostInterface {
    let (inputs, params): (Vec<&ParamDecl>, Vec<&ParamDecl>) =
        declared.iter().partition(|p| p.input);
    let inputs_ident = format_ident!("{}Inputs", model);
    let f64_ty = quote!(::core::primitive::f64);
    // Flat parameter access: each number in declaration order, matrices row by row.
    let mut reads = Vec::new();
    let mut writes = Vec::new();
    let mut at = 0usize;
    for p in &params {
        let name = p.name;
        let places: Vec<TokenStream> = match p.shape {
            Shape::Scalar => vec![quote!()],
            Shape::Vector(n) => (0..n).map(|i| quote!([#i])).collect(),
            Shape::Matrix(r, c) => (0..r)
                .flat_map(|i| (0..c).map(move |j| quote!([#i][#j])))
                .collect(),
        };
        for place in places {
            reads.push(quote!(__out[#at] = self.params.#name #place;));
            writes.push(quote!(self.params.#name #place = __values[#at];));
            at += 1;
        }
    }
    let n_values = at;
    let model_items = quote! {
        const N_PARAMETER_VALUES: ::core::primitive::usize = #n_values;
        fn parameter_values(&self, __out: &mut [#f64_ty]) {
            ::core::assert_eq!(__out.len(), #n_values, "parameter vector length");
            #(#reads)*
        }
        fn set_parameter_values(&mut self, __values: &[#f64_ty]) {
            ::core::assert_eq!(__values.len(), #n_values, "parameter vector length");
            #(#writes)*
            #refresh
        }
    };
    let names: Vec<&Ident> = inputs.iter().map(|p| p.name).collect();
    let defaults = inputs.iter().map(|p| f64_expr(p.default));
    let indices: Vec<usize> = (0..inputs.len()).collect();
    let n_inputs = inputs.len();
    let field_docs = inputs.iter().map(|p| {
        let unit = p
            .unit
            .map(|u| format!(" Unit: {}.", u.value()))
            .unwrap_or_default();
        let default = p.default;
        let default_text = quote!(#default).to_string();
        let text = doc_text(p.attrs).unwrap_or_else(|| format!("Input `{}`.", p.name));
        format!("{text}\n\nDefault: `{default_text}`.{unit}")
    });
    let doc =
        format!("Inputs of [`{model}`]: values its laws read that the host sets between steps.");
    let input_infos = infos(&inputs);
    let inputs_struct = quote! {
        #[doc = #doc]
        #[derive(
            ::core::clone::Clone,
            ::core::marker::Copy,
            ::core::fmt::Debug,
            ::core::cmp::PartialEq,
            ::bgdsl_runtime::__private::serde::Serialize,
            ::bgdsl_runtime::__private::serde::Deserialize,
        )]
        #[serde(crate = "::bgdsl_runtime::__private::serde", default, deny_unknown_fields)]
        #[allow(non_snake_case)]
        #vis struct #inputs_ident {
            #( #[doc = #field_docs] pub #names: #f64_ty, )*
        }

        #[automatically_derived]
        impl ::core::default::Default for #inputs_ident {
            #[allow(non_snake_case, clippy::all)]
            fn default() -> Self {
                // Without std, `f64` has no `sqrt`, `sin`, ...: the `Scalar` trait gives
                // them (with std the inherent methods still win).
                #[allow(unused_imports)]
                use ::bgdsl_runtime::Scalar as _;
                #( let #names: #f64_ty = #defaults; )*
                Self { #(#names),* }
            }
        }
    };
    let with_inputs = quote! {
        #[automatically_derived]
        impl ::bgdsl_runtime::WithInputs for #model {
            type Inputs = #inputs_ident;
            const INPUTS: &'static [::bgdsl_runtime::InputInfo] = #input_infos;
            fn inputs(&self) -> #inputs_ident {
                self.inputs
            }
            fn set_inputs(&mut self, inputs: #inputs_ident) {
                self.inputs = inputs;
            }
            #[allow(unused_variables)]
            fn input_values(&self, __out: &mut [#f64_ty]) {
                ::core::assert_eq!(__out.len(), #n_inputs, "input vector length");
                #( __out[#indices] = self.inputs.#names; )*
            }
            #[allow(unused_variables)]
            fn set_input_values(&mut self, __values: &[#f64_ty]) {
                ::core::assert_eq!(__values.len(), #n_inputs, "input vector length");
                #( self.inputs.#names = __values[#indices]; )*
            }
        }
    };
    HostInterface {
        inputs_struct,
        inputs_ident,
        parameter_infos: infos(&params),
        model_items,
        with_inputs,
    }
}

/// The entries of `Model::PARAMETERS` (or `WithInputs::INPUTS`): name, unit, doc text
/// and length of each, in declaration order.
fn infos(params: &[&ParamDecl]) -> TokenStream {
    let infos = params.iter().map(|p| {
        let name = crate::keywords::unraw(&p.name.to_string());
        let unit = p.unit.map(syn::LitStr::value).unwrap_or_default();
        let doc = doc_text(p.attrs).unwrap_or_default();
        let len = p.shape.len();
        if p.input {
            quote! {
                ::bgdsl_runtime::InputInfo {
                    name: #name,
                    unit: #unit,
                    doc: #doc,
                }
            }
        } else {
            quote! {
                ::bgdsl_runtime::ParameterInfo {
                    name: #name,
                    unit: #unit,
                    doc: #doc,
                    len: #len,
                }
            }
        }
    });
    quote!(&[#(#infos),*])
}

fn params_struct(vis: &Visibility, model: &Ident, declared: &[ParamDecl]) -> TokenStream {
    let params: Vec<&ParamDecl> = declared.iter().filter(|p| !p.input).collect();
    let ident = params_ident(model);
    let doc = format!("Parameters of [`{model}`], with the declared values as defaults.");
    let fields = params.iter().map(|p| {
        let name = p.name;
        let attrs = p.attrs;
        let default = p.default;
        let default_text = quote!(#default).to_string();
        let unit = p
            .unit
            .map(|u| format!(" Unit: {}.", u.value()))
            .unwrap_or_default();
        let doc = if doc_text(attrs).is_some() {
            format!("\n\nDefault: `{default_text}`.{unit}")
        } else {
            format!("Parameter `{name}`; default `{default_text}`.{unit}")
        };
        let ty = param_field_type(p.shape);
        quote!(#(#attrs)* #[doc = #doc] pub #name: #ty,)
    });
    let names: Vec<&Ident> = params.iter().map(|p| p.name).collect();
    let types: Vec<TokenStream> = params.iter().map(|p| param_field_type(p.shape)).collect();
    let defaults = params.iter().map(|p| f64_expr(p.default));
    quote! {
        #[doc = #doc]
        #[derive(
            ::core::clone::Clone,
            ::core::fmt::Debug,
            ::core::cmp::PartialEq,
            ::bgdsl_runtime::__private::serde::Serialize,
            ::bgdsl_runtime::__private::serde::Deserialize,
        )]
        #[serde(crate = "::bgdsl_runtime::__private::serde", default, deny_unknown_fields)]
        #[allow(non_snake_case)]
        #vis struct #ident {
            #(#fields)*
        }

        #[automatically_derived]
        impl ::core::default::Default for #ident {
            #[allow(non_snake_case, clippy::all)]
            fn default() -> Self {
                // Without std, `f64` has no `sqrt`, `sin`, ...: the `Scalar` trait gives
                // them (with std the inherent methods still win).
                #[allow(unused_imports)]
                use ::bgdsl_runtime::Scalar as _;
                #( let #names: #types = #defaults; )*
                Self { #(#names),* }
            }
        }
    }
}

/// Records with more fields than this compare field by field in flat statements
/// rather than through the derived `&&` chain (see [`record_struct`]).
const FLAT_EQ_ABOVE: usize = 64;

fn record_struct(
    vis: &Visibility,
    ident: &Ident,
    doc: &str,
    fields: &[impl quote::ToTokens],
    docs: &[String],
) -> TokenStream {
    let n = fields.len();
    let indices = 0..n;
    let indices2 = 0..n;
    // A record with no entries still needs its type parameter used.
    let (marker_field, marker_value) = if n == 0 {
        (
            quote!(#[doc(hidden)] pub __marker: ::core::marker::PhantomData<T>,),
            quote!(__marker: ::core::marker::PhantomData,),
        )
    } else {
        (quote!(), quote!())
    };
    // The derived `==` is one `a == b && ...` expression, nested as deep as the record
    // has fields: at 10,000 states rustc's name resolution overflows its stack on it.
    // A large record compares field by field in flat statements instead.
    let (partial_eq_derive, partial_eq_impl) = if n > FLAT_EQ_ABOVE {
        let compare = fields
            .iter()
            .map(|f| quote!(if self.#f != other.#f { return false; }));
        (
            quote!(),
            quote! {
                impl<T: ::core::cmp::PartialEq> ::core::cmp::PartialEq for #ident<T> {
                    fn eq(&self, other: &Self) -> bool {
                        #(#compare)*
                        true
                    }
                }
            },
        )
    } else {
        (quote!(, ::core::cmp::PartialEq), quote!())
    };
    quote! {
        #[doc = #doc]
        #[derive(::core::clone::Clone, ::core::marker::Copy, ::core::fmt::Debug, ::core::default::Default #partial_eq_derive)]
        #[allow(non_snake_case)]
        #vis struct #ident<T> {
            #( #[doc = #docs] pub #fields: T, )*
            #marker_field
        }

        #partial_eq_impl

        impl<T: ::core::marker::Copy> #ident<T> {
            /// Reads the values in vector order. Panics if `values` has the wrong length.
            #[allow(unused_variables)]
            pub fn from_slice(values: &[T]) -> Self {
                ::core::assert_eq!(values.len(), #n, "vector length");
                Self { #( #fields: values[#indices], )* #marker_value }
            }

            /// Writes the values in vector order. Panics if `values` has the wrong length.
            #[allow(unused_variables)]
            pub fn write_to(&self, values: &mut [T]) {
                ::core::assert_eq!(values.len(), #n, "vector length");
                #( values[#indices2] = self.#fields; )*
            }
        }
    }
}

fn initial_state(graph: &Graph, equations: &Equations) -> TokenStream {
    let f64_type = quote!(::core::primitive::f64);
    let x0 = Ident::new("__x0", Span::call_site());
    let assignments = equations
        .states
        .iter()
        .zip(equations.offsets())
        .map(|(state, offset)| {
            if let Some(m) = state.mode {
                let mode = &graph.modes[m];
                let span = syn::spanned::Spanned::span(&mode.init);
                // An `i64` mode's integer literal stays one.
                let init = match mode.kind {
                    crate::events::ModeKind::Integer => mode.init.to_token_stream(),
                    _ => f64_expr(&mode.init),
                };
                let value = crate::event_code::stored(mode.kind, init, span);
                return write_value(state.shape, value, &x0, offset, &f64_type);
            }
            let declared = match (state.element, state.kinematic) {
                (Some(element), _) => graph
                    .inits
                    .iter()
                    .find(|init| init.element == element)
                    .map(|init| &init.value),
                (None, Some(k)) => Some(&graph.kinematics[k].init),
                (None, None) => None,
            };
            let ty = value_type(state.shape, &f64_type);
            let value = match declared {
                Some(value) if state.shape == Shape::Scalar => f64_expr(value),
                // `[f64; 3]` or an nalgebra value, for a vector or a matrix.
                Some(value) => {
                    let value = f64_expr(value);
                    quote!({ let __value: #ty = ::core::convert::From::from(#value); __value })
                }
                None => zero(state.shape, &f64_type),
            };
            write_value(state.shape, value, &x0, offset, &f64_type)
        });
    quote!(#(#assignments)*)
}

/// Binds each parameter by name, converted to `scalar` (`f64` or the model's scalar
/// type): a number, an nalgebra vector or a matrix.
///
/// Each is read through [`Scalar::parameter`] or [`Scalar::input`] with its index (the
/// flat order of `parameter_values`, the order of `INPUTS`): the constant for `f64`
/// and state duals, a seeded tangent for parameter derivatives.
pub fn bind_params(graph: &Graph, scalar: &TokenStream) -> TokenStream {
    let (mut param_index, mut input_index) = (0usize, 0usize);
    let binds = graph.params.iter().map(|p| {
        let name = &p.name;
        let ty = value_type(p.shape, scalar);
        let (at, next) = if p.input {
            (input_index, &mut input_index)
        } else {
            (param_index, &mut param_index)
        };
        *next += p.shape.len();
        let value = match p.shape {
            _ if p.input => {
                quote!(<#scalar as ::bgdsl_runtime::Scalar>::input(__inputs.#name, #at))
            }
            Shape::Scalar => {
                quote!(<#scalar as ::bgdsl_runtime::Scalar>::parameter(self.params.#name, #at))
            }
            Shape::Vector(_) => {
                quote!(::bgdsl_runtime::multibond::vector_parameter(&self.params.#name, #at))
            }
            Shape::Matrix(..) => {
                quote!(::bgdsl_runtime::multibond::matrix_parameter(&self.params.#name, #at))
            }
        };
        quote!(let #name: #ty = #value;)
    });
    quote! {
        let __inputs = &self.inputs;
        #(#binds)*
    }
}

/// The Rust type of a value of `shape` with entries of type `scalar`.
pub fn value_type(shape: Shape, scalar: &TokenStream) -> TokenStream {
    match shape {
        Shape::Scalar => scalar.clone(),
        Shape::Vector(n) => quote!(::bgdsl_runtime::multibond::SVector<#scalar, #n>),
        Shape::Matrix(r, c) => quote!(::bgdsl_runtime::multibond::SMatrix<#scalar, #r, #c>),
    }
}

/// The field type of a parameter in the parameter struct: plain arrays, rows first.
fn param_field_type(shape: Shape) -> TokenStream {
    match shape {
        Shape::Scalar => quote!(::core::primitive::f64),
        Shape::Vector(n) => quote!([::core::primitive::f64; #n]),
        Shape::Matrix(r, c) => quote!([[::core::primitive::f64; #c]; #r]),
    }
}

/// A zero of `shape`.
pub fn zero(shape: Shape, scalar: &TokenStream) -> TokenStream {
    match shape {
        Shape::Scalar => quote!(<#scalar as ::bgdsl_runtime::Scalar>::from_f64(0.0)),
        _ => {
            let ty = value_type(shape, scalar);
            quote!(<#ty>::zeros())
        }
    }
}

/// Writes `value` (of `shape`) into `target[offset..]`, matrices column by column.
pub fn write_value(
    shape: Shape,
    value: TokenStream,
    target: &Ident,
    offset: usize,
    scalar: &TokenStream,
) -> TokenStream {
    match shape {
        Shape::Scalar => quote!(#target[#offset] = #value;),
        _ => {
            let ty = value_type(shape, scalar);
            let end = offset + shape.len();
            quote! {
                let __value: #ty = #value;
                ::bgdsl_runtime::multibond::StateValue::write(&__value, &mut #target[#offset..#end]);
            }
        }
    }
}

/// The names of a value's entries: the name itself for a number, `_x`, `_y`, `_z` for
/// a 3-vector (`_1` ... `_n` otherwise), `_rc` for a matrix, column by column (the
/// order nalgebra stores them in, and the order of the paper's results file).
fn component_names(base: &str, shape: Shape) -> Vec<String> {
    match shape {
        Shape::Scalar => vec![base.to_string()],
        Shape::Vector(3) => ["x", "y", "z"]
            .iter()
            .map(|c| format!("{base}_{c}"))
            .collect(),
        Shape::Vector(n) => (1..=n).map(|i| format!("{base}_{i}")).collect(),
        Shape::Matrix(r, c) => (1..=c)
            .flat_map(|col| (1..=r).map(move |row| format!("{base}_{row}{col}")))
            .collect(),
    }
}

/// Each output's shape: as declared, else its expression's (a signal, a component of
/// one, a parameter, a product of them, ...), else a number.
pub fn output_shapes(graph: &Graph, equations: &Equations) -> Vec<Shape> {
    let mut state_of = vec![None; graph.elements.len()];
    let mut kinematic_state = vec![0; graph.kinematics.len()];
    for (i, state) in equations.states.iter().enumerate() {
        if let Some(element) = state.element {
            state_of[element.0] = Some(i);
        }
        if let Some(k) = state.kinematic {
            kinematic_state[k] = i;
        }
    }
    let scope = crate::rewrite::Scope {
        graph,
        state_of: &state_of,
        kinematic_state: &kinematic_state,
    };
    graph
        .outputs
        .iter()
        .map(|output| {
            let locals = std::collections::BTreeSet::new();
            let env = crate::rewrite::Env {
                scope: &scope,
                locals: &locals,
            };
            output
                .shape
                .or_else(|| crate::shapes::shape(&output.expr, &env))
                .unwrap_or(Shape::Scalar)
        })
        .collect()
}

/// Binds time, parameters and states, then computes every bond variable in order (the
/// torn unknowns of an implicit model read from `__z` first).
pub fn evaluation_body(
    graph: &Graph,
    equations: &Equations,
    derived: &crate::derived::Derived,
) -> TokenStream {
    let time = Ident::new("t", Span::call_site());
    let prelude = prelude(graph, equations, derived);
    let unknowns = crate::staged::unknowns(equations);
    let assignments = equations
        .ordered
        .iter()
        .map(|eq| assignment(graph, equations, eq));
    quote! {
        let #time: Scalar = <Scalar as ::bgdsl_runtime::Scalar>::from_f64(__t);
        #prelude
        #unknowns
        #(#assignments)*
    }
}

/// Binds parameters, hoisted parameter expressions and states (in `Scalar`).
pub fn prelude(
    graph: &Graph,
    equations: &Equations,
    derived: &crate::derived::Derived,
) -> TokenStream {
    let scalar = quote!(Scalar);
    let params = bind_params(graph, &scalar);
    let hoisted = derived.bindings(graph);
    let states = equations.states.iter().zip(equations.offsets()).enumerate().map(|(i, (state, offset))| {
        let ident = Signal::State(i).ident(Span::call_site());
        let ty = value_type(state.shape, &scalar);
        match state.shape {
            Shape::Scalar => quote!(let #ident: Scalar = __x[#offset];),
            shape => {
                let end = offset + shape.len();
                quote!(let #ident: #ty = <#ty as ::bgdsl_runtime::multibond::StateValue<Scalar>>::read(&__x[#offset..#end]);)
            }
        }
    });
    let modes = crate::event_code::bind_modes(graph, equations);
    quote! {
        #params
        #hoisted
        #(#states)*
        #modes
    }
}

/// `let <signal>: <type> = <value>;` for one equation.
pub fn assignment(
    graph: &Graph,
    equations: &Equations,
    eq: &crate::equations::Equation,
) -> TokenStream {
    let scalar = quote!(Scalar);
    let span = graph.element(eq.element).name.span();
    let target = eq.defines.ident(span);
    let shape = equations.shape_of(graph, eq.defines);
    let ty = value_type(shape, &scalar);
    let value = match &eq.rhs {
        Rhs::Law {
            negate,
            bindings,
            expr,
        } => {
            let binds = bindings.iter().map(|(var, term)| {
                let var = Ident::new(var, Span::call_site());
                let bound_type = value_type(equations.shape_of(graph, term.signal), &scalar);
                let term = term_tokens(*term, span);
                quote!(let #var: #bound_type = #term;)
            });
            let sign = negate.then(|| quote!(-));
            quote_spanned!(span=> #sign { #(#binds)* #expr })
        }
        Rhs::Sum(terms) if terms.is_empty() => zero(shape, &scalar),
        Rhs::Sum(terms) => sum(terms, span),
        Rhs::Component { of, index } => {
            let of = of.ident(span);
            quote_spanned!(span=> #of[#index])
        }
        Rhs::Assemble(parts) => {
            let n = parts.len();
            let parts = parts.iter().map(|part| part.ident(span));
            quote_spanned!(span=> ::bgdsl_runtime::multibond::SVector::<Scalar, #n>::from([#(#parts),*]))
        }
        Rhs::Scaled {
            term: scaled,
            modulus,
            op,
        } => {
            let term = term_tokens(*scaled, span);
            let input = equations.shape_of(graph, scaled.signal);
            match (shape, op) {
                _ if input != shape => non_square(shape, input, *op, modulus, term),
                (Shape::Scalar, Op::Apply | Op::ApplyTranspose) => {
                    quote_spanned!(span=> #term * (#modulus))
                }
                (Shape::Scalar, Op::Solve | Op::SolveTranspose) => {
                    quote_spanned!(span=> #term / (#modulus))
                }
                (shape, op) => linear_op(shape, *op, modulus, term, span),
            }
        }
        Rhs::Dependent(index) => crate::staged::dependent_rate(equations, *index, span),
    };
    quote!(let #target: #ty = #value;)
}

/// A matrix (or vector) coefficient applied to a value: `k v`, `kᵀ v`, `k⁻¹ v`, `k⁻ᵀ v`.
pub fn linear_op(
    shape: Shape,
    op: Op,
    modulus: &Expr,
    term: TokenStream,
    span: Span,
) -> TokenStream {
    let n = shape.len();
    let method = match op {
        Op::Apply => quote!(apply),
        Op::ApplyTranspose => quote!(apply_transpose),
        Op::Solve => quote!(solve),
        Op::SolveTranspose => quote!(solve_transpose),
    };
    quote_spanned!(span=> ::bgdsl_runtime::multibond::Linear::<Scalar, #n>::#method(&(#modulus), #term))
}

/// The checks of the inverses two-ports' laws give: `Model::check` (every residual
/// ‖M X − I‖ at a state, in `f64`) and, for the derivatives in debug builds, the same
/// as an assertion for each inverse they compute with, when they are evaluated in
/// `f64`. Both empty when no law gives one.
fn inverse_checks(
    graph: &Graph,
    equations: &Equations,
    body: &TokenStream,
) -> (TokenStream, TokenStream) {
    if equations.inverses.is_empty() {
        return (TokenStream::new(), TokenStream::new());
    }
    let rt = quote!(::bgdsl_runtime);
    let residuals: Vec<(bool, TokenStream, TokenStream)> = equations
        .inverses
        .iter()
        .map(|check| {
            let (modulus, inverse, n) = (&check.modulus, &check.inverse, check.dimension);
            let name = crate::flatten::display(&graph.element(check.element).name.to_string());
            let residual = quote!(#rt::multibond::inverse_residual::<Scalar, #n>(&(#modulus), &(#inverse)));
            let error = quote!(#rt::ModelError::WrongInverse { element: #name, t: __t, residual: __residual });
            (check.used, residual, error)
        })
        .collect();
    let returns = residuals.iter().map(|(_, residual, error)| {
        quote! {
            let __residual = #residual;
            if __residual > #rt::ModelError::INVERSE_TOLERANCE {
                return ::core::result::Result::Err(#error);
            }
        }
    });
    let check = quote! {
        #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
        fn check(&self, __t: ::core::primitive::f64, __x: &[::core::primitive::f64]) -> ::core::result::Result<(), #rt::ModelError> {
            type Scalar = ::core::primitive::f64;
            #body
            #(#returns)*
            ::core::result::Result::Ok(())
        }
    };
    let asserts = residuals
        .iter()
        .filter(|(used, ..)| *used)
        .map(|(_, residual, error)| {
            quote! {
                let __residual = #residual;
                ::core::assert!(!(__residual > #rt::ModelError::INVERSE_TOLERANCE), "{}", #error);
            }
        });
    let debug = quote! {
        #[cfg(debug_assertions)]
        if ::core::any::TypeId::of::<Scalar>() == ::core::any::TypeId::of::<::core::primitive::f64>() {
            #(#asserts)*
        }
    };
    (check, debug)
}

/// A two-port between bonds of different dimensions: its modulus must be an r×c matrix
/// (`f2 = M f1`, `e1 = Mᵀ e2`), bound with that type at the user's expression so that
/// a modulus of another shape is a type error there, naming the shape expected.
fn non_square(
    output: Shape,
    input: Shape,
    op: Op,
    modulus: &Expr,
    term: TokenStream,
) -> TokenStream {
    let rt = quote!(::bgdsl_runtime::multibond);
    let (out_len, in_len) = (output.len(), input.len());
    let (rows, columns, apply) = match op {
        Op::ApplyTranspose => (in_len, out_len, quote!(__modulus.transpose())),
        // Solving is refused for a non-square modulus when equations are derived.
        _ => (out_len, in_len, quote!(__modulus)),
    };
    let column = match input {
        Shape::Scalar => quote!(#rt::SVector::<Scalar, 1>::new(#term)),
        _ => term,
    };
    let product = quote!((#apply * #column));
    let value = match output {
        Shape::Scalar => quote!(#product[0]),
        _ => product,
    };
    let at = syn::spanned::Spanned::span(modulus);
    let typed = quote_spanned!(at=> let __modulus: ::bgdsl_runtime::multibond::SMatrix<Scalar, #rows, #columns> = #modulus;);
    quote!({ #typed #value })
}

fn sum(terms: &[Term], span: Span) -> TokenStream {
    let mut tokens = TokenStream::new();
    for (i, term) in terms.iter().enumerate() {
        let ident = term.signal.ident(span);
        tokens.extend(match (i, term.negate) {
            (0, false) => quote!(#ident),
            (0, true) => quote!(-#ident),
            (_, false) => quote!(+ #ident),
            (_, true) => quote!(- #ident),
        });
    }
    tokens
}

fn graph_description(graph: &Graph, causality: &Causality, equations: &Equations) -> TokenStream {
    let rt = quote!(::bgdsl_runtime);
    let model = graph.name.to_string();
    // Each element as `__e(name, group, code)`, `code` = 10 kind + causality (+ 100
    // when modulated), indices into the tables of `__e` below; each bond as
    // `__b(label or "", from, to, dimension, stroke_at)`. A call is a quarter of the
    // tokens of a struct literal, and a large model lists tens of thousands.
    let elements = graph.element_ids().map(|id| {
        let element = graph.element(id);
        // `crank__tip__v`: the element `v` of the instance `crank.tip`.
        let full = element.name.to_string();
        let (group, name) = match full.rsplit_once(crate::flatten::SEPARATOR) {
            Some((group, name)) => (
                crate::flatten::display(group),
                crate::flatten::display(name),
            ),
            None => (String::new(), crate::flatten::display(&full)),
        };
        let kind: u8 = match element.kind {
            ElementKind::Se => 0,
            ElementKind::Sf => 1,
            ElementKind::C => 2,
            ElementKind::I => 3,
            ElementKind::R => 4,
            ElementKind::Tf => 5,
            ElementKind::Gy => 6,
            ElementKind::Zero => 7,
            ElementKind::One => 8,
            ElementKind::Split => 9,
        };
        let element_causality: u8 = match causality.element[id.0] {
            ElementCausality::Integral => 0,
            ElementCausality::Resistance => 1,
            ElementCausality::Conductance => 2,
            ElementCausality::Fixed => 3,
            ElementCausality::Derivative => 4,
        };
        let code = proc_macro2::Literal::u8_unsuffixed(
            10 * kind + element_causality + if element.modulated { 100 } else { 0 },
        );
        quote!(__e(#name, #group, #code))
    });
    let bonds = graph.bond_ids().map(|id| {
        let bond = graph.bond(id);
        let label = bond
            .label
            .as_ref()
            .map(|label| crate::flatten::display(&label.to_string()))
            .unwrap_or_default();
        let number = |n: usize| proc_macro2::Literal::usize_unsuffixed(n);
        let (from, to, stroke) = (
            number(bond.from.0),
            number(bond.to.0),
            number(causality.stroke_at[id.0].0),
        );
        let dimension = number(graph.bond_dims[id.0]);
        quote!(__b(#label, #from, #to, #dimension, #stroke))
    });
    let loops = equations
        .implicit
        .groups
        .iter()
        .filter(|g| g.is_loop())
        .map(|g| {
            let members = g.elements.iter().map(|e| e.0);
            quote!(&[#(#members),*])
        });
    quote! {
        /// The causal bond graph this model was generated from.
        pub const GRAPH: #rt::CausalGraph = {
            use #rt::{GraphElement as __E, ElementKind as __K, ElementCausality as __C, GraphBond as __B};
            use ::core::primitive::{str as __str, u8 as __u8, usize as __usize};
            const fn __e(name: &'static __str, group: &'static __str, code: __u8) -> __E {
                const KINDS: [__K; 10] = [
                    __K::Se, __K::Sf, __K::C, __K::I, __K::R,
                    __K::Tf, __K::Gy, __K::Zero, __K::One, __K::Split,
                ];
                const CAUSALITIES: [__C; 5] = [
                    __C::Integral, __C::Resistance, __C::Conductance, __C::Fixed, __C::Derivative,
                ];
                __E {
                    name,
                    group,
                    kind: KINDS[(code % 100 / 10) as __usize],
                    modulated: code >= 100,
                    causality: CAUSALITIES[(code % 10) as __usize],
                }
            }
            const fn __b(label: &'static __str, from: __usize, to: __usize, dimension: __usize, stroke_at: __usize) -> __B {
                let label = if label.is_empty() {
                    ::core::option::Option::None
                } else {
                    ::core::option::Option::Some(label)
                };
                __B { label, from, to, dimension, stroke_at }
            }
            #rt::CausalGraph {
                model: #model,
                elements: &[#(#elements),*],
                bonds: &[#(#bonds),*],
                loops: &[#(#loops),*],
            }
        };
    }
}

/// `const BODIES` for a model with instances of the library's `RigidBody` (nothing
/// otherwise): where each one's `R_11` and `r_x` lie in the state vector.
fn bodies_const(graph: &Graph, state_names: &[String]) -> TokenStream {
    let entries: Vec<TokenStream> = graph
        .bodies
        .iter()
        .filter_map(|path| {
            let name = crate::flatten::display(path);
            let at = |state: &str| {
                let wanted = format!("{name}.{state}");
                state_names.iter().position(|n| *n == wanted)
            };
            // Both are states of every RigidBody; a body without them is skipped.
            let (orientation, position) = (at("R_11")?, at("r_x")?);
            Some(quote! {
                ::bgdsl_runtime::BodyInfo {
                    name: #name,
                    orientation: #orientation,
                    position: #position,
                }
            })
        })
        .collect();
    if entries.is_empty() {
        return TokenStream::new();
    }
    quote! {
        const BODIES: &'static [::bgdsl_runtime::BodyInfo] = &[#(#entries),*];
    }
}
