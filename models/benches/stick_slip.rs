//! What events cost against a steep smooth law on the stick-slip oscillator: the mass
//! on a belt with Coulomb friction and stiction ([`BeltFriction`]: modes and events,
//! DOPRI5) beside the same mass on the smooth law of [`BeltFrictionSmooth`] (`tanh`
//! with a velocity scale of 1e-6 m/s and a Stribeck bump; stiff: Radau5), over 0–20 s
//! (two start-up slips, then four stick-slip cycles), 2001 samples.
//!
//! `cargo bench -p models --bench stick_slip -- --warm-up-time 1 --measurement-time 3`
//!
//! Both run at rtol 1e-6, atol 1e-8; the events model also at rtol 1e-4. Before timing,
//! each run's largest position error against the closed-form reference of
//! `tests/belt_friction/reference.rs` is printed with its step count: the smooth law's
//! error is its own (a stuck mass creeps at a slip of order `v_s`, and it breaks away a
//! little early and late), so no tolerance brings it to the events model's accuracy,
//! and the comparison at one tolerance is the fair one for time.

use std::hint::black_box;

use bgdsl_runtime::{
    DormandPrinceOptions, Model, Radau5Options, Simulation, Solver, Stats, Trajectory,
};
use criterion::{criterion_group, criterion_main, Criterion};
use models::hybrid::{BeltFriction, BeltFrictionSmooth};

#[path = "../tests/belt_friction/reference.rs"]
#[allow(dead_code)]
mod reference;

const T_END: f64 = 20.0;
const SAMPLES: usize = 2001;

fn dopri5(rtol: f64) -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol,
        atol: rtol * 1e-2,
        ..Default::default()
    })
}

fn radau5(rtol: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol: rtol * 1e-2,
        ..Default::default()
    })
}

/// Runs `model` from its initial state over 0–20 s into `traj` (cleared first).
fn run<M: Model>(model: &M, solver: Solver, traj: &mut Trajectory) -> Stats {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    traj.clear();
    Simulation::new(model, solver)
        .unwrap()
        .run_uniform(0.0, &x0, T_END, SAMPLES, traj)
        .unwrap()
}

/// The largest |x − x_reference| over the samples.
fn error(traj: &Trajectory) -> f64 {
    let belt = reference::Belt {
        m: 1.0,
        k: 10.0,
        v_b: 0.1,
        fs: 0.6 * 9.81,
        fc: 0.4 * 9.81,
    };
    let segments = belt.solve(-1.0, 0.0, T_END);
    let x = traj.column("x").unwrap();
    traj.times()
        .iter()
        .zip(x)
        .map(|(&t, &x)| (x - belt.at(&segments, t).0).abs())
        .fold(0.0, f64::max)
}

fn stick_slip(c: &mut Criterion) {
    let events = BeltFriction::default();
    let smooth = BeltFrictionSmooth::default();
    assert_eq!(smooth.params.v_s, 1e-6);
    let mut traj = Trajectory::for_model::<BeltFriction>(SAMPLES).with_event_capacity(64);
    let mut smooth_traj = Trajectory::for_model::<BeltFrictionSmooth>(SAMPLES);
    for rtol in [1e-6, 1e-4] {
        let stats = run(&events, dopri5(rtol), &mut traj);
        eprintln!(
            "events, dopri5 rtol {rtol:e}: {} steps, {} events, max |x − reference| {:.2e} m",
            stats.steps(),
            stats.events,
            error(&traj)
        );
    }
    let stats = run(&smooth, radau5(1e-6), &mut smooth_traj);
    eprintln!(
        "smooth, radau5 rtol 1e-6: {} steps, {} LU, max |x − reference| {:.2e} m",
        stats.steps(),
        stats.n_lu,
        error(&smooth_traj)
    );
    let mut group = c.benchmark_group("stick_slip_20s");
    group.bench_function("events_dopri5_rtol1e-6", |b| {
        b.iter(|| run(black_box(&events), dopri5(1e-6), &mut traj))
    });
    group.bench_function("events_dopri5_rtol1e-4", |b| {
        b.iter(|| run(black_box(&events), dopri5(1e-4), &mut traj))
    });
    group.bench_function("smooth_radau5_rtol1e-6", |b| {
        b.iter(|| run(black_box(&smooth), radau5(1e-6), &mut smooth_traj))
    });
    group.finish();
}

criterion_group!(benches, stick_slip);
criterion_main!(benches);
