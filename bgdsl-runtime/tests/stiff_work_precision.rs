//! Work-precision data of the stiff methods on the Bari test-set problems (see
//! `stiff_common` for the problems and the sources of their reference values). Not a
//! check: run with
//!
//! ```sh
//! cargo test --release -p bgdsl-runtime --test stiff_work_precision -- --ignored --nocapture
//! ```
//!
//! For each problem, method and tolerance it prints the work counters, the wall time
//! (best of three) and the achieved accuracy: the largest error relative to the
//! reference component, and the number of correct digits as in the test set's reports
//! (`-log10` of that error).

mod stiff_common;

use std::time::{Duration, Instant};

use bgdsl_runtime::{Model, Radau5Options, Rodas4Options, Simulation, Solver};
use stiff_common::*;

fn table<M: Model>(model: &M, t_end: f64, reference: &[f64], atol_per_rtol: f64) {
    println!("\n{} (atol = {atol_per_rtol:e} rtol)", M::NAME);
    println!(
        "{:<7} {:>6} {:>6} {:>4} {:>7} {:>6} {:>6} {:>9} {:>9} {:>6}",
        "method", "rtol", "steps", "rej", "rhs", "jac", "lu", "wall µs", "rel.err", "digits"
    );
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let atol = atol_per_rtol * rtol;
        let solvers = [
            Solver::Radau5(Radau5Options {
                rtol,
                atol,
                ..Default::default()
            }),
            Solver::Rodas4(Rodas4Options {
                rtol,
                atol,
                ..Default::default()
            }),
        ];
        for solver in solvers {
            let mut x0 = vec![0.0; M::N_STATES];
            model.initial_state(&mut x0);
            let mut best = Duration::MAX;
            let mut sim = Simulation::new(model, solver).unwrap();
            for _ in 0..3 {
                let started = Instant::now();
                sim.run(0.0, &x0, &[t_end], &mut ()).unwrap();
                best = best.min(started.elapsed());
            }
            let s = sim.stats();
            let err = relative_error(sim.state(), reference);
            println!(
                "{:<7} {:>6.0e} {:>6} {:>4} {:>7} {:>6} {:>6} {:>9.0} {:>9.2e} {:>6.1}",
                solver.name(),
                rtol,
                s.accepted,
                s.rejected,
                s.n_rhs,
                s.n_jac,
                s.n_lu,
                best.as_secs_f64() * 1e6,
                err,
                -err.log10()
            );
        }
    }
}

#[test]
#[ignore = "prints a work-precision table; run in release mode"]
fn work_precision_on_the_bari_test_set() {
    table(&Robertson, 1e11, &ROBERTSON_REF, 1e-8);
    table(&VanDerPol, 2.0, &VDP_REF, 1.0);
    table(&Hires, HIRES_T_END, &HIRES_REF, 1e-3);
    table(&Oregonator, 360.0, &OREGO_REF, 1.0);
    table(&Pollution, 60.0, &POLLU_REF, 1.0);
    table(&E5, E5_T_END, &E5_REF, 1e-20);
}
