//! Rust keywords as names: a model may call an element `r#loop` (a raw identifier),
//! which messages, state names and drawings show as `loop`, and which the generated
//! code spells `r#loop` wherever it becomes a Rust name.

use proc_macro2::{Ident, Span};

/// Strict and reserved keywords of Rust 2021 (the Reference, "Keywords"): none can be a
/// plain identifier.
const KEYWORDS: [&str; 51] = [
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub",
    "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "type",
    "unsafe", "use", "where", "while", "abstract", "become", "box", "do", "final", "macro",
    "override", "priv", "typeof", "unsized", "virtual", "yield", "try",
];

/// Keywords that cannot be raw identifiers either (`r#self` is not Rust).
const NOT_RAW: [&str; 4] = ["crate", "self", "Self", "super"];

/// Whether `word` is a keyword a model may use as a name by writing `r#word`.
pub fn is_raw_able_keyword(word: &str) -> bool {
    KEYWORDS.contains(&word) && !NOT_RAW.contains(&word)
}

/// A name as the user reads it: `r#loop` as `loop` (also inside a submodel path).
pub fn unraw(name: &str) -> String {
    name.replace("r#", "")
}

/// The Rust identifier for a generated name: raw when the name is a keyword.
pub fn rust_ident(name: &str, span: Span) -> Ident {
    if is_raw_able_keyword(name) {
        Ident::new_raw(name, span)
    } else {
        Ident::new(name, span)
    }
}

/// `help: write `r#loop`` for a keyword written as a name.
pub fn keyword_error(word: &str, span: Span) -> syn::Error {
    syn::Error::new(
        span,
        format!(
            "`{word}` is a Rust keyword, so it cannot be a name as it stands\n\
             help: write `r#{word}` (a raw identifier) here and wherever it names the same \
             thing; messages, state names and drawings show it as `{word}`"
        ),
    )
}

#[cfg(test)]
mod should {
    use super::*;

    #[test]
    fn know_which_keywords_can_be_raw() {
        assert!(is_raw_able_keyword("loop"));
        assert!(is_raw_able_keyword("type"));
        assert!(!is_raw_able_keyword("self"));
        assert!(!is_raw_able_keyword("spring"));
    }

    #[test]
    fn show_raw_names_without_their_prefix() {
        assert_eq!(unraw("r#loop"), "loop");
        assert_eq!(unraw("crank.r#loop"), "crank.loop");
        assert_eq!(rust_ident("loop", Span::call_site()).to_string(), "r#loop");
        assert_eq!(
            rust_ident("loop_q", Span::call_site()).to_string(),
            "loop_q"
        );
    }
}
