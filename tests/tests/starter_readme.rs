//! The README's section "Your own model" shows the starter template's files: each of
//! its code blocks is the template's text word for word, so that what CI builds and
//! runs (`.ci/starter`: the template copied out, built, its program run with the
//! section's commands, its FMU checked in FMPy) is what the README shows.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn read(path: &str) -> String {
    let path = root().join(path);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The fenced blocks of the README's section `heading`: (info string, text).
fn blocks(heading: &str) -> Vec<(String, String)> {
    let readme = read("README.md");
    let start = readme
        .find(&format!("\n## {heading}\n"))
        .unwrap_or_else(|| panic!("the README has a section `{heading}`"));
    let section = &readme[start + 1..];
    let end = section[3..].find("\n## ").map_or(section.len(), |i| i + 3);
    let mut found = Vec::new();
    let mut lines = section[..end].lines();
    while let Some(line) = lines.next() {
        if let Some(info) = line.strip_prefix("```") {
            let mut text = String::new();
            for inner in lines.by_ref().take_while(|l| *l != "```") {
                text.push_str(inner);
                text.push('\n');
            }
            found.push((info.to_string(), text));
        }
    }
    found
}

#[test]
fn the_readme_shows_the_starters_main_rs_whole() {
    let main = read("examples/starter/src/main.rs");
    // The file is the block, after its module doc.
    let body = main
        .lines()
        .skip_while(|l| l.starts_with("//!") || l.is_empty())
        .map(|l| format!("{l}\n"))
        .collect::<String>();
    let shown: Vec<String> = blocks("Your own model")
        .into_iter()
        .filter(|(info, text)| info == "rust,ignore" && text.contains("fn main()"))
        .map(|(_, text)| text)
        .collect();
    assert_eq!(shown, [body]);
}

#[test]
fn the_readmes_excerpts_are_the_starters_text() {
    let files = [
        ("toml", read("examples/starter/Cargo.toml")),
        ("rust,ignore", read("examples/starter/src/lib.rs")),
        ("text", read(".ci/starter")),
    ];
    let mut checked = 0;
    for (info, text) in blocks("Your own model") {
        if text.contains("fn main()") {
            continue;
        }
        if let Some((_, file)) = files.iter().find(|(kind, _)| *kind == info) {
            // The error line is in CI's script inside quotes, without its newline.
            let excerpt = text.trim_end_matches('\n');
            assert!(file.contains(excerpt), "not in the starter:\n{excerpt}");
            checked += 1;
        }
    }
    assert_eq!(checked, 3, "the toml, lib.rs and error blocks");
}

#[test]
fn the_readmes_commands_name_the_starters_scenarios_and_model() {
    let (_, commands) = blocks("Your own model")
        .into_iter()
        .find(|(info, _)| info == "sh")
        .expect("a block of commands");
    let mut scenarios = 0;
    for word in commands.split_whitespace() {
        if word.starts_with("scenarios/") {
            assert!(
                root().join("examples/starter").join(word).is_file(),
                "{word}"
            );
            scenarios += 1;
        }
    }
    assert_eq!(scenarios, 2, "{commands}");
    assert!(read("examples/starter/src/main.rs").contains("Entry::of::<Scale>()"));
}
