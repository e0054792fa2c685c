//! Whole 0–5 s runs of the quick return mechanism with Radau5, recorded into the
//! results-file columns (`models::quick_return::results::Results`) without writing a
//! file: the flagship written with `bond_graph!` (`models::quick_return::QuickReturn`,
//! which declares its exact Jacobian sparsity pattern) and, as a second case, the
//! hand-written model of the same equations (`quick_return_hand/model.rs`, which
//! declares none: its Jacobians are dense), each at
//!
//! - (a) `rtol1e-6`: rtol 1e-6, atol 1e-10, sampled every 1 ms (5001 samples, the
//!   flagship run; the target: under 50 ms);
//! - (b) `authors_rtol1e-4`: the authors' setting (MATLAB ode15s, RelTol 1e-4,
//!   AbsTol 1e-8) with 10,000 output points evenly spaced over 0–5 s (target: under
//!   20 ms);
//!
//! plus `write_csv`: writing the 5001-row results file (atomically, to the target's
//! temporary directory), for comparison.
//!
//! Before timing, once per model, it prints for (a) and (b) the solver's counters and
//! the achieved error against a run at rtol 1e-10 (atol 1e-14) at the same sample times:
//! the largest absolute deviation of each recorded column relative to that column's
//! peak |value|, the worst column named; and a breakdown of where the time of one run
//! goes (the counters times the measured cost of one derivative and of one directional
//! derivative on dual numbers; the rest is the LU factorizations, the linear solves,
//! the recording and the solver's own work).
//!
//! `cargo bench -p models --bench quick_return_run -- --warm-up-time 1 --measurement-time 5`
//!
//! Measured on the project's 2-core machine (shared: ±10 % from run to run), the
//! generated model, before (commit 0a8a911) and after the sparse iteration matrices,
//! the compressed Jacobians and the new default `reuse_jacobian_below` (see
//! `bgdsl-runtime/src/linalg/`, `bgdsl-runtime/src/jacobian.rs`):
//!
//! | setting | wall | steps | rhs | Jacobians (directions) | LU | achieved error |
//! |---|---|---|---|---|---|---|
//! | (a) before | 197 ms | 962 | 7268 | 546 (40950) | 1602 | 6.4e-6 |
//! | (a) after | 25 ms | 973 | 7595 | 276 (8660) | 1354 | 5.1e-6 |
//! | (b) before | 106 ms | 459 | 3319 | 274 (20550) | 842 | 3.8e-4 |
//! | (b) after | 17–18 ms | 461 | 3466 | 189 (5963) | 816 | 3.8e-4 |
//!
//! Issue 15 (matrix products written out for dual numbers, the CSV through `ryu`, h4's
//! tolerance change): see `docs/flagship-speed.md`, measured in thread CPU time with
//! `models/examples/flagship_profile.rs` because the shared machine's wall times varied
//! 3x during that work.
//!
//! The hand-written model declares no pattern, so it keeps the banded (here dense)
//! linear algebra and uncompressed Jacobians: (a) 141 → 110 ms, (b) 78 → 65 ms (its
//! Jacobians evaluate four directions per call of the model, and are kept longer).

#[path = "quick_return_hand/model.rs"]
#[allow(dead_code)]
mod hand;

use std::hint::black_box;
use std::time::Duration;

use bgdsl_runtime::{JacobianEvaluator, Model, Radau5Options, Solver};
#[path = "common/timing.rs"]
mod timing;
use timing::time_per_call;

use criterion::{criterion_group, criterion_main, Criterion};
use models::quick_return::results::{sample_times, COLUMNS};
use models::quick_return::run::{record, Recorded};
use models::quick_return::QuickReturn;

use hand::QuickReturnHand;

/// (a): the flagship setting.
fn flagship() -> Solver {
    radau5(1e-6, 1e-10)
}

/// (b): the authors' setting.
fn authors() -> Solver {
    radau5(1e-4, 1e-8)
}

fn radau5(rtol: f64, atol: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol,
        ..Default::default()
    })
}

/// `n` times evenly spaced over 0–5 s, as MATLAB's `linspace(0, 5, n)`.
fn linspace(n: usize) -> Vec<f64> {
    (0..n).map(|k| 5.0 * k as f64 / (n - 1) as f64).collect()
}

/// The largest deviation of `run` from `reference` over all columns after `t`, each
/// relative to the column's peak |value| in the reference: (deviation, column).
fn achieved_error(run: &Recorded, reference: &Recorded) -> (f64, &'static str) {
    let mut worst = (0.0, "");
    for (i, name) in COLUMNS.iter().enumerate().skip(1) {
        let (a, b) = (run.results.column_at(i), reference.results.column_at(i));
        let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let deviation = a
            .iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        // Columns that are zero throughout (the out-of-plane ones) have no scale.
        if peak > 0.0 && deviation / peak > worst.0 {
            worst = (deviation / peak, name);
        }
    }
    worst
}

