//! The whole 0–5 s run of the hand-written quick return mechanism
//! (`quick_return_hand/model.rs`) with Radau5, recorded into the results-file columns
//! (`models::quick_return::results::Results`) without writing a file:
//!
//! - (a) `radau5_rtol1e-6`: rtol 1e-6, atol 1e-10, sampled every 1 ms (5001 samples,
//!   the flagship run; target under 50 ms);
//! - (b) `radau5_authors_rtol1e-4`: the authors' setting (MATLAB ode15s, RelTol 1e-4,
//!   AbsTol 1e-8) with 10,000 output points evenly spaced over 0–5 s (target under
//!   20 ms);
//! - `write_csv`: writing the 5001-row results file (atomically, to the target's
//!   temporary directory), for comparison.
//!
//! Before timing, once, it prints for (a) and (b) the solver's counters and the achieved
//! error against a run at rtol 1e-10 (atol 1e-14) at the same sample times: the largest
//! absolute deviation of each recorded column relative to that column's peak |value|,
//! the worst column named; and a breakdown of where the time of one run goes (the
//! counters times the measured cost of one derivative and one Jacobian; the rest is
//! the LU factorizations, the linear solves and the solver's own work).
//!
//! `cargo bench -p models --bench quick_return_run -- --warm-up-time 1 --measurement-time 5`
//!
//! Measured on the project's 2-core machine (shared, so ±10 %): (a) ~150 ms (963 steps,
//! 7282 rhs, 552 Jacobians, 1604 LU; achieved error 6.5e-6), (b) ~80 ms (456 steps,
//! 3302 rhs, 278 Jacobians, 840 LU; 4.0e-4): both miss the targets (50 ms,
//! 20 ms). `perf` puts the time in the LU factorizations (~45 %: the complex one 30 %,
//! the real one 14 %), the linear solves (~20 %), the Jacobians by automatic
//! differentiation (~20 %: the hand model declares no sparsity pattern, so 117
//! dual-number evaluations each) and assembling the iteration matrices (~5 %); the
//! model's own derivative on `f64` is under 1 %. Its 117 × 117 Jacobian is 12.5 % full
//! (62 colours), but in this state order its band is (104, 102), so the banded LU is
//! dense; declaring the pattern alone changes little, a bandwidth-reducing order
//! (reverse Cuthill–McKee: (43, 42)) gives ~100 ms and ~52 ms.

#[path = "quick_return_hand/model.rs"]
#[allow(dead_code)]
mod model;

use std::hint::black_box;
use std::time::{Duration, Instant};

use bgdsl_runtime::{JacobianEvaluator, Model, Radau5Options, Solver};
use criterion::{criterion_group, criterion_main, Criterion};
use models::quick_return::results::{sample_times, COLUMNS};
use models::quick_return::run::{record, Recorded};

use model::{QuickReturnHand, N_STATES};

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

/// Mean wall time of `f` over enough repetitions to take ~0.2 s.
fn time_per_call(mut f: impl FnMut()) -> Duration {
    f();
    let started = Instant::now();
    let mut n = 0u32;
    while started.elapsed() < Duration::from_millis(200) {
        f();
        n += 1;
    }
    started.elapsed() / n
}

fn report(model: &QuickReturnHand) {
    // States along a run, for timing one derivative and one Jacobian.
    let mut states = Vec::new();
    {
        let mut sim = bgdsl_runtime::Simulation::new(model, flagship()).unwrap();
        let mut x0 = [0.0; N_STATES];
        model.initial_state(&mut x0);
        let mut keep = |_t: f64, x: &[f64], _y: &[f64]| states.push(x.to_vec());
        sim.run(0.0, &x0, &linspace(64), &mut keep).unwrap();
    }
    let mut dx = vec![0.0; N_STATES];
    let rhs = time_per_call(|| {
        for x in &states {
            model.derivatives::<f64>(0.0, black_box(x), &mut dx);
        }
    }) / states.len() as u32;
    let mut evaluator = JacobianEvaluator::new(model);
    let mut jac = vec![0.0; N_STATES * N_STATES];
    let jacobian = time_per_call(|| {
        for x in &states {
            evaluator.evaluate(model, 0.0, black_box(x), &mut jac);
        }
    }) / states.len() as u32;
    println!(
        "one derivative {:.2} us; one Jacobian {:.1} us ({} colours of {} states)",
        rhs.as_secs_f64() * 1e6,
        jacobian.as_secs_f64() * 1e6,
        evaluator.n_colours(),
        N_STATES
    );

    for (label, solver, times) in [
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
    ] {
        let reference = record(model, radau5(1e-10, 1e-14), &times).expect("reference run");
        let run = record(model, solver, &times).expect("the run succeeds");
        let wall = time_per_call(|| {
            black_box(record(model, solver, &times).unwrap());
        });
        let s = run.stats;
        let (error, column) = achieved_error(&run, &reference);
        let rhs_time = rhs * s.n_rhs as u32;
        let jac_time = jacobian * s.n_jac as u32;
        let rest = wall.saturating_sub(rhs_time + jac_time);
        let pct = |d: Duration| 100.0 * d.as_secs_f64() / wall.as_secs_f64();
        println!("{label}:");
        println!(
            "  {:.2} ms per run; {} steps ({} accepted, {} rejected), {} rhs, {} Jacobians \
             ({} rhs on duals), {} LU",
            wall.as_secs_f64() * 1e3,
            s.steps(),
            s.accepted,
            s.rejected,
            s.n_rhs,
            s.n_jac,
            s.n_jac_rhs,
            s.n_lu
        );
        println!(
            "  achieved error vs rtol 1e-10: {error:.2e} of the column's peak (worst: {column}); \
             reference run: {} steps",
            reference.stats.steps()
        );
        println!(
            "  time: rhs {:.1} %, Jacobians {:.1} %, LU + solves + the rest {:.1} % \
             ({:.1} us per LU counted)",
            pct(rhs_time),
            pct(jac_time),
            pct(rest),
            rest.as_secs_f64() * 1e6 / s.n_lu.max(1) as f64
        );
    }
}

fn runs(c: &mut Criterion) {
    let model = QuickReturnHand::default();
    // Only under `cargo bench` (which passes `--bench`), not when `cargo test` runs
    // the benchmarks once as a smoke test.
    if std::env::args().any(|a| a == "--bench") {
        report(&model);
    }

    let mut group = c.benchmark_group("quick_return_run");
    group.sample_size(20);
    let times = sample_times();
    group.bench_function("radau5_rtol1e-6", |b| {
        b.iter(|| record(black_box(&model), flagship(), &times).unwrap())
    });
    let points = linspace(10_000);
    group.bench_function("radau5_authors_rtol1e-4", |b| {
        b.iter(|| record(black_box(&model), authors(), &points).unwrap())
    });
    let recorded = record(&model, flagship(), &times).unwrap();
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("quick_return_bench.csv");
    group.bench_function("write_csv", |b| {
        b.iter(|| recorded.results.write_csv(&path).unwrap())
    });
    group.finish();
}

criterion_group!(benches, runs);
criterion_main!(benches);
