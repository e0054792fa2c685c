//! Physical validation of parameters: what a problem is, and the small vocabulary the
//! models' checks are written in.

use core::fmt;

use bgdsl_runtime::ParameterInfo;
use serde_yaml::{Mapping, Value};

use super::params::format_number;

/// Something wrong with a model's parameters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// The parameters at fault, the most likely culprit first (callers point at the
    /// first of them that the user set).
    pub keys: Vec<String>,
    /// What is wrong, as a sentence fragment that names the parameter(s).
    pub message: String,
}

impl Problem {
    /// A problem with the parameters `keys`.
    pub fn new(keys: &[&str], message: String) -> Self {
        Problem {
            keys: keys.iter().map(|k| (*k).to_owned()).collect(),
            message,
        }
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// Collects the problems of one set of parameters; each check names the parameter, its
/// meaning and unit (from [`ParameterInfo`]) and the value found.
#[derive(Debug)]
pub struct Checks {
    infos: &'static [ParameterInfo],
    problems: Vec<Problem>,
}

impl Checks {
    /// No problems yet, for a model with these parameters.
    pub fn new(infos: &'static [ParameterInfo]) -> Self {
        Checks {
            infos,
            problems: Vec::new(),
        }
    }

    /// The number of problems found so far.
    pub fn count(&self) -> usize {
        self.problems.len()
    }

    /// The problems found so far.
    pub fn problems(&self) -> &[Problem] {
        &self.problems
    }

    /// The problems found.
    pub fn into_problems(self) -> Vec<Problem> {
        self.problems
    }

    /// `parameter `m1` (crank mass, kg)`.
    pub fn label(&self, name: &str) -> String {
        let info = self.infos.iter().find(|p| p.name == name);
        let doc = info
            .map(|p| p.doc.split_whitespace().collect::<Vec<_>>().join(" "))
            .unwrap_or_default();
        let unit = info.map(|p| p.unit).unwrap_or("");
        match (doc.is_empty(), unit.is_empty()) {
            (false, false) => format!("parameter `{name}` ({doc}, {unit})"),
            (false, true) => format!("parameter `{name}` ({doc})"),
            (true, false) => format!("parameter `{name}` ({unit})"),
            (true, true) => format!("parameter `{name}`"),
        }
    }

    /// Records a problem with `keys`.
    pub fn problem(&mut self, keys: &[&str], message: String) {
        self.problems.push(Problem::new(keys, message));
    }

    fn compare(&mut self, name: &str, value: f64, ok: bool, expected: &str) {
        if !ok {
            let message = format!(
                "{} must be {expected}, found {}",
                self.label(name),
                format_number(value)
            );
            self.problem(&[name], message);
        }
    }

    /// `value > 0`: masses, inertias, inductances, capacitances.
    pub fn positive(&mut self, name: &str, value: f64) {
        self.compare(name, value, value > 0.0, "> 0");
    }

    /// `value >= 0`: stiffnesses, dampings, resistances.
    pub fn non_negative(&mut self, name: &str, value: f64) {
        self.compare(name, value, value >= 0.0, ">= 0");
    }

    /// Every component `>= 0`.
    pub fn non_negative_each(&mut self, name: &str, values: &[f64]) {
        if let Some((i, v)) = values
            .iter()
            .enumerate()
            .find(|(_, v)| v.is_nan() || **v < 0.0)
        {
            let message = format!(
                "every component of {} must be >= 0, found {} at index {i}",
                self.label(name),
                format_number(*v)
            );
            self.problem(&[name], message);
        }
    }

    /// `value` is one of `allowed` (a switch).
    pub fn one_of(&mut self, name: &str, value: f64, allowed: &[f64]) {
        if !allowed.contains(&value) {
            let list: Vec<String> = allowed.iter().map(|v| format_number(*v)).collect();
            let message = format!(
                "{} must be one of {}, found {}",
                self.label(name),
                list.join(", "),
                format_number(value)
            );
            self.problem(&[name], message);
        }
    }

    /// Every number in `params` is finite (not NaN, not infinite).
    pub fn finite(&mut self, params: &Mapping) {
        for (key, value) in params {
            let name = key.as_str().unwrap_or("?");
            if !all_finite(value) {
                let message = format!(
                    "{} must be finite, found {}",
                    self.label(name),
                    super::format_value(value)
                );
                self.problem(&[name], message);
            }
        }
    }
}

fn all_finite(value: &Value) -> bool {
    match value {
        Value::Number(n) => n.as_f64().is_some_and(f64::is_finite),
        Value::Sequence(items) => items.iter().all(all_finite),
        _ => true,
    }
}
