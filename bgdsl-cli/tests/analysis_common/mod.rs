//! What the analysis commands' tests share: running a command line in-process over a
//! catalogue, and reading the files back (scratch folders: `common::Scratch`).
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::sync::LazyLock;

use bgdsl_cli::cli::{command, execute, Cli, Failure};
use bgdsl_cli::Catalogue;
use clap::FromArgMatches;

/// The `models` program's catalogue.
pub static MODELS: LazyLock<Catalogue> = LazyLock::new(models::catalog::catalogue);

/// Parses `args` (without the program's name) as the program of `catalogue` does and
/// runs the command.
pub fn run(catalogue: &'static Catalogue, args: &[&str]) -> Result<(), Failure> {
    let matches = command(catalogue)
        .try_get_matches_from(std::iter::once("models").chain(args.iter().copied()))
        .unwrap_or_else(|e| panic!("{args:?}: {e}"));
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| panic!("{e}"));
    execute(cli, catalogue)
}

/// The names in `dir`, sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Every file of `dir` with its bytes.
pub fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    names(dir)
        .into_iter()
        .map(|n| {
            let bytes = fs::read(dir.join(&n)).unwrap();
            (n, bytes)
        })
        .collect()
}

/// A YAML (or JSON) file as a value.
pub fn yaml(path: &Path) -> serde_yaml::Value {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_yaml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A list of numbers.
pub fn numbers(value: &serde_yaml::Value) -> Vec<f64> {
    value
        .as_sequence()
        .unwrap_or_else(|| panic!("not a list: {value:?}"))
        .iter()
        .map(|v| v.as_f64().unwrap_or_else(|| panic!("not a number: {v:?}")))
        .collect()
}

/// A list of rows of numbers.
pub fn rows(value: &serde_yaml::Value) -> Vec<Vec<f64>> {
    value
        .as_sequence()
        .unwrap_or_else(|| panic!("not a list: {value:?}"))
        .iter()
        .map(numbers)
        .collect()
}

/// A list of strings.
pub fn strings(value: &serde_yaml::Value) -> Vec<String> {
    value
        .as_sequence()
        .unwrap_or_else(|| panic!("not a list: {value:?}"))
        .iter()
        .map(|v| v.as_str().unwrap().to_owned())
        .collect()
}

/// A CSV file: its header and its rows of numbers (a field that is not a number, such
/// as a quoted list of names, reads as NaN).
pub fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    (header, rows)
}

/// Checks that `path` is a PNG image (its signature) of some substance.
pub fn assert_png(path: &Path) {
    let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        bytes.starts_with(b"\x89PNG\r\n\x1a\n"),
        "{} is not a PNG",
        path.display()
    );
    assert!(bytes.len() > 5000, "{} is nearly empty", path.display());
}

/// `|a − b| ≤ tol · |b|`.
pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs()
}
