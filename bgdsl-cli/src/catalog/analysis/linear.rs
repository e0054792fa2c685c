//! `models linearize` (and the linear model behind `models bode`): `A`, `B`, `C`, `D`
//! of a catalogue model at an [`OperatingPoint`], exact by dual numbers
//! ([`bgdsl_analysis::linearize`]), from declared inputs or parameters
//! ([`Channel`]), to all or some outputs.

use bgdsl_analysis::export::{linear_json, linear_m, matrix_csvs};
use bgdsl_analysis::{linearize as linearize_at, modes, Channel, LinearModel, Mode};
use bgdsl_runtime::{FromParams, WithInputs};
use serde::de::DeserializeOwned;
use serde_yaml::{Mapping, Value};

use super::steady::{model, solve, SteadyRequest};
use super::{html, initial, state_at_time, AnalysisFailure, AnalysisSet, DataFile, Figure};
use super::{OperatingPoint, StateAt};
use crate::catalog::{format_significant, Entry, RunPlan};
use crate::plot::{ChartOptions, LineChart, Series, SeriesStyle, PALETTE};

/// What a linear model is asked of.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinearRequest {
    /// Where: the initial state, the equilibrium, or the state of a run at a time.
    pub at: OperatingPoint,
    /// For [`OperatingPoint::Steady`]: the equilibrium's guess, held states and
    /// settings.
    pub steady: SteadyRequest,
    /// The inputs, by name: declared inputs or scalar parameters (a vector
    /// parameter's component as `name[i]`); empty: every declared input.
    pub inputs: Vec<String>,
    /// The outputs, by name; empty: every output.
    pub outputs: Vec<String>,
}

/// The state at `at` of `model` run by `plan`.
pub(crate) fn operating_point<M: WithInputs>(
    model: &M,
    plan: &RunPlan,
    at: OperatingPoint,
    steady: &SteadyRequest,
) -> Result<StateAt, AnalysisFailure> {
    match at {
        OperatingPoint::Initial => Ok(initial(model, plan)),
        OperatingPoint::Steady => {
            let found = solve(model, plan, steady)?;
            Ok(StateAt {
                t: found.t,
                x: found.x,
            })
        }
        OperatingPoint::Time(t) => state_at_time(model, plan, t),
    }
}

/// The generic body of
/// [`CatalogModel::linearize`](crate::catalog::CatalogModel::linearize).
pub(crate) fn linearize<M>(
    plan: &RunPlan,
    request: &LinearRequest,
) -> Result<LinearModel, AnalysisFailure>
where
    M: FromParams + WithInputs + Clone,
    M::Params: DeserializeOwned,
{
    let model = model::<M>(plan)?;
    let channels: Vec<Channel> = if request.inputs.is_empty() {
        (0..M::INPUTS.len()).map(Channel::Input).collect()
    } else {
        request
            .inputs
            .iter()
            .map(|name| Channel::named::<M>(name))
            .collect::<Result<_, _>>()?
    };
    let point = operating_point(&model, plan, request.at, &request.steady)?;
    let full = linearize_at(&model, point.t, &point.x, &channels)?;
    select_outputs(full, &request.outputs)
}

/// `linear` with only the outputs `names` (rows of `C` and `D`), in that order; all of
/// them when `names` is empty.
///
/// # Errors
///
/// [`AnalysisFailure::Usage`] for an unknown output.
pub fn select_outputs(
    linear: LinearModel,
    names: &[String],
) -> Result<LinearModel, AnalysisFailure> {
    if names.is_empty() {
        return Ok(linear);
    }
    let rows: Vec<usize> = names
        .iter()
        .map(|n| linear.output_index(n))
        .collect::<Result<_, _>>()?;
    Ok(LinearModel {
        outputs: rows.iter().map(|&i| linear.outputs[i].clone()).collect(),
        output_units: rows
            .iter()
            .map(|&i| linear.output_units[i].clone())
            .collect(),
        c: linear.c.select_rows(&rows),
        d: linear.d.select_rows(&rows),
        ..linear
    })
}

/// The modes table's file.
pub const MODES_FILE: &str = "modes.csv";

/// The eigenvalue-plane figure's id.
pub const EIGENVALUE_FIGURE: &str = "eigenvalues";

