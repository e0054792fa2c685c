//! A Monte Carlo study against a sweep of as many runs of the same model (the anchor,
//! in the same run), and `merge` of its four shards: what the study's trajectories,
//! bands and files cost over the runs themselves, and what joining shards costs.
//!
//! `cargo bench -p models --bench study -- --warm-up-time 1 --measurement-time 5`
//!
//! - `sweep_40`: the quarter car over its bump, 0–2 s sampled every 10 ms, 40 runs
//!   (sprung mass 250–400 kg), peaks of four outputs into `sweep.csv`; no figures.
//! - `study_40`: the same model, span and sampling, 40 samples
//!   (`models/scenarios/quarter_car_monte_carlo.yaml`: mass, stiffness and damping
//!   drawn), the four outputs recorded at every sample into `samples.csv`,
//!   `trajectories.csv` and `bands.csv`; no figures.
//! - `merge_4_shards`: joining the study's four shard folders into the same files.
//!
//! Each iteration writes its results set (staging folder, swap) in the target's
//! temporary directory.
//!
//! Measured on the project's 2-core machine, shared with other builds (±10 % and more
//! from run to run): `sweep_40` 92 ms, `study_40` 115 ms (the trajectories, bands and
//! 0.6 MB of CSV add a quarter to the same number of runs), `merge_4_shards` 38 ms
//! (28–48 ms: reading the shards' CSVs back, the bands and the writing; a third of the
//! study).

use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion};
use models::catalog::{merge, run_study, run_sweep, shared, Silent};
use models::scenario::{load, parse, resolve, Job, Overrides, Plan};

fn tmp(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("bench-study")
        .join(name)
}

fn plan_of(loaded: &models::scenario::Loaded, out: &Path) -> Plan {
    let overrides = Overrides {
        no_plots: true,
        out: Some(out.to_path_buf()),
        ..Overrides::default()
    };
    resolve(
        shared(),
        Some(&loaded.source),
        &loaded.scenario,
        &overrides,
        "bench",
    )
    .unwrap_or_else(|d| panic!("{d}"))
}

fn bench(c: &mut Criterion) {
    let scenarios = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let study = load(&scenarios.join("quarter_car_monte_carlo.yaml")).unwrap();
    let sweep = parse(
        "sweep.yaml".into(),
        "model: quarter_car\ntime: {end: 2.0}\noutput: {interval: 0.01}\nsweep:\n  \
         parameters:\n    - {name: sprung_mass, from: 250, to: 400, steps: 40}\n  \
         peaks: [body_height, body_acceleration, suspension_travel, tyre_force]\n  \
         window: {from: 0.0}\n"
            .to_owned(),
    )
    .unwrap();
    let mut group = c.benchmark_group("study");
    group.sample_size(20);

    let plan = plan_of(&sweep, &tmp("sweep"));
    let Job::Sweep(sweep_plan) = &plan.job else {
        panic!("a sweep")
    };
    group.bench_function("sweep_40", |b| {
        b.iter(|| run_sweep(plan.entry, sweep_plan, None, &Silent).unwrap())
    });

    let plan = plan_of(&study, &tmp("study"));
    let Job::Study(study_plan) = &plan.job else {
        panic!("a study")
    };
    group.bench_function("study_40", |b| {
        b.iter(|| run_study(plan.entry, study_plan, None, &Silent).unwrap())
    });

    let shards: Vec<PathBuf> = (1..=4)
        .map(|k| {
            let mut shard_plan = study_plan.clone();
            shard_plan.base.out_dir = tmp(&format!("shard-{k}"));
            let shard = format!("{k}/4").parse().unwrap();
            run_study(plan.entry, &shard_plan, Some(shard), &Silent).unwrap();
            shard_plan.base.out_dir
        })
        .collect();
    let merged = tmp("merged");
    group.bench_function("merge_4_shards", |b| {
        b.iter(|| merge(&shards, &merged, &Silent).unwrap().unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
