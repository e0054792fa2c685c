//! The generated quarter car against the same equations written by hand, and one full
//! integration.
//!
//! `cargo bench -p models --bench quarter_car -- --warm-up-time 1 --measurement-time 3`
//!
//! Both derivative functions are evaluated on the same 256 (time, state) points, a
//! quarter of them on the bump, so neither gets a constant input to fold away or one
//! branch of the road law only.

use std::hint::black_box;

use bgdsl_runtime::{Model, Simulation, Solver, Trajectory};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use models::reference::quarter_car_derivatives;
use models::{QuarterCar, QuarterCarParams};

const POINTS: usize = 256;

/// Deterministic evaluation points around the static equilibrium.
fn points(params: &QuarterCarParams) -> Vec<(f64, [f64; 4])> {
    let mut x0 = [0.0; 4];
    QuarterCar::new(params.clone()).initial_state(&mut x0);
    (0..POINTS)
        .map(|i| {
            let s = (i as f64 * 0.618_033_988_749_895).fract() - 0.5;
            let t = if i % 4 == 0 {
                0.5 + 0.2 * (s + 0.5)
            } else {
                2.0 * (s + 0.5)
            };
            let x = [
                x0[0] + 0.01 * s,
                params.unsprung_mass * 0.5 * s,
                x0[2] - 0.02 * s,
                params.sprung_mass * 0.3 * s,
            ];
            (t, x)
        })
        .collect()
}

fn derivatives(c: &mut Criterion) {
    let params = QuarterCarParams {
        wave_amplitude: 0.01,
        ..Default::default()
    };
    let model = QuarterCar::new(params.clone());
    let points = points(&params);
    let mut group = c.benchmark_group("quarter_car_derivatives");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.bench_function("generated", |b| {
        let mut dx = [0.0; 4];
        b.iter(|| {
            let model = black_box(&model);
            let mut sum = 0.0;
            for (t, x) in black_box(&points) {
                model.derivatives::<f64>(*t, x, &mut dx);
                sum += dx[0] + dx[1] + dx[2] + dx[3];
            }
            sum
        })
    });
    group.bench_function("hand_written", |b| {
        let mut dx = [0.0; 4];
        b.iter(|| {
            let params = black_box(&params);
            let mut sum = 0.0;
            for (t, x) in black_box(&points) {
                quarter_car_derivatives(params, *t, x, &mut dx);
                sum += dx[0] + dx[1] + dx[2] + dx[3];
            }
            sum
        })
    });
    group.finish();
}

fn integration(c: &mut Criterion) {
    let model = QuarterCar::default();
    let mut x0 = [0.0; 4];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(&model, Solver::dopri5()).unwrap();
    let mut trajectory = Trajectory::for_model::<QuarterCar>(1001);
    c.bench_function("quarter_car_dopri5_0_to_10_s", |b| {
        b.iter(|| {
            trajectory.clear();
            sim.run_uniform(0.0, black_box(&x0), 10.0, 1001, &mut trajectory)
                .unwrap()
        })
    });
}

criterion_group!(benches, derivatives, integration);
criterion_main!(benches);
