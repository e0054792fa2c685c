//! The cost of events in the allocation-free integrators of `rk`: the ball of
//! `tests/support/hybrid.rs` bouncing 20 times (to its 20th apex, in one call) on
//! `rk::Rk4` (step 0.01 s) and `rk::DormandPrince` (default tolerances), against two
//! anchors in the same run: the same integrator on the free fall whose floor is 1e9 m
//! below (no event), and the std driver on the bouncing ball with the same settings
//! (one sample, at the end).
//!
//! `cargo bench -p bgdsl-runtime --bench rk_events` first prints a table (per method:
//! the median wall time over 101 interleaved repetitions of the three runs, the cost
//! per event, and the ratio to the driver), then times the runs with criterion.
//!
//! One run when this was written (2 cores shared with other builds, so noisy), the
//! table's medians: RK4 free fall 30.7 µs, bouncing 38.7 µs, the driver 41.9 µs (0.4
//! µs per event, 0.92 × the driver); DOPRI5 free fall 0.84 µs (a quadratic flight
//! takes huge steps), bouncing 17.3 µs, the driver 20.9 µs (0.8 µs per event, 0.83 ×
//! the driver).

use std::hint::black_box;
use std::time::{Duration, Instant};

use bgdsl_runtime::rk::{DormandPrince, Rk4};
use bgdsl_runtime::{DormandPrinceOptions, FixedStep, Simulation, Solver, Stats};
use criterion::{BenchmarkId, Criterion};

#[path = "../tests/support/hybrid.rs"]
mod hybrid;

use hybrid::Ball;

const BOUNCES: usize = 20;

/// A method: its name, the driver's solver, and a run of the rk integrator on a ball
/// to `t_end` in one call, returning the work.
type RkRun = fn(&Ball, f64) -> Stats;

fn rk4(ball: &Ball, t_end: f64) -> Stats {
    let mut rk4 = Rk4::<2, 1, 32>::new(FixedStep::new(0.01)).unwrap();
    let (mut t, mut x) = (0.0, [ball.h0, 0.0]);
    rk4.advance_to(ball, &mut t, &mut x, t_end).unwrap();
    rk4.stats()
}

fn dopri5(ball: &Ball, t_end: f64) -> Stats {
    let mut dopri = DormandPrince::<2, 1, 32>::new(DormandPrinceOptions::default()).unwrap();
    let (mut t, mut x) = (0.0, [ball.h0, 0.0]);
    dopri.advance_to(ball, &mut t, &mut x, t_end).unwrap();
    dopri.stats()
}

fn methods() -> [(&'static str, Solver, RkRun); 2] {
    [
        ("rk4", Solver::Rk4(FixedStep::new(0.01)), rk4),
        ("dopri5", Solver::dopri5(), dopri5),
    ]
}

fn driver(sim: &mut Simulation<'_, Ball>, ball: &Ball, t_end: f64) -> Stats {
    sim.run(0.0, &[ball.h0, 0.0], &[t_end], &mut ()).unwrap()
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn table() {
    let ball = Ball::default();
    let free = Ball {
        floor: -1e9,
        ..Ball::default()
    };
    let t_end = ball.apex(BOUNCES).0;
    println!(
        "{:<8} {:>14} {:>10} {:>13} {:>10} {:>12}",
        "method", "rk free µs", "rk ball µs", "driver µs", "µs/event", "rk/driver"
    );
    for (name, solver, run) in methods() {
        let mut sim = Simulation::new(&ball, solver).unwrap();
        let (mut tf, mut tb, mut td) = (Vec::new(), Vec::new(), Vec::new());
        let (mut sf, mut sb, mut sd) = (Stats::default(), Stats::default(), Stats::default());
        for _ in 0..101 {
            let start = Instant::now();
            sf = black_box(run(&free, t_end));
            tf.push(start.elapsed());
            let start = Instant::now();
            sb = black_box(run(&ball, t_end));
            tb.push(start.elapsed());
            let start = Instant::now();
            sd = black_box(driver(&mut sim, &ball, t_end));
            td.push(start.elapsed());
        }
        assert_eq!((sf.events, sb.events, sd.events), (0, BOUNCES, BOUNCES));
        let [tf, tb, td] = [tf, tb, td].map(|v| median(v).as_secs_f64());
        println!(
            "{:<8} {:>14.2} {:>10.2} {:>13.2} {:>10.3} {:>12.2}",
            name,
            tf * 1e6,
            tb * 1e6,
            td * 1e6,
            (tb - tf) / BOUNCES as f64 * 1e6,
            tb / td
        );
    }
}

fn bench(c: &mut Criterion) {
    let ball = Ball::default();
    let free = Ball {
        floor: -1e9,
        ..Ball::default()
    };
    let t_end = ball.apex(BOUNCES).0;
    let mut group = c.benchmark_group("rk_ball_20_bounces");
    for (name, solver, run) in methods() {
        group.bench_function(BenchmarkId::new("rk_free_fall_anchor", name), |b| {
            b.iter(|| black_box(run(&free, t_end)))
        });
        group.bench_function(BenchmarkId::new("rk_bouncing", name), |b| {
            b.iter(|| black_box(run(&ball, t_end)))
        });
        let mut sim = Simulation::new(&ball, solver).unwrap();
        group.bench_function(BenchmarkId::new("driver_bouncing_anchor", name), |b| {
            b.iter(|| black_box(driver(&mut sim, &ball, t_end)))
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
