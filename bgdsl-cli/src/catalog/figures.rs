//! The catalogue's calls into the plotting modules: one chart per output against time,
//! the sweep's charts (all with [`crate::plot`]), and `index.html` ([`crate::report`]).
//! Every image is written in PNG and SVG.

pub(super) mod energy;
mod energy_chart;
pub(super) mod generic;
pub(super) mod graph;
pub(super) mod phase;
pub(super) mod states;

use std::path::{Path, PathBuf};

use super::columns::{column_unit, Table};
use super::params::format_number;
use super::sweep::SweepShape;
use super::{Entry, Plots, RunError};
use crate::plot::{draw_line_chart, ImageFormat, LineChart, PlotError, Series};
use crate::report::{write_index, DrawnFigure};

/// An image that cannot be drawn or written (a full disk: the PNG encoder reports it as
/// a drawing error) is an I/O error, and the set is abandoned; any other failure (no
/// font) leaves the results and the index without figures.
pub fn plot_error(e: PlotError) -> RunError {
    match e {
        PlotError::Io {
            path,
            action,
            source,
        } => RunError::Io {
            path,
            action,
            source,
        },
        PlotError::Draw { path, message } => RunError::Io {
            path,
            action: "drawing",
            source: std::io::Error::other(message),
        },
        other => RunError::Figures(other.to_string()),
    }
}

/// An error once a signal asked the program to stop ([`crate::interrupt`]): drawing
/// stops between charts.
pub(super) fn stop_if_interrupted() -> Result<(), RunError> {
    if crate::interrupt::requested() {
        Err(plot_error(PlotError::Interrupted))
    } else {
        Ok(())
    }
}

/// A file name from a column name: letters, digits, `_` and `-` kept, the rest `_`.
pub(super) fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// An axis label: `name (unit)`, or the bare name where the unit is not known.
pub(super) fn with_unit(name: &str, unit: &str) -> String {
    if unit.is_empty() {
        name.to_owned()
    } else {
        format!("{name} ({unit})")
    }
}

/// One chart per recorded output (or per chosen output) against time.
pub(super) fn trajectory(
    entry: &Entry,
    table: &Table,
    dir: &Path,
    plots: &Plots,
) -> Result<Vec<DrawnFigure>, RunError> {
    let outputs = entry.model.output_names();
    let mut drawn = Vec::new();
    for (name, values) in table.columns() {
        let wanted = match plots {
            // A state named in `plots` is drawn by `states`, not here.
            Plots::Only(ids) => outputs.contains(&name) && ids.iter().any(|id| id == name),
            _ => outputs.contains(&name),
        };
        if !wanted || table.len() < 2 {
            continue;
        }
        stop_if_interrupted()?;
        let chart = LineChart {
            title: format!(
                "{} ({}): {name} against time",
                entry.model.type_name(),
                entry.name
            ),
            x_label: "time t (s)".to_owned(),
            y_label: with_unit(name, column_unit(&*entry.model, name).0),
            series: vec![Series::new(
                name,
                table
                    .times()
                    .iter()
                    .copied()
                    .zip(values.iter().copied())
                    .collect(),
            )],
        };
        let files = draw_line_chart(&chart, &dir.join(file_stem(name)), &ImageFormat::ALL)
            .map_err(plot_error)?;
        drawn.push(DrawnFigure {
            id: name.to_owned(),
            title: chart.title,
            caption: format!("Output `{name}` of {} at every sample.", entry.name),
            files,
        });
    }
    Ok(drawn)
}

