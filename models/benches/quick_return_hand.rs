//! The quick return mechanism's derivative and outputs on `f64`: the hand-written
//! model (`quick_return_hand/model.rs`) against the one `bond_graph!` generates
//! (`models::quick_return::QuickReturn`), in one run (the target: the
//! generated one within 1.1x).
//!
//! `cargo bench -p models --bench quick_return_hand -- --warm-up-time 1 --measurement-time 3`

#[path = "quick_return_hand/model.rs"]
#[allow(dead_code)]
mod model;

use std::hint::black_box;

use bgdsl_runtime::{DormandPrinceOptions, Model, Simulation, Solver};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

use model::{QuickReturnHand, N_OUTPUTS, N_STATES};
use models::quick_return::QuickReturn;

const POINTS: usize = 64;

/// States along the start of the default run (one every 5 ms from 0.05 s), so the
/// derivative sees moving links and loaded couplings, not the initial rest. Each model
/// is run itself, in its own state order.
fn states_along_the_run<M: Model>(model: &M) -> Vec<[f64; N_STATES]> {
    let mut x0 = [0.0; N_STATES];
    model.initial_state(&mut x0);
    let options = DormandPrinceOptions {
        rtol: 1e-6,
        atol: 1e-9,
        ..Default::default()
    };
    let mut sim = Simulation::new(model, Solver::DormandPrince(options)).unwrap();
    let times: Vec<f64> = (0..POINTS).map(|i| 0.05 + 0.005 * i as f64).collect();
    let mut states = Vec::with_capacity(POINTS);
    let mut keep = |_t: f64, x: &[f64], _y: &[f64]| {
        states.push(<[f64; N_STATES]>::try_from(x).unwrap());
    };
    sim.run(0.0, &x0, &times, &mut keep).unwrap();
    states
}

fn derivatives(c: &mut Criterion) {
    let model = QuickReturnHand::default();
    let points = states_along_the_run(&model);
    let mut group = c.benchmark_group("quick_return_hand");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.bench_function("derivatives_f64", |b| {
        let mut dx = [0.0; N_STATES];
        b.iter(|| {
            let model = black_box(&model);
            let mut sum = 0.0;
            for x in black_box(&points) {
                model.derivatives::<f64>(0.0, x, &mut dx);
                // Every entry observable: otherwise an inlined model loses the work
                // whose results nobody reads.
                black_box(&dx);
                sum += dx[0];
            }
            sum
        })
    });
    group.bench_function("outputs_f64", |b| {
        let mut y = [0.0; N_OUTPUTS];
        b.iter(|| {
            let model = black_box(&model);
            let mut sum = 0.0;
            for x in black_box(&points) {
                model.outputs::<f64>(0.0, x, &mut y);
                black_box(&y);
                sum += y[0];
            }
            sum
        })
    });
    group.finish();

    let generated = QuickReturn::default();
    let generated_points = states_along_the_run(&generated);
    let mut group = c.benchmark_group("quick_return_generated");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.bench_function("derivatives_f64", |b| {
        let mut dx = [0.0; N_STATES];
        b.iter(|| {
            let model = black_box(&generated);
            let mut sum = 0.0;
            for x in black_box(&generated_points) {
                model.derivatives::<f64>(0.0, x, &mut dx);
                // Every entry observable: otherwise an inlined model loses the work
                // whose results nobody reads.
                black_box(&dx);
                sum += dx[0];
            }
            sum
        })
    });
    group.bench_function("outputs_f64", |b| {
        let mut y = [0.0; QuickReturn::N_OUTPUTS];
        b.iter(|| {
            let model = black_box(&generated);
            let mut sum = 0.0;
            for x in black_box(&generated_points) {
                model.outputs::<f64>(0.0, x, &mut y);
                black_box(&y);
                sum += y[0];
            }
            sum
        })
    });
    group.finish();
}

criterion_group!(benches, derivatives);
criterion_main!(benches);
