//! The size guard's estimates: how much a run writes, how much work a sweep is.

use super::{Entry, RunPlan, StudyPlan, SweepPlan};
use crate::plot::decimate::thousands;
use crate::study::shard::Shard;

/// The most bytes one number takes in a results CSV, with its separator: the shortest
/// decimal that reads back to an `f64` has at most 17 significant digits, a sign, a
/// point and a three-digit exponent (`-1.2345678901234567e-100,` is 25; 24 covers all
/// but the rarest).
pub const BYTES_PER_NUMBER: u64 = 24;

/// A run's results size above which the program asks first (or needs `--yes`): 1 GB.
pub const MAX_RUN_BYTES: u64 = 1_000_000_000;

/// A sweep's run count above which the program asks first (or needs `--yes`).
pub const MAX_SWEEP_RUNS: usize = 1000;

/// A sweep's estimated wall time above which the program asks first (or needs
/// `--yes`): an hour.
pub const MAX_SWEEP_SECONDS: f64 = 3600.0;

/// A sweep's samples in all (runs × samples per run) above which the program asks
/// first (or needs `--yes`).
pub const MAX_SWEEP_SAMPLES: u64 = 100_000_000;

/// The columns of every results file a run of `entry` with `plan` writes: the
/// extras' ([`Extras::result_columns`](super::Extras::result_columns)), and the table's
/// (`t` and the recorded columns) when it records any.
pub fn results_columns(entry: &Entry, plan: &RunPlan) -> u64 {
    let table = match (&plan.record, entry.record) {
        (Some(chosen), _) => chosen.len(),
        (None, Some(names)) => names
            .iter()
            .filter_map(|name| super::resolve_columns(&*entry.model, name))
            .map(|group| group.len())
            .sum(),
        (None, None) => entry.model.state_names().len() + entry.model.output_names().len(),
    } as u64;
    entry.extras.result_columns() + if table > 0 { 1 + table } else { 0 }
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

/// As [`run_too_large`] for a Monte Carlo study (or its `shard`): its
/// `trajectories.csv`, every sample at every time (`index`, `t` and the banded
/// columns), is most of what it writes.
pub fn study_too_large(plan: &StudyPlan, shard: Option<Shard>) -> Option<String> {
    let samples = shard.map_or(plan.samples, |s| s.range(plan.samples).len()) as u64;
    let rows = samples * plan.base.times.len() as u64;
    let columns = 2 + plan.columns.len() as u64;
    let bytes = rows * columns * BYTES_PER_NUMBER;
    (bytes > MAX_RUN_BYTES).then(|| {
        format!(
            "this study would write up to {} of trajectories ({} samples × {} times × {} \
             columns), more than the {} the program writes without asking; fewer samples, \
             a larger interval or --shard K/N make it smaller",
            format_bytes(bytes),
            thousands(samples),
            thousands(plan.base.times.len() as u64),
            columns,
            format_bytes(MAX_RUN_BYTES)
        )
    })
}

/// As [`run_too_large`] for a sweep: too many runs or samples in all, or an estimated
/// time over [`MAX_SWEEP_SECONDS`]. The time is measured: the first point is run over
/// its first [`PROBE_SAMPLES`] samples, and the time scaled to every sample of every
/// run, spread over rayon's threads.
pub fn sweep_too_large(entry: &Entry, plan: &SweepPlan) -> Option<String> {
    let runs = plan.points().len();
    let per_run = plan.base.times.len() as u64;
    let samples = runs as u64 * per_run;
    let threads = rayon::current_num_threads().max(1);
    let seconds =
        probe_seconds_per_sample(entry, plan).map(|s| s * samples as f64 / threads as f64);
    let too_long = seconds.is_some_and(|s| s > MAX_SWEEP_SECONDS);
    if runs <= MAX_SWEEP_RUNS && samples <= MAX_SWEEP_SAMPLES && !too_long {
        return None;
    }
    let time = seconds
        .map(|s| format!(", about {} on {threads} threads", format_duration(s)))
        .unwrap_or_default();
    Some(format!(
        "this sweep has {} runs of {} samples each, {} samples to integrate in all{time} \
         (the program runs at most {} runs, {} samples or {} without asking)",
        thousands(runs as u64),
        thousands(per_run),
        thousands(samples),
        thousands(MAX_SWEEP_RUNS as u64),
        thousands(MAX_SWEEP_SAMPLES),
        format_duration(MAX_SWEEP_SECONDS)
    ))
}

/// How many samples of the first point the time estimate of a sweep integrates.
pub const PROBE_SAMPLES: usize = 2000;

/// Wall time per sample of the sweep's first point over its first samples, s; `None`
/// when the probe fails.
fn probe_seconds_per_sample(entry: &Entry, plan: &SweepPlan) -> Option<f64> {
    let first = plan.points().into_iter().next()?;
    let mut probe = plan.plan_at(&first);
    probe.times.truncate(PROBE_SAMPLES);
    let started = std::time::Instant::now();
    entry
        .model
        .sweep_point(&probe, &plan.metrics, plan.window, &super::Silent)
        .ok()?;
    Some(started.elapsed().as_secs_f64() / probe.times.len().max(1) as f64)
}

/// `3.2 s`, `12 min`, `4.5 h`.
pub fn format_duration(seconds: f64) -> String {
    if seconds < 60.0 {
        format!("{seconds:.1} s")
    } else if seconds < 3600.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
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
        assert_eq!(format_duration(3.25), "3.2 s");
        assert_eq!(format_duration(720.0), "12 min");
        assert_eq!(format_duration(16200.0), "4.5 h");
    }
}
