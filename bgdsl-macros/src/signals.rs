//! The variables of a causal bond graph, and the identifiers the generated code gives
//! them. One place decides the names, so the stages that emit references and the stage
//! that emits definitions agree.

use proc_macro2::{Ident, Span};
use quote::format_ident;

use crate::ir::BondId;

/// A variable of the model's equations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Signal {
    /// The effort on a bond.
    Effort(BondId),
    /// The flow on a bond (positive in the half arrow's direction).
    Flow(BondId),
    /// A state, by its index in the state vector.
    State(usize),
}

impl Signal {
    /// The local variable holding this signal in generated code. Mixed-site hygiene, so
    /// a user's expression can reach it only through the macro's own rewriting.
    pub fn ident(self, located_at: Span) -> Ident {
        let span = Span::mixed_site().located_at(located_at);
        match self {
            Signal::Effort(b) => format_ident!("__e{}", b.0, span = span),
            Signal::Flow(b) => format_ident!("__f{}", b.0, span = span),
            Signal::State(i) => format_ident!("__x{}", i, span = span),
        }
    }
}

/// A signal, possibly negated: how port variables relate to bond variables when a
/// bond points against an element's own sign convention.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Term {
    /// Whether the signal enters with a minus sign.
    pub negate: bool,
    /// The signal.
    pub signal: Signal,
}

impl Term {
    /// The signal as it is.
    pub fn plus(signal: Signal) -> Self {
        Term {
            negate: false,
            signal,
        }
    }

    /// The signal, negated when `negate`.
    pub fn signed(negate: bool, signal: Signal) -> Self {
        Term { negate, signal }
    }
}
