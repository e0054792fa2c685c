//! `models list` and `models params`.

use std::io::Write;

use serde_yaml::Value;

use super::Failure;
use crate::catalog::{format_value, Catalogue};

/// Writes `text` to stdout.
pub(super) fn print(text: &str) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure::Other(format!("writing to stdout failed: {e}")))
}

/// `models list`.
pub(super) fn list(catalogue: &Catalogue) -> Result<(), Failure> {
    let entries = catalogue.entries();
    let width = entries.iter().map(|e| e.name.len()).max().unwrap_or(0);
    let mut text = String::new();
    for entry in entries {
        text.push_str(&format!("{:<width$}  {}\n", entry.name, entry.description));
    }
    print(&text)
}

/// `models params <model>`.
pub(super) fn params(
    catalogue: &Catalogue,
    name: &str,
    states: bool,
    outputs: bool,
) -> Result<(), Failure> {
    let entry = catalogue
        .find(name)
        .map_err(|e| Failure::Usage(e.to_string()))?;
    let model = &*entry.model;
    let defaults = model.default_parameters();
    let rows: Vec<[String; 4]> = model
        .parameters()
        .iter()
        .map(|p| {
            let default = defaults
                .get(Value::String(p.name.to_owned()))
                .map(format_value)
                .unwrap_or_default();
            let doc = p.doc.split_whitespace().collect::<Vec<_>>().join(" ");
            [p.name.to_owned(), default, p.unit.to_owned(), doc]
        })
        .collect();
    let width = |i: usize, title: &str| {
        rows.iter()
            .map(|r| r[i].chars().count())
            .max()
            .unwrap_or(0)
            .max(title.len())
    };
    let (w0, w1, w2) = (width(0, "name"), width(1, "default"), width(2, "unit"));
    let mut text = format!(
        "{} ({}): {}\n\nparameters (set with `--set NAME=VALUE` or a scenario's `parameters:`)\n",
        entry.name,
        model.type_name(),
        entry.description
    );
    text.push_str(&format!(
        "  {:<w0$}  {:<w1$}  {:<w2$}  {}\n",
        "name", "default", "unit", "meaning"
    ));
    for [name, default, unit, doc] in &rows {
        let line = format!("  {name:<w0$}  {default:<w1$}  {unit:<w2$}  {doc}");
        text.push_str(line.trim_end());
        text.push('\n');
    }
    if !model.inputs().is_empty() {
        text.push_str("\ninputs (set by a host between steps: a Stepper, an FMU's importer)\n");
        for input in model.inputs() {
            let doc = input.doc.split_whitespace().collect::<Vec<_>>().join(" ");
            let line = format!("  {:<w0$}  {:<w2$}  {doc}", input.name, input.unit);
            text.push_str(line.trim_end());
            text.push('\n');
        }
    }
    if states {
        let x0 = model
            .initial_state(&defaults)
            .map_err(|e| Failure::Other(e.to_string()))?;
        let names = model.state_names();
        text.push_str(&format!(
            "\nstates ({}; set initial values in a scenario's `initial:`)\n",
            names.len()
        ));
        let rows: Vec<[String; 4]> = names
            .iter()
            .zip(&x0)
            .enumerate()
            .map(|(i, (name, x))| {
                let (unit, doc) = described(model.states(), i);
                [(*name).to_owned(), x.to_string(), unit, doc]
            })
            .collect();
        text.push_str(&table(["name", "initial", "unit", "meaning"], &rows));
    }
    if outputs {
        let names = model.output_names();
        text.push_str(&format!(
            "\noutputs ({}; record them with a scenario's `output: record:`)\n",
            names.len()
        ));
        let rows: Vec<[String; 3]> = names
            .iter()
            .enumerate()
            .map(|(i, name)| {
                let (unit, doc) = described(model.outputs(), i);
                [(*name).to_owned(), unit, doc]
            })
            .collect();
        text.push_str(&table(["name", "unit", "meaning"], &rows));
    }
    print(&text)
}

/// The unit and the one-line documentation of entry `i` of `infos` (empty where the
/// model does not describe it).
fn described(infos: &[bgdsl_runtime::SignalInfo], i: usize) -> (String, String) {
    infos.get(i).map_or_else(Default::default, |info| {
        let doc = info.doc.split_whitespace().collect::<Vec<_>>().join(" ");
        (info.unit.to_owned(), doc)
    })
}

/// Rows under a title row, in columns as wide as their widest cell, indented by two.
fn table<const N: usize>(titles: [&str; N], rows: &[[String; N]]) -> String {
    let widths: Vec<usize> = (0..N)
        .map(|i| {
            rows.iter()
                .map(|r| r[i].chars().count())
                .chain([titles[i].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let line = |cells: Vec<&str>| {
        let padded: Vec<String> = cells
            .iter()
            .zip(&widths)
            .map(|(cell, &w)| format!("{cell:<w$}"))
            .collect();
        format!("  {}", padded.join("  ").trim_end())
    };
    let mut text = line(titles.to_vec());
    text.push('\n');
    for row in rows {
        text.push_str(&line(row.iter().map(String::as_str).collect()));
        text.push('\n');
    }
    text
}
