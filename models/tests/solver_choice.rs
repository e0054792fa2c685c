//! Which stiff method for the flagship: Radau5, Rodas4 and Rodas5P on the quick return
//! mechanism (117 states, 0–5 s, the results file's 5001 samples) at rtol 1e-3…1e-10
//! (atol = 1e-4 rtol). Not a check (speed is not asserted in tests): run with
//!
//! ```sh
//! nice -n 10 cargo test --release -p models --test solver_choice -- --ignored --nocapture
//! ```
//!
//! For each method and tolerance it prints the counters, the wall time (best of five
//! runs, recording included), the ratio to Radau5's at the same rtol (the anchor, in
//! the same run), and the achieved error against Radau5 at rtol 1e-11 (atol 1e-15): the
//! largest deviation of any recorded column relative to that column's peak |value|.
//! `docs/solvers.md` quotes the numbers.

use std::time::Duration;

use bgdsl_runtime::{Radau5Options, Rodas4Options, Rodas5POptions, Solver};
use models::quick_return::results::{sample_times, COLUMNS};
use models::quick_return::run::{record, Recorded};
use models::quick_return::QuickReturn;

/// The largest deviation of `run` from `reference` over the columns, each relative to
/// the column's peak |value| in the reference (columns zero throughout are skipped).
fn achieved_error(run: &Recorded, reference: &Recorded) -> f64 {
    (1..COLUMNS.len())
        .map(|i| {
            let (a, b) = (run.results.column_at(i), reference.results.column_at(i));
            let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let deviation = a
                .iter()
                .zip(b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            if peak > 0.0 {
                deviation / peak
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max)
}

fn methods(rtol: f64, atol: f64) -> [Solver; 3] {
    [
        Solver::Radau5(Radau5Options {
            rtol,
            atol,
            ..Default::default()
        }),
        Solver::Rodas4(Rodas4Options {
            rtol,
            atol,
            max_steps: 1_000_000,
            ..Default::default()
        }),
        Solver::Rodas5P(Rodas5POptions {
            rtol,
            atol,
            max_steps: 1_000_000,
            ..Default::default()
        }),
    ]
}

#[test]
#[ignore = "prints the flagship's work-precision table; run in release mode"]
fn flagship_work_precision() {
    let model = QuickReturn::default();
    let times = sample_times();
    let reference_solver = Solver::Radau5(Radau5Options {
        rtol: 1e-11,
        atol: 1e-15,
        ..Default::default()
    });
    let reference = record(&model, reference_solver, &times).expect("reference run");
    println!(
        "{:<8} {:>6} {:>6} {:>4} {:>7} {:>7} {:>6} {:>6} {:>9} {:>6} {:>9}",
        "method",
        "rtol",
        "steps",
        "rej",
        "rhs",
        "jac dir",
        "jac",
        "lu",
        "wall ms",
        "ratio",
        "error"
    );
    for k in 3..=10 {
        let rtol = 10f64.powi(-k);
        let mut anchor = None;
        for solver in methods(rtol, 1e-4 * rtol) {
            let mut best = Duration::MAX;
            let mut last = None;
            for _ in 0..5 {
                match record(&model, solver, &times) {
                    Ok(run) => {
                        best = best.min(run.wall);
                        last = Some(run);
                    }
                    Err(e) => {
                        println!("{:<8} {rtol:>6.0e} failed: {e}", solver.name());
                        break;
                    }
                }
            }
            let Some(run) = last else { continue };
            let anchor = *anchor.get_or_insert(best);
            let s = run.stats;
            println!(
                "{:<8} {:>6.0e} {:>6} {:>4} {:>7} {:>7} {:>6} {:>6} {:>9.2} {:>6.2} {:>9.2e}",
                solver.name(),
                rtol,
                s.accepted,
                s.rejected,
                s.n_rhs,
                s.n_jac_rhs,
                s.n_jac,
                s.n_lu,
                best.as_secs_f64() * 1e3,
                best.as_secs_f64() / anchor.as_secs_f64(),
                achieved_error(&run, &reference)
            );
        }
    }
}
