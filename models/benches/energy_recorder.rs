//! What the energy balance's recorder (`bgdsl_cli::catalog::EnergyRecorder`, kept by
//! every run of a model without figures of its own) costs a run: the same integration
//! recording nothing (the anchor) and with the recorder, in one run of the bench.
//!
//! `cargo bench -p models --bench energy_recorder -- --warm-up-time 1 --measurement-time 3`
//!
//! Per sample the recorder evaluates the derivatives once, the power balance once on
//! dual numbers and four times more for the sources' time derivative.

use std::hint::black_box;

use bgdsl_cli::catalog::EnergyRecorder;
use bgdsl_runtime::{Model, Recorder, Simulation, Solver};
use criterion::{criterion_group, criterion_main, Criterion};
use models::catalog::flagship_solver;
use models::quick_return::QuickReturn;
use models::{QuarterCar, SeriesRlc};

/// `model` integrated over `times` into `recorder`.
fn run<M: Model>(model: &M, solver: Solver, times: &[f64], recorder: &mut dyn Recorder) {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, solver).unwrap();
    sim.run(times[0], &x0, times, recorder).unwrap();
}

fn compare<M: Model + Clone>(
    c: &mut Criterion,
    name: &str,
    model: &M,
    solver: Solver,
    times: &[f64],
) {
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    group.bench_function("no recorder", |b| {
        b.iter(|| run(black_box(model), solver, times, &mut ()))
    });
    group.bench_function("energy recorder", |b| {
        b.iter(|| {
            let mut energy = EnergyRecorder::new(black_box(model).clone(), times.len());
            run(model, solver, times, &mut energy);
            energy.into_balance()
        })
    });
    group.finish();
}

fn grid(end: f64, interval: f64) -> Vec<f64> {
    let n = (end / interval).round() as usize;
    (0..=n).map(|k| k as f64 * interval).collect()
}

fn energy_recorder(c: &mut Criterion) {
    // The catalogue's defaults: 10 µs samples over 10 ms; 1 ms samples over 3 s.
    let rlc = SeriesRlc::new(Default::default());
    compare(c, "energy_rlc", &rlc, Solver::stiff(), &grid(0.01, 1e-5));
    let car = QuarterCar::new(Default::default());
    compare(
        c,
        "energy_quarter_car",
        &car,
        Solver::stiff(),
        &grid(3.0, 1e-3),
    );
    // 121 states: the first 50 ms of the flagship at its 1 ms sampling.
    let flagship = QuickReturn::new(Default::default());
    compare(
        c,
        "energy_quick_return",
        &flagship,
        flagship_solver(),
        &grid(0.05, 1e-3),
    );
}

criterion_group!(benches, energy_recorder);
criterion_main!(benches);
