//! The cost of one derivative evaluation, one Jacobian-vector product and one full
//! Jacobian (dense AD: one dual evaluation per column; compressed AD: one per colour),
//! on a generated model (the quarter car, 4 states, 4 colours: compression cannot help)
//! and on a hand-written 120-state chain of masses coupled by stiff spring-dampers
//! (5 colours: compression saves 115 of 120 evaluations).
//!
//! `cargo bench -p bgdsl-runtime --bench jacobian -- --warm-up-time 1 --measurement-time 3`
//!
//! Each iteration is one call at a fixed point (inputs behind `black_box`): ns per call.

#[path = "../tests/support/chain.rs"]
mod chain;

use std::hint::black_box;

use bgdsl_runtime::{bond_graph, Dual, JacobianEvaluator, Model, SparsityPattern};
use criterion::{criterion_group, criterion_main, Criterion};

bond_graph! {
    /// The quarter car of the `models` crate (same graph and laws), generated here so
    /// the runtime's benchmarks need no dependency on `models`.
    model QuarterCar {
        param sprung_mass = 300.0;
        param unsprung_mass = 40.0;
        param suspension_stiffness = 20000.0;
        param suspension_damping = 1500.0;
        param tyre_stiffness = 200000.0;
        param g = 9.81;
        param speed = 10.0;
        param bump_distance = 5.0;
        param bump_height = 0.05;
        param bump_length = 1.0;
        param wave_amplitude = 0.01;
        param wavelength = 20.0;

        Sf road = (if t > bump_distance / speed && t < (bump_distance + bump_length) / speed {
                0.5 * bump_height * (6.283185307179586 * speed / bump_length)
                    * (6.283185307179586 * (speed * t - bump_distance) / bump_length).sin()
            } else {
                0.0
            })
            + wave_amplitude * (6.283185307179586 * speed / wavelength)
                * (6.283185307179586 * speed * t / wavelength).cos();
        0  contact;
        C  tyre = tyre_stiffness;
        1  wheel;
        I  unsprung = unsprung_mass;
        Se wheel_weight = -unsprung_mass * g;
        0  strut;
        1  deflection;
        C  spring = suspension_stiffness;
        R  damper = suspension_damping;
        1  body;
        I  sprung = sprung_mass;
        Se body_weight = -sprung_mass * g;

        road -> contact -> { tyre, wheel };
        wheel -> { unsprung, strut };
        wheel_weight -> wheel;
        strut -> deflection -> { spring, damper };
        strut -> body -> sprung;
        body_weight -> body;

        init tyre.q = (sprung_mass + unsprung_mass) * g / tyre_stiffness;
        init spring.q = sprung_mass * g / suspension_stiffness;

        output body_velocity = body.f;
    }
}

/// Benchmarks `model` at `(t, x)` under `name`.
fn bench_model<M: Model>(c: &mut Criterion, name: &str, model: &M, t: f64, x: &[f64]) {
    let n = M::N_STATES;
    let mut compressed = JacobianEvaluator::new(model);
    let mut dense = JacobianEvaluator::with_pattern(SparsityPattern::dense(n));
    eprintln!(
        "{name}: {n} states, {} colours (dense: {})",
        compressed.n_colours(),
        dense.n_colours()
    );
    let v: Vec<f64> = (0..n).map(|i| 1.0 + 0.01 * i as f64).collect();
    let xd: Vec<Dual> = x.iter().zip(&v).map(|(&a, &b)| Dual::new(a, b)).collect();
    let mut dx = vec![0.0; n];
    let mut dxd = vec![Dual::default(); n];
    let mut out = vec![0.0; n];
    let mut jac = vec![0.0; n * n];

    let mut group = c.benchmark_group(name);
    group.bench_function("derivatives f64", |b| {
        b.iter(|| black_box(model).derivatives(black_box(t), black_box(x), &mut dx))
    });
    group.bench_function("derivatives Dual", |b| {
        b.iter(|| black_box(model).derivatives(black_box(t), black_box(&xd), &mut dxd))
    });
    group.bench_function("jvp", |b| {
        b.iter(|| {
            compressed.jvp(
                black_box(model),
                black_box(t),
                black_box(x),
                black_box(&v),
                &mut out,
            )
        })
    });
    group.bench_function("jacobian dense AD", |b| {
        b.iter(|| dense.evaluate(black_box(model), black_box(t), black_box(x), &mut jac))
    });
    group.bench_function("jacobian compressed AD", |b| {
        b.iter(|| compressed.evaluate(black_box(model), black_box(t), black_box(x), &mut jac))
    });
    group.finish();
}

fn quarter_car(c: &mut Criterion) {
    let model = QuarterCar::default();
    let mut x = [0.0; 4];
    model.initial_state(&mut x);
    x[1] += 4.0;
    x[3] -= 30.0;
    bench_model(c, "quarter_car (generated)", &model, 0.55, &x);
}

fn chain_of_masses(c: &mut Criterion) {
    let model = chain::Chain::default();
    let x: Vec<f64> = (0..chain::N_STATES)
        .map(|r| {
            let s = (r as f64 * 0.618_033_988_749_895).fract() - 0.5;
            if r.is_multiple_of(2) {
                1.0e-3 * s
            } else {
                1.0e-2 * s
            }
        })
        .collect();
    bench_model(c, "chain_120 (hand-written)", &model, 0.3, &x);
}

criterion_group!(benches, quarter_car, chain_of_masses);
criterion_main!(benches);
