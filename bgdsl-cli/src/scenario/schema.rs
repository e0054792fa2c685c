//! The shape of a scenario file, checked on the parsed YAML before it is read into a
//! [`Scenario`](super::Scenario): serde stops at the first unknown key or wrong type,
//! this reports every one of them (at its key, located by [`locate`](super::locate))
//! and drops the entries at fault, so that the rest of the file can still be read and
//! checked.

use serde::de::DeserializeOwned;
use serde_yaml::{Mapping, Value};

use super::locate::KeyPath;
use super::{Diagnostics, Origin, Source};
use crate::catalog::{format_value, overflow_message, overflowing_number};

/// What a key holds.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// A string.
    Text,
    /// A number.
    Number,
    /// A whole number >= 0.
    Count,
    /// A list of strings.
    Texts,
    /// A list of numbers.
    Numbers,
    /// A mapping of anything (checked later: parameters, initial conditions).
    Mapping,
    /// A number, or a mapping of anything (checked later: `solver.atol`).
    NumberOrMapping,
    /// Anything (checked later: `plots`).
    Any,
    /// A mapping with these keys.
    Section(&'static [Field]),
    /// A list of mappings with these keys.
    Sections(&'static [Field]),
}

/// One key of a section.
#[derive(Clone, Copy, Debug)]
struct Field {
    name: &'static str,
    kind: Kind,
    required: bool,
}

const fn optional(name: &'static str, kind: Kind) -> Field {
    Field {
        name,
        kind,
        required: false,
    }
}

const fn required(name: &'static str, kind: Kind) -> Field {
    Field {
        name,
        kind,
        required: true,
    }
}

const TIME: &[Field] = &[
    optional("start", Kind::Number),
    optional("end", Kind::Number),
];

const SOLVER: &[Field] = &[
    optional("method", Kind::Text),
    optional("rtol", Kind::Number),
    optional("atol", Kind::NumberOrMapping),
    optional("non_negative", Kind::Texts),
    optional("step", Kind::Number),
    optional("max_step", Kind::Number),
    optional("max_steps", Kind::Count),
    optional("max_wall_time", Kind::Number),
];

const OUTPUT: &[Field] = &[
    optional("interval", Kind::Number),
    optional("count", Kind::Count),
    optional("record", Kind::Texts),
];

const AXIS: &[Field] = &[
    required("name", Kind::Text),
    optional("values", Kind::Numbers),
    optional("from", Kind::Number),
    optional("to", Kind::Number),
    optional("steps", Kind::Count),
];

const WINDOW: &[Field] = &[optional("from", Kind::Number), optional("to", Kind::Number)];

const SWEEP: &[Field] = &[
    required("parameters", Kind::Sections(AXIS)),
    required("peaks", Kind::Texts),
    optional("window", Kind::Section(WINDOW)),
];

const MONTE_CARLO: &[Field] = &[
    required("samples", Kind::Count),
    required("seed", Kind::Count),
    required("parameters", Kind::Mapping),
];

/// The keys of a scenario file.
const SCENARIO: &[Field] = &[
    required("model", Kind::Text),
    optional("description", Kind::Text),
    optional("parameters", Kind::Mapping),
    optional("initial", Kind::Mapping),
    optional("time", Kind::Section(TIME)),
    optional("solver", Kind::Section(SOLVER)),
    optional("output", Kind::Section(OUTPUT)),
    optional("plots", Kind::Any),
    optional("sweep", Kind::Section(SWEEP)),
    optional("monte_carlo", Kind::Section(MONTE_CARLO)),
];

/// Checks the whole document `root` against the scenario's keys, reporting into `d`
/// every unknown key, wrong type and missing key, and removing what is at fault: a
/// wrong value is dropped (its key then takes its default); a section missing a
/// required key is dropped whole. Returns whether what is left can be read (false only
/// when `model` itself is unusable, or the document is not a mapping).
pub(super) fn check(root: &mut Value, source: &Source, d: &mut Diagnostics) -> bool {
    let places = Places { source };
    match root {
        Value::Mapping(map) => section(map, SCENARIO, &KeyPath::default(), &places, d),
        Value::Null => {
            d.push(
                places.at(&KeyPath::default()),
                "the file is empty; a scenario names at least its `model`",
            );
            false
        }
        other => {
            d.push(
                places.at(&KeyPath::default()),
                format!(
                    "a scenario is a mapping of keys (`model: ...`), found {}",
                    crate::catalog::describe_value(other)
                ),
            );
            false
        }
    }
}

struct Places<'a> {
    source: &'a Source,
}

impl Places<'_> {
    /// The key at `path`; the file's first line for the document itself.
    fn at(&self, path: &KeyPath) -> Origin {
        match self.source.at(path) {
            Origin::File {
                path,
                position: None,
            } => Origin::File {
                path,
                position: Some(super::locate::Position { line: 1, column: 1 }),
            },
            origin => origin,
        }
    }
}

/// `path: message`, or the message alone at the root (as serde_yaml words it).
fn prefixed(path: &KeyPath, message: impl core::fmt::Display) -> String {
    if path.0.is_empty() {
        message.to_string()
    } else {
        format!("{path}: {message}")
    }
}

