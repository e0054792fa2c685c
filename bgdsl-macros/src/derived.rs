//! Code for the parameter expressions the rewriter hoisted (see [`crate::hoist`]): the
//! model's derived-value cache and the bindings that lift hoisted values into the
//! scalar type at the start of every evaluation.
//!
//! The cache is a private field of the model, `(Params, values...)`: the parameters
//! it was computed from, then one `f64`, vector or matrix per constant expression. The
//! constructor and `set_parameter_values` compute it; an evaluation reads it when it
//! was computed from the current parameters and otherwise computes it afresh on the
//! stack (so a parameter written directly into the public `params` field is never read
//! stale, only slower).

use proc_macro2::{Delimiter, Ident, Span, TokenStream, TokenTree};
use quote::{format_ident, quote, quote_spanned};

use crate::hoist::{hidden_span, Kind, MARKER};
use crate::ir::{Graph, Shape};

/// One hoisted expression.
struct Hoisted {
    kind: Kind,
    shape: Option<Shape>,
    /// The expression in its `f64` form.
    expr: TokenStream,
    /// The expression in the scalar type, when it has one that carries parameter
    /// tangents (see [`crate::hoist::tangent_safe`]).
    scalar: Option<TokenStream>,
    /// Where the user wrote it.
    span: Span,
    /// Its text, to find the same expression written twice.
    key: String,
}

/// Every hoisted expression of a model, each once.
#[derive(Default)]
pub struct Derived {
    list: Vec<Hoisted>,
}

impl Derived {
    /// Gathers the markers in `streams` (every law, modulus, `der` and output of the
    /// model), in order of first appearance.
    pub fn collect(streams: impl IntoIterator<Item = TokenStream>) -> Self {
        let mut derived = Derived::default();
        for stream in streams {
            derived.find(stream);
        }
        derived
    }

    fn find(&mut self, stream: TokenStream) {
        let trees: Vec<TokenTree> = stream.into_iter().collect();
        let mut i = 0;
        while i < trees.len() {
            if let Some((kind, shape, expr, scalar, span)) = marker_at(&trees[i..]) {
                let key = format!("{kind:?} {shape:?} {expr}");
                // The marker's own content has no markers: hoisting takes whole
                // expressions.
                if !self.list.iter().any(|h| h.key == key) {
                    self.list.push(Hoisted {
                        kind,
                        shape,
                        expr,
                        scalar,
                        span,
                        key,
                    });
                }
                i += 3;
                continue;
            }
            if let TokenTree::Group(group) = &trees[i] {
                self.find(group.stream());
            }
            i += 1;
        }
    }

    /// `stream` with every marker replaced by the variable holding its lifted value.
    pub fn replace(&self, stream: TokenStream) -> TokenStream {
        let trees: Vec<TokenTree> = stream.into_iter().collect();
        let mut out = TokenStream::new();
        let mut i = 0;
        while i < trees.len() {
            if let Some((kind, shape, expr, _, span)) = marker_at(&trees[i..]) {
                let key = format!("{kind:?} {shape:?} {expr}");
                if let Some(k) = self.list.iter().position(|h| h.key == key) {
                    out.extend(std::iter::once(TokenTree::Ident(value_ident(k, span))));
                    i += 3;
                    continue;
                }
            }
            match &trees[i] {
                TokenTree::Group(group) => {
                    let mut replaced =
                        proc_macro2::Group::new(group.delimiter(), self.replace(group.stream()));
                    replaced.set_span(group.span());
                    out.extend(std::iter::once(TokenTree::Group(replaced)));
                }
                other => out.extend(std::iter::once(other.clone())),
            }
            i += 1;
        }
        out
    }

    fn cached(&self) -> impl Iterator<Item = (usize, &Hoisted, Shape)> {
        self.list
            .iter()
            .enumerate()
            .filter_map(|(k, h)| match (h.kind, h.shape) {
                (Kind::Cached, Some(shape)) => Some((k, h, shape)),
                _ => None,
            })
    }

    /// Whether every hoisted expression that reads a parameter or an input has a
    /// scalar form, so that a scalar type seeding them gets every tangent exactly.
    pub fn exact_tangents(&self, graph: &Graph) -> bool {
        self.list.iter().all(|hoisted| {
            let mut names = std::collections::BTreeSet::new();
            idents(hoisted.expr.clone(), &mut names);
            hoisted.scalar.is_some()
                || !graph
                    .params
                    .iter()
                    .any(|p| names.contains(&p.name.to_string()))
        })
    }

