//! Work-precision data of the stiff methods on the Bari test-set problems (see
//! `stiff_common` for the problems and the sources of their reference values): the
//! Rust half of `docs/work-precision/run.sh`, which runs scipy and SUNDIALS on the same
//! problems and writes `docs/work-precision.md`. Not a check: run with
//!
//! ```sh
//! cargo test --release -p bgdsl-runtime --test stiff_work_precision -- --ignored --nocapture
//! ```
//!
//! For each problem, method and `rtol` in 1e-3…1e-10 (with `atol = c rtol`, `c` fixed
//! per problem, the same for every tool) it prints one tab-separated row starting with
//! `WP`: the work counters, the wall time (best of three runs) and the achieved
//! accuracy in two measures, defined in `docs/work-precision/problems.py` (and equal
//! there): the correct digits `-log10 max_i |x_i - ref_i| / (c + |ref_i|)` and the
//! factor `k = max_i |x_i - ref_i| / (atol + rtol |ref_i|)` by which the end point
//! misses (`k > 1`) or meets (`k <= 1`) the tolerance asked for.

mod stiff_common;

use std::time::{Duration, Instant};

use bgdsl_runtime::{Model, Radau5Options, Rodas4Options, Simulation, Solver};
use stiff_common::*;

/// The tolerances of the table.
const RTOLS: [f64; 8] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

/// The methods of the table at tolerances `rtol`, `atol`.
fn methods(rtol: f64, atol: f64) -> [Solver; 2] {
    [
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
    ]
}

/// Prints the rows of `problem` (its name in the table), integrated to `t_end` with
/// `atol = c rtol`, against `reference`.
fn rows<M: Model>(problem: &str, model: &M, t_end: f64, reference: &[f64], c: f64) {
    for rtol in RTOLS {
        let atol = c * rtol;
        for solver in methods(rtol, atol) {
            let mut x0 = vec![0.0; M::N_STATES];
            model.initial_state(&mut x0);
            let mut best = Duration::MAX;
            let mut sim = Simulation::new(model, solver).unwrap();
            let mut failed = None;
            for _ in 0..3 {
                let started = Instant::now();
                if let Err(e) = sim.run(0.0, &x0, &[t_end], &mut ()) {
                    failed = Some(e);
                    break;
                }
                best = best.min(started.elapsed());
            }
            let s = sim.stats();
            let (digits, k, status) = match failed {
                Some(e) => (
                    f64::NAN,
                    f64::NAN,
                    format!("failed: {e}").replace('\t', " "),
                ),
                None => {
                    let x = sim.state();
                    let mixed = x
                        .iter()
                        .zip(reference)
                        .map(|(x, r)| (x - r).abs() / (c + r.abs()))
                        .fold(0.0, f64::max);
                    let k = scaled_error(x, reference, rtol, atol);
                    (-mixed.log10(), k, "ok".to_owned())
                }
            };
            println!(
                "WP\t{problem}\tbgdsl\t{}\t{rtol:e}\t{atol:e}\t{}\t{}\t{}\t{}\t{}\t{:.6e}\t{digits:.3}\t{k:.3e}\t{status}",
                solver.name(),
                s.accepted,
                s.rejected,
                s.n_rhs,
                s.n_jac,
                s.n_lu,
                best.as_secs_f64(),
            );
        }
    }
}

#[test]
#[ignore = "prints work-precision rows for docs/work-precision/run.sh; run in release mode"]
fn work_precision_on_the_bari_test_set() {
    // The ratios `c = atol / rtol` are those of docs/work-precision/problems.py.
    rows("ROBER", &Robertson, 1e11, &ROBERTSON_REF, 1e-8);
    rows("VDPOL", &VanDerPol, 2.0, &VDP_REF, 1.0);
    rows("HIRES", &Hires, HIRES_T_END, &HIRES_REF, 1e-4);
    rows("OREGO", &Oregonator, 360.0, &OREGO_REF, 1.0);
    rows("POLLU", &Pollution, 60.0, &POLLU_REF, 1.0);
    rows("E5", &E5, E5_T_END, &E5_REF, 1e-24);
}