/// Checks the keys of one mapping; returns false when a required key is missing or
/// unusable (the caller drops the mapping).
fn section(
    map: &mut Mapping,
    fields: &'static [Field],
    path: &KeyPath,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> bool {
    let names: Vec<&'static str> = fields.iter().map(|f| f.name).collect();
    let mut unknown = Vec::new();
    for key in map.keys() {
        match key.as_str() {
            Some(name) if names.contains(&name) => {}
            Some(name) => {
                let message = unknown_field(name, &names);
                d.push(places.at(&path.key(name)), prefixed(path, message));
                unknown.push(key.clone());
            }
            None => {
                d.push(
                    places.at(path),
                    prefixed(
                        path,
                        format!("a key must be a name, found {}", format_value(key)),
                    ),
                );
                unknown.push(key.clone());
            }
        }
    }
    for key in unknown {
        map.remove(&key);
    }
    let mut readable = true;
    for field in fields {
        let at = path.key(field.name);
        let usable = match map.get_mut(field.name) {
            None => {
                if field.required {
                    d.push(
                        places.at(path),
                        prefixed(path, format!("missing field `{}`", field.name)),
                    );
                }
                !field.required
            }
            // An optional key with nothing under it is the same as absent.
            Some(Value::Null) if !field.required => {
                map.remove(field.name);
                true
            }
            Some(value) => {
                let ok = self::value(value, field.kind, &at, places, d);
                if !ok {
                    map.remove(field.name);
                }
                ok || !field.required
            }
        };
        readable &= usable;
    }
    readable
}

/// `unknown field `x`, expected one of `a`, `b`, `c``, worded as serde words it.
fn unknown_field(name: &str, expected: &[&str]) -> String {
    let quoted: Vec<String> = expected.iter().map(|e| format!("`{e}`")).collect();
    let expected = match quoted.as_slice() {
        [] => "there are no fields".to_owned(),
        [one] => format!("expected {one}"),
        [a, b] => format!("expected {a} or {b}"),
        many => format!("expected one of {}", many.join(", ")),
    };
    format!("unknown field `{name}`, {expected}")
}

/// Checks one value; false when it is unusable (the caller drops it).
fn value(
    value: &mut Value,
    kind: Kind,
    path: &KeyPath,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> bool {
    // YAML reads `description: 2024` as a number; as text it is what was written.
    let as_text = |v: &mut Value| {
        if let Value::Number(_) | Value::Bool(_) = v {
            let text = serde_yaml::to_string(v).unwrap_or_default();
            *v = Value::String(text.trim_end().to_owned());
        }
    };
    match kind {
        Kind::Text => {
            as_text(value);
            leaf::<String>(value, path, places, d)
        }
        Kind::Texts => {
            if let Value::Sequence(items) = value {
                items.iter_mut().for_each(as_text);
            }
            leaf::<Vec<String>>(value, path, places, d)
        }
        Kind::Number => leaf::<f64>(value, path, places, d),
        Kind::Count => leaf::<usize>(value, path, places, d),
        Kind::Numbers => leaf::<Vec<f64>>(value, path, places, d),
        Kind::Mapping => leaf::<Mapping>(value, path, places, d),
        Kind::NumberOrMapping => match value {
            Value::Mapping(_) => true,
            _ => leaf::<f64>(value, path, places, d),
        },
        Kind::Any => true,
        Kind::Section(fields) => match value {
            Value::Mapping(map) => section(map, fields, path, places, d),
            other => {
                mismatch(other, "a mapping of keys", path, places, d);
                false
            }
        },
        Kind::Sections(fields) => match value {
            Value::Sequence(items) => {
                let mut readable = true;
                for (i, item) in items.iter_mut().enumerate() {
                    let at = path.index(i);
                    readable &= match item {
                        Value::Mapping(map) => section(map, fields, &at, places, d),
                        other => {
                            mismatch(other, "a mapping of keys", &at, places, d);
                            false
                        }
                    };
                }
                readable
            }
            other => {
                mismatch(other, "a list", path, places, d);
                false
            }
        },
    }
}

/// Whether `value` reads as a `T`; if not, says why (a number too large for an `f64`
/// is said to overflow).
fn leaf<T: DeserializeOwned>(
    value: &Value,
    path: &KeyPath,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> bool {
    match serde_yaml::from_value::<T>(value.clone()) {
        Ok(_) => true,
        Err(e) => {
            let message = match overflowing_number(value) {
                Some(text) => overflow_message(text),
                None => e.to_string(),
            };
            d.push(places.at(path), prefixed(path, message));
            false
        }
    }
}

fn mismatch(
    found: &Value,
    expected: &str,
    path: &KeyPath,
    places: &Places<'_>,
    d: &mut Diagnostics,
) {
    d.push(
        places.at(path),
        prefixed(
            path,
            format!(
                "expected {expected}, found {}",
                crate::catalog::describe_value(found)
            ),
        ),
    );
}
