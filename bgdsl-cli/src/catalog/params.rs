//! Parameters as YAML values: overriding one by name with a check of its shape, and
//! showing values to people.

use serde_yaml::{Mapping, Value};

use super::{Entry, Problem};

/// Sets parameter `name` of `params` (a mapping of every parameter of `entry`'s model)
/// to `value`, after checking that the model has such a parameter and that `value` has
/// the default's shape: a number where the default is a number, a list of as many
/// numbers where it is a list (integers are numbers too).
///
/// # Errors
///
/// A [`Problem`] naming the parameter: an unknown name (the message lists the model's
/// parameters) or a value of the wrong shape (the message says what was expected and
/// what was found).
pub fn set_parameter(
    entry: &Entry,
    params: &mut Mapping,
    name: &str,
    value: Value,
) -> Result<(), Problem> {
    let key = Value::String(name.to_owned());
    let Some(default) = params.get(&key) else {
        let names: Vec<&str> = entry.model.parameters().iter().map(|p| p.name).collect();
        return Err(Problem::new(
            &[name],
            format!(
                "unknown parameter `{name}`; the parameters of {} are: {}",
                entry.name,
                names.join(", ")
            ),
        ));
    };
    if let Some(text) = overflowing_number(&value) {
        return Err(Problem::new(
            &[name],
            format!("parameter `{name}`: {}", overflow_message(text)),
        ));
    }
    if let Some(expected) = shape_mismatch(default, &value) {
        let unit = entry
            .model
            .parameters()
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.unit)
            .filter(|u| !u.is_empty())
            .map(|u| format!(" in {u}"))
            .unwrap_or_default();
        return Err(Problem::new(
            &[name],
            format!(
                "parameter `{name}` must be {expected}{unit}, found {}",
                describe_value(&value)
            ),
        ));
    }
    params.insert(key, value);
    Ok(())
}

/// A number written in `value` (or in a list of it) too large for an `f64`: YAML reads
/// `1e400` as a string, since it is no finite number.
pub fn overflowing_number(value: &Value) -> Option<&str> {
    match value {
        Value::String(text) => {
            let looks_numeric = text
                .trim()
                .chars()
                .all(|c| c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'e' | 'E' | '_'));
            let overflows = text
                .trim()
                .replace('_', "")
                .parse::<f64>()
                .is_ok_and(f64::is_infinite);
            (looks_numeric && overflows).then_some(text.as_str())
        }
        Value::Sequence(items) => items.iter().find_map(overflowing_number),
        _ => None,
    }
}

/// The message for a number that overflows an `f64`.
pub fn overflow_message(text: &str) -> String {
    format!(
        "the number {} overflows: the largest finite number is about {:e}",
        text.trim(),
        f64::MAX
    )
}

/// What `value` should have been, when its shape differs from `default`'s.
fn shape_mismatch(default: &Value, value: &Value) -> Option<String> {
    match default {
        Value::Number(_) => (!matches!(value, Value::Number(_))).then(|| "a number".to_owned()),
        Value::Sequence(items) => {
            let ok = match value {
                Value::Sequence(given) => {
                    given.len() == items.len()
                        && items
                            .iter()
                            .zip(given)
                            .all(|(d, v)| shape_mismatch(d, v).is_none())
                }
                _ => false,
            };
            let inner = match items.first() {
                Some(Value::Sequence(row)) => format!("lists of {} numbers", row.len()),
                _ => "numbers".to_owned(),
            };
            (!ok).then(|| {
                format!(
                    "a list of {} {inner}, like {}",
                    items.len(),
                    format_value(default)
                )
            })
        }
        _ => (std::mem::discriminant(default) != std::mem::discriminant(value))
            .then(|| format!("like {}", format_value(default))),
    }
}

/// Parses the `VALUE` of a `--set NAME=VALUE` as YAML, so that `0.5`, `1e5` and
/// `[0.2, 0.01, 0.01]` all work.
///
/// # Errors
///
/// The YAML parser's message.
pub fn parse_value(text: &str) -> Result<Value, String> {
    if text.trim().is_empty() {
        return Err("the value is empty".to_owned());
    }
    serde_yaml::from_str(text).map_err(|e| e.to_string())
}

/// A value as people read it: numbers in their shortest exact form (`100000`, `0.5`,
/// `1e-14`), lists as `[a, b, c]`.
pub fn format_value(value: &Value) -> String {
    match value {
        Value::Number(n) => match n.as_f64() {
            Some(v) => format_number(v),
            None => n.to_string(),
        },
        Value::Sequence(items) => {
            let inner: Vec<String> = items.iter().map(format_value).collect();
            format!("[{}]", inner.join(", "))
        }
        Value::String(s) => format!("{s:?}"),
        Value::Bool(b) => b.to_string(),
        Value::Null => "null".to_owned(),
        Value::Mapping(_) => "a mapping".to_owned(),
        Value::Tagged(t) => format!("!{}", t.tag),
    }
}

/// A number in the shortest form that reads back to it: plain from 1e-4 to 1e15,
/// scientific outside.
pub fn format_number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Six significant digits, for tables: `49.3641`, `2.00000`, `1.00000e-5`, `0`.
pub fn format_significant(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        format!("{v}")
    } else if v.abs() >= 1e6 || v.abs() < 1e-3 {
        format!("{v:.5e}")
    } else {
        let digits = (5 - v.abs().log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    }
}

/// What a value is, for messages: `a string "abc"`, `a list of 2 items`, `0.5`.
pub fn describe_value(value: &Value) -> String {
    match value {
        Value::Number(_) => format_value(value),
        Value::Sequence(items) if items.iter().all(|v| matches!(v, Value::Number(_))) => {
            format!("{} (a list of {})", format_value(value), items.len())
        }
        Value::Sequence(items) => format!("a list of {} items", items.len()),
        Value::String(s) => format!("a string {s:?}"),
        Value::Bool(b) => format!("`{b}`"),
        Value::Null => "nothing (null)".to_owned(),
        Value::Mapping(_) => "a mapping".to_owned(),
        Value::Tagged(t) => format!("a value tagged !{}", t.tag),
    }
}
