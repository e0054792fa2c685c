//! What events cost against steep smooth laws: the bouncing ball's 20 bounces with
//! impact events (DOPRI5) beside the same ball on a steep smooth penalty contact
//! (Radau5), and the half-wave rectifier with the ideal diode (events, DOPRI5) beside
//! the exponential-law diode (smooth, Radau5), each pair in one run.
//!
//! `cargo bench -p bgdsl-tests --bench hybrid -- --warm-up-time 1 --measurement-time 3`
//!
//! Both members of a pair run at the same tolerances (rtol 1e-8, atol 1e-10) over the
//! same interval: the ball until the apex after its 21st impact, the rectifier five
//! periods of 50 Hz. The ratio of a pair's times is the price of the smooth law.

use std::hint::black_box;

use bgdsl_runtime::{
    DormandPrinceOptions, Model, Radau5Options, Simulation, Solver, Trajectory,
};
use criterion::{criterion_group, criterion_main, Criterion};
use models::hybrid::{BallPenalty, BouncingBall, HalfWaveRectifier, HalfWaveRectifierExp};

const RTOL: f64 = 1e-8;
const ATOL: f64 = 1e-10;
const SAMPLES: usize = 101;

fn dopri5() -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol: RTOL,
        atol: ATOL,
        ..Default::default()
    })
}

fn radau5() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: RTOL,
        atol: ATOL,
        ..Default::default()
    })
}

/// Runs `model` with `solver` from its initial state to `t_end`, sampled uniformly,
/// and returns the number of events (for the bench's one-line report).
fn run<M: Model>(model: &M, solver: Solver, t_end: f64, traj: &mut Trajectory) -> usize {
    let mut x0 = vec![0.0; M::STATE_NAMES.len()];
    model.initial_state(&mut x0);
    traj.clear();
    let stats = Simulation::new(model, solver)
        .unwrap()
        .run_uniform(0.0, &x0, t_end, SAMPLES, traj)
        .unwrap();
    stats.events
}

/// The closed form's apex after the 21st impact of the default ball: (time, height).
fn ball_end(ball: &BouncingBall) -> (f64, f64) {
    let p = &ball.params;
    let mut t = (2.0 * p.h0 / p.g).sqrt();
    let mut u = p.g * t;
    for _ in 0..20 {
        u *= p.restitution;
        t += 2.0 * u / p.g;
    }
    let w = p.restitution * u;
    (t + w / p.g, w * w / (2.0 * p.g))
}

fn ball(c: &mut Criterion) {
    let events = BouncingBall::default();
    let smooth = BallPenalty::default();
    let (t_end, apex) = ball_end(&events);
    let mut traj = Trajectory::for_model::<BouncingBall>(SAMPLES).with_event_capacity(64);
    let mut smooth_traj = Trajectory::for_model::<BallPenalty>(SAMPLES);
    let n = run(&events, dopri5(), t_end, &mut traj);
    assert_eq!(n, 21, "21 impacts");
    run(&smooth, radau5(), t_end, &mut smooth_traj);
    let last = SAMPLES - 1;
    eprintln!(
        "ball at the closed form's 21st apex ({apex:.6} m at {t_end:.6} s): events {:.6} m, \
         penalty {:.6} m",
        traj.value(last, "height").unwrap(),
        smooth_traj.value(last, "height").unwrap()
    );
    let mut group = c.benchmark_group("ball_20_bounces");
    group.bench_function("events_dopri5", |b| {
        b.iter(|| run(black_box(&events), dopri5(), t_end, &mut traj))
    });
    group.bench_function("penalty_radau5", |b| {
        b.iter(|| run(black_box(&smooth), radau5(), t_end, &mut smooth_traj))
    });
    group.finish();
}

fn rectifier(c: &mut Criterion) {
    let ideal = HalfWaveRectifier::default();
    let smooth = HalfWaveRectifierExp::default();
    let t_end = 5.0 / ideal.params.frequency;
    let mut traj = Trajectory::for_model::<HalfWaveRectifier>(SAMPLES).with_event_capacity(32);
    let mut smooth_traj = Trajectory::for_model::<HalfWaveRectifierExp>(SAMPLES);
    let mut group = c.benchmark_group("rectifier_5_periods");
    group.bench_function("ideal_events_dopri5", |b| {
        b.iter(|| run(black_box(&ideal), dopri5(), t_end, &mut traj))
    });
    group.bench_function("exponential_radau5", |b| {
        b.iter(|| run(black_box(&smooth), radau5(), t_end, &mut smooth_traj))
    });
    group.finish();
}

criterion_group!(benches, ball, rectifier);
criterion_main!(benches);
