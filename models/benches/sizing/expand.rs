//! The sizing benchmark's macro timer (run.sh builds it with the macro crate's modules,
//! as `bgdsl-macros/benches/expansion.rs` does): expands the `bond_graph!` block of the
//! file given as the first argument and prints the time and the size of the Rust out.

#![allow(dead_code, unused_imports)]

use std::str::FromStr;
use std::time::Instant;

use proc_macro2::TokenStream;

fn main() {
    let path = std::env::args().nth(1).expect("usage: expand MODEL.rs");
    let source = std::fs::read_to_string(&path).expect("the model file");
    let start = source.find('{').expect("a bond_graph! block") + 1;
    let end = source.rfind('}').expect("a bond_graph! block");
    let input = TokenStream::from_str(&source[start..end]).expect("the model tokenizes");
    let mut best = f64::INFINITY;
    let mut output = String::new();
    for _ in 0..3 {
        let begin = Instant::now();
        let tokens = expand::expand(input.clone());
        best = best.min(begin.elapsed().as_secs_f64());
        output = tokens.to_string();
    }
    assert!(!output.contains("compile_error"), "the model expands without errors");
    println!("expand_s={best:.4}");
    println!("rust_bytes={}", output.len());
    if let Some(out) = std::env::args().nth(2) {
        std::fs::write(out, &output).expect("write the expansion");
    }
}
