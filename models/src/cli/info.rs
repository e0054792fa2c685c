//! `models list` and `models params`.

use std::io::Write;

use serde_yaml::Value;

use super::Failure;
use crate::catalog::{self, format_value, MODELS};

/// Writes `text` to stdout.
pub(super) fn print(text: &str) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure::Other(format!("writing to stdout failed: {e}")))
}

/// `models list`.
pub(super) fn list() -> Result<(), Failure> {
    let width = MODELS.iter().map(|e| e.name.len()).max().unwrap_or(0);
    let mut text = String::new();
    for entry in MODELS {
        text.push_str(&format!("{:<width$}  {}\n", entry.name, entry.description));
    }
    print(&text)
}

/// `models params <model>`.
pub(super) fn params(name: &str, states: bool, outputs: bool) -> Result<(), Failure> {
    let entry = catalog::find(name).map_err(|e| Failure::Usage(e.to_string()))?;
    let model = entry.model;
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
        let w = names.iter().map(|n| n.len()).max().unwrap_or(0);
        text.push_str(&format!(
            "\nstates ({}; set initial values in a scenario's `initial:`)\n",
            names.len()
        ));
        text.push_str(&format!("  {:<w$}  initial value\n", "name"));
        for (n, v) in names.iter().zip(&x0) {
            text.push_str(&format!("  {n:<w$}  {v}\n"));
        }
    }
    if outputs {
        let names = model.output_names();
        text.push_str(&format!(
            "\noutputs ({}; record them with a scenario's `output: record:`)\n",
            names.len()
        ));
        for n in names {
            text.push_str(&format!("  {n}\n"));
        }
    }
    print(&text)
}
