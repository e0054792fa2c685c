//! `models bode`: frequency responses `H(jω) = C (jωI − A)⁻¹ B + D` of a linear model
//! ([`bgdsl_analysis::frequency_response`]) from each input to each output, on a
//! logarithmic grid of frequencies given in hertz; `bode.csv` and the magnitude and
//! phase figures.

use core::f64::consts::PI;

use bgdsl_analysis::{frequency_response, log_grid, modes, FrequencyResponse, LinearModel};
use serde_yaml::{Mapping, Value};

use super::{html, AnalysisSet, DataFile, Figure, OperatingPoint};
use crate::catalog::{format_number, format_significant, Entry};
use crate::plot::{ChartOptions, LineChart, Series, Tick};

/// The file of the responses.
pub const FILE_NAME: &str = "bode.csv";

/// The default number of frequencies.
pub const DEFAULT_POINTS: usize = 200;

/// The frequency band of a Bode diagram, Hz.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// The lowest frequency, Hz, > 0.
    pub from: f64,
    /// The highest frequency, Hz, > `from`.
    pub to: f64,
    /// The number of frequencies, at least 2, spaced evenly in logarithm.
    pub points: usize,
}

impl Band {
    /// The frequencies, Hz: `from` and `to` exactly, the others evenly in logarithm.
    pub fn hertz(&self) -> Vec<f64> {
        let mut hz = log_grid(self.from, self.to, self.points);
        if let Some(first) = hz.first_mut() {
            *first = self.from;
        }
        if self.points > 1 {
            if let Some(last) = hz.last_mut() {
                *last = self.to;
            }
        }
        hz
    }

    /// The angular frequencies `2π f`, rad/s.
    pub fn omega(&self) -> Vec<f64> {
        self.hertz().iter().map(|f| 2.0 * PI * f).collect()
    }

    /// Checks the band: positive, increasing, finite, at least two points.
    ///
    /// # Errors
    ///
    /// A sentence saying what is wrong.
    pub fn check(&self) -> Result<(), String> {
        if !(self.from.is_finite() && self.to.is_finite() && self.from > 0.0) {
            return Err(format!(
                "the frequencies must be finite and > 0 Hz (--from {}, --to {})",
                self.from, self.to
            ));
        }
        if self.to <= self.from {
            return Err(format!(
                "--to ({} Hz) must be above --from ({} Hz)",
                self.to, self.from
            ));
        }
        if self.points < 2 {
            return Err(format!("--points must be at least 2 (got {})", self.points));
        }
        Ok(())
    }
}

/// The default band of `linear`: from a decade below its slowest non-zero mode to a
/// decade above its fastest, widened to whole decades; 0.01–100 Hz when every
/// eigenvalue is zero (or there are no states).
pub fn default_band(linear: &LinearModel, points: usize) -> Band {
    let hz: Vec<f64> = modes(&linear.a)
        .iter()
        .map(|m| m.natural_frequency / (2.0 * PI))
        .filter(|f| f.is_finite() && *f > 0.0)
        .collect();
    let (lo, hi) = match (
        hz.iter().copied().reduce(f64::min),
        hz.iter().copied().reduce(f64::max),
    ) {
        (Some(lo), Some(hi)) => (lo / 10.0, hi * 10.0),
        _ => (0.01, 100.0),
    };
    Band {
        from: 10f64.powf(lo.log10().floor()),
        to: 10f64.powf(hi.log10().ceil()),
        points,
    }
}

/// The response from every input to every output of `linear` over `band`, input by
/// input.
pub fn responses(linear: &LinearModel, band: &Band) -> Vec<FrequencyResponse> {
    let omega = band.omega();
    let mut out = Vec::new();
    for input in 0..linear.inputs.len() {
        for output in 0..linear.outputs.len() {
            out.push(frequency_response(linear, input, output, &omega));
        }
    }
    out
}