/// What the eigenvalues say about stability.
fn stability(modes: &[Mode]) -> &'static str {
    let largest = modes
        .iter()
        .map(|m| m.eigenvalue.re)
        .fold(f64::NEG_INFINITY, f64::max);
    let scale = modes
        .iter()
        .map(|m| m.natural_frequency)
        .fold(0.0f64, f64::max);
    if modes.is_empty() {
        "no states"
    } else if largest > 1e-9 * scale {
        "unstable (an eigenvalue in the right half-plane)"
    } else if largest >= -1e-9 * scale {
        "marginal (an eigenvalue on the imaginary axis, within 1e-9 of the largest |λ|)"
    } else {
        "asymptotically stable (every eigenvalue in the left half-plane)"
    }
}

/// `modes.csv`: one row per eigenvalue (a complex pair once, with positive imaginary
/// part), with natural frequency, damping ratio and dominant states.
pub fn modes_csv(linear: &LinearModel, modes: &[Mode]) -> String {
    let mut out = String::from(
        "real_per_s,imag_rad_per_s,natural_frequency_rad_per_s,natural_frequency_hz,\
         damping_ratio,dominant_states\n",
    );
    for m in modes {
        let dominant: Vec<&str> = m
            .dominant
            .iter()
            .map(|&i| linear.states[i].as_str())
            .collect();
        out.push_str(&format!(
            "{:?},{:?},{:?},{:?},{:?},\"{}\"\n",
            m.eigenvalue.re,
            m.eigenvalue.im,
            m.natural_frequency,
            m.natural_frequency / (2.0 * core::f64::consts::PI),
            m.damping_ratio,
            dominant.join(" ")
        ));
    }
    out
}

/// The eigenvalues in the complex plane, each a cross (both members of a pair).
fn eigenvalue_figure(linear: &LinearModel, modes: &[Mode]) -> Figure {
    let points: Vec<(f64, f64)> = modes
        .iter()
        .flat_map(|m| {
            let l = m.eigenvalue;
            if l.im > 0.0 {
                vec![(l.re, l.im), (l.re, -l.im)]
            } else {
                vec![(l.re, l.im)]
            }
        })
        .collect();
    // The imaginary axis is always in view; the real one too.
    let x_lo = points.iter().map(|p| p.0).fold(0.0f64, f64::min);
    let x_hi = points.iter().map(|p| p.0).fold(0.0f64, f64::max);
    let x_span = (x_hi - x_lo).max(1e-12);
    let x_range = (x_lo - 0.1 * x_span, x_hi + 0.1 * x_span);
    let y_extent = match points.iter().map(|p| p.1.abs()).fold(0.0f64, f64::max) {
        y if y > 0.0 => y,
        _ => 0.5 * x_span,
    };
    let range = (-1.15 * y_extent, 1.15 * y_extent);
    // Crosses of a fixed fraction of the plot each way, two strokes between gaps.
    let dx = 0.012 * (x_range.1 - x_range.0);
    let dy = 0.02 * (range.1 - range.0);
    let mut crosses = Vec::new();
    for &(x, y) in &points {
        crosses.extend([
            (x - dx, y - dy),
            (x + dx, y + dy),
            (f64::NAN, f64::NAN),
            (x - dx, y + dy),
            (x + dx, y - dy),
            (f64::NAN, f64::NAN),
        ]);
    }
    let axis = |from: (f64, f64), to: (f64, f64)| vec![from, to];
    Figure {
        id: EIGENVALUE_FIGURE.to_owned(),
        title: format!("Eigenvalues of A: {}", linear.model),
        caption: format!(
            "The {} eigenvalues of the linear model's A in the complex plane (×), with the \
             axes; left of the imaginary axis is stable. Natural frequency |λ|, damping \
             ratio −Re λ/|λ|: see {MODES_FILE}.",
            points.len()
        ),
        chart: LineChart {
            title: format!("Eigenvalues of A ({}, t = {} s)", linear.model, linear.t),
            x_label: "Re λ (1/s)".to_owned(),
            y_label: "Im λ (rad/s)".to_owned(),
            series: vec![
                Series::new("eigenvalue", crosses),
                Series::new("axes", {
                    let mut a = axis((x_range.0, 0.0), (x_range.1, 0.0));
                    a.push((f64::NAN, f64::NAN));
                    a.extend(axis((0.0, range.0), (0.0, range.1)));
                    a
                }),
            ],
        },
        options: ChartOptions {
            x_range: Some(x_range),
            y_range: Some(range),
            styles: vec![
                SeriesStyle::solid(PALETTE[2]),
                SeriesStyle::dashed((128, 128, 128)),
            ],
            ..ChartOptions::default()
        },
    }
}

