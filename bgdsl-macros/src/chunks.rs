//! Part of code generation: a large model's evaluation split into chunk functions of
//! bounded size, shared by `derivatives`, `outputs` and `power_balance`.
//!
//! LLVM's optimisation and register allocation grow faster than linearly with the
//! size of one function, so one straight-line `derivatives` of 10,000 states takes
//! minutes and gigabytes to build. Here the equations, in their computation order, are
//! cut into runs of about [`CHUNK_TOKENS`] tokens; each run becomes an
//! `#[inline(never)]` function `__chunk_<k>` generic over the scalar, which
//! - binds the parameters, hoisted values and states it reads (cheap, so re-bound
//!   rather than passed),
//! - takes the signals it reads from earlier chunks as arguments,
//! - computes its equations (the same statements as the straight-line code, so the
//!   numbers are bit for bit the same),
//! - writes the derivatives, outputs and power terms whose last input it computes
//!   into `__dx`, `__y` and `__p` when they are not empty,
//! - returns the signals later chunks read.
//!
//! `derivatives` calls every chunk with `__dx`, `outputs` with `__y`, `power_balance`
//! with `__p`: one copy of the equations serves all three.
//!
//! Each chunk is the method of a trait of its own (`__<Model>Part<k>`) implemented for
//! one of the runtime's slot types (`bgdsl_runtime::__private::spread::m<k % 16>::Slot`),
//! taking the model as `__model`. rustc puts a method into the codegen unit of its self
//! type's module: as methods of the model, all chunks landed in one unit, and LLVM
//! optimised them on one core (at 10,000 states, most of a two-minute build); as
//! methods of the slots they spread over 16 units, wherever the model is declared.
//!
//! Only models without torn unknowns, dependent storage or inverse checks are chunked
//! (those keep the straight-line code, which [`crate::staged`] builds on).

use std::collections::{BTreeMap, BTreeSet};

use proc_macro2::{Ident, Span, TokenStream, TokenTree};
use quote::{format_ident, quote, ToTokens};

use crate::codegen::{assignment, value_type, write_value};
use crate::derived::Derived;
use crate::equations::{Derivative, Equations};
use crate::ir::Graph;
use crate::rewrite::term_tokens;

/// About how many tokens of equations one chunk function holds.
pub const CHUNK_TOKENS: usize = 3000;

/// Models whose evaluation has more tokens than this are chunked: 1.6 times the
/// flagship's (9,400), which keeps its straight-line code and its speed.
pub const CHUNKED_ABOVE: usize = 15_000;

/// Whether the model is chunked: large, and with none of what the staged evaluation
/// handles.
pub fn applies(equations: &Equations, body: &TokenStream) -> bool {
    !crate::staged::needed(equations)
        && equations.inverses.is_empty()
        && count_tokens(body.clone()) > CHUNKED_ABOVE
}

/// Where a piece of code writes when its chunk is called with a non-empty target.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Sink {
    Derivatives,
    Outputs,
    Power,
}

/// One statement of the evaluation: what it defines (and its type), what it reads.
struct Item {
    tokens: TokenStream,
    reads: BTreeSet<String>,
    size: usize,
}

/// A binding of the prelude (time, a parameter, a hoisted value, a state, a mode).
struct Binding {
    defines: String,
    tokens: TokenStream,
    reads: BTreeSet<String>,
}

/// An equation with what it defines, and the writes that wait for it.
struct Step {
    item: Item,
    signal: crate::signals::Signal,
    name: String,
    ty: TokenStream,
    sinks: Vec<(Sink, Item)>,
}

/// The chunked evaluation: the chunk methods and, for each caller, its body.
pub struct Chunked {
    /// The `__chunk_<k>` functions: per chunk a trait and its impl for a slot type,
    /// items placed beside the model (not inside its `impl`).
    pub methods: TokenStream,
    /// The body of `derivatives` after its length checks.
    pub derivatives: TokenStream,
    /// The body of `outputs` after its length checks.
    pub outputs: TokenStream,
    /// The body of `power_balance` after its length check.
    pub power: TokenStream,
}

