//! Which method should be the default: the evidence behind `Model::default_solver`
//! and the table in `docs/solvers.md`. Not a check (speed is not asserted in tests):
//!
//! ```sh
//! nice -n 10 cargo test --release -p bgdsl-runtime --test solver_choice -- --ignored --nocapture
//! ```
//!
//! Radau5, Rodas5P, Rodas4 and Dormand–Prince 5(4) run each problem at a sweep of
//! `rtol`; each run's cost is its **thread CPU time** (best of up to five runs; the
//! machine is shared, CPU time is what a run costs it), and its error is measured
//! against an independent reference (below). The table then gives, for each method, the
//! CPU time at which it reaches a target error, Radau5's achieved error at `rtol` 1e-3
//! and at 1e-6 (interpolated in log–log between the two runs that bracket it), as a
//! ratio to Radau5's (the anchor, in the same run): **a comparison at equal achieved
//! error, not at equal `rtol`**.
//!
//! - a non-stiff small model: Duffing's forced oscillator (2 states) to `t = 20`,
//!   reference Dormand–Prince at `rtol = atol = 1e-13`, absolute error (amplitude ~1);
//! - the Bari test set's ROBER, VDPOL, HIRES, OREGO, POLLU (3–20 states), the
//!   published references (`stiff_common`), error relative to each component;
//! - mass–spring–damper chains (`support/large_chains.rs`, `k = 1e4`, `c = 1e3`:
//!   eigenvalues from about −10 to −4000, stiff) with 1,000 and 10,000 states, sparse
//!   (split order), to `t = 1`; reference Radau5 at `rtol = 1e-11`, error relative to
//!   the initial amplitude 0.01; the same chain interleaved (banded LU) at 10,000; and
//!   the same sparse chain driven by `sin(5 t)` at its end to `t = 10` (a long run);
//!   the block chain (dense 20-state blocks coupled to their neighbours, rates 1 to
//!   1000: a stand-in for rigid bodies in a chain) at 1,000 and 10,000, error relative
//!   to its amplitude 0.1.
//!
//! The flagship's rows come from `models/tests/solver_choice.rs`.

#[path = "support/large_chains.rs"]
mod large_chains;
mod stiff_common;

use bgdsl_runtime::{
    DormandPrinceOptions, Model, Radau5Options, Rodas4Options, Rodas5POptions, Scalar, Simulation,
    Solver, SolverError, Stats,
};
use large_chains::{BlockChain, MassChain};
use stiff_common::*;

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

