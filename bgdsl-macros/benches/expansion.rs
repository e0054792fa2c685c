//! Macro expansion cost: the whole pipeline (parse, submodels, resolve, causality,
//! equations, code generation) on the flagship's `bond_graph!` block, as rustc would
//! run it. The target: at most 0.5 s.
//!
//! A proc-macro crate exports nothing but its macros, so the bench compiles the
//! compiler's modules itself, from the same files.
//!
//! `cargo bench -p bgdsl-macros --bench expansion -- --warm-up-time 1 --measurement-time 3`

#![allow(dead_code, unused_imports)]

#[path = "../src/allow.rs"]
mod allow;
#[path = "../src/causality/mod.rs"]
mod causality;
#[path = "../src/chunks.rs"]
mod chunks;
#[path = "../src/codegen.rs"]
mod codegen;
#[path = "../src/compliance.rs"]
mod compliance;
#[path = "../src/components.rs"]
mod components;
#[path = "../src/derived.rs"]
mod derived;
#[path = "../src/dims.rs"]
mod dims;
#[path = "../src/equations.rs"]
mod equations;
#[path = "../src/errors.rs"]
mod errors;
#[path = "../src/event_code.rs"]
mod event_code;
#[path = "../src/event_syntax.rs"]
mod event_syntax;
#[path = "../src/events.rs"]
mod events;
#[path = "../src/expand.rs"]
mod expand;
#[path = "../src/flatten.rs"]
mod flatten;
#[path = "../src/hoist.rs"]
mod hoist;
#[path = "../src/implicit.rs"]
mod implicit;
#[path = "../src/ir.rs"]
mod ir;
#[path = "../src/keywords.rs"]
mod keywords;
#[path = "../src/power.rs"]
mod power;
#[path = "../src/resolve.rs"]
mod resolve;
#[path = "../src/rewrite.rs"]
mod rewrite;
#[path = "../src/shapes.rs"]
mod shapes;
#[path = "../src/signals.rs"]
mod signals;
#[path = "../src/split.rs"]
mod split;
#[path = "../src/staged.rs"]
mod staged;
#[path = "../src/stdlib.rs"]
mod stdlib;
#[path = "../src/syntax.rs"]
mod syntax;
#[path = "../src/units.rs"]
mod units;
#[path = "../src/value_shape.rs"]
mod value_shape;

use std::hint::black_box;
use std::str::FromStr;

use criterion::{criterion_group, criterion_main, Criterion};
use proc_macro2::TokenStream;

/// The flagship's `bond_graph! { ... }` contents, cut from its source file.
fn flagship() -> TokenStream {
    let source = include_str!("../../models/src/quick_return/model.rs");
    let start = source.find("bond_graph! {").expect("the flagship's block") + "bond_graph! ".len();
    let mut depth = 0;
    let mut end = start;
    for (i, c) in source[start..].char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    end = start + i;
                    break;
                }
            }
            _ => {}
        }
    }
    TokenStream::from_str(&source[start + 1..end]).expect("the flagship tokenizes")
}

fn expansion(c: &mut Criterion) {
    let input = flagship();
    let output = expand::expand(input.clone()).to_string();
    assert!(
        !output.contains("compile_error"),
        "the flagship expands without errors"
    );
    println!(
        "flagship expansion: {} tokens in, {} characters of Rust out",
        input.clone().into_iter().count(),
        output.len()
    );
    c.bench_function("expand_quick_return", |b| {
        b.iter(|| expand::expand(black_box(input.clone())))
    });
}

criterion_group!(benches, expansion);
criterion_main!(benches);
