//! The quick return mechanism with rigid joints
//! (`models::quick_return_rigid::QuickReturnRigid`, the crank driven by a flow source:
//! one state, no solve; `QuickReturnRigidCoupled`, driven through the compliant drive
//! coupling: one independent inertia, one linear solve per evaluation) against the
//! compliant flagship (`models::quick_return::QuickReturn`, Radau5 at rtol 1e-6, atol
//! 1e-10), each a whole 0–5 s run recorded into the results-file columns every 1 ms
//! (5001 samples, `models::quick_return::run::record`), in the same bench run:
//!
//! - `rigid_<method>_rtol1e-6`: the flow-driven rigid model with each method at rtol
//!   1e-6 (atol 1e-9); the catalogue's choice is DOPRI5 (the target: under
//!   3 ms);
//! - `coupled_radau5_rtol1e-6`, `coupled_dopri5_rtol1e-6`: the coupled rigid model;
//! - `flagship_radau5_rtol1e-6`: the compliant model, for the ratio;
//! - `rigid_derivative`, `coupled_derivative`, `rigid_outputs`, `coupled_outputs`:
//!   the cost of one evaluation (the coupled model's includes its solve).
//!
//! Before timing it prints, per setting, the solver's counters, the median wall time,
//! its ratio to the flagship's and, for the flow-driven model, the largest deviation of
//! the drive torque from the rigid inverse dynamics (`reference::rigid_state`) relative
//! to its peak.
//!
//! `cargo bench -p models --bench quick_return_rigid -- --warm-up-time 1 --measurement-time 3`
//!
//! Measured on the project's 2-core machine (shared with other jobs: ±10 % and more):
//! see the README's section "Rigid joints and algebraic loops".

use core::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

use bgdsl_runtime::{DormandPrinceOptions, FixedStep, Model, Radau5Options, Rodas4Options, Solver};
#[path = "common/timing.rs"]
mod timing;
use timing::time_per_call;

use criterion::{criterion_group, criterion_main, Criterion};
use models::quick_return::results::sample_times;
use models::quick_return::run::record;
use models::quick_return::QuickReturn;
use models::quick_return_rigid::{
    rigid_state, Mechanism, QuickReturnRigid, QuickReturnRigidCoupled,
};

fn dopri5(rtol: f64) -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol,
        atol: 1e-9,
        ..Default::default()
    })
}

fn radau5(rtol: f64, atol: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol,
        ..Default::default()
    })
}

fn rodas4(rtol: f64) -> Solver {
    Solver::Rodas4(Rodas4Options {
        rtol,
        atol: 1e-9,
        ..Default::default()
    })
}