/// The settings (a) and (b): label, solver, sample times.
fn settings() -> [(&'static str, Solver, Vec<f64>); 2] {
    [
        (
            "(a) rtol 1e-6, atol 1e-10, 5001 samples",
            flagship(),
            sample_times(),
        ),
        (
            "(b) rtol 1e-4, atol 1e-8, 10000 samples",
            authors(),
            linspace(10_000),
        ),
    ]
}

fn report<M: Model>(model: &M) {
    let n = M::N_STATES;
    // States along a run, for timing one derivative and one Jacobian.
    let mut states = Vec::new();
    {
        let mut sim = bgdsl_runtime::Simulation::new(model, flagship()).unwrap();
        let mut x0 = vec![0.0; n];
        model.initial_state(&mut x0);
        let mut keep = |_t: f64, x: &[f64], _y: &[f64]| states.push(x.to_vec());
        sim.run(0.0, &x0, &linspace(64), &mut keep).unwrap();
    }
    let mut dx = vec![0.0; n];
    let rhs = time_per_call(|| {
        for x in &states {
            model.derivatives::<f64>(0.0, black_box(x), &mut dx);
        }
    }) / states.len() as u32;
    let mut evaluator = JacobianEvaluator::new(model);
    let mut jac = vec![0.0; n * n];
    let jacobian = time_per_call(|| {
        for x in &states {
            evaluator.evaluate(model, 0.0, black_box(x), &mut jac);
        }
    }) / states.len() as u32;
    // The solver compresses by the numerical pattern: its Jacobians cost `n_jac_rhs`
    // directional derivatives, each about this.
    let direction = jacobian / evaluator.n_colours().max(1) as u32;
    println!(
        "{}: one derivative {:.2} us; one Jacobian with the declared pattern {:.1} us \
         ({} colours of {} states: {:.2} us per directional derivative)",
        M::NAME,
        rhs.as_secs_f64() * 1e6,
        jacobian.as_secs_f64() * 1e6,
        evaluator.n_colours(),
        n,
        direction.as_secs_f64() * 1e6
    );

    for (label, solver, times) in settings() {
        let reference = record(model, radau5(1e-10, 1e-14), &times).expect("reference run");
        let run = record(model, solver, &times).expect("the run succeeds");
        let (error, column) = achieved_error(&run, &reference);
        let (s, reference_steps) = (run.stats, reference.stats.steps());
        // Timed with no other results held, as criterion times it below.
        drop((run, reference));
        let wall = time_per_call(|| {
            black_box(record(model, solver, &times).unwrap());
        });
        let rhs_time = rhs * s.n_rhs as u32;
        let jac_time = direction * s.n_jac_rhs as u32;
        let rest = wall.saturating_sub(rhs_time + jac_time);
        let pct = |d: Duration| 100.0 * d.as_secs_f64() / wall.as_secs_f64();
        println!("  {label}:");
        println!(
            "    {:.2} ms per run (median); {} steps ({} accepted, {} rejected), {} rhs, {} \
             Jacobians ({} directional derivatives), {} LU ({} fell back to partial pivoting)",
            wall.as_secs_f64() * 1e3,
            s.steps(),
            s.accepted,
            s.rejected,
            s.n_rhs,
            s.n_jac,
            s.n_jac_rhs,
            s.n_lu,
            s.n_lu_fallback
        );
        println!(
            "    achieved error vs rtol 1e-10: {error:.2e} of the column's peak (worst: \
             {column}); reference run: {} steps",
            reference_steps
        );
        println!(
            "    time: rhs {:.1} %, Jacobians {:.1} %, LU + solves + the rest {:.1} % \
             ({:.1} us per LU counted)",
            pct(rhs_time),
            pct(jac_time),
            pct(rest),
            rest.as_secs_f64() * 1e6 / s.n_lu.max(1) as f64
        );
    }
}

/// The timed runs of `model`, named `<prefix>_<setting>`.
fn bench_model<M: Model>(c: &mut Criterion, prefix: &str, model: &M) {
    let mut group = c.benchmark_group("quick_return_run");
    group.sample_size(20);
    let [(_, a, times_a), (_, b, times_b)] = settings();
    group.bench_function(format!("{prefix}_rtol1e-6"), |bench| {
        bench.iter(|| record(black_box(model), a, &times_a).unwrap())
    });
    group.bench_function(format!("{prefix}_authors_rtol1e-4"), |bench| {
        bench.iter(|| record(black_box(model), b, &times_b).unwrap())
    });
    group.finish();
}

fn runs(c: &mut Criterion) {
    let generated = QuickReturn::default();
    let hand = QuickReturnHand::default();
    // Only under `cargo bench` (which passes `--bench`), not when `cargo test` runs
    // the benchmarks once as a smoke test.
    if std::env::args().any(|a| a == "--bench") {
        report(&generated);
        report(&hand);
    }
    bench_model(c, "generated", &generated);
    bench_model(c, "hand", &hand);

    let times = sample_times();
    let recorded = record(&generated, flagship(), &times).unwrap();
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("quick_return_bench.csv");
    let mut group = c.benchmark_group("quick_return_run");
    group.sample_size(20);
    group.bench_function("write_csv", |b| {
        b.iter(|| recorded.results.write_csv(&path).unwrap())
    });
    group.finish();
}

criterion_group!(benches, runs);
criterion_main!(benches);
