//! Collects independent errors so that one compile reports all of them.

use proc_macro2::Span;

/// Errors gathered by a stage; checked at the stage boundary.
#[derive(Default)]
pub struct Errors {
    list: Vec<syn::Error>,
}

impl Errors {
    /// Records an error.
    pub fn push(&mut self, error: syn::Error) {
        self.list.push(error);
    }

    /// Records an error at `span`.
    pub fn at(&mut self, span: Span, message: impl core::fmt::Display) {
        self.push(syn::Error::new(span, message));
    }

    /// Records an error at `span` with a note at `note_span` (shown as a second error
    /// there, the way rustc's "first defined here" notes read).
    pub fn with_note(
        &mut self,
        span: Span,
        message: impl core::fmt::Display,
        note_span: Span,
        note: impl core::fmt::Display,
    ) {
        let mut error = syn::Error::new(span, message);
        error.combine(syn::Error::new(note_span, format!("note: {note}")));
        self.push(error);
    }

    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// All the errors as one, or `Ok` when there were none.
    pub fn finish(self) -> syn::Result<()> {
        let mut list = self.list.into_iter();
        match list.next() {
            None => Ok(()),
            Some(mut first) => {
                first.extend(list);
                Err(first)
            }
        }
    }
}
