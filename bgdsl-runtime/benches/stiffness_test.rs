//! The cost of Dormand–Prince's stiffness test (Hairer's `h |λ|` estimate after every
//! accepted step, `DormandPrinceOptions::detect_stiffness`): the restricted three-body
//! orbit of Arenstorf (4 states, one period, rtol = atol = 1e-10, 843 steps; see
//! `tests/arenstorf.rs`) with the test on, against the same run with it off (the
//! anchor, in the same process).
//!
//! `cargo bench -p bgdsl-runtime --bench stiffness_test` first prints the medians of
//! 201 interleaved repetitions of both runs and their ratio, then times them with
//! criterion.

use std::hint::black_box;
use std::time::Instant;

use bgdsl_runtime::{DormandPrinceOptions, Model, Scalar, Simulation, Solver};
use criterion::Criterion;

const MU: f64 = 0.012277471;
const PERIOD: f64 = 17.065_216_560_157_963;
const Y0: [f64; 4] = [0.994, 0.0, 0.0, -2.001_585_106_379_082_5];

/// Arenstorf's orbit (Hairer, Nørsett & Wanner, *Solving ODEs I*, Sect. II.0).
struct Arenstorf;

impl Model for Arenstorf {
    type Params = ();
    const NAME: &'static str = "arenstorf";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2", "v1", "v2"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&Y0);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let (mu, mu1) = (T::from_f64(MU), T::from_f64(1.0 - MU));
        let (y1, y2, v1, v2) = (x[0], x[1], x[2], x[3]);
        let r1 = (y1 + mu) * (y1 + mu) + y2 * y2;
        let r2 = (y1 - mu1) * (y1 - mu1) + y2 * y2;
        let (d1, d2) = (r1 * r1.sqrt(), r2 * r2.sqrt());
        let two = T::from_f64(2.0);
        dx[0] = v1;
        dx[1] = v2;
        dx[2] = y1 + two * v2 - mu1 * (y1 + mu) / d1 - mu * (y1 - mu1) / d2;
        dx[3] = y2 - two * v1 - mu1 * y2 / d1 - mu * y2 / d2;
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

fn simulation(detect_stiffness: bool) -> Simulation<'static, Arenstorf> {
    let solver = Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-10,
        atol: 1e-10,
        detect_stiffness,
        ..Default::default()
    });
    Simulation::new(&Arenstorf, solver).unwrap()
}

fn run(sim: &mut Simulation<'_, Arenstorf>) -> usize {
    black_box(sim.run(0.0, &Y0, &[PERIOD], &mut ()).unwrap()).accepted
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let (mut on, mut off) = (simulation(true), simulation(false));
    assert_eq!(run(&mut on), run(&mut off), "the test changed the steps");
    let (mut t_on, mut t_off) = (Vec::new(), Vec::new());
    for _ in 0..201 {
        for (sim, times) in [(&mut on, &mut t_on), (&mut off, &mut t_off)] {
            let start = Instant::now();
            run(sim);
            times.push(start.elapsed().as_secs_f64() * 1e6);
        }
    }
    let (m_on, m_off) = (median(&mut t_on), median(&mut t_off));
    println!(
        "Arenstorf, one period: test on {m_on:.1} µs, off {m_off:.1} µs, ratio {:.3}",
        m_on / m_off
    );

    let mut c = Criterion::default().configure_from_args();
    c.bench_function("dopri5 arenstorf, stiffness test on", |b| {
        b.iter(|| run(&mut on))
    });
    c.bench_function("dopri5 arenstorf, stiffness test off", |b| {
        b.iter(|| run(&mut off))
    });
    c.final_summary();
}