/// The results set of `models linearize`: `linear.json`, `A.csv`–`D.csv`,
/// `linear.m`, `modes.csv`, the eigenvalue plane.
pub fn results_set(entry: &Entry, at: OperatingPoint, linear: &LinearModel) -> AnalysisSet {
    let modes = modes(&linear.a);
    let mut files = vec![DataFile::new("linear.json", linear_json(linear, &modes))];
    for (name, text) in matrix_csvs(linear) {
        files.push(DataFile::new(name, text));
    }
    files.push(DataFile::new("linear.m", linear_m(linear)));
    files.push(DataFile::new(MODES_FILE, modes_csv(linear, &modes)));

    let mut summary = format!(
        "model          {}: {}\noperating pt   {} (t = {} s)\nlinear model   {} states, {} \
         inputs, {} outputs; A and C exact (dual numbers), B and D {}\nstability      {}\n",
        entry.name,
        entry.description,
        at,
        linear.t,
        linear.states.len(),
        linear.inputs.len(),
        linear.outputs.len(),
        linear.method.describe(),
        stability(&modes)
    );
    if !linear.inputs.is_empty() {
        summary.push_str(&format!("inputs         {}\n", linear.inputs.join(", ")));
    }
    if !linear.outputs.is_empty() {
        summary.push_str(&format!("outputs        {}\n", linear.outputs.join(", ")));
    }
    summary.push_str(
        "modes          eigenvalue (1/s)                    ωn (rad/s)   f (Hz)       ζ        dominant states\n",
    );
    let mut rows = String::new();
    for m in &modes {
        let l = m.eigenvalue;
        let eigenvalue = if l.im == 0.0 {
            format_significant(l.re)
        } else {
            format!(
                "{} ± {}i",
                format_significant(l.re),
                format_significant(l.im)
            )
        };
        let dominant: Vec<&str> = m
            .dominant
            .iter()
            .map(|&i| linear.states[i].as_str())
            .collect();
        let hz = m.natural_frequency / (2.0 * core::f64::consts::PI);
        summary.push_str(&format!(
            "               {eigenvalue:<35} {:<12} {:<12} {:<8} {}\n",
            format_significant(m.natural_frequency),
            format_significant(hz),
            format_significant(m.damping_ratio),
            dominant.join(", ")
        ));
        rows.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            html(&eigenvalue),
            format_significant(m.natural_frequency),
            format_significant(hz),
            format_significant(m.damping_ratio),
            html(&dominant.join(", "))
        ));
    }
    summary
        .push_str("results        linear.json, A.csv, B.csv, C.csv, D.csv, linear.m, modes.csv\n");
    let section = format!(
        "<h2>Modes</h2>\n<p>Eigenvalues of A (a complex pair once), natural frequency \
         ω<sub>n</sub> = |λ|, damping ratio ζ = −Re λ/|λ|, and the states with the largest \
         participation factors. {}.</p>\n<table>\n<tr><th>eigenvalue (1/s)</th><th>ω<sub>n</sub> \
         (rad/s)</th><th>f<sub>n</sub> (Hz)</th><th>ζ</th><th>dominant states</th></tr>\n{rows}\
         </table>\n",
        html(stability(&modes))
    );
    let mut record = Mapping::new();
    record.insert(Value::from("at"), Value::from(at.to_string()));
    record.insert(Value::from("t"), Value::from(linear.t));
    let strings =
        |v: &[String]| Value::Sequence(v.iter().map(|s| Value::from(s.as_str())).collect());
    record.insert(Value::from("inputs"), strings(&linear.inputs));
    record.insert(Value::from("outputs"), strings(&linear.outputs));
    record.insert(
        Value::from("eigenvalues"),
        Value::Sequence(
            modes
                .iter()
                .map(|m| {
                    Value::Sequence(vec![
                        Value::from(m.eigenvalue.re),
                        Value::from(m.eigenvalue.im),
                    ])
                })
                .collect(),
        ),
    );
    AnalysisSet {
        command: "linearize",
        summary,
        files,
        figures: if modes.is_empty() {
            Vec::new()
        } else {
            vec![eigenvalue_figure(linear, &modes)]
        },
        sections: vec![section],
        record,
    }
}
