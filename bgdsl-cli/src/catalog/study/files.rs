//! The files of a study and of a shard of one: written by one writer for the
//! one-process run and for `merge` (so that they are equal), and read back from shard
//! folders.

use core::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use bgdsl_runtime::record::{write_atomically, write_number};

use super::super::params::format_significant;
use super::super::run::Observer;
use super::super::{figures, RunError};
use super::{SampleRow, StudyShape};
use crate::report::INDEX_FILE;
use crate::study::bands::{bands, SUFFIXES};
use crate::study::manifest::{self, Manifest};

/// The drawing's result, for [`settle_drawing`].
pub(super) type Drawn = Result<Vec<crate::report::DrawnFigure>, RunError>;

/// Writes a shard's files: its rows of `samples.csv` and `trajectories.csv`,
/// `shard.yaml` and a short `index.html`. Returns the file names.
pub(super) fn write_shard(
    dir: &Path,
    shape: &StudyShape,
    times: &[f64],
    rows: &[SampleRow],
    manifest: &Manifest,
    head: &str,
) -> Result<(Vec<String>, Drawn, String), RunError> {
    write_samples(dir, shape, rows)?;
    write_trajectories(dir, shape, times, rows)?;
    let path = dir.join(manifest::FILE_NAME);
    write_atomically(&path, |out| out.write_all(manifest.to_yaml().as_bytes()))?;
    let summary = format!(
        "shard {} of a study: samples {}..{} of {} (end excluded); join the shards with \
         the `merge` command\n{head}",
        manifest.shard(),
        manifest.first,
        manifest.end,
        manifest.items
    );
    figures::index(dir, &shape.title, &summary, &[], &[])?;
    Ok((
        vec![
            SAMPLES.to_owned(),
            TRAJECTORIES.to_owned(),
            manifest::FILE_NAME.to_owned(),
            INDEX_FILE.to_owned(),
        ],
        Ok(Vec::new()),
        summary,
    ))
}

/// `samples.csv`.
pub const SAMPLES: &str = "samples.csv";
/// `trajectories.csv`.
pub const TRAJECTORIES: &str = "trajectories.csv";
/// `bands.csv`.
pub const BANDS: &str = "bands.csv";