    /// Whether the model has a cache at all.
    pub fn has_cache(&self) -> bool {
        self.cached().next().is_some()
    }

    /// The cache's type: `__FooDerived`.
    pub fn cache_type(model: &Ident) -> Ident {
        format_ident!("__{}Derived", model)
    }

    /// The cache's struct: the parameters it was computed from, then each value.
    pub fn cache_struct(&self, model: &Ident, params: &Ident) -> TokenStream {
        let f64_type = quote!(::core::primitive::f64);
        let ident = Self::cache_type(model);
        let fields = self.cached().map(|(k, _, shape)| {
            let field = format_ident!("v{}", k);
            let ty = crate::codegen::value_type(shape, &f64_type);
            quote!(#field: #ty,)
        });
        let doc = format!("The parameter expressions of [`{model}`], computed once.");
        quote! {
            #[doc = #doc]
            #[doc(hidden)]
            #[derive(::core::clone::Clone, ::core::fmt::Debug, ::core::cmp::PartialEq)]
            #[allow(non_camel_case_types)]
            struct #ident {
                params: #params,
                #(#fields)*
            }
        }
    }

    /// `fn __derive(params) -> cache`: every constant expression in `f64`.
    pub fn derive_fn(&self, graph: &Graph, model: &Ident, params: &Ident) -> TokenStream {
        let f64_type = quote!(::core::primitive::f64);
        let cache_type = Self::cache_type(model);
        let source = quote!(__params);
        let values = self.cached().map(|(k, hoisted, shape)| {
            let field = format_ident!("v{}", k);
            let ty = crate::codegen::value_type(shape, &f64_type);
            let binds = bind_f64(graph, &hoisted.expr, &source, None);
            let expr = &hoisted.expr;
            quote_spanned!(hoisted.span=> #field: { let __value: #ty = { #binds #expr }; __value },)
        });
        quote! {
            /// The values of the model's parameter expressions for `__params`.
            #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
            fn __derive(__params: &#params) -> #cache_type {
                #[allow(unused_imports)]
                use ::bgdsl_runtime::Scalar as _;
                #cache_type {
                    params: ::core::clone::Clone::clone(__params),
                    #(#values)*
                }
            }
        }
    }