/// How many slot types the runtime has (`bgdsl_runtime::__private::spread::SLOTS`).
const SLOTS: usize = 16;

/// `tokens` with `self` and `Self` (the model, in the code written for a method of it)
/// replaced by `__model` and the model's type, for a chunk that is a function of a slot.
fn as_model(tokens: TokenStream, model: &Ident) -> TokenStream {
    tokens
        .into_iter()
        .map(|tree| match tree {
            TokenTree::Ident(i) if i == "self" => TokenTree::Ident(Ident::new("__model", i.span())),
            TokenTree::Ident(i) if i == "Self" => TokenTree::Ident(model.clone()),
            TokenTree::Group(g) => {
                let mut out = proc_macro2::Group::new(g.delimiter(), as_model(g.stream(), model));
                out.set_span(g.span());
                TokenTree::Group(out)
            }
            other => other,
        })
        .collect()
}

/// Splits the evaluation into chunks. `power` holds the power account's terms: the
/// bucket (0 stored, 1 input, 2 dissipated) and the term.
pub fn split(
    graph: &Graph,
    equations: &Equations,
    derived: &Derived,
    power: Vec<(usize, TokenStream)>,
) -> Chunked {
    let scalar = quote!(Scalar);
    let rt = quote!(::bgdsl_runtime);
    let bindings = prelude_bindings(graph, equations, derived);
    let mut defined_by: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for (i, binding) in bindings.iter().enumerate() {
        defined_by.entry(&binding.defines).or_default().push(i);
    }
    let mut steps: Vec<Step> = equations
        .ordered
        .iter()
        .map(|eq| {
            let ident = eq.defines.ident(Span::call_site());
            Step {
                item: item(derived.replace(assignment(graph, equations, eq))),
                signal: eq.defines,
                name: ident.to_string(),
                ty: value_type(equations.shape_of(graph, eq.defines), &scalar),
                sinks: Vec::new(),
            }
        })
        .collect();
    let defined_at: BTreeMap<String, usize> = steps
        .iter()
        .enumerate()
        .map(|(i, s)| (s.name.clone(), i))
        .collect();
    // The first equation that reads each name (a state, a parameter): where a write
    // that reads no equation goes, so that such writes (a storage element's energy)
    // spread over the chunks instead of all landing in the first.
    let mut first_reader: BTreeMap<String, usize> = BTreeMap::new();
    for (i, step) in steps.iter().enumerate() {
        for read in &step.item.reads {
            first_reader.entry(read.clone()).or_insert(i);
        }
    }
    // Each write goes with the last equation it reads, else with the first equation
    // that reads what it reads (the first equation when none does).
    let mut place = |sink: Sink, tokens: TokenStream| {
        let item = item(derived.replace(tokens));
        let at = item
            .reads
            .iter()
            .filter_map(|r| defined_at.get(r))
            .max()
            .or_else(|| item.reads.iter().filter_map(|r| first_reader.get(r)).max())
            .copied()
            .unwrap_or(0);
        steps[at].sinks.push((sink, item));
    };
    let dx = Ident::new("__dx", Span::call_site());
    for (state, offset) in equations.states.iter().zip(equations.offsets()) {
        let value = match &state.derivative {
            Derivative::Term(term) => term_tokens(*term, Span::call_site()),
            Derivative::Expr(der) => der.expr.to_token_stream(),
        };
        place(
            Sink::Derivatives,
            write_value(state.shape, value, &dx, offset, &scalar),
        );
    }
    let y = Ident::new("__y", Span::call_site());
    let mut offset = 0;
    for (output, shape) in equations
        .outputs
        .iter()
        .zip(crate::codegen::output_shapes(graph, equations))
    {
        let write = write_value(shape, output.expr.to_token_stream(), &y, offset, &scalar);
        offset += shape.len();
        place(Sink::Outputs, write);
    }
    for (bucket, term) in power {
        place(Sink::Power, quote!(__p[#bucket] += #term;));
    }
    let n_states: usize = equations.states.iter().map(|s| s.shape.len()).sum();
    let n_outputs: usize = crate::codegen::output_shapes(graph, equations)
        .iter()
        .map(|s| s.len())
        .sum();
    let has_cache = derived.has_cache();
    let cache_type = Derived::cache_type(&graph.name);
    let derived_param = has_cache.then(|| quote!(__derived: &#cache_type,));
    let derived_arg = has_cache.then(|| quote!(__derived,));
    // Cut into chunks of about CHUNK_TOKENS.
    let mut chunks: Vec<Vec<Step>> = vec![Vec::new()];
    let mut size = 0;
    for step in steps {
        let step_size = step.item.size + step.sinks.iter().map(|(_, i)| i.size).sum::<usize>();
        if size > 0 && size + step_size > CHUNK_TOKENS {
            chunks.push(Vec::new());
            size = 0;
        }
        size += step_size;
        if let Some(current) = chunks.last_mut() {
            current.push(step);
        }
    }
    // What each chunk reads from earlier ones, and so what each returns.
    let chunk_of: BTreeMap<&str, usize> = chunks
        .iter()
        .enumerate()
        .flat_map(|(c, steps)| steps.iter().map(move |s| (s.name.as_str(), c)))
        .collect();
    let type_of: BTreeMap<&str, &TokenStream> = chunks
        .iter()
        .flatten()
        .map(|s| (s.name.as_str(), &s.ty))
        .collect();
    // The signals' own identifiers (their hygiene is the macro's mixed site).
    let ident_of: BTreeMap<&str, Ident> = chunks
        .iter()
        .flatten()
        .map(|s| (s.name.as_str(), s.signal.ident(Span::call_site())))
        .collect();
    let reads: Vec<BTreeSet<String>> = chunks
        .iter()
        .map(|steps| {
            let mut all = BTreeSet::new();
            for step in steps {
                all.extend(step.item.reads.iter().cloned());
                for (_, item) in &step.sinks {
                    all.extend(item.reads.iter().cloned());
                }
            }
            all
        })
        .collect();
    let inputs: Vec<Vec<&str>> = reads
        .iter()
        .enumerate()
        .map(|(c, reads)| {
            reads
                .iter()
                .filter_map(|r| chunk_of.get_key_value(r.as_str()))
                .filter(|&(_, &at)| at < c)
                .map(|(&name, _)| name)
                .collect()
        })
        .collect();
    let mut returned: Vec<BTreeSet<&str>> = vec![BTreeSet::new(); chunks.len()];
    for names in &inputs {
        for name in names {
            returned[chunk_of[name]].insert(name);
        }
    }
    let mut methods = TokenStream::new();
    let mut calls = TokenStream::new();
    for (c, steps) in chunks.iter().enumerate() {
        let method = format_ident!("__chunk_{}", c);
        let ident = |name: &str| ident_of[name].clone();
        let params = inputs[c].iter().map(|name| {
            let (name, ty) = (ident(name), type_of[name]);
            quote!(#name: #ty,)
        });
        let args = inputs[c].iter().map(|name| {
            let name = ident(name);
            quote!(#name,)
        });
        let out_names: Vec<Ident> = returned[c].iter().map(|n| ident(n)).collect();
        let out_types = returned[c].iter().map(|n| type_of[n]);
        let prelude = needed_bindings(&bindings, &defined_by, &reads[c]);
        let statements = steps.iter().map(|s| &s.item.tokens);
        let sink = |which: Sink, guard: TokenStream| {
            let writes: Vec<&TokenStream> = steps
                .iter()
                .flat_map(|s| &s.sinks)
                .filter(|(k, _)| *k == which)
                .map(|(_, item)| &item.tokens)
                .collect();
            (!writes.is_empty()).then(|| quote!(if #guard { #(#writes)* }))
        };
        let dx_writes = sink(
            Sink::Derivatives,
            quote!(let ::core::option::Option::Some(__dx) = __dx),
        );
        let y_writes = sink(
            Sink::Outputs,
            quote!(let ::core::option::Option::Some(__y) = __y),
        );
        let p_writes = sink(
            Sink::Power,
            quote!(let ::core::option::Option::Some(__p) = __p),
        );
        let doc = format!(
            "Part {} of the model's evaluation (see `derivatives`).",
            c + 1
        );
        // A trait method on a slot type of the runtime: rustc places it in the slot's
        // codegen unit (see `bgdsl_runtime::__private::spread`), so the chunks spread
        // over the units that LLVM optimises in parallel.
        let part = format_ident!("__{}Part{}", graph.name, c);
        let slot = format_ident!("m{}", c % SLOTS);
        let slot = quote!(#rt::__private::spread::#slot::Slot);
        let model = &graph.name;
        let body = as_model(
            quote! {
                #prelude
                #(#statements)*
                #dx_writes
                #y_writes
                #p_writes
                (#(#out_names,)*)
            },
            model,
        );
        let signature = quote! {
            fn #method<Scalar: #rt::Scalar>(
                __model: &#model,
                __t: ::core::primitive::f64,
                __x: &[Scalar; #n_states],
                #derived_param
                #(#params)*
                __dx: ::core::option::Option<&mut [Scalar; #n_states]>,
                __y: ::core::option::Option<&mut [Scalar; #n_outputs]>,
                __p: ::core::option::Option<&mut [Scalar; 3]>,
            ) -> (#(#out_types,)*)
        };
        methods.extend(quote! {
            #[doc = #doc]
            #[doc(hidden)]
            #[allow(non_camel_case_types, clippy::all)]
            trait #part {
                #[allow(clippy::too_many_arguments)]
                #signature;
            }
            #[doc(hidden)]
            impl #part for #slot {
                #[inline(never)]
                #[allow(unused_variables, unused_parens, unused_braces, unused_mut, non_snake_case, clippy::all)]
                #signature {
                    #body
                }
            }
        });
        calls.extend(quote! {
            let (#(#out_names,)*) = <#slot as #part>::#method::<Scalar>(
                self,
                __t,
                __x,
                #derived_arg
                #(#args)*
                __dx.as_deref_mut(),
                __y.as_deref_mut(),
                __p.as_deref_mut(),
            );
        });
    }
    let cache = has_cache.then(|| {
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
    let zero = quote!(<Scalar as #rt::Scalar>::from_f64(0.0));
    let option = quote!(::core::option::Option);
    // The callers checked the lengths: as arrays, the chunks' indices need no checks.
    let state_array = quote! {
        let ::core::result::Result::Ok(__x) = <&[Scalar; #n_states]>::try_from(__x) else {
            ::core::unreachable!("state vector length")
        };
    };
    let none = |n: TokenStream| quote!(#option::<&mut [Scalar; #n]>::None);
    let (no_dx, no_y, no_p) = (
        none(quote!(#n_states)),
        none(quote!(#n_outputs)),
        none(quote!(3)),
    );
    Chunked {
        methods,
        derivatives: quote! {
            #cache
            #state_array
            let mut __dx = <&mut [Scalar; #n_states]>::try_from(__dx).ok();
            let (mut __y, mut __p) = (#no_y, #no_p);
            #calls
        },
        outputs: quote! {
            #cache
            #state_array
            let mut __y = <&mut [Scalar; #n_outputs]>::try_from(__y).ok();
            let (mut __dx, mut __p) = (#no_dx, #no_p);
            #calls
        },
        power: quote! {
            #cache
            #state_array
            let mut __sums = [#zero, #zero, #zero];
            {
                let (mut __dx, mut __y, mut __p) = (#no_dx, #no_y, #option::Some(&mut __sums));
                #calls
            }
            let [stored, input, dissipated] = __sums;
            ::core::option::Option::Some(#rt::PowerBalance { stored, input, dissipated })
        },
    }
}

/// The prelude's `let` statements, one binding each (the derived-value cache is a
/// chunk's argument instead).
fn prelude_bindings(graph: &Graph, equations: &Equations, derived: &Derived) -> Vec<Binding> {
    let time = quote!(let t: Scalar = <Scalar as ::bgdsl_runtime::Scalar>::from_f64(__t););
    let prelude = crate::codegen::prelude(graph, equations, derived);
    statements(quote!(#time #prelude))
        .into_iter()
        .filter_map(|tokens| {
            let defines = let_name(&tokens)?;
            if defines == "__derived" || defines == "__derived_now" {
                return None;
            }
            let tokens = derived.replace(tokens);
            let mut reads = BTreeSet::new();
            scan(tokens.clone(), &mut reads);
            Some(Binding {
                defines,
                tokens,
                reads,
            })
        })
        .collect()
}

/// The bindings that `reads` need, with what they read in turn, in prelude order.
/// `defined_by` maps a name to the bindings that define it, in prelude order, so each
/// chunk costs what it reads, not the whole prelude.
fn needed_bindings(
    bindings: &[Binding],
    defined_by: &BTreeMap<&str, Vec<usize>>,
    reads: &BTreeSet<String>,
) -> TokenStream {
    let mut keep = BTreeSet::new();
    let mut pending: Vec<(&str, usize)> =
        reads.iter().map(|r| (r.as_str(), bindings.len())).collect();
    while let Some((name, before)) = pending.pop() {
        // The binding in scope just before `before` (a later `let` shadows).
        let Some(&at) = defined_by
            .get(name)
            .and_then(|all| all.iter().rev().find(|&&i| i < before))
        else {
            continue;
        };
        if !keep.insert(at) {
            continue;
        }
        pending.extend(bindings[at].reads.iter().map(|r| (r.as_str(), at)));
    }
    keep.into_iter()
        .map(|i| bindings[i].tokens.clone())
        .collect()
}

/// Top-level statements of `stream`, split at `;`.
fn statements(stream: TokenStream) -> Vec<TokenStream> {
    let mut out = Vec::new();
    let mut current = TokenStream::new();
    for tree in stream {
        let end = matches!(&tree, TokenTree::Punct(p) if p.as_char() == ';');
        current.extend(std::iter::once(tree));
        if end {
            out.push(std::mem::take(&mut current));
        }
    }
    out
}

/// `x` of a statement `let x ...;` (`let mut x` too).
fn let_name(statement: &TokenStream) -> Option<String> {
    let mut trees = statement.clone().into_iter();
    match trees.next()? {
        TokenTree::Ident(i) if i == "let" => {}
        _ => return None,
    }
    match trees.next()? {
        TokenTree::Ident(i) if i == "mut" => match trees.next()? {
            TokenTree::Ident(i) => Some(i.to_string()),
            _ => None,
        },
        TokenTree::Ident(i) => Some(i.to_string()),
        _ => None,
    }
}

fn item(tokens: TokenStream) -> Item {
    let mut reads = BTreeSet::new();
    let size = scan(tokens.clone(), &mut reads);
    Item {
        tokens,
        reads,
        size,
    }
}

/// Collects every identifier in `stream` into `idents` (a superset of what it reads:
/// a name it only defines or shadows costs at most an unused argument) and returns the
/// number of tokens.
fn scan(stream: TokenStream, idents: &mut BTreeSet<String>) -> usize {
    let mut count = 0;
    for tree in stream {
        count += 1;
        match tree {
            TokenTree::Ident(i) => {
                idents.insert(i.to_string());
            }
            TokenTree::Group(g) => count += scan(g.stream(), idents),
            _ => {}
        }
    }
    count
}

/// The number of tokens in `stream`, groups counted through.
fn count_tokens(stream: TokenStream) -> usize {
    scan(stream, &mut BTreeSet::new())
}

#[cfg(test)]
mod tests {
    use proc_macro2::{TokenStream, TokenTree};

    /// The sizing benchmark's damped chain (`models/benches/sizing/generate.sh scalar`)
    /// of `cells` cells: a force, then mass, spring and damper per cell.
    fn chain(cells: usize) -> TokenStream {
        let mut text = String::from(
            "pub model Chain { param m = 1.0; param k = 100.0; param c = 0.5; param force = 1.0;
             Se source = force * (3.0 * t).sin(); R ground = c; source -> v1; v1 -> ground;",
        );
        for i in 1..=cells {
            let w = 1.0 + (i % 7) as f64 * 0.125;
            text += &format!(
                "1 v{i}; I m{i} = m * {w:.3}; 0 n{i}; C k{i} = k / {w:.3}; 1 d{i};
                 R r{i} = c * {w:.3}; v{i} -> {{ m{i}, n{i} }}; n{i} -> d{i} -> {{ k{i}, r{i} }};"
            );
            if i < cells {
                text += &format!("n{i} -> v{};", i + 1);
            }
        }
        text += "output x1 = k1.q; }";
        text.parse().expect("the chain tokenizes")
    }

    /// Each `fn __chunk_<k>` item's token count (its signature and body), in order.
    fn chunk_sizes(expansion: TokenStream) -> Vec<usize> {
        let trees: Vec<TokenTree> = expansion.into_iter().collect();
        let mut sizes = Vec::new();
        for (i, tree) in trees.iter().enumerate() {
            if let TokenTree::Group(group) = tree {
                sizes.extend(chunk_sizes(group.stream()));
            }
            let is_chunk = matches!(tree, TokenTree::Ident(f) if f == "fn")
                && matches!(trees.get(i + 1), Some(TokenTree::Ident(n)) if n.to_string().starts_with("__chunk_"));
            if is_chunk {
                let body = trees[i..]
                    .iter()
                    .find(|t| matches!(t, TokenTree::Group(g) if g.delimiter() == proc_macro2::Delimiter::Brace));
                if let Some(TokenTree::Group(body)) = body {
                    sizes.push(super::count_tokens(body.stream()));
                }
            }
        }
        sizes
    }

    /// Every chunk stays near the chunk size, the first included: the writes that read
    /// no equation (each storage element's energy reads only its state) spread over
    /// the chunks with their states. Before, all 400 energy terms of this chain landed
    /// in the first chunk, 9 times the size of the others.
    #[test]
    fn no_chunk_grows_with_the_model() {
        let sizes = chunk_sizes(crate::expand::expand(chain(400)));
        assert!(sizes.len() > 10, "the chain is chunked: {sizes:?}");
        let largest = sizes.iter().max().copied().unwrap_or(0);
        assert!(
            largest < 2 * super::CHUNK_TOKENS,
            "largest chunk {largest} tokens (target {}): {sizes:?}",
            super::CHUNK_TOKENS
        );
    }

    /// The chunks are functions of the runtime's slot types, every slot used, and none
    /// is a method of the model: rustc places a method in its self type's module, so
    /// methods of the model all landed in one codegen unit, optimised on one core.
    #[test]
    fn chunks_spread_over_the_slots() {
        let text = crate::expand::expand(chain(400)).to_string();
        for k in 0..super::SLOTS {
            let slot = format!("spread :: m{k} :: Slot");
            assert!(text.contains(&slot), "no chunk in slot {k}");
        }
        assert!(!text.contains("spread :: m16"), "a slot the runtime lacks");
        assert!(
            !text.contains("self . __chunk_"),
            "a chunk is a method of the model"
        );
    }
}
