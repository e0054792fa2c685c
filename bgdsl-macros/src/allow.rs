//! Stage 2, opt-ins: the bond-graph lints a model may allow, read from Rust's own
//! `#[allow(...)]` attributes on the model, an element or a bond statement.
//!
//! A storage element in derivative causality and an algebraic loop are errors by
//! default; `#[allow(derivative_causality)]` and `#[allow(algebraic_loops)]` turn them
//! into dependent storage and loops solved at each evaluation where the model means it.
//! Other lints in the same attribute are Rust's: on the model they stay on the generated
//! struct; on an element or a bond, where nothing of Rust's is generated, they are
//! errors. A name close to one of ours is reported with the one meant.

use proc_macro2::Span;
use syn::punctuated::Punctuated;
use syn::{Attribute, Meta, Token};

use crate::errors::Errors;

/// A bond-graph mistake a model may allow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lint {
    /// A C or I element in derivative causality (dependent storage).
    DerivativeCausality,
    /// Equations that compute each other at the same instant.
    AlgebraicLoops,
}

impl Lint {
    /// Every lint, in the order messages list them.
    pub const ALL: [Lint; 2] = [Lint::DerivativeCausality, Lint::AlgebraicLoops];

    /// The lint's name as written in `#[allow(...)]`.
    pub fn name(self) -> &'static str {
        match self {
            Lint::DerivativeCausality => "derivative_causality",
            Lint::AlgebraicLoops => "algebraic_loops",
        }
    }

    fn named(name: &str) -> Option<Lint> {
        Lint::ALL.into_iter().find(|lint| lint.name() == name)
    }
}

/// Where a written `allow` applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// Before `model`: Rust's own lints pass through to the generated items.
    Model,
    /// Before an element or a bond statement (`what` says which, for messages).
    Statement(&'static str),
}

/// Takes the bond-graph lints out of the `#[allow(...)]` attributes among `attrs`,
/// returning each with the span of its name. An attribute left with none of Rust's
/// lints is removed; at [`Placement::Statement`] any other attribute than a doc comment
/// or an `allow` of ours is reported.
pub fn take_lints(
    attrs: &mut Vec<Attribute>,
    placement: Placement,
    errors: &mut Errors,
) -> Vec<(Lint, Span)> {
    let mut found = Vec::new();
    let mut kept = Vec::with_capacity(attrs.len());
    for attr in attrs.drain(..) {
        if !attr.path().is_ident("allow") {
            if let (Placement::Statement(what), false) = (placement, attr.path().is_ident("doc")) {
                errors.push(syn::Error::new_spanned(
                    &attr,
                    format!(
                        "`#[{}]` has no meaning before {what}: only `#[allow({})]` and `#[allow({})]` do",
                        quote::ToTokens::to_token_stream(attr.path()),
                        Lint::DerivativeCausality.name(),
                        Lint::AlgebraicLoops.name(),
                    ),
                ));
                continue;
            }
            kept.push(attr);
            continue;
        }
        let Meta::List(list) = &attr.meta else {
            kept.push(attr);
            continue;
        };
        let paths = match list.parse_args_with(Punctuated::<syn::Path, Token![,]>::parse_terminated)
        {
            Ok(paths) => paths,
            Err(error) => {
                errors.push(error);
                continue;
            }
        };
        let mut foreign: Punctuated<syn::Path, Token![,]> = Punctuated::new();
        for path in paths {
            let name = path
                .get_ident()
                .map(|ident| ident.to_string())
                .unwrap_or_default();
            if let Some(lint) = Lint::named(&name) {
                found.push((lint, path_span(&path)));
            } else if let Some(meant) = close_to_ours(&name) {
                errors.at(
                    path_span(&path),
                    format!(
                        "unknown bond-graph lint `{name}`\nhelp: did you mean `{}`?",
                        meant.name()
                    ),
                );
            } else if let Placement::Statement(what) = placement {
                errors.at(
                    path_span(&path),
                    format!(
                        "`{}` is not a bond-graph lint: before {what}, `allow` takes `{}` or `{}`",
                        quote::ToTokens::to_token_stream(&path),
                        Lint::DerivativeCausality.name(),
                        Lint::AlgebraicLoops.name(),
                    ),
                );
            } else {
                foreign.push(path);
            }
        }
        if !foreign.is_empty() {
            let mut attr = attr;
            attr.meta = syn::parse_quote!(allow(#foreign));
            kept.push(attr);
        }
    }
    *attrs = kept;
    found
}

fn path_span(path: &syn::Path) -> Span {
    path.segments
        .first()
        .map_or_else(Span::call_site, |segment| segment.ident.span())
}

/// One of our lints that `name` looks like a misspelling of: one or two edits away,
/// or the same words in another form (`algebraic_loop`, `derivative-causality`).
fn close_to_ours(name: &str) -> Option<Lint> {
    let squashed: String = name
        .chars()
        .filter(|c| c.is_alphanumeric())
        .collect::<String>()
        .to_lowercase();
    Lint::ALL.into_iter().find(|lint| {
        let ours: String = lint.name().chars().filter(|c| *c != '_').collect();
        edit_distance(&squashed, &ours) <= 2 || squashed.starts_with(&ours[..ours.len() - 1])
    })
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (diagonal + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(above + 1);
            diagonal = above;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn take(text: &str, placement: Placement) -> (Vec<Lint>, Vec<String>, Result<(), String>) {
        let file: syn::File = syn::parse_str(&format!("{text} struct S;")).unwrap();
        let syn::Item::Struct(item) = &file.items[0] else {
            unreachable!()
        };
        let mut attrs = item.attrs.clone();
        let mut errors = Errors::default();
        let lints = take_lints(&mut attrs, placement, &mut errors)
            .into_iter()
            .map(|(lint, _)| lint)
            .collect();
        let kept = attrs
            .iter()
            .map(|a| quote::ToTokens::to_token_stream(a).to_string())
            .collect();
        (lints, kept, errors.finish().map_err(|e| e.to_string()))
    }

    #[test]
    fn take_ours_and_leave_rusts_lints_on_the_model() {
        let (lints, kept, result) = take(
            "/// doc\n#[allow(algebraic_loops, dead_code)] #[allow(derivative_causality)]",
            Placement::Model,
        );
        assert_eq!(lints, [Lint::AlgebraicLoops, Lint::DerivativeCausality]);
        assert_eq!(kept.len(), 2, "{kept:?}");
        assert!(kept[1].contains("allow (dead_code)"), "{kept:?}");
        assert!(result.is_ok());
    }

    #[test]
    fn name_the_lint_a_misspelling_meant() {
        for written in [
            "algebraic_loop",
            "derivative_casuality",
            "derivativecausality",
        ] {
            let (lints, _, result) = take(&format!("#[allow({written})]"), Placement::Model);
            assert!(lints.is_empty());
            let message = result.unwrap_err();
            assert!(message.contains("did you mean"), "{written}: {message}");
        }
    }

    #[test]
    fn reject_rusts_lints_and_other_attributes_on_a_statement() {
        let (_, _, result) = take("#[allow(dead_code)]", Placement::Statement("an element"));
        assert!(result.unwrap_err().contains("not a bond-graph lint"));
        let (_, _, result) = take("#[inline]", Placement::Statement("a bond statement"));
        assert!(result.unwrap_err().contains("`#[inline]` has no meaning"));
        let (lints, kept, result) = take(
            "/// the rigid gear\n#[allow(derivative_causality)]",
            Placement::Statement("an element"),
        );
        assert_eq!((lints, kept.len()), (vec![Lint::DerivativeCausality], 1));
        assert!(result.is_ok());
    }
}