    /// The start of an evaluation: each hoisted value, lifted into the scalar type.
    pub fn bindings(&self, graph: &Graph) -> TokenStream {
        let lift = quote!(::bgdsl_runtime::lift::lift::<Scalar, _>);
        let cache = self.has_cache().then(|| {
            quote! {
                let __derived_now;
                let __derived = if self.__derived.params == self.params {
                    &self.__derived
                } else {
                    __derived_now = Self::__derive(&self.params);
                    &__derived_now
                };
            }
        });
        let binds = self.list.iter().enumerate().map(|(k, hoisted)| {
            let ident = value_ident(k, hoisted.span);
            let span = hoisted.span;
            let value = match (hoisted.kind, hoisted.shape) {
                (Kind::Cached, Some(_)) => {
                    let field = format_ident!("v{}", k);
                    quote_spanned!(span=> #lift(__derived.#field))
                }
                _ => {
                    let self_params = quote!(self.params);
                    let inputs = quote!(self.inputs);
                    let binds = bind_f64(graph, &hoisted.expr, &self_params, Some(&inputs));
                    let expr = &hoisted.expr;
                    // Of a type the compiler may not know: lifted if it is a number,
                    // vector or matrix, passed through if not (a flag, a user's enum).
                    quote_spanned!(span=> {
                        #[allow(unused_imports)]
                        use ::bgdsl_runtime::lift::{ViaIdentity as _, ViaLift as _};
                        (&::bgdsl_runtime::lift::Lifting::<Scalar, _>::new({ #binds #expr })).lift_value()
                    })
                }
            };
            // A scalar type with parameter tangents evaluates the expression itself (a
            // branch on a constant: gone from the code for any other type).
            match &hoisted.scalar {
                Some(scalar) => quote_spanned!(span=> let #ident =
                    if <Scalar as ::bgdsl_runtime::Scalar>::PARAMETER_TANGENTS { #scalar } else { #value };),
                None => quote_spanned!(span=> let #ident = #value;),
            }
        });
        let binds: Vec<TokenStream> = binds.collect();
        quote! {
            #cache
            #(#binds)*
        }
    }
}

/// The variable holding hoisted value `k`.
fn value_ident(k: usize, span: Span) -> Ident {
    format_ident!("__h{}", k, span = hidden_span(span))
}

/// Binds, in `f64`, the parameters, and in an evaluation (`inputs` given) the inputs
/// and `t`, that `expr` names.
fn bind_f64(
    graph: &Graph,
    expr: &TokenStream,
    params: &TokenStream,
    inputs: Option<&TokenStream>,
) -> TokenStream {
    let mut names = std::collections::BTreeSet::new();
    idents(expr.clone(), &mut names);
    let f64_type = quote!(::core::primitive::f64);
    let binds = graph
        .params
        .iter()
        .filter(|p| names.contains(&p.name.to_string()) && (inputs.is_some() || !p.input))
        .map(|p| {
            let name = &p.name;
            let ty = crate::codegen::value_type(p.shape, &f64_type);
            let value = match (p.shape, inputs) {
                (_, Some(inputs)) if p.input => quote!(#inputs.#name),
                (Shape::Scalar, _) => quote!(#params.#name),
                (Shape::Vector(_), _) => {
                    quote!(::bgdsl_runtime::multibond::vector_param(&#params.#name))
                }
                (Shape::Matrix(..), _) => {
                    quote!(::bgdsl_runtime::multibond::matrix_param(&#params.#name))
                }
            };
            quote!(let #name: #ty = #value;)
        });
    let time = (inputs.is_some() && names.contains("t")).then(|| {
        let t = Ident::new("t", Span::call_site());
        quote!(let #t: #f64_type = __t;)
    });
    quote!(#(#binds)* #time)
}

fn idents(stream: TokenStream, out: &mut std::collections::BTreeSet<String>) {
    for tree in stream {
        match tree {
            TokenTree::Ident(ident) => {
                out.insert(ident.to_string());
            }
            TokenTree::Group(group) => idents(group.stream(), out),
            _ => {}
        }
    }
}

/// The marker at the start of `trees`, if there is one: its kind, shape, expression
/// and span.
#[allow(clippy::type_complexity)]
fn marker_at(
    trees: &[TokenTree],
) -> Option<(Kind, Option<Shape>, TokenStream, Option<TokenStream>, Span)> {
    let [TokenTree::Ident(name), TokenTree::Punct(bang), TokenTree::Group(body), ..] = trees else {
        return None;
    };
    if name != MARKER || bang.as_char() != '!' || body.delimiter() != Delimiter::Brace {
        return None;
    }
    let inner: Vec<TokenTree> = body.stream().into_iter().collect();
    let word = |i: usize| match inner.get(i) {
        Some(TokenTree::Ident(ident)) => Some(ident.to_string()),
        _ => None,
    };
    let number = |i: usize| match inner.get(i) {
        Some(TokenTree::Literal(lit)) => lit.to_string().parse::<usize>().ok(),
        _ => None,
    };
    let kind = match word(0)?.as_str() {
        "cached" => Kind::Cached,
        _ => Kind::PerCall,
    };
    let (shape, rest) = match word(1)?.as_str() {
        "scalar" => (Some(Shape::Scalar), 2),
        "vector" => (Some(Shape::Vector(number(2)?)), 3),
        "matrix" => (Some(Shape::Matrix(number(2)?, number(3)?)), 4),
        _ => (None, 2),
    };
    // `;`, the expression, `;` and its scalar form (if any).
    let mut parts =
        inner[rest + 1..].split(|tree| matches!(tree, TokenTree::Punct(p) if p.as_char() == ';'));
    let expr: TokenStream = parts.next()?.iter().cloned().collect();
    let scalar: TokenStream = parts.next().unwrap_or_default().iter().cloned().collect();
    let scalar = (!scalar.is_empty()).then_some(scalar);
    Some((kind, shape, expr, scalar, name.span()))
}

#[cfg(test)]
mod should {
    /// The generated code of a model, as text.
    fn expanded(text: &str) -> String {
        let tokens: proc_macro2::TokenStream = text.parse().unwrap();
        crate::expand::expand(tokens).to_string()
    }

    /// The text of the generated function `name`, up to the next function.
    fn function<'a>(code: &'a str, name: &str) -> &'a str {
        let start = code
            .find(&format!("fn {name}"))
            .unwrap_or_else(|| panic!("no fn {name} in {code}"));
        let rest = &code[start + 3..];
        &rest[..rest.find(" fn ").unwrap_or(rest.len())]
    }

    /// `code` without the branches a scalar type with parameter tangents takes (what
    /// `f64` and the state's dual numbers run).
    fn without_tangent_branches(code: &str) -> String {
        let open = "PARAMETER_TANGENTS {";
        let mut out = String::new();
        let mut rest = code;
        while let Some(start) = rest.find(open) {
            out.push_str(&rest[..start]);
            let body = &rest[start + open.len()..];
            let mut depth = 1;
            let end = body
                .char_indices()
                .find_map(|(i, c)| {
                    depth += match c {
                        '{' => 1,
                        '}' => -1,
                        _ => 0,
                    };
                    (depth == 0).then_some(i)
                })
                .expect("a closed branch");
            rest = &body[end + 1..];
        }
        out.push_str(rest);
        out
    }

    /// A hoisted expression that reads parameters has a branch evaluating it in the
    /// scalar type for parameter tangents; everything else runs the lifted value.
    #[test]
    fn evaluate_parameter_expressions_in_the_scalar_type_for_parameter_tangents() {
        let code = expanded(
            "model M {
                param m = 2.0; param a = 0.1;
                I[3] body { f = p.component_div(&box_inertia(m, a, a, a)) };
                1 w; Se[3] torque = vec3(1.0, 0.0, 0.0);
                torque -> w -> body;
            }",
        );
        let derivatives = function(&code, "derivatives");
        assert!(
            derivatives.contains("PARAMETER_TANGENTS { :: bgdsl_runtime :: multibond :: box_inertia (m , a , a , a) }")
                || derivatives.contains("PARAMETER_TANGENTS { box_inertia (m , a , a , a) }"),
            "{derivatives}"
        );
        assert!(
            code.contains(
                "const EXACT_PARAMETER_DERIVATIVES : :: core :: primitive :: bool = true"
            ),
            "{code}"
        );
        // A user's function of a parameter has no scalar form: the model says so.
        let code = expanded(
            "model M {
                param k = 2.0;
                C c = my_stiffness(k);
                1 v; I mass = 1.0;
                v -> { mass, c };
            }",
        );
        assert!(
            code.contains(
                "const EXACT_PARAMETER_DERIVATIVES : :: core :: primitive :: bool = false"
            ),
            "{code}"
        );
    }

    #[test]
    fn keep_parameter_expressions_out_of_the_evaluation() {
        let code = expanded(
            "model M {
                param m = 2.0; param a = 0.1; param k = 4.0; param freq = 1.0;
                Se s = (2.0 * core::f64::consts::PI * freq * t).sin();
                I[3] body { f = p.component_div(&box_inertia(m, a, a, a)) };
                I mass = m; C c = (k / m).sqrt();
                1 v; 1 w; Se[3] torque = vec3(1.0, 0.0, 0.0);
                s -> v -> { mass, c }; torque -> w -> body;
            }",
        );
        let derivatives = without_tangent_branches(function(&code, "derivatives"));
        let derivatives = derivatives.as_str();
        let derive = function(&code, "__derive");
        for constant in ["box_inertia", "sqrt"] {
            assert!(
                !derivatives.contains(constant),
                "{constant} in {derivatives}"
            );
            assert!(derive.contains(constant), "{constant} not in {derive}");
        }
        // A function of time is computed in f64 in each evaluation, then lifted.
        assert!(derivatives.contains("lift"), "{derivatives}");
        assert!(!derive.contains("freq"), "{derive}");
        assert!(derivatives.contains(". sin ()"), "{derivatives}");
        assert!(
            !code.contains(crate::hoist::MARKER),
            "a marker left in {code}"
        );
    }

    /// A product whose left factor is a matrix is the runtime's written-out product
    /// (fast on dual numbers); a scalar times a vector, and a constant product, stay
    /// as written (the constant one computed once, in `f64`).
    #[test]
    fn write_matrix_products_out() {
        let code = expanded(
            "model M {
                param m = 2.0; param k = 3.0;
                param R0: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
                state R: Matrix3 = R0;
                der R = skew(w.f) * R;
                I[3] body { f = R * (R.transpose() * p) / m };
                C[3] spring = k;
                1 w; w -> { body, spring };
                output turned: Vector3 = R0 * vec3(1.0, 0.0, 0.0);
                output scaled: Vector3 = k * body.p;
            }",
        );
        let derivatives = without_tangent_branches(function(&code, "derivatives"));
        assert_eq!(
            derivatives.matches("MatMul :: mat_mul").count(),
            3,
            "{derivatives}"
        );
        let outputs = function(&code, "outputs");
        assert!(outputs.contains("= k * __x"), "{outputs}");
        assert!(function(&code, "__derive").contains("R0 * vec3"), "{code}");
    }
}
