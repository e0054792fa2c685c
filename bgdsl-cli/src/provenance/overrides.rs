//! What differs from a model's defaults in a plan: the `overrides` of `run.yaml` and
//! the summary's `overrides` (and `initial`) lines.

use serde_yaml::Value;

use super::Override;
use crate::catalog::{format_value, Entry, RunError, RunPlan};
use crate::scenario::Origin;

/// Whether two parameter values are the same numbers (an integer and a float alike).
fn same_value(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.as_f64() == y.as_f64(),
        (Value::Sequence(x), Value::Sequence(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(a, b)| same_value(a, b))
        }
        _ => a == b,
    }
}

/// `file:line:column`, the flag, or nothing.
fn origin_text(origin: &Origin) -> String {
    match origin {
        Origin::File {
            path,
            position: Some(p),
        } => format!("{}:{}:{}", path.display(), p.line, p.column),
        Origin::File {
            path,
            position: None,
        } => path.display().to_string(),
        Origin::Flag(flag) => flag.clone(),
        Origin::Nowhere => String::new(),
    }
}

/// The parameters of `plan` that differ from `entry`'s defaults, in declaration order,
/// leaving out those named in `except`.
pub fn overrides(entry: &Entry, plan: &RunPlan, except: &[&str]) -> Vec<Override> {
    let defaults = entry.model.default_parameters();
    defaults
        .iter()
        .filter_map(|(key, default)| {
            let name = key.as_str()?;
            let value = plan.params.get(key)?;
            (!except.contains(&name) && !same_value(value, default)).then(|| Override {
                name: name.to_owned(),
                value: value.clone(),
                default: default.clone(),
                from: plan
                    .context
                    .parameter_origins
                    .get(name)
                    .map(origin_text)
                    .unwrap_or_default(),
            })
        })
        .collect()
}

/// The declared initial state of `plan`'s model for its parameters, and the plan's
/// replacements applied to a copy: `(declared, used)`.
pub(super) fn initial_states(
    entry: &Entry,
    plan: &RunPlan,
) -> Result<(Vec<f64>, Vec<f64>), RunError> {
    let declared = entry.model.initial_state(&plan.params)?;
    let mut used = declared.clone();
    for &(i, v) in &plan.initial {
        used[i] = v;
    }
    Ok((declared, used))
}

/// The summary's lines on what differs from the model's defaults:
/// `overrides      g = 1.5 (default 9.81), w_drive = 4 (default 5)` (or `none`), and,
/// when the plan replaces initial states,
/// `initial        spring.q = 0.05 (declared 0.01)`. Parameters named in `except`
/// (a sweep's axes) are left out.
pub fn summary_lines(entry: &Entry, plan: &RunPlan, except: &[&str]) -> String {
    let listed: Vec<String> = overrides(entry, plan, except)
        .iter()
        .map(|o| {
            format!(
                "{} = {} (default {})",
                o.name,
                format_value(&o.value),
                format_value(&o.default)
            )
        })
        .collect();
    let mut lines = format!(
        "overrides      {}\n",
        if listed.is_empty() {
            "none".to_owned()
        } else {
            listed.join(", ")
        }
    );
    if let (false, Ok((declared, used))) = (plan.initial.is_empty(), initial_states(entry, plan)) {
        let names = entry.model.state_names();
        let states: Vec<String> = plan
            .initial
            .iter()
            .map(|&(i, _)| {
                format!(
                    "{} = {} (declared {})",
                    names[i],
                    format_value(&Value::from(used[i])),
                    format_value(&Value::from(declared[i]))
                )
            })
            .collect();
        lines.push_str(&format!("initial        {}\n", states.join(", ")));
    }
    lines
}