/// A pair's name: `output/input`.
fn pair(r: &FrequencyResponse) -> String {
    format!("{}/{}", r.output, r.input)
}

/// A pair's unit: `A/V`, `1/V` or `` (both undeclared).
fn pair_unit(r: &FrequencyResponse) -> String {
    match (r.output_unit.as_str(), r.input_unit.as_str()) {
        ("", "") => String::new(),
        (out, "") => out.to_owned(),
        ("", input) => format!("1/{input}"),
        (out, input) => format!("{out}/{input}"),
    }
}

/// `bode.csv`: `frequency_hz`, `omega_rad_per_s`, then for each pair `Y/U_db` (the
/// magnitude `20 log₁₀ |H|` in dB re one output unit per input unit) and `Y/U_deg`
/// (the phase, unwrapped along the grid).
pub fn bode_csv(band: &Band, responses: &[FrequencyResponse]) -> String {
    let mut out = String::from("frequency_hz,omega_rad_per_s");
    for r in responses {
        let name = pair(r);
        let quoted = |suffix: &str| {
            let field = format!("{name}_{suffix}");
            if field.contains([',', '"']) {
                format!("\"{}\"", field.replace('"', "\"\""))
            } else {
                field
            }
        };
        out.push(',');
        out.push_str(&quoted("db"));
        out.push(',');
        out.push_str(&quoted("deg"));
    }
    out.push('\n');
    let columns: Vec<(Vec<f64>, Vec<f64>)> = responses
        .iter()
        .map(|r| (r.magnitude_db(), r.phase_deg()))
        .collect();
    for (k, (hz, omega)) in band.hertz().iter().zip(band.omega()).enumerate() {
        out.push_str(&format!("{hz:?},{omega:?}"));
        for (db, deg) in &columns {
            out.push_str(&format!(",{:?},{:?}", db[k], deg[k]));
        }
        out.push('\n');
    }
    out
}

/// Ticks at the decades of `[from, to]` Hz on a `log₁₀ f` axis (with 2 and 5 between
/// them when the band spans fewer than three decades).
fn decade_ticks(from: f64, to: f64) -> Vec<Tick> {
    let (lo, hi) = (from.log10(), to.log10());
    let steps: &[f64] = if hi - lo < 3.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let mut ticks = Vec::new();
    for decade in (lo.floor() as i32)..=(hi.ceil() as i32) {
        for &m in steps {
            let f = m * 10f64.powi(decade);
            let x = f.log10();
            if x >= lo - 1e-9 && x <= hi + 1e-9 {
                ticks.push(Tick::new(x, format_number(f)));
            }
        }
    }
    ticks
}