/// The flow-driven model's methods, by name.
fn rigid_methods() -> [(&'static str, Solver); 4] {
    [
        ("dopri5", dopri5(1e-6)),
        ("radau5", radau5(1e-6, 1e-9)),
        ("rodas4", rodas4(1e-6)),
        (
            "rk4_1ms",
            Solver::Rk4(FixedStep {
                step: 1e-3,
                ..Default::default()
            }),
        ),
    ]
}

/// One derivative and one evaluation of the outputs, at states along a run.
fn evaluation_costs<M: Model>(model: &M) -> (Duration, Duration) {
    let n = M::N_STATES;
    let mut states = Vec::new();
    {
        let mut sim = bgdsl_runtime::Simulation::new(model, radau5(1e-6, 1e-9)).unwrap();
        let mut x0 = vec![0.0; n];
        model.initial_state(&mut x0);
        let times: Vec<f64> = (0..64).map(|k| 5.0 * f64::from(k) / 63.0).collect();
        let mut keep = |t: f64, x: &[f64], _y: &[f64]| states.push((t, x.to_vec()));
        sim.run(0.0, &x0, &times, &mut keep).unwrap();
    }
    let mut dx = vec![0.0; n];
    let mut y = vec![0.0; M::N_OUTPUTS];
    let per = |d: Duration| d / states.len() as u32;
    let derivative = per(time_per_call(|| {
        for (t, x) in &states {
            model.derivatives::<f64>(*t, black_box(x), &mut dx);
        }
    }));
    let outputs = per(time_per_call(|| {
        for (t, x) in &states {
            model.outputs::<f64>(*t, black_box(x), &mut y);
        }
    }));
    (derivative, outputs)
}

fn report() {
    let times = sample_times();
    let flagship = QuickReturn::default();
    let flagship_wall = time_per_call(|| {
        black_box(record(&flagship, radau5(1e-6, 1e-10), &times).unwrap());
    });
    println!(
        "flagship (compliant, radau5 rtol 1e-6, atol 1e-10): {:.2} ms per run",
        flagship_wall.as_secs_f64() * 1e3
    );
    let ratio = |wall: Duration| wall.as_secs_f64() / flagship_wall.as_secs_f64();

    let rigid = QuickReturnRigid::default();
    let (derivative, outputs) = evaluation_costs(&rigid);
    println!(
        "QuickReturnRigid: one derivative {:.3} us, one evaluation of the outputs {:.3} us",
        derivative.as_secs_f64() * 1e6,
        outputs.as_secs_f64() * 1e6
    );
    let mechanism = rigid.params.rigid_params();
    let w = rigid.params.w_drive;
    let peak = (0..3600)
        .map(|i| rigid_state(TAU * f64::from(i) / 3600.0, w, 0.0, &mechanism).tc[2].abs())
        .fold(0.0, f64::max);
    for (name, solver) in rigid_methods() {
        let run = record(&rigid, solver, &times).unwrap();
        let angle = run.results.column("crank_angle").unwrap();
        let torque = run.results.column("Tc_z").unwrap();
        let error = angle
            .iter()
            .zip(torque)
            .map(|(&a, &tc)| (tc - rigid_state(a, w, 0.0, &mechanism).tc[2]).abs())
            .fold(0.0, f64::max);
        let s = run.stats;
        let wall = time_per_call(|| {
            black_box(record(&rigid, solver, &times).unwrap());
        });
        println!(
            "  {name}: {:.3} ms per run ({:.4} of the flagship's); {} steps ({} rejected), \
             {} rhs, {} Jacobians; drive torque vs the inverse dynamics {:.1e} of its peak",
            wall.as_secs_f64() * 1e3,
            ratio(wall),
            s.steps(),
            s.rejected,
            s.n_rhs,
            s.n_jac,
            error / peak
        );
    }

    let coupled = QuickReturnRigidCoupled::default();
    let (derivative, outputs) = evaluation_costs(&coupled);
    println!(
        "QuickReturnRigidCoupled: one derivative (with its solve) {:.3} us, one evaluation \
         of the outputs {:.3} us",
        derivative.as_secs_f64() * 1e6,
        outputs.as_secs_f64() * 1e6
    );
    for (name, solver) in [("radau5", radau5(1e-6, 1e-9)), ("dopri5", dopri5(1e-6))] {
        let s = record(&coupled, solver, &times).unwrap().stats;
        let wall = time_per_call(|| {
            black_box(record(&coupled, solver, &times).unwrap());
        });
        println!(
            "  {name}: {:.3} ms per run ({:.4} of the flagship's); {} steps ({} rejected), \
             {} rhs, {} Jacobians ({} directional derivatives)",
            wall.as_secs_f64() * 1e3,
            ratio(wall),
            s.steps(),
            s.rejected,
            s.n_rhs,
            s.n_jac,
            s.n_jac_rhs
        );
    }
}

fn runs(c: &mut Criterion) {
    // Only under `cargo bench` (which passes `--bench`), not when `cargo test` runs
    // the benchmarks once as a smoke test.
    if std::env::args().any(|a| a == "--bench") {
        report();
    }
    let times = sample_times();
    let rigid = QuickReturnRigid::default();
    let coupled = QuickReturnRigidCoupled::default();
    let flagship = QuickReturn::default();
    let mut group = c.benchmark_group("quick_return_rigid");
    group.sample_size(20);
    for (name, solver) in rigid_methods() {
        group.bench_function(format!("rigid_{name}_rtol1e-6"), |b| {
            b.iter(|| record(black_box(&rigid), solver, &times).unwrap())
        });
    }
    for (name, solver) in [("radau5", radau5(1e-6, 1e-9)), ("dopri5", dopri5(1e-6))] {
        group.bench_function(format!("coupled_{name}_rtol1e-6"), |b| {
            b.iter(|| record(black_box(&coupled), solver, &times).unwrap())
        });
    }
    group.bench_function("flagship_radau5_rtol1e-6", |b| {
        b.iter(|| record(black_box(&flagship), radau5(1e-6, 1e-10), &times).unwrap())
    });
    let mut x = vec![0.0; QuickReturnRigid::N_STATES];
    rigid.initial_state(&mut x);
    let mut dx = x.clone();
    let mut y = vec![0.0; QuickReturnRigid::N_OUTPUTS];
    group.bench_function("rigid_derivative", |b| {
        b.iter(|| rigid.derivatives::<f64>(0.3, black_box(&x), &mut dx))
    });
    group.bench_function("rigid_outputs", |b| {
        b.iter(|| rigid.outputs::<f64>(0.3, black_box(&x), &mut y))
    });
    let mut xc = vec![0.0; QuickReturnRigidCoupled::N_STATES];
    coupled.initial_state(&mut xc);
    let mut dxc = xc.clone();
    let mut yc = vec![0.0; QuickReturnRigidCoupled::N_OUTPUTS];
    group.bench_function("coupled_derivative", |b| {
        b.iter(|| coupled.derivatives::<f64>(0.3, black_box(&xc), &mut dxc))
    });
    group.bench_function("coupled_outputs", |b| {
        b.iter(|| coupled.outputs::<f64>(0.3, black_box(&xc), &mut yc))
    });
    group.finish();
}

criterion_group!(benches, runs);
criterion_main!(benches);
