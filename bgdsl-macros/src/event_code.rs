//! Stage 5, events: `Model::MODES`, `Model::EVENTS`, `event_indicators` and
//! `apply_event` of a model with modes or `when` blocks (nothing for a model without).
//!
//! Both functions evaluate the model's signals in `f64` at (t, x) with the same
//! straight-line body as `outputs`; an action's values and `if` conditions read those
//! pre-event values, and the states it assigns are written only after every value of
//! the event is computed (simultaneous assignment).

use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote, quote_spanned};
use syn::Ident;

use crate::equations::Equations;
use crate::events::{ActionCode, Direction, ModeKind};
use crate::ir::Graph;

/// Where the runtime's event types live.
fn rt() -> TokenStream {
    quote!(::bgdsl_runtime::event)
}

/// Binds each mode by name as the plain value laws read: `bool`, `i64`, or a constant
/// of the scalar type for an `f64` mode (no derivative part).
pub fn bind_modes(graph: &Graph, equations: &Equations) -> TokenStream {
    let offsets = equations.offsets();
    let binds = equations.states.iter().zip(offsets).filter_map(|(state, offset)| {
        let mode = &graph.modes[state.mode?];
        let name = &mode.name;
        let value = quote!(::bgdsl_runtime::Scalar::to_f64(__x[#offset]));
        Some(match mode.kind {
            ModeKind::Bool => quote!(let #name: ::core::primitive::bool = #value != 0.0;),
            ModeKind::Integer => quote!(let #name: ::core::primitive::i64 = #value as ::core::primitive::i64;),
            ModeKind::Real => {
                quote!(let #name: Scalar = <Scalar as ::bgdsl_runtime::Scalar>::from_f64(#value);)
            }
        })
    });
    quote!(#(#binds)*)
}

/// A mode's value as the `f64` stored in the state vector, typed at the user's
/// expression (`span`) so that a value of the wrong type is an error there.
pub fn stored(kind: ModeKind, value: TokenStream, span: Span) -> TokenStream {
    let typed = |ty: TokenStream| quote_spanned!(span=> let __mode_value: #ty = #value;);
    match kind {
        ModeKind::Bool => {
            let typed = typed(quote!(::core::primitive::bool));
            quote!({ #typed if __mode_value { 1.0 } else { 0.0 } })
        }
        ModeKind::Integer => {
            let typed = typed(quote!(::core::primitive::i64));
            quote!({ #typed __mode_value as ::core::primitive::f64 })
        }
        ModeKind::Real => {
            let typed = typed(quote!(::core::primitive::f64));
            quote!({ #typed __mode_value })
        }
    }
}

/// The event items of the `Model` implementation; `body` evaluates every signal.
pub fn model_items(graph: &Graph, equations: &Equations, body: &TokenStream) -> TokenStream {
    if graph.modes.is_empty() && graph.events.is_empty() {
        return TokenStream::new();
    }
    let rt = rt();
    let f64_ty = quote!(::core::primitive::f64);
    let n_states: usize = equations.states.iter().map(|s| s.shape.len()).sum();
    let n_events = graph.events.len();
    let modes = graph.modes.iter().map(|mode| {
        let name = crate::flatten::display(&mode.name.to_string());
        let doc = mode.doc.clone().unwrap_or_default();
        let kind = match mode.kind {
            ModeKind::Bool => quote!(Bool),
            ModeKind::Integer => quote!(Integer),
            ModeKind::Real => quote!(Real),
        };
        quote!(#rt::ModeInfo { name: #name, kind: #rt::ModeKind::#kind, doc: #doc })
    });
    let events = graph.events.iter().map(|event| {
        let name = crate::flatten::display(&event.name.to_string());
        let doc = &event.doc;
        let direction = match event.direction {
            Direction::Rising => quote!(Rising),
            Direction::Falling => quote!(Falling),
            Direction::Both => quote!(Both),
        };
        quote!(#rt::EventInfo { name: #name, direction: #rt::Direction::#direction, doc: #doc })
    });
    let indicators = equations.events.iter().enumerate().map(|(i, event)| {
        let g = &event.indicator;
        quote!(__g[#i] = #g;)
    });
    let solve_g = crate::staged::solve_first(equations, crate::staged::fill_nan("__g"));
    let solve_apply =
        crate::staged::solve_first(equations, quote!(return #rt::EventAction::Continue;));
    let arms = equations.events.iter().enumerate().map(|(i, event)| {
        let mut writes = Vec::new();
        let tree = actions(&event.actions, &mut writes);
        let offsets = equations.offsets();
        let declare = writes.iter().map(|(ident, state)| {
            let ty = crate::codegen::value_type(equations.states[*state].shape, &f64_ty);
            quote!(let mut #ident: ::core::option::Option<#ty> = ::core::option::Option::None;)
        });
        let apply = writes.iter().map(|(ident, state)| {
            let value = Ident::new("__value_new", Span::call_site());
            let write = crate::codegen::write_value(
                equations.states[*state].shape,
                quote!(#value),
                &Ident::new("__x", Span::call_site()),
                offsets[*state],
                &f64_ty,
            );
            quote!(if let ::core::option::Option::Some(#value) = #ident { #write })
        });
        quote! {
            #i => {
                let mut __stop = false;
                #(#declare)*
                #tree
                #(#apply)*
                if __stop { #rt::EventAction::Stop } else { #rt::EventAction::Continue }
            }
        }
    });
    quote! {
        const MODES: &'static [#rt::ModeInfo] = &[#(#modes),*];
        const EVENTS: &'static [#rt::EventInfo] = &[#(#events),*];

        #[allow(unused_variables, unused_parens, unused_braces, non_snake_case, clippy::all)]
        fn event_indicators(&self, __t: #f64_ty, __x: &[#f64_ty], __g: &mut [#f64_ty]) {
            ::core::assert_eq!(__x.len(), #n_states, "state vector length");
            ::core::assert_eq!(__g.len(), #n_events, "indicator vector length");
            type Scalar = #f64_ty;
            #solve_g
            #body
            #(#indicators)*
        }

        #[allow(unused_variables, unused_parens, unused_braces, unused_mut, non_snake_case, clippy::all)]
        fn apply_event(&self, __index: ::core::primitive::usize, __t: #f64_ty, __x: &mut [#f64_ty]) -> #rt::EventAction {
            ::core::assert_eq!(__x.len(), #n_states, "state vector length");
            type Scalar = #f64_ty;
            #solve_apply
            #body
            match __index {
                #(#arms)*
                _ => #rt::EventAction::Continue,
            }
        }
    }
}

/// The action tree: each assignment stores its value in a pending `Option` (one per
/// assignment, listed in `writes` with its state), `stop` sets `__stop`.
fn actions(actions: &[ActionCode], writes: &mut Vec<(Ident, usize)>) -> TokenStream {
    let code = actions.iter().map(|action| match action {
        ActionCode::Write { state, value, mode } => {
            let ident = format_ident!("__new_{}", writes.len());
            writes.push((ident.clone(), *state));
            let value = match mode {
                Some(kind) => stored(*kind, quote!(#value), syn::spanned::Spanned::span(value)),
                None => quote!(#value),
            };
            quote!(#ident = ::core::option::Option::Some(#value);)
        }
        ActionCode::Stop => quote!(__stop = true;),
        ActionCode::If {
            cond,
            then,
            otherwise,
        } => {
            let then = self::actions(then, writes);
            let otherwise = self::actions(otherwise, writes);
            quote!(if #cond { #then } else { #otherwise })
        }
    });
    quote!(#(#code)*)
}

/// The events' rewritten expressions, for the hoisted parameter expressions they hold.
pub fn expressions(equations: &Equations) -> Vec<TokenStream> {
    fn walk(actions: &[ActionCode], out: &mut Vec<TokenStream>) {
        for action in actions {
            match action {
                ActionCode::Write { value, .. } => out.push(quote!(#value)),
                ActionCode::If {
                    cond,
                    then,
                    otherwise,
                } => {
                    out.push(quote!(#cond));
                    walk(then, out);
                    walk(otherwise, out);
                }
                ActionCode::Stop => {}
            }
        }
    }
    let mut out = Vec::new();
    for event in &equations.events {
        let g = &event.indicator;
        out.push(quote!(#g));
        walk(&event.actions, &mut out);
    }
    out
}
