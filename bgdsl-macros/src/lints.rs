//! TEMPORARY stand-in for the lead's opt-in front end (h5: `ir::Lint`, `ir::Allowance`,
//! `Graph::allowance`): reads `#[allow(...)]` from the model's own attributes only.
//! Replaced by the real front end when it lands.

use proc_macro2::Span;

use crate::ir::{BondId, ElementId, Graph};

/// A lint a model may allow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lint {
    /// `derivative_causality`
    DerivativeCausality,
    /// `algebraic_loops`
    AlgebraicLoops,
}

impl Lint {
    fn name(self) -> &'static str {
        match self {
            Lint::DerivativeCausality => "derivative_causality",
            Lint::AlgebraicLoops => "algebraic_loops",
        }
    }
}

/// The model-level allowances: (lint, span) in order.
pub fn allowances(graph: &Graph) -> Vec<(Lint, Span)> {
    let mut found = Vec::new();
    for attr in graph.attrs.iter().filter(|a| a.path().is_ident("allow")) {
        let _ = attr.parse_nested_meta(|meta| {
            for lint in [Lint::DerivativeCausality, Lint::AlgebraicLoops] {
                if meta.path.is_ident(lint.name()) {
                    found.push((lint, attr.bracket_token.span.join()));
                }
            }
            Ok(())
        });
    }
    found
}

/// The first allowance of `lint` covering these elements or bonds (or the model).
pub fn allowance(
    graph: &Graph,
    lint: Lint,
    _elements: &[ElementId],
    _bonds: &[BondId],
) -> Option<usize> {
    allowances(graph).iter().position(|&(l, _)| l == lint)
}

/// Where allowance `index` is written.
pub fn allowance_span(graph: &Graph, index: usize) -> Span {
    allowances(graph)
        .get(index)
        .map_or_else(|| graph.name.span(), |&(_, span)| span)
}

/// Whether an attribute is one of these allowances (kept out of the generated items).
pub fn is_allowance(attr: &syn::Attribute) -> bool {
    if !attr.path().is_ident("allow") {
        return false;
    }
    let mut any = false;
    let _ = attr.parse_nested_meta(|meta| {
        any |= meta.path.is_ident("derivative_causality") || meta.path.is_ident("algebraic_loops");
        Ok(())
    });
    any
}
