//! The mapping form of `plots` and its phase portraits:
//!
//! ```yaml
//! plots:
//!   figures: all                 # all (default) | none | [ids]
//!   phase: [[spring.q, speed]]   # pairs of states or outputs: one portrait each
//! ```
//!
//! and the command line's `--phase X,Y` (repeatable), which adds a portrait. Each name
//! is one state or output (a vector's component, not the vector), checked like
//! `output.record`'s, with the file's line and column.

use serde_yaml::Value;

use super::locate::KeyPath;
use super::resolve::{column, Places};
use super::{Diagnostics, Origin, Scenario};
use crate::catalog::{describe_value, Entry, PhasePair};

/// The keys of `plots` in its mapping form.
const KEYS: [&str; 2] = ["figures", "phase"];

/// The value that chooses figures (`all`, `none` or a list of ids) and where it is:
/// `plots` itself, or its `figures` in the mapping form (`None`: all, the default).
pub(super) fn figures_value(scenario: &Scenario) -> (Option<&Value>, KeyPath) {
    match &scenario.plots {
        Some(Value::Mapping(map)) => (map.get("figures"), KeyPath::keys(&["plots", "figures"])),
        other => (other.as_ref(), KeyPath::keys(&["plots"])),
    }
}

/// The phase portraits the scenario's `plots.phase` and the `--phase` flags ask for;
/// also reports unknown keys of the mapping form.
pub(super) fn phase_pairs(
    entry: &Entry,
    scenario: &Scenario,
    flags: &[String],
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Vec<PhasePair> {
    let mut pairs = Vec::new();
    if let Some(Value::Mapping(map)) = &scenario.plots {
        for key in map.keys() {
            if !key.as_str().is_some_and(|k| KEYS.contains(&k)) {
                let name = key
                    .as_str()
                    .map_or_else(|| describe_value(key), str::to_owned);
                let origin = match key.as_str() {
                    Some(k) => places.keys(&["plots", k]),
                    None => places.keys(&["plots"]),
                };
                d.push(
                    origin,
                    format!(
                        "unknown key `{name}` in `plots`; the keys are: {}",
                        KEYS.join(", ")
                    ),
                );
            }
        }
        if let Some(value) = map.get("phase") {
            let path = KeyPath::keys(&["plots", "phase"]);
            let Value::Sequence(items) = value else {
                d.push(
                    places.file(&path),
                    format!(
                        "`phase` must be a list of pairs of names, e.g. `[[x, v]]`, found {}",
                        describe_value(value)
                    ),
                );
                return pairs;
            };
            for (i, item) in items.iter().enumerate() {
                let at = path.index(i);
                let names: Option<Vec<&str>> = match item {
                    Value::Sequence(two) if two.len() == 2 => {
                        two.iter().map(Value::as_str).collect()
                    }
                    _ => None,
                };
                let Some(names) = names else {
                    d.push(
                        places.file(&at),
                        format!(
                            "a phase portrait is a pair of state or output names, `[x, v]`, \
                             found {}",
                            describe_value(item)
                        ),
                    );
                    continue;
                };
                let x = scalar(entry, names[0], places.file(&at.index(0)), d);
                let y = scalar(entry, names[1], places.file(&at.index(1)), d);
                if let (Some(x), Some(y)) = (x, y) {
                    pairs.push(PhasePair { x, y });
                }
            }
        }
    }
    for flag in flags {
        let origin = || Origin::Flag(format!("--phase {flag}"));
        let Some((x, y)) = flag.split_once(',') else {
            d.push(
                origin(),
                "expected X,Y: two state or output names, e.g. `--phase x,speed`",
            );
            continue;
        };
        let x = scalar(entry, x.trim(), origin(), d);
        let y = scalar(entry, y.trim(), origin(), d);
        if let (Some(x), Some(y)) = (x, y) {
            pairs.push(PhasePair { x, y });
        }
    }
    pairs
}

/// One state or output by name, or a diagnostic.
fn scalar(
    entry: &Entry,
    name: &str,
    origin: Origin,
    d: &mut Diagnostics,
) -> Option<(String, crate::catalog::Column)> {
    let found = column(entry, name, origin.clone(), d)?;
    if found.len() != 1 || found[0].0 != name {
        let parts: Vec<&str> = found.iter().map(|(n, _)| n.as_str()).collect();
        d.push(
            origin,
            format!(
                "a phase portrait's axis is one state or output; `{name}` stands for {}: \
                 name one of them",
                parts.join(", ")
            ),
        );
        return None;
    }
    found.into_iter().next()
}

/// A sweep or a Monte Carlo study draws no phase portraits: each one asked for is an error.
pub(super) fn refuse_in_study(
    scenario: &Scenario,
    flags: &[String],
    places: &Places<'_>,
    d: &mut Diagnostics,
) {
    const WHY: &str = "a sweep or a Monte Carlo study draws no phase portraits (it keeps no \
                       run's samples); run one point alone to draw them";
    if let Some(Value::Mapping(map)) = &scenario.plots {
        if map.contains_key("phase") {
            d.push(places.keys(&["plots", "phase"]), WHY);
        }
    }
    for flag in flags {
        d.push(Origin::Flag(format!("--phase {flag}")), WHY);
    }
}
