//! The pipeline: parse -> resolve -> causality -> equations -> codegen.

use proc_macro2::TokenStream;

use crate::syntax::{File, ModelDef};
use crate::{causality, codegen, equations, resolve};

/// Expands a `bond_graph!` invocation. Never panics: every mistake becomes a spanned
/// compile error, next to a stub of each model so the rest of the user's crate still
/// type-checks.
pub fn expand(input: TokenStream) -> TokenStream {
    let file: File = match syn::parse2(input) {
        Ok(file) => file,
        Err(error) => return error.to_compile_error(),
    };
    file.models.into_iter().map(expand_model).collect()
}

fn expand_model(model: ModelDef) -> TokenStream {
    let stub = codegen::stub(&model);
    match try_expand(model) {
        Ok(tokens) => tokens,
        Err(error) => {
            let mut tokens = stub;
            tokens.extend(error.to_compile_error());
            tokens
        }
    }
}

fn try_expand(model: ModelDef) -> syn::Result<TokenStream> {
    let graph = resolve::resolve(model)?;
    let causality = causality::assign(&graph).map_err(|errors| {
        causality::independent(&graph, &errors)
            .into_iter()
            .map(|e| causality::render(&graph, e))
            .reduce(|mut all, next| {
                all.combine(next);
                all
            })
            // `assign` fails only with at least one error; kept so a bug never panics.
            .unwrap_or_else(|| {
                syn::Error::new(
                    graph.name.span(),
                    "internal error in bgdsl's causality assignment: it failed without naming \
                     a reason; this is a bug in bond_graph!, not in your model: please report it \
                     with this model",
                )
            })
    })?;
    let equations = equations::derive(&graph, &causality)?;
    Ok(codegen::generate(&graph, &causality, &equations))
}