/// One chart per metric of a sweep, against the first axis (one curve per value of
/// the second axis, if any).
pub(super) fn sweep(
    plan: &SweepShape,
    points: &[Vec<f64>],
    rows: &[Vec<f64>],
    dir: &Path,
) -> Result<Vec<DrawnFigure>, RunError> {
    let Some(first) = plan.axes.first() else {
        return Ok(Vec::new());
    };
    let mut drawn = Vec::new();
    for (m, metric) in plan.metrics.iter().enumerate() {
        stop_if_interrupted()?;
        let series = match plan.axes.get(1) {
            None => vec![Series::new(
                metric.1.clone(),
                points.iter().zip(rows).map(|(p, r)| (p[0], r[m])).collect(),
            )],
            Some(second) => second
                .values
                .iter()
                .map(|&v| {
                    let label = format!("{} = {} {}", second.name, format_number(v), second.unit);
                    let curve = points
                        .iter()
                        .zip(rows)
                        .filter(|(p, _)| p[1] == v)
                        .map(|(p, r)| (p[0], r[m]))
                        .collect();
                    Series::new(label.trim_end(), curve)
                })
                .collect(),
        };
        let chart = LineChart {
            title: format!(
                "Peak |{}| over {} to {} s of each run, against {}",
                metric.0, plan.window[0], plan.window[1], first.name
            ),
            x_label: with_unit(&first.name, &first.unit),
            y_label: metric.1.clone(),
            series,
        };
        let column = format!("peak_{}", metric.0);
        let stem = format!("sweep_{}", file_stem(&column));
        let files =
            draw_line_chart(&chart, &dir.join(stem), &ImageFormat::ALL).map_err(plot_error)?;
        drawn.push(DrawnFigure {
            id: column,
            title: chart.title,
            caption: format!(
                "The largest magnitude of {} over {} to {} s of each run, against {}.",
                metric.0, plan.window[0], plan.window[1], first.name
            ),
            files,
        });
    }
    Ok(drawn)
}

/// Writes `index.html` with the summary, the HTML `sections` and the figures.
pub(super) fn index(
    dir: &Path,
    title: &str,
    summary: &str,
    figures: &[DrawnFigure],
    sections: &[String],
) -> Result<PathBuf, RunError> {
    write_index(dir, title, summary, figures, sections).map_err(plot_error)
}

/// One chart per banded column of a Monte Carlo study: the median, the 25–75 % band
/// and the 5–95 % band over the samples, against time.
pub(super) fn bands(
    shape: &super::study::StudyShape,
    times: &[f64],
    bands: &[Vec<[f64; 5]>],
    samples: usize,
    dir: &Path,
) -> Result<Vec<DrawnFigure>, RunError> {
    use crate::plot::{draw_line_chart_with, ChartOptions, Fill, SeriesStyle};
    let mut drawn = Vec::new();
    for (c, (name, unit)) in shape.columns.iter().enumerate() {
        if shape.only.as_ref().is_some_and(|ids| !ids.contains(name)) {
            continue;
        }
        stop_if_interrupted()?;
        let band = |lo: usize, hi: usize| -> Vec<(f64, f64, f64)> {
            times
                .iter()
                .zip(bands)
                .map(|(t, row)| (*t, row[c][lo], row[c][hi]))
                .collect()
        };
        let blue = (31, 119, 180);
        let options = ChartOptions {
            fills: vec![
                Fill {
                    points: band(0, 4),
                    color: blue,
                    opacity: 0.18,
                },
                Fill {
                    points: band(1, 3),
                    color: blue,
                    opacity: 0.35,
                },
            ],
            styles: vec![SeriesStyle::solid(blue)],
            ..ChartOptions::default()
        };
        let chart = LineChart {
            title: format!(
                "{}: {name} over {samples} samples, median and the 25–75 % and 5–95 % bands",
                shape.model
            ),
            x_label: "time t (s)".to_owned(),
            y_label: with_unit(name, unit),
            series: vec![Series::new(
                "median",
                times
                    .iter()
                    .zip(bands)
                    .map(|(t, row)| (*t, row[c][2]))
                    .collect(),
            )],
        };
        let stem = format!("band_{}", file_stem(name));
        let files = draw_line_chart_with(&chart, &options, &dir.join(stem), &ImageFormat::ALL)
            .map_err(plot_error)?;
        drawn.push(DrawnFigure {
            id: format!("band_{name}"),
            title: chart.title,
            caption: format!(
                "`{name}` at every sample time over the study's samples: the median (line), \
                 the 25–75 % band (dark) and the 5–95 % band (light); quantiles of type 7, \
                 as in bands.csv."
            ),
            files,
        });
    }
    Ok(drawn)
}
