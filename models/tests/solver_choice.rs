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

/// The CPU time this thread has used, in seconds.
fn thread_cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant Linux knows.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The CPU time at which `runs` (`(error, cpu)`) reach `target`, interpolated in
/// log–log between the two runs that bracket it (as `bgdsl-runtime`'s
/// `tests/solver_choice.rs` does); `None` when none reaches it or none is less
/// accurate.
fn cost_at(runs: &[(f64, f64)], target: f64) -> Option<f64> {
    let mut points = runs.to_vec();
    points.sort_by(|a, b| b.0.total_cmp(&a.0));
    points
        .windows(2)
        .filter(|w| w[0].0 >= target && target >= w[1].0)
        .map(|w| {
            let (l0, l1, lt) = (w[0].0.ln(), w[1].0.ln(), target.ln());
            let s = if l0 > l1 { (l0 - lt) / (l0 - l1) } else { 0.0 };
            (w[0].1.ln() + s * (w[1].1.ln() - w[0].1.ln())).exp()
        })
        .min_by(f64::total_cmp)
}

/// The flagship's row of the default-solver table (`docs/solvers.md`): Radau5,
/// Rodas5P, Rodas4 and Dormand–Prince 5(4) at rtol 1e-2…1e-8 (atol = 1e-4 rtol),
/// **thread CPU time** of each whole recorded run (best of up to three), error as in
/// [`flagship_work_precision`]; then each method's CPU time at Radau5's achieved error
/// at rtol 1e-3 and 1e-6, as a ratio to Radau5's. Run with
///
/// ```sh
/// nice -n 10 cargo test --release -p models --test solver_choice default -- --ignored --nocapture
/// ```
#[test]
#[ignore = "prints the flagship's default-solver rows; run in release mode"]
fn flagship_default_solver() {
    let model = QuickReturn::default();
    let times = sample_times();
    let reference_solver = Solver::Radau5(Radau5Options {
        rtol: 1e-11,
        atol: 1e-15,
        ..Default::default()
    });
    let reference = record(&model, reference_solver, &times).expect("reference run");
    let rtols = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];
    let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new(); 4];
    let mut radau_at = Vec::new();
    println!("| rtol | method | CPU ms | error | steps | rejected | Jacobians | LUs |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    for rtol in rtols {
        let [radau, rodas4, rodas5p] = methods(rtol, 1e-4 * rtol);
        let dopri = Solver::DormandPrince(bgdsl_runtime::DormandPrinceOptions {
            rtol,
            atol: 1e-4 * rtol,
            ..Default::default()
        });
        for (k, solver) in [radau, rodas5p, rodas4, dopri].into_iter().enumerate() {
            let (mut best, mut spent, mut last) = (f64::INFINITY, 0.0, None);
            for _ in 0..3 {
                let started = thread_cpu();
                let outcome = record(&model, solver, &times);
                let used = thread_cpu() - started;
                match outcome {
                    Ok(run) => {
                        best = best.min(used);
                        spent += used;
                        last = Some(run);
                    }
                    Err(e) => {
                        let text: String = e.to_string().chars().take(100).collect();
                        println!(
                            "| {rtol:.0e} | {} | failed: {text} | | | | | |",
                            solver.name()
                        );
                        break;
                    }
                }
                if spent > 2.0 {
                    break;
                }
            }
            let Some(run) = last else { continue };
            let err = achieved_error(&run, &reference);
            let s = run.stats;
            println!(
                "| {rtol:.0e} | {} | {:.2} | {err:.1e} | {} | {} | {} | {} |",
                solver.name(),
                best * 1e3,
                s.accepted,
                s.rejected,
                s.n_jac,
                s.n_lu
            );
            runs[k].push((err, best));
            if k == 0 && (rtol == 1e-3 || rtol == 1e-6) {
                radau_at.push((rtol, err));
            }
        }
    }
    for (rtol, target) in radau_at {
        let anchor = cost_at(&runs[0], target);
        let cells: Vec<String> = runs
            .iter()
            .map(|r| match (cost_at(r, target), anchor) {
                (Some(t), Some(a)) => format!("{:.2} ms ({:.2})", t * 1e3, t / a),
                (Some(t), None) => format!("{:.2} ms", t * 1e3),
                (None, _) => "not reached".to_owned(),
            })
            .collect();
        println!(
            "SUMMARY | flagship (quick return) | 117 | {rtol:.0e}: {target:.1e} | {} |",
            cells.join(" | ")
        );
    }
}