/// Writes the study's files from its rows (all samples, in index order): the one
/// writer of both the one-process run and [`merge`], so that their files are equal.
pub(super) fn write_study(
    dir: &Path,
    shape: &StudyShape,
    times: &[f64],
    rows: &[SampleRow],
    head: &str,
    observer: &dyn Observer,
) -> Result<(Vec<String>, Drawn, String), RunError> {
    write_samples(dir, shape, rows)?;
    write_trajectories(dir, shape, times, rows)?;
    let width = shape.columns.len();
    let traces: Vec<&[f64]> = rows
        .iter()
        .filter_map(|r| r.trajectory.as_deref())
        .collect();
    let bands = bands(&traces, times.len(), width);
    write_atomically(&dir.join(BANDS), |out| {
        let mut header = vec!["t".to_owned()];
        for (name, _) in &shape.columns {
            header.extend(SUFFIXES.iter().map(|s| format!("{name}_{s}")));
        }
        writeln!(out, "{}", header.join(","))?;
        for (t, row) in times.iter().zip(&bands) {
            write_number(out, *t)?;
            for q in row.iter().flatten() {
                out.write_all(b",")?;
                write_number(out, *q)?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    })?;
    let drawing = if !shape.plots || observer.stop_requested() {
        Ok(Vec::new())
    } else {
        figures::bands(shape, times, &bands, traces.len(), dir)
    };
    let mut summary = String::from(head);
    let _ = writeln!(
        summary,
        "\nat the end ({} s), over the samples:",
        super::super::format_number(times.last().copied().unwrap_or(0.0))
    );
    let _ = writeln!(
        summary,
        "  {:>24} {:>12} {:>12} {:>12}",
        "column", "q05", "q50", "q95"
    );
    if let Some(last) = bands.last() {
        for ((name, unit), q) in shape.columns.iter().zip(last) {
            let label = if unit.is_empty() {
                name.clone()
            } else {
                format!("{name} ({unit})")
            };
            let _ = writeln!(
                summary,
                "  {label:>24} {:>12} {:>12} {:>12}",
                format_significant(q[0]),
                format_significant(q[2]),
                format_significant(q[4])
            );
        }
    }
    let drawn_ok = match &drawing {
        Ok(d) => d.clone(),
        Err(_) => Vec::new(),
    };
    figures::index(dir, &shape.title, &summary, &drawn_ok, &[])?;
    let mut files = vec![
        SAMPLES.to_owned(),
        TRAJECTORIES.to_owned(),
        BANDS.to_owned(),
    ];
    files.extend(drawn_ok.iter().flat_map(|f| {
        f.files
            .iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
    }));
    files.push(INDEX_FILE.to_owned());
    Ok((files, drawing, summary))
}

/// The per-sample metrics of a trajectory: for each column, the peak magnitude and
/// the final value (NaN for a failed run).
fn metrics(trajectory: Option<&[f64]>, width: usize) -> Vec<f64> {
    let Some(values) = trajectory.filter(|v| !v.is_empty() && width > 0) else {
        return vec![f64::NAN; 2 * width];
    };
    let times = values.len() / width;
    let peak = (0..width).map(|c| {
        (0..times)
            .map(|t| values[t * width + c].abs())
            .fold(f64::NAN, f64::max)
    });
    let last = (0..width).map(|c| values[(times - 1) * width + c]);
    peak.chain(last).collect()
}

/// `samples.csv`: `index`, the drawn values, `peak_<c>` and `final_<c>` of each column.
fn write_samples(dir: &Path, shape: &StudyShape, rows: &[SampleRow]) -> Result<(), RunError> {
    let width = shape.columns.len();
    write_atomically(&dir.join(SAMPLES), |out| {
        let header: Vec<String> = std::iter::once("index".to_owned())
            .chain(shape.parameters.iter().map(|(n, _)| n.clone()))
            .chain(shape.columns.iter().map(|(n, _)| format!("peak_{n}")))
            .chain(shape.columns.iter().map(|(n, _)| format!("final_{n}")))
            .collect();
        writeln!(out, "{}", header.join(","))?;
        for row in rows {
            write!(out, "{}", row.index)?;
            for v in row
                .drawn
                .iter()
                .chain(&metrics(row.trajectory.as_deref(), width))
            {
                out.write_all(b",")?;
                write_number(out, *v)?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    })?;
    Ok(())
}

/// `trajectories.csv`: `index`, `t`, the banded columns; one row per sample and time
/// (failed samples left out).
fn write_trajectories(
    dir: &Path,
    shape: &StudyShape,
    times: &[f64],
    rows: &[SampleRow],
) -> Result<(), RunError> {
    let width = shape.columns.len();
    write_atomically(&dir.join(TRAJECTORIES), |out| {
        let header: Vec<&str> = ["index", "t"]
            .into_iter()
            .chain(shape.columns.iter().map(|(n, _)| n.as_str()))
            .collect();
        writeln!(out, "{}", header.join(","))?;
        for row in rows {
            let Some(values) = &row.trajectory else {
                continue;
            };
            for (k, t) in times.iter().enumerate() {
                write!(out, "{},", row.index)?;
                write_number(out, *t)?;
                for v in &values[k * width..(k + 1) * width] {
                    out.write_all(b",")?;
                    write_number(out, *v)?;
                }
                out.write_all(b"\n")?;
            }
        }
        Ok(())
    })?;
    Ok(())
}

/// The numbers of a CSV file written by this module: its header and rows.
pub(in crate::catalog) fn read_table(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read it: {e}", path.display()))?;
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::to_owned)
        .collect::<Vec<_>>();
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let row: Result<Vec<f64>, _> = line.split(',').map(str::parse::<f64>).collect();
        match row {
            Ok(row) if row.len() == header.len() => rows.push(row),
            _ => {
                return Err(format!(
                    "{}:{}: not a row of {} numbers; was the file edited?",
                    path.display(),
                    i + 2,
                    header.len()
                ))
            }
        }
    }
    Ok((header, rows))
}

/// The rows of one Monte Carlo shard folder, and its sample times.
pub(super) fn read_shard(
    dir: &Path,
    shape: &StudyShape,
    m: &Manifest,
) -> Result<(Vec<f64>, Vec<SampleRow>), String> {
    let (_, samples) = read_table(&dir.join(SAMPLES))?;
    let (_, points) = read_table(&dir.join(TRAJECTORIES))?;
    let drawn = shape.parameters.len();
    let width = shape.columns.len();
    let count = m.end - m.first;
    if samples.len() != count {
        return Err(format!(
            "{}: {SAMPLES} has {} rows, the manifest says {count} samples",
            dir.display(),
            samples.len()
        ));
    }
    let times_len = points.len().checked_div(count).unwrap_or(0);
    if times_len * count != points.len() {
        return Err(format!("{}: {TRAJECTORIES} is incomplete", dir.display()));
    }
    let times: Vec<f64> = points.iter().take(times_len).map(|r| r[1]).collect();
    let rows = samples
        .iter()
        .zip(points.chunks(times_len.max(1)))
        .map(|(s, chunk)| SampleRow {
            index: s[0] as usize,
            drawn: s[1..1 + drawn].to_vec(),
            trajectory: Some(
                chunk
                    .iter()
                    .flat_map(|r| r[2..2 + width].iter().copied())
                    .collect(),
            ),
        })
        .collect();
    Ok((times, rows))
}
