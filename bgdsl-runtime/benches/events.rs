//! The cost of an event (detection, location, action and restart) for every method: a
//! ball bouncing 20 times (restitution 0.9, dropped from 1 m, run to its 20th apex,
//! 201 samples) against the anchor of the same run without events, the same free
//! fall with its floor 1e9 m below (the indicator is evaluated after every step but
//! never crosses).
//!
//! `cargo bench -p bgdsl-runtime --bench events` first prints a table (per method: the
//! median wall time of both runs over 101 interleaved repetitions, their steps, the
//! ratio, and the cost per event in microseconds and in steps of the anchor; and the
//! ball again with `interior_points = 0`, so the last column is what looking inside
//! every step costs the run), then times both runs with criterion.

use std::hint::black_box;
use std::time::{Duration, Instant};

use bgdsl_runtime::{
    EventOptions, FixedStep, Radau5Options, Rodas4Options, Simulation, Solver, Stats, Trajectory,
};
use criterion::{BenchmarkId, Criterion};

#[path = "../tests/support/hybrid.rs"]
mod hybrid;

use hybrid::Ball;

const BOUNCES: usize = 20;
const SAMPLES: usize = 201;

fn methods() -> [(&'static str, Solver); 5] {
    [
        ("rk4", Solver::Rk4(FixedStep::new(0.01))),
        ("dopri5", Solver::dopri5()),
        (
            "dopri5-fixed",
            Solver::DormandPrinceFixed(FixedStep::new(0.01)),
        ),
        ("radau5", Solver::Radau5(Radau5Options::default())),
        ("rodas4", Solver::Rodas4(Rodas4Options::default())),
    ]
}

/// The bouncing ball and its anchor, the free fall whose floor is never reached.
fn models() -> (Ball, Ball) {
    let ball = Ball::default();
    let free = Ball {
        floor: -1e9,
        ..Ball::default()
    };
    (ball, free)
}

/// A simulation of `model` with its trajectory, ready to run.
struct Prepared<'a> {
    sim: Simulation<'a, Ball>,
    traj: Trajectory,
    x0: [f64; 2],
    t_end: f64,
}

impl<'a> Prepared<'a> {
    fn new(model: &'a Ball, solver: Solver, t_end: f64) -> Self {
        Prepared {
            sim: Simulation::new(model, solver).unwrap(),
            traj: Trajectory::for_model::<Ball>(SAMPLES).with_event_capacity(2 * BOUNCES),
            x0: [model.h0, 0.0],
            t_end,
        }
    }

    fn run(&mut self) -> Stats {
        self.traj.clear();
        self.sim
            .run_uniform(0.0, &self.x0, self.t_end, SAMPLES, &mut self.traj)
            .unwrap()
    }
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn table() {
    let (ball, free) = models();
    let t_end = ball.apex(BOUNCES).0;
    println!(
        "{:<13} {:>11} {:>6} {:>11} {:>6} {:>7} {:>6} {:>10} {:>11} {:>14}",
        "method",
        "anchor µs",
        "steps",
        "ball µs",
        "steps",
        "events",
        "ratio",
        "µs/event",
        "steps/event",
        "inside points"
    );
    for (name, solver) in methods() {
        let mut anchor = Prepared::new(&free, solver, t_end);
        let mut bouncing = Prepared::new(&ball, solver, t_end);
        let mut ends_only = Prepared::new(&ball, solver, t_end);
        let options = EventOptions {
            interior_points: 0,
            ..EventOptions::default()
        };
        ends_only.sim.set_event_options(options).unwrap();
        let (mut ta, mut tb, mut tc) = (Vec::new(), Vec::new(), Vec::new());
        let (mut sa, mut sb) = (Stats::default(), Stats::default());
        for _ in 0..101 {
            let start = Instant::now();
            sa = black_box(anchor.run());
            ta.push(start.elapsed());
            let start = Instant::now();
            sb = black_box(bouncing.run());
            tb.push(start.elapsed());
            let start = Instant::now();
            black_box(ends_only.run());
            tc.push(start.elapsed());
        }
        assert_eq!((sa.events, sb.events), (0, BOUNCES));
        let (ta, tb) = (median(ta).as_secs_f64(), median(tb).as_secs_f64());
        let tc = median(tc).as_secs_f64();
        let per_event = (tb - ta) / BOUNCES as f64;
        let per_step = ta / sa.steps() as f64;
        println!(
            "{:<13} {:>11.1} {:>6} {:>11.1} {:>6} {:>7} {:>6.2} {:>10.2} {:>11.1} {:>+13.0}%",
            name,
            ta * 1e6,
            sa.steps(),
            tb * 1e6,
            sb.steps(),
            sb.events,
            tb / ta,
            per_event * 1e6,
            per_event / per_step,
            100.0 * (tb / tc - 1.0)
        );
    }
}

fn bench(c: &mut Criterion) {
    let (ball, free) = models();
    let t_end = ball.apex(BOUNCES).0;
    let mut group = c.benchmark_group("ball_20_bounces");
    for (name, solver) in methods() {
        let mut anchor = Prepared::new(&free, solver, t_end);
        group.bench_function(BenchmarkId::new("free_fall_anchor", name), |b| {
            b.iter(|| black_box(anchor.run()))
        });
        let mut bouncing = Prepared::new(&ball, solver, t_end);
        group.bench_function(BenchmarkId::new("bouncing", name), |b| {
            b.iter(|| black_box(bouncing.run()))
        });
    }
    group.finish();
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` does not, and only checks
    // that the benchmarks run.
    if std::env::args().any(|a| a == "--bench") {
        table();
    }
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c);
    c.final_summary();
}
