//! The cost of the analyses on the flagship (`models::quick_return::QuickReturn`, 117
//! states), beside its anchors in the same run:
//!
//! - `derivatives_f64`: one `f64` evaluation of the right-hand side (the anchor);
//! - `simulate_0_5s`: the plain 0–5 s run (Radau5, the catalogue's defaults: rtol 1e-6,
//!   5001 samples);
//! - `linearize`: A, B, C, D exact at the initial state, B and D from three
//!   parameters (the drive speed and two joint stiffnesses), without the modes;
//! - `modes`: the eigenvalues, eigenvectors and participation factors of that A;
//! - `bode_200`: a 200-point frequency response (drive speed to the output slider's
//!   x-position) from that linear model: one Hessenberg reduction, 200 solves.
//!
//! `cargo bench -p bgdsl-analysis --bench analysis -- --warm-up-time 1 --measurement-time 5`
//!
//! Criterion reports wall time; on the shared 2-core machine compare the ratios to the
//! anchors of the same run (the report lists them in `docs/analysis.md`).

use std::hint::black_box;

use bgdsl_analysis::{bode::Sweep, linearize, log_grid, modes, Channel};
use bgdsl_runtime::{simulate, Model, Radau5Options, Solver};
use criterion::{criterion_group, criterion_main, Criterion};
use models::quick_return::QuickReturn;

fn channels() -> Vec<Channel> {
    ["w_drive", "K01", "K34"]
        .iter()
        .map(|name| Channel::named::<QuickReturn>(name).expect("a parameter of the flagship"))
        .collect()
}

fn bench(c: &mut Criterion) {
    let model = QuickReturn::default();
    let mut x = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x);
    let channels = channels();
    let mut group = c.benchmark_group("flagship_analysis");
    let mut dx = vec![0.0; QuickReturn::N_STATES];
    group.bench_function("derivatives_f64", |b| {
        b.iter(|| model.derivatives(0.0, black_box(&x), &mut dx))
    });
    group.sample_size(10);
    group.bench_function("simulate_0_5s", |b| {
        let solver = Solver::Radau5(Radau5Options::default());
        b.iter(|| simulate(&model, solver, 0.0, 5.0, 5001).expect("the flagship runs"))
    });
    group.sample_size(20);
    group.bench_function("linearize", |b| {
        b.iter(|| linearize(&model, 0.0, black_box(&x), &channels).expect("linearises"))
    });
    let linear = linearize(&model, 0.0, &x, &channels).expect("linearises");
    group.bench_function("modes", |b| b.iter(|| modes(black_box(&linear.a))));
    let output = linear.output_index("r_C5_x").unwrap_or(0);
    let omega = log_grid(0.1, 1e4, 200);
    group.bench_function("bode_200", |b| {
        b.iter(|| {
            let sweep = Sweep::new(&linear, 0, output);
            omega
                .iter()
                .map(|&w| sweep.at(w))
                .fold(0.0, |s, h| s + h.norm())
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
