//! What a host pays per call of its loop: the DC servo under its 1 kHz PI speed loop,
//! one second (1,000 `advance_with` calls, each restarting the method), with each
//! solver the `Stepper` can use.
//!
//! `cargo bench -p models --bench stepping -- --warm-up-time 1 --measurement-time 3`

use bgdsl_runtime::Solver;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use models::dc_servo::{run_speed_loop, DcServo, SPEED_LOOP};

fn speed_loop(c: &mut Criterion) {
    let mut group = c.benchmark_group("dc_servo_1kHz_1s");
    group.throughput(Throughput::Elements(1000));
    for name in ["dopri5", "radau5", "rodas4"] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let solver = Solver::from_name(name).expect("a known solver");
                run_speed_loop(
                    DcServo::default(),
                    solver,
                    SPEED_LOOP,
                    |t| if t >= 0.05 { 10.0 } else { 0.0 },
                    |t| if t >= 0.6 { 0.1 } else { 0.02 },
                    1000,
                )
                .expect("runs")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, speed_loop);
criterion_main!(benches);
