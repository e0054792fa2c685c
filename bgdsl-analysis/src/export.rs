//! A linear model as files other tools read: `linear.json` (the keys issue 16 fixes:
//! `states`, `inputs`, `outputs`, `x`, `u`, `t`, `A`, `B`, `C`, `D` as lists of rows),
//! one CSV per matrix (labelled rows and columns), and a MATLAB/Octave script that
//! defines the same matrices and names (`run linear.m`, then `ss(A, B, C, D)`).
//!
//! Numbers are written with Rust's shortest round-trip form, so reading them back gives
//! the same `f64`s; a non-finite entry is `null` in JSON, `NaN`/`Inf` in CSV and MATLAB.

use std::fmt::Write as _;

use nalgebra::DMatrix;

use crate::linear::LinearModel;
use crate::modes::Mode;

/// A number as JSON: shortest round-trip digits, `null` when not finite.
fn json_number(v: f64) -> String {
    if v.is_finite() {
        format!("{v:?}")
    } else {
        "null".to_string()
    }
}

/// A string as JSON.
fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn json_list<T>(items: &[T], each: impl Fn(&T) -> String) -> String {
    let inner: Vec<String> = items.iter().map(each).collect();
    format!("[{}]", inner.join(", "))
}

fn json_rows(m: &DMatrix<f64>) -> String {
    let rows: Vec<String> = m
        .row_iter()
        .map(|row| {
            let v: Vec<f64> = row.iter().copied().collect();
            json_list(&v, |x| json_number(*x))
        })
        .collect();
    if rows.is_empty() {
        "[]".to_string()
    } else {
        format!("[\n    {}\n  ]", rows.join(",\n    "))
    }
}

/// `linear.json`: names, operating point, matrices as lists of rows, and (beyond the
/// fixed keys) the model, the units, how `B` and `D` were computed, and the modes.
pub fn linear_json(linear: &LinearModel, modes: &[Mode]) -> String {
    let strings = |v: &[String]| json_list(v, |s| json_string(s));
    let numbers = |v: &[f64]| json_list(v, |x| json_number(*x));
    let mode_entries: Vec<String> = modes
        .iter()
        .map(|m| {
            let dominant: Vec<String> = m.dominant.iter().map(|&i| linear.states[i].clone()).collect();
            format!(
                "{{\"eigenvalue\": [{}, {}], \"natural_frequency\": {}, \"damping_ratio\": {}, \"dominant_states\": {}}}",
                json_number(m.eigenvalue.re),
                json_number(m.eigenvalue.im),
                json_number(m.natural_frequency),
                json_number(m.damping_ratio),
                strings(&dominant)
            )
        })
        .collect();
    format!(
        "{{\n  \"model\": {},\n  \"states\": {},\n  \"inputs\": {},\n  \"outputs\": {},\n  \
         \"state_units\": {},\n  \"input_units\": {},\n  \"output_units\": {},\n  \
         \"t\": {},\n  \"x\": {},\n  \"u\": {},\n  \"A\": {},\n  \"B\": {},\n  \"C\": {},\n  \
         \"D\": {},\n  \"derivatives\": {},\n  \"modes\": [{}]\n}}\n",
        json_string(&linear.model),
        strings(&linear.states),
        strings(&linear.inputs),
        strings(&linear.outputs),
        strings(&linear.state_units),
        strings(&linear.input_units),
        strings(&linear.output_units),
        json_number(linear.t),
        numbers(&linear.x),
        numbers(&linear.u),
        json_rows(&linear.a),
        json_rows(&linear.b),
        json_rows(&linear.c),
        json_rows(&linear.d),
        json_string(linear.method.describe()),
        if mode_entries.is_empty() {
            String::new()
        } else {
            format!("\n    {}\n  ", mode_entries.join(",\n    "))
        }
    )
}

/// A CSV field, quoted when it needs to be.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// One matrix as CSV: a header of column names (after an empty corner), then one row
/// per row name.
pub fn matrix_csv(m: &DMatrix<f64>, rows: &[String], columns: &[String]) -> String {
    let mut out = String::new();
    let header: Vec<String> = std::iter::once(String::new())
        .chain(columns.iter().map(|c| csv_field(c)))
        .collect();
    out.push_str(&header.join(","));
    out.push('\n');
    for (i, name) in rows.iter().enumerate() {
        out.push_str(&csv_field(name));
        for j in 0..m.ncols() {
            let _ = write!(out, ",{:?}", m[(i, j)]);
        }
        out.push('\n');
    }
    out
}

/// The four CSV files of a linear model: `(file name, contents)` for `A.csv` …
/// `D.csv`.
pub fn matrix_csvs(linear: &LinearModel) -> [(&'static str, String); 4] {
    [
        (
            "A.csv",
            matrix_csv(&linear.a, &linear.states, &linear.states),
        ),
        (
            "B.csv",
            matrix_csv(&linear.b, &linear.states, &linear.inputs),
        ),
        (
            "C.csv",
            matrix_csv(&linear.c, &linear.outputs, &linear.states),
        ),
        (
            "D.csv",
            matrix_csv(&linear.d, &linear.outputs, &linear.inputs),
        ),
    ]
}

fn matlab_number(v: f64) -> String {
    match v {
        v if v.is_nan() => "NaN".to_string(),
        v if v.is_infinite() => if v > 0.0 { "Inf" } else { "-Inf" }.to_string(),
        v => format!("{v:?}"),
    }
}

fn matlab_matrix(name: &str, m: &DMatrix<f64>) -> String {
    if m.nrows() == 0 || m.ncols() == 0 {
        return format!("{name} = zeros({}, {});\n", m.nrows(), m.ncols());
    }
    let rows: Vec<String> = m
        .row_iter()
        .map(|row| {
            row.iter()
                .map(|v| matlab_number(*v))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    format!("{name} = [\n  {}\n];\n", rows.join(";\n  "))
}

fn matlab_names(name: &str, names: &[String]) -> String {
    let quoted: Vec<String> = names
        .iter()
        .map(|n| format!("'{}'", n.replace('\'', "''")))
        .collect();
    format!("{name} = {{{}}};\n", quoted.join(", "))
}

/// A MATLAB/Octave script defining `A`, `B`, `C`, `D`, the names `states`, `inputs`,
/// `outputs` (cell arrays) and the operating point `x`, `u`, `t`.
pub fn linear_m(linear: &LinearModel) -> String {
    let column = |name: &str, v: &[f64]| {
        let m = DMatrix::from_column_slice(v.len(), 1, v);
        matlab_matrix(name, &m)
    };
    let mut out = format!(
        "% Linear model of {} at t = {:?}: dx/dt = A dx + B du, dy = C dx + D du.\n\
         % Derivatives: {}. Written by bgdsl; sys = ss(A, B, C, D) in the Control toolbox.\n",
        linear.model,
        linear.t,
        linear.method.describe()
    );
    out.push_str(&matlab_names("states", &linear.states));
    out.push_str(&matlab_names("inputs", &linear.inputs));
    out.push_str(&matlab_names("outputs", &linear.outputs));
    let _ = writeln!(out, "t = {};", matlab_number(linear.t));
    out.push_str(&column("x", &linear.x));
    out.push_str(&column("u", &linear.u));
    out.push_str(&matlab_matrix("A", &linear.a));
    out.push_str(&matlab_matrix("B", &linear.b));
    out.push_str(&matlab_matrix("C", &linear.c));
    out.push_str(&matlab_matrix("D", &linear.d));
    out
}