/// The four methods at `rtol`, `atol`, with budgets large enough for tight runs.
fn methods(rtol: f64, atol: f64) -> [Solver; 4] {
    [
        Solver::Radau5(Radau5Options {
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
        Solver::Rodas4(Rodas4Options {
            rtol,
            atol,
            max_steps: 1_000_000,
            ..Default::default()
        }),
        Solver::DormandPrince(DormandPrinceOptions {
            rtol,
            atol,
            ..Default::default()
        }),
    ]
}

/// One run's outcome: CPU seconds, achieved error, counters; or why it failed.
type Outcome = Result<(f64, f64, Stats), String>;

/// Runs `model` over `[0, t_end]` with `solver` (best CPU time of up to five runs, fewer
/// once they have used a second) and measures the end state's error with `error`.
fn measure<M: Model>(
    model: &M,
    solver: Solver,
    t_end: f64,
    error: &dyn Fn(&[f64]) -> f64,
) -> Outcome {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, solver).map_err(|e| e.to_string())?;
    let (mut best, mut spent, mut stats) = (f64::INFINITY, 0.0, Stats::default());
    for _ in 0..5 {
        let started = thread_cpu();
        stats = sim
            .run(0.0, &x0, &[t_end], &mut ())
            .map_err(|e| short(&e))?;
        let used = thread_cpu() - started;
        best = best.min(used);
        spent += used;
        if spent > 1.0 {
            break;
        }
    }
    Ok((best, error(sim.state()), stats))
}

/// A failure in a few words for the table.
fn short(error: &SolverError) -> String {
    match error {
        SolverError::StiffnessDetected { .. } => "stopped: stiffness detected".to_owned(),
        other => other.to_string().chars().take(100).collect(),
    }
}

/// The CPU time at which a method's runs reach error `target`: interpolated linearly in
/// `log cpu` against `log error` between the two runs whose errors bracket it; when
/// every run is more accurate than `target`, the cheapest run (an upper bound, marked
/// `≤`); `None` when no run reaches it.
fn cost_at(runs: &[Outcome], target: f64) -> Option<(f64, bool)> {
    let mut points: Vec<(f64, f64)> = runs
        .iter()
        .filter_map(|r| r.as_ref().ok())
        .filter(|(_, err, _)| *err > 0.0)
        .map(|&(cpu, err, _)| (err, cpu))
        .collect();
    points.sort_by(|a, b| b.0.total_cmp(&a.0));
    let bracketed = points
        .windows(2)
        .filter(|w| w[0].0 >= target && target >= w[1].0)
        .map(|w| {
            let (l0, l1, lt) = (w[0].0.ln(), w[1].0.ln(), target.ln());
            let s = if l0 > l1 { (l0 - lt) / (l0 - l1) } else { 0.0 };
            (w[0].1.ln() + s * (w[1].1.ln() - w[0].1.ln())).exp()
        })
        .min_by(f64::total_cmp);
    match (bracketed, points.first()) {
        (Some(cpu), _) => Some((cpu, false)),
        (None, Some(&(largest, _))) if largest <= target => points
            .iter()
            .map(|p| p.1)
            .min_by(f64::total_cmp)
            .map(|cpu| (cpu, true)),
        _ => None,
    }
}

/// Prints one problem's sweep and its summary rows (the markdown `docs/solvers.md`
/// quotes).
fn study<M: Model>(
    model: &M,
    label: &str,
    t_end: f64,
    rtols: &[f64],
    atol_per_rtol: f64,
    error: &dyn Fn(&[f64]) -> f64,
) {
    println!("\n### {label} ({} states)\n", M::N_STATES);
    println!("| rtol | method | CPU ms | error | steps | rejected | Jacobians | LUs |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    let names = methods(1.0, 1.0).map(|s| s.name());
    let mut runs: Vec<Vec<Outcome>> = vec![Vec::new(); names.len()];
    for &rtol in rtols {
        for (k, solver) in methods(rtol, atol_per_rtol * rtol).into_iter().enumerate() {
            let outcome = measure(model, solver, t_end, error);
            match &outcome {
                Ok((cpu, err, s)) => println!(
                    "| {rtol:.0e} | {} | {:.3} | {err:.1e} | {} | {} | {} | {} |",
                    names[k],
                    cpu * 1e3,
                    s.accepted,
                    s.rejected,
                    s.n_jac,
                    s.n_lu
                ),
                Err(e) => println!("| {rtol:.0e} | {} | failed: {e} | | | | | |", names[k]),
            }
            runs[k].push(outcome);
        }
    }
    println!();
    // The targets: Radau5's achieved error at rtol 1e-3 and 1e-6.
    let radau_error = |rtol: f64| {
        let k = rtols.iter().position(|&r| r == rtol)?;
        runs[0][k].as_ref().ok().map(|(_, err, _)| *err)
    };
    for (rtol, target) in [1e-3, 1e-6].map(|r| (r, radau_error(r))) {
        let Some(target) = target else {
            println!(
                "SUMMARY | {label} | {} | radau5 at {rtol:.0e} failed |",
                M::N_STATES
            );
            continue;
        };
        let anchor = cost_at(&runs[0], target).map(|(t, _)| t);
        let cells: Vec<String> = runs
            .iter()
            .map(|r| {
                let (t, bound) = match cost_at(r, target) {
                    Some(found) => found,
                    None => return "not reached".to_owned(),
                };
                let le = if bound { "≤ " } else { "" };
                match anchor {
                    Some(a) => format!("{le}{:.3} ms ({:.2})", t * 1e3, t / a),
                    None => format!("{le}{:.3} ms", t * 1e3),
                }
            })
            .collect();
        println!(
            "SUMMARY | {label} | {} | {rtol:.0e}: {target:.1e} | {} |",
            M::N_STATES,
            cells.join(" | ")
        );
    }
}

/// Duffing's forced, hardening oscillator `x'' + 0.3 x' + x + x³ = 0.5 cos(1.2 t)`
/// from `(1, 0)`: non-stiff, and not chaotic (the softening `- x` of Holmes' chaotic
/// example is not used).
struct Duffing;

impl Model for Duffing {
    type Params = ();
    const NAME: &'static str = "duffing";
    const STATE_NAMES: &'static [&'static str] = &["x", "v"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.0, 0.0]);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let c = T::from_f64;
        dx[0] = x[1];
        dx[1] = c(0.5 * (1.2 * t).cos()) - c(0.3) * x[1] - x[0] - x[0] * x[0] * x[0];
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// The largest error relative to each reference component (components below 1e-100
/// left out).
fn relative_to(reference: &[f64]) -> impl Fn(&[f64]) -> f64 + '_ {
    move |x| {
        x.iter()
            .zip(reference)
            .filter(|(_, r)| r.abs() > 1e-100)
            .map(|(x, r)| ((x - r) / r).abs())
            .fold(0.0, f64::max)
    }
}

