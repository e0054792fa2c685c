//! The `monte_carlo:` section of a scenario: its distributions (each checked at its key),
//! the banded columns, and every sample's parameters checked physically.

use std::collections::BTreeMap;
use std::path::Path;

use crate::study::distribution::{draw, Distribution};
use serde_yaml::{Mapping, Value};

use super::locate::KeyPath;
use super::resolve::Places;
use super::{Diagnostics, MonteCarloSpec, Origin, Source};
use crate::catalog::{
    all_outputs, describe_value, DrawnParameter, Entry, Plots, RunPlan, StudyPlan,
};

/// The most samples a study may have.
pub const MAX_SAMPLES: usize = 1_000_000;

/// The study: distributions, banded columns, every sample checked.
pub(super) fn study(
    entry: &Entry,
    spec: &MonteCarloSpec,
    base: RunPlan,
    origins: &BTreeMap<String, Origin>,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<StudyPlan> {
    let root = KeyPath::keys(&["monte_carlo"]);
    let before = d.0.len();
    if !(2..=MAX_SAMPLES).contains(&spec.samples) {
        d.push(
            places.file(&root.key("samples")),
            format!(
                "a study needs from 2 to {MAX_SAMPLES} samples, found {}",
                spec.samples
            ),
        );
    }
    if spec.parameters.is_empty() {
        d.push(
            places.file(&root.key("parameters")),
            "`parameters` lists no parameter to draw",
        );
    }
    let mut drawn = Vec::new();
    for (key, value) in &spec.parameters {
        let Some(name) = key.as_str() else {
            d.push(
                places.file(&root.key("parameters")),
                format!(
                    "a parameter name must be a string, found {}",
                    describe_value(key)
                ),
            );
            continue;
        };
        let at = root.key("parameters").key(name);
        let info = entry.model.parameters().iter().find(|p| p.name == name);
        match info {
            None => {
                let names: Vec<&str> = entry.model.parameters().iter().map(|p| p.name).collect();
                d.push(
                    places.file(&at),
                    format!(
                        "unknown parameter `{name}`; the parameters of {} are: {}",
                        entry.name,
                        names.join(", ")
                    ),
                );
                continue;
            }
            Some(p) if p.len != 1 => {
                d.push(
                    places.file(&at),
                    format!(
                        "only scalar parameters can be drawn; `{name}` has {} numbers",
                        p.len
                    ),
                );
                continue;
            }
            Some(_) => {}
        }
        if let Some(origin @ (Origin::Flag(_) | Origin::File { .. })) = origins.get(name) {
            d.push(
                origin.clone(),
                format!(
                    "`{name}` is drawn by the study (monte_carlo.parameters), so this value \
                     would be ignored; drop it, or the distribution"
                ),
            );
        }
        let Some(distribution) = distribution(value, spec.samples, &at, places, d) else {
            continue;
        };
        drawn.push(DrawnParameter {
            name: name.to_owned(),
            unit: info.map(|p| p.unit.to_owned()).unwrap_or_default(),
            distribution,
        });
    }
    let columns = match &base.record {
        Some(record) => record.clone(),
        None => all_outputs(&*entry.model),
    };
    if let Plots::Only(ids) = &base.plots {
        for (i, id) in ids.iter().enumerate() {
            if !columns.iter().any(|(name, _)| name == id) {
                let names: Vec<&str> = columns.iter().map(|(n, _)| n.as_str()).collect();
                d.push(
                    places.file(&KeyPath::keys(&["plots"]).index(i)),
                    format!(
                        "figure `{id}` would draw nothing: a study draws the band of each \
                         banded column ({}); name one of those, or band `{id}` with \
                         `output.record`",
                        names.join(", ")
                    ),
                );
            }
        }
    }
    if columns.is_empty() {
        d.push(
            places.file(&KeyPath::keys(&["output", "record"])),
            format!(
                "{} has no outputs; name the states to band in `output.record`",
                entry.name
            ),
        );
    }
    if d.0.len() > before {
        return None;
    }
    let plan = StudyPlan {
        base,
        samples: spec.samples,
        seed: spec.seed,
        parameters: drawn,
        columns,
    };
    // Every sample must make physical sense; report the first that does not, at the
    // distribution of a parameter it involves.
    for index in 0..plan.samples {
        let mut problems = entry.model.check(&plan.plan_at(index).params);
        problems.retain(|p| plan.parameters.iter().any(|q| p.keys.contains(&q.name)));
        let Some(problem) = problems.first() else {
            continue;
        };
        let name = plan
            .parameters
            .iter()
            .find(|q| problem.keys.contains(&q.name))
            .map(|q| q.name.as_str())
            .unwrap_or_default();
        let values = draw(plan.seed, index, &plan.distributions());
        let at: Vec<String> = plan
            .parameters
            .iter()
            .zip(values)
            .map(|(q, v)| format!("{} = {v}", q.name))
            .collect();
        d.push(
            places.file(&root.key("parameters").key(name)),
            format!(
                "sample {index} ({}): {}; narrow the distribution or change the seed",
                at.join(", "),
                problem.message
            ),
        );
        return None;
    }
    Some(plan)
}

/// One parameter's distribution: a mapping with exactly one of `uniform: [lo, hi]`,
/// `normal: {mean, sd}`, `lognormal: {mu, sigma}`, `csv: {file, column}`, `values:
/// [...]` (sample i takes the i-th; what `run.yaml` records for a `csv` column).
fn distribution(
    value: &Value,
    samples: usize,
    at: &KeyPath,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<Distribution> {
    const KINDS: &str = "`uniform: [lo, hi]`, `normal: {mean: M, sd: S}`, \
                         `lognormal: {mu: M, sigma: S}`, `csv: {file: F, column: C}` or \
                         `values: [x0, x1, ...]`";
    let entries = match value {
        Value::Mapping(map) if map.len() == 1 => map,
        other => {
            d.push(
                places.file(at),
                format!(
                    "a distribution is one of {KINDS}, found {}",
                    describe_value(other)
                ),
            );
            return None;
        }
    };
    let (kind, settings) = entries.iter().next()?;
    let kind = kind.as_str().unwrap_or_default();
    let here = at.key(kind);
    let number = |map: &Mapping, key: &str, d: &mut Diagnostics| -> Option<f64> {
        match map.get(key) {
            Some(v) if v.as_f64().is_some() => v.as_f64(),
            Some(v) => {
                d.push(
                    places.file(&here.key(key)),
                    format!("`{key}` must be a number, found {}", describe_value(v)),
                );
                None
            }
            None => {
                d.push(places.file(&here), format!("`{kind}` needs `{key}`"));
                None
            }
        }
    };
    let keys_only = |map: &Mapping, keys: &[&str], d: &mut Diagnostics| {
        for key in map.keys() {
            let name = key.as_str().unwrap_or_default();
            if !keys.contains(&name) {
                d.push(
                    places.file(&here.key(name)),
                    format!(
                        "unknown key `{name}` of `{kind}`, expected {}",
                        keys.iter()
                            .map(|k| format!("`{k}`"))
                            .collect::<Vec<_>>()
                            .join(" and ")
                    ),
                );
            }
        }
    };
    let made = match (kind, settings) {
        ("uniform", Value::Sequence(ends)) if ends.len() == 2 => {
            match (ends[0].as_f64(), ends[1].as_f64()) {
                (Some(lo), Some(hi)) => Some(Distribution::Uniform { lo, hi }),
                _ => None,
            }
        }
        ("values", Value::Sequence(items)) => items
            .iter()
            .map(Value::as_f64)
            .collect::<Option<Vec<f64>>>()
            .map(Distribution::Values),
        ("normal", Value::Mapping(map)) => {
            keys_only(map, &["mean", "sd"], d);
            let (mean, sd) = (number(map, "mean", d), number(map, "sd", d));
            Some(Distribution::Normal {
                mean: mean?,
                sd: sd?,
            })
        }
        ("lognormal", Value::Mapping(map)) => {
            keys_only(map, &["mu", "sigma"], d);
            let (mu, sigma) = (number(map, "mu", d), number(map, "sigma", d));
            Some(Distribution::LogNormal {
                mu: mu?,
                sigma: sigma?,
            })
        }
        ("csv", Value::Mapping(map)) => {
            keys_only(map, &["file", "column"], d);
            let text = |key: &str, d: &mut Diagnostics| match map.get(key).and_then(Value::as_str) {
                Some(s) => Some(s.to_owned()),
                None => {
                    d.push(
                        places.file(&here.key(key)),
                        format!("`csv` needs `{key}`, a string"),
                    );
                    None
                }
            };
            let (file, column) = (text("file", d), text("column", d));
            let (file, column) = (file?, column?);
            match read_column(places.source, &file, &column) {
                Ok(values) => Some(Distribution::Values(values)),
                Err((key, message)) => {
                    d.push(places.file(&here.key(key)), message);
                    return None;
                }
            }
        }
        ("uniform" | "normal" | "lognormal" | "csv" | "values", other) => {
            let expected = match kind {
                "uniform" => "a list of two numbers `[lo, hi]`",
                "values" => "a list of numbers, one per sample",
                _ => "a mapping of keys",
            };
            d.push(
                places.file(&here),
                format!("`{kind}` takes {expected}, found {}", describe_value(other)),
            );
            return None;
        }
        _ => {
            d.push(
                places.file(&here),
                format!("unknown distribution `{kind}`; use {KINDS}"),
            );
            return None;
        }
    };
    let Some(made) = made else {
        if kind == "values" {
            d.push(
                places.file(&here),
                "`values` takes a list of numbers, one per sample",
            );
        }
        if kind == "uniform" {
            d.push(
                places.file(&here),
                format!(
                    "`uniform` takes a list of two numbers `[lo, hi]`, found {}",
                    describe_value(settings)
                ),
            );
        }
        return None;
    };
    match made.check(samples) {
        Ok(()) => Some(made),
        Err(e) => {
            d.push(places.file(&here), e.0);
            None
        }
    }
}

/// The numbers of `column` in the CSV file `file` (relative to the scenario's folder):
/// a header row, then one row per sample. On error, the key to blame and the message.
fn read_column(
    source: Option<&Source>,
    file: &str,
    column: &str,
) -> Result<Vec<f64>, (&'static str, String)> {
    let folder = source
        .and_then(|s| s.path.parent())
        .unwrap_or_else(|| Path::new(""));
    let path = folder.join(file);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| ("file", format!("cannot read {}: {e}", path.display())))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::trim)
        .collect();
    let Some(index) = header.iter().position(|h| *h == column) else {
        return Err((
            "column",
            format!(
                "{} has no column `{column}`; its columns are: {}",
                path.display(),
                header.join(", ")
            ),
        ));
    };
    let mut values = Vec::new();
    for (row, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let cell = line.split(',').nth(index).unwrap_or_default().trim();
        match cell.parse::<f64>() {
            Ok(v) => values.push(v),
            Err(_) => {
                return Err((
                    "file",
                    format!(
                        "{}:{}: `{column}` is not a number: `{cell}`",
                        path.display(),
                        row + 2
                    ),
                ))
            }
        }
    }
    Ok(values)
}