/// The magnitude or the phase of every pair against `log₁₀ f`.
fn figure(responses: &[FrequencyResponse], band: &Band, magnitude: bool) -> Figure {
    let series = responses
        .iter()
        .map(|r| {
            let values = if magnitude {
                r.magnitude_db()
            } else {
                r.phase_deg()
            };
            let points = band
                .hertz()
                .iter()
                .zip(values)
                .map(|(f, v)| (f.log10(), if v.is_finite() { v } else { f64::NAN }))
                .collect();
            let unit = pair_unit(r);
            let label = match (magnitude, unit.is_empty()) {
                (true, false) => format!("{} (dB re 1 {unit})", pair(r)),
                _ => pair(r),
            };
            Series::new(label, points)
        })
        .collect();
    let units: Vec<String> = responses.iter().map(pair_unit).collect();
    let same_unit = units.windows(2).all(|w| w[0] == w[1]);
    let (id, title, y_label) = if magnitude {
        let y_label = match units.first() {
            Some(u) if same_unit && !u.is_empty() => format!("magnitude 20 log₁₀|H| (dB re 1 {u})"),
            _ => "magnitude 20 log₁₀|H| (dB)".to_owned(),
        };
        ("bode_magnitude", "Bode diagram: magnitude", y_label)
    } else {
        (
            "bode_phase",
            "Bode diagram: phase",
            "phase ∠H (°)".to_owned(),
        )
    };
    Figure {
        id: id.to_owned(),
        title: title.to_owned(),
        caption: format!(
            "{} of H(jω) = C (jωI − A)⁻¹ B + D for {} at {} frequencies from {} Hz to {} Hz, \
             spaced evenly in logarithm (the x axis is logarithmic: ticks in Hz).{}",
            if magnitude {
                "The magnitude 20 log₁₀|H|"
            } else {
                "The phase (unwrapped along the frequencies)"
            },
            responses.iter().map(pair).collect::<Vec<_>>().join(", "),
            band.points,
            format_number(band.from),
            format_number(band.to),
            if magnitude && !same_unit {
                " Each pair's dB are relative to one of its own units (legend)."
            } else {
                ""
            }
        ),
        chart: LineChart {
            title: title.to_owned(),
            x_label: "frequency f (Hz)".to_owned(),
            y_label,
            series,
        },
        options: ChartOptions {
            x_range: Some((band.from.log10(), band.to.log10())),
            x_ticks: Some(decade_ticks(band.from, band.to)),
            ..ChartOptions::default()
        },
    }
}

/// The results set of `models bode`: `bode.csv`, the magnitude and phase figures.
pub fn results_set(
    entry: &Entry,
    at: OperatingPoint,
    linear: &LinearModel,
    band: &Band,
    responses: &[FrequencyResponse],
) -> AnalysisSet {
    let mut summary = format!(
        "model          {}: {}\noperating pt   {} (t = {} s); B and D {}\nfrequencies    {} from \
         {} Hz to {} Hz (log spaced)\n",
        entry.name,
        entry.description,
        at,
        linear.t,
        linear.method.describe(),
        band.points,
        format_number(band.from),
        format_number(band.to)
    );
    let mut rows = String::new();
    for r in responses {
        let db = r.magnitude_db();
        let (k, peak) = db
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
        let hz = band.hertz();
        let unit = pair_unit(r);
        let line = format!(
            "{}: {} dB at {} Hz (lowest), peak {} dB at {} Hz{}",
            pair(r),
            format_significant(db[0]),
            format_significant(hz[0]),
            format_significant(peak),
            format_significant(hz[k]),
            if unit.is_empty() {
                String::new()
            } else {
                format!(" (dB re 1 {unit})")
            }
        );
        summary.push_str(&format!("response       {line}\n"));
        rows.push_str(&format!("<li>{}</li>\n", html(&line)));
    }
    summary.push_str(&format!("results        {FILE_NAME}\n"));
    let section = format!(
        "<h2>Frequency responses</h2>\n<p>At the operating point {} (t = {} s). The \
         numbers are in {FILE_NAME} (frequency in Hz and rad/s, magnitude in dB, phase in \
         degrees).</p>\n<ul>\n{rows}</ul>\n",
        html(&at.to_string()),
        linear.t
    );
    let mut record = Mapping::new();
    record.insert(Value::from("at"), Value::from(at.to_string()));
    record.insert(Value::from("t"), Value::from(linear.t));
    record.insert(Value::from("from_hz"), Value::from(band.from));
    record.insert(Value::from("to_hz"), Value::from(band.to));
    record.insert(Value::from("points"), Value::from(band.points as u64));
    record.insert(
        Value::from("pairs"),
        Value::Sequence(responses.iter().map(|r| Value::from(pair(r))).collect()),
    );
    AnalysisSet {
        command: "bode",
        summary,
        files: vec![DataFile::new(FILE_NAME, bode_csv(band, responses))],
        figures: if responses.is_empty() {
            Vec::new()
        } else {
            vec![
                figure(responses, band, true),
                figure(responses, band, false),
            ]
        },
        sections: vec![section],
        record,
    }
}
