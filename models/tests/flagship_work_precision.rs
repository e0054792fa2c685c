//! Work-precision rows of the flagship (the quick return mechanism, 0–5 s) for
//! `docs/work-precision/run.sh`, in the format of
//! `bgdsl-runtime/tests/stiff_work_precision.rs`: Radau5 and Rodas4 at `rtol` 1e-3 …
//! 1e-10 with `atol = 1e-4 rtol` (the flagship's ratio: rtol 1e-6, atol 1e-10), the
//! end state at `t = 5` against a reference run of Radau5 at `rtol` 1e-12, `atol`
//! 1e-16 (no published reference exists; Rodas4 at `rtol` 1e-11 checks it, printed as
//! a `WPNOTE` row). Not a check: run with
//!
//! ```sh
//! cargo test --release -p models --test flagship_work_precision -- --ignored --nocapture
//! ```

use std::time::{Duration, Instant};

use bgdsl_runtime::{Model, Radau5Options, Rodas4Options, Simulation, Solver};
use models::quick_return::QuickReturn;

const T_END: f64 = 5.0;
const C: f64 = 1e-4;

/// The end state of a run of the flagship with `solver`, and the best wall time of
/// `repeat` runs, with the run's counters.
fn run(solver: Solver, repeat: usize) -> (Vec<f64>, Duration, bgdsl_runtime::Stats) {
    let model = QuickReturn::default();
    let mut x0 = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(&model, solver).unwrap();
    let mut best = Duration::MAX;
    for _ in 0..repeat {
        let started = Instant::now();
        sim.run(0.0, &x0, &[T_END], &mut ()).unwrap();
        best = best.min(started.elapsed());
    }
    (sim.state().to_vec(), best, sim.stats())
}

fn radau5(rtol: f64, atol: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol,
        max_steps: 10_000_000,
        ..Default::default()
    })
}

fn rodas4(rtol: f64, atol: f64) -> Solver {
    Solver::Rodas4(Rodas4Options {
        rtol,
        atol,
        max_steps: 10_000_000,
        ..Default::default()
    })
}

/// `(digits, k)` as in `stiff_work_precision.rs`.
fn accuracy(x: &[f64], reference: &[f64], rtol: f64, atol: f64) -> (f64, f64) {
    let (mut mixed, mut k) = (0.0f64, 0.0f64);
    for (x, r) in x.iter().zip(reference) {
        mixed = mixed.max((x - r).abs() / (C + r.abs()));
        k = k.max((x - r).abs() / (atol + rtol * r.abs()));
    }
    (-mixed.log10(), k)
}

#[test]
#[ignore = "prints work-precision rows for docs/work-precision/run.sh; run in release mode"]
fn flagship_work_precision() {
    let (reference, _, _) = run(radau5(1e-12, 1e-16), 1);
    let (check, _, _) = run(rodas4(1e-11, 1e-15), 1);
    let (digits, _) = accuracy(&check, &reference, 1.0, 0.0);
    println!("WPNOTE\tFLAGSHIP\treference: Radau5 at rtol 1e-12 and Rodas4 at rtol 1e-11 agree to {digits:.2} digits");
    for rtol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10] {
        let atol = C * rtol;
        for solver in [radau5(rtol, atol), rodas4(rtol, atol)] {
            let (x, wall, s) = run(solver, 3);
            let (digits, k) = accuracy(&x, &reference, rtol, atol);
            println!(
                "WP\tFLAGSHIP\tbgdsl\t{}\t{rtol:e}\t{atol:e}\t{}\t{}\t{}\t{}\t{}\t{:.6e}\t{digits:.3}\t{k:.3e}\tok",
                solver.name(),
                s.accepted,
                s.rejected,
                s.n_rhs,
                s.n_jac,
                s.n_lu,
                wall.as_secs_f64(),
            );
        }
    }
}