/// The largest error relative to a fixed `scale`.
fn absolute_over(reference: &[f64], scale: f64) -> impl Fn(&[f64]) -> f64 + '_ {
    move |x| {
        x.iter()
            .zip(reference)
            .map(|(x, r)| (x - r).abs() / scale)
            .fold(0.0, f64::max)
    }
}

/// A stiff chain: `k = 1e4`, `c = 1e3`.
fn stiff_chain<const S: usize, const NNZ: usize>() -> MassChain<S, NNZ> {
    MassChain { k: 1e4, c: 1e3 }
}

/// A [`MassChain`] driven at its last mass by a force `sin(5 t)` N: it keeps moving, so
/// a long run has work to do after the transient (the same Jacobian pattern).
struct Forced<const S: usize, const NNZ: usize>(MassChain<S, NNZ>);

impl<const S: usize, const NNZ: usize> Model for Forced<S, NNZ> {
    type Params = ();
    const NAME: &'static str = "forced_chain";
    const STATE_NAMES: &'static [&'static str] = MassChain::<S, NNZ>::STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> =
        MassChain::<S, NNZ>::JACOBIAN_SPARSITY;
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        self.0.initial_state(x0);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.0.derivatives(t, x, dx);
        // The last mass's velocity: the last state (interleaved) or the last of the
        // velocities (split); both are index S - 1.
        dx[S - 1] += T::from_f64((5.0 * t).sin());
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// `model` to `t = 1` against Radau5 at `rtol = 1e-11`, the error relative to `scale`
/// (the initial amplitude), `atol = 1e-2 rtol scale`.
fn large_study<M: Model>(model: &M, label: &str, scale: f64, rtols: &[f64]) {
    long_study(model, label, 1.0, scale, rtols);
}

/// [`large_study`] to `t_end`.
fn long_study<M: Model>(model: &M, label: &str, t_end: f64, scale: f64, rtols: &[f64]) {
    let tight = Solver::Radau5(Radau5Options {
        rtol: 1e-11,
        atol: 1e-12 * scale,
        max_steps: 1_000_000,
        ..Default::default()
    });
    let (reference, _) = solve(model, tight, t_end);
    let error = absolute_over(&reference, scale);
    study(model, label, t_end, rtols, 1e-2 * scale, &error);
}

const SWEEP: [f64; 7] = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];

#[test]
#[ignore = "prints the default-solver study; run in release mode"]
fn small_models() {
    let tight = Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-13,
        atol: 1e-13,
        ..Default::default()
    });
    let (duffing, _) = solve(&Duffing, tight, 20.0);
    study(
        &Duffing,
        "Duffing (non-stiff)",
        20.0,
        &SWEEP,
        1e-3,
        &absolute_over(&duffing, 1.0),
    );
    let rober = relative_to(&ROBERTSON_REF);
    study(&Robertson, "ROBER", 1e11, &SWEEP, 1e-8, &rober);
    study(
        &VanDerPol,
        "VDPOL",
        2.0,
        &SWEEP,
        1.0,
        &relative_to(&VDP_REF),
    );
    let hires = relative_to(&HIRES_REF);
    study(&Hires, "HIRES", HIRES_T_END, &SWEEP, 1e-3, &hires);
    let orego = relative_to(&OREGO_REF);
    study(&Oregonator, "OREGO", 360.0, &SWEEP, 1.0, &orego);
    let pollu = relative_to(&POLLU_REF);
    study(&Pollution, "POLLU", 60.0, &SWEEP, 1.0, &pollu);
}

#[test]
#[ignore = "prints the default-solver study on large chains; run in release mode"]
fn large_models() {
    let rtols = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7];
    let chain = "stiff mass chain, sparse";
    large_study(&stiff_chain::<1000, 3496>(), chain, 0.01, &rtols);
    large_study(&stiff_chain::<10000, 34996>(), chain, 0.01, &rtols);
    let banded = "stiff mass chain, banded";
    large_study(&stiff_chain::<10000, 0>(), banded, 0.01, &rtols);
    let forced = "forced stiff mass chain, sparse, to t = 10";
    long_study(
        &Forced(stiff_chain::<1000, 3496>()),
        forced,
        10.0,
        0.01,
        &rtols,
    );
    long_study(
        &Forced(stiff_chain::<10000, 34996>()),
        forced,
        10.0,
        0.01,
        &rtols,
    );
    let blocks = "block chain (dense 20-state blocks)";
    large_study(&BlockChain::<1000>, blocks, 0.1, &rtols);
    large_study(&BlockChain::<10000>, blocks, 0.1, &rtols);
}
