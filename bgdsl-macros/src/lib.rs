//! The `bond_graph!` compiler. (Grammar documented on the macro.)
use proc_macro::TokenStream;

/// Compiles a textual bond graph into a model.
#[proc_macro]
pub fn bond_graph(input: TokenStream) -> TokenStream {
    let _ = input;
    TokenStream::new()
}
