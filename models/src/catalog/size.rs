//! The size guard's estimates: how much a run writes, how much work a sweep is.

use super::{Entry, ResultsKind, RunPlan, SweepPlan};
use crate::plot::decimate::thousands;
use crate::quick_return::results::N_COLUMNS;

/// The most bytes one number takes in a results CSV, with its separator: the shortest
/// decimal that reads back to an `f64` has at most 17 significant digits, a sign, a
/// point and a three-digit exponent (`-1.2345678901234567e-100,` is 25; 24 covers all
/// but the rarest).
pub const BYTES_PER_NUMBER: u64 = 24;

/// A run's results size above which the program asks first (or needs `--yes`): 1 GB.
pub const MAX_RUN_BYTES: u64 = 1_000_000_000;

/// A sweep's run count above which the program asks first (or needs `--yes`).
pub const MAX_SWEEP_RUNS: usize = 1000;

/// A sweep's samples in all (runs × samples per run) above which the program asks
/// first (or needs `--yes`).
pub const MAX_SWEEP_SAMPLES: u64 = 100_000_000;

/// The columns of every results file a run of `entry` with `plan` writes.
pub fn results_columns(entry: &Entry, plan: &RunPlan) -> u64 {
    let recorded = |all: usize| 1 + plan.record.as_ref().map_or(all, |chosen| chosen.len()) as u64;
    match entry.results {
        ResultsKind::QuickReturn => {
            N_COLUMNS as u64 + plan.record.as_ref().map_or(0, |c| 1 + c.len() as u64)
        }
        ResultsKind::Trajectory => {
            recorded(entry.model.state_names().len() + entry.model.output_names().len())
        }
    }
}

/// At most how many bytes a run's results files take: rows × columns ×
/// [`BYTES_PER_NUMBER`] (the figures and the page are decimated to a few MB).
pub fn estimated_run_bytes(entry: &Entry, plan: &RunPlan) -> u64 {
    plan.times.len() as u64 * results_columns(entry, plan) * BYTES_PER_NUMBER
}

/// Why a run or a sweep is larger than the guard allows, with the estimate; `None`
/// when it is not.
pub fn run_too_large(entry: &Entry, plan: &RunPlan) -> Option<String> {
    let bytes = estimated_run_bytes(entry, plan);
    (bytes > MAX_RUN_BYTES).then(|| {
        format!(
            "this run would write up to {} of results ({} rows × {} columns), more than \
             the {} the program writes without asking",
            format_bytes(bytes),
            thousands(plan.times.len() as u64),
            results_columns(entry, plan),
            format_bytes(MAX_RUN_BYTES)
        )
    })
}

/// As [`run_too_large`] for a sweep: too many runs, or too many samples in all.
pub fn sweep_too_large(plan: &SweepPlan) -> Option<String> {
    let runs = plan.points().len();
    let per_run = plan.base.times.len() as u64;
    let samples = runs as u64 * per_run;
    (runs > MAX_SWEEP_RUNS || samples > MAX_SWEEP_SAMPLES).then(|| {
        format!(
            "this sweep has {} runs of {} samples each, {} samples to integrate in all \
             (the program runs at most {} runs or {} samples without asking)",
            thousands(runs as u64),
            thousands(per_run),
            thousands(samples),
            thousands(MAX_SWEEP_RUNS as u64),
            thousands(MAX_SWEEP_SAMPLES)
        )
    })
}

/// `1.3 GB`, `420 MB`, `12 kB`, `512 B` (decimal units).
pub fn format_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.0} MB", b / 1e6)
    } else if b >= 1e3 {
        format!("{:.0} kB", b / 1e3)
    } else {
        format!("{bytes} B")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_sizes() {
        assert_eq!(format_bytes(1_344_000_000), "1.3 GB");
        assert_eq!(format_bytes(420_400_000), "420 MB");
        assert_eq!(format_bytes(999), "999 B");
    }
}
