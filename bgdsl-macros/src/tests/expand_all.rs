//! A check that code generation keeps its output: expands every `bond_graph!` in the
//! workspace's sources and writes the expansions to `$BGDSL_EXPAND_TO` (ignored test;
//! run it before and after a change and diff the files).

use proc_macro2::{TokenStream, TokenTree};

fn collect(stream: TokenStream, out: &mut Vec<TokenStream>) {
    let tokens: Vec<TokenTree> = stream.into_iter().collect();
    for (i, token) in tokens.iter().enumerate() {
        if let TokenTree::Group(group) = token {
            let is_call = i >= 2
                && matches!(&tokens[i - 2], TokenTree::Ident(id) if id == "bond_graph")
                && matches!(&tokens[i - 1], TokenTree::Punct(p) if p.as_char() == '!');
            if is_call {
                out.push(group.stream());
            } else {
                collect(group.stream(), out);
            }
        }
    }
}

fn rust_files(dir: &std::path::Path, files: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() && !path.ends_with("target") && !path.ends_with("ui") {
            rust_files(&path, files);
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
}

#[test]
#[ignore = "writes every expansion to $BGDSL_EXPAND_TO for a before/after diff"]
fn write_every_expansion() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in [
        "models",
        "tests",
        "bgdsl-runtime",
        "bgdsl-fmi",
        "bgdsl-embedded",
    ] {
        rust_files(&root.join(dir), &mut files);
    }
    let mut text = String::new();
    let mut count = 0;
    for file in files {
        let source = std::fs::read_to_string(&file).unwrap();
        let Ok(stream) = source.parse::<TokenStream>() else {
            continue;
        };
        let mut calls = Vec::new();
        collect(stream, &mut calls);
        for call in calls {
            count += 1;
            text.push_str(&format!(
                "// {}\n{}\n",
                file.display(),
                crate::expand::expand(call)
            ));
        }
    }
    assert!(count > 10, "found only {count} models");
    std::fs::write(std::env::var("BGDSL_EXPAND_TO").unwrap(), text).unwrap();
}
