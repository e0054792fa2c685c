//! The stiff solvers against published reference solutions of the Bari *Test Set for
//! IVP Solvers* (see `stiff_common`).
//!
//! Each test asks for a tolerance, checks that every component of the final state is
//! within `k (atol + rtol |ref|)` of the reference (`k = 1` unless stated), and pins the
//! work counters. **The counters are pinned so that a change of the algorithm
//! (step-size control, Newton control, Jacobian and LU reuse) is deliberate**: such a
//! change must update them, and the diff shows what it costs or saves.
//!
//! Deliberate change (issue 15, tolerances that mean what users expect): Radau5's
//! tolerance transformation went from RADAU5's `rtol' = 0.1 rtol^(2/3)` to
//! `0.3 rtol^(4/5)` (at rtol 1e-6: `rtol'` 1e-5 → 4.7e-6), and a first Newton iteration
//! stops only when the contraction rate it relies on was measured with the same step
//! size (or the first correction is below the Newton tolerance). The Radau5 pins
//! (accepted, rejected, rhs, Jacobians, LU) moved from Robertson
//! [308, 2, 2503, 68, 320], Van der Pol [493, 12, 4414, 106, 786], HIRES
//! [105, 10, 1034, 37, 148], Oregonator [541, 36, 5421, 198, 876], POLLU
//! [22, 3, 201, 10, 48], E5 [391, 3, 3135, 86, 350] to the values below: 9–21 % more
//! steps and 13–24 % more evaluations at the same `rtol`, for smaller end-point errors
//! (in units of the tolerance, Bari atol ratios at rtol 1e-6: ROBER 0.20 → 0.09, VDPOL
//! 0.056 → 0.013, OREGO 0.29 → 0.14, POLLU 135 → 0.68).
//!
//! Earlier deliberate change: Radau5's default `reuse_jacobian_below` went from 0.001
//! (RADAU5's default for small systems) to 0.03, towards the 0.1 Hairer & Wanner advise
//! when Jacobians are costly, as they are for mechanism models (a Jacobian of the
//! 117-state quick return model costs about ten Newton iterations): 40–75 % fewer
//! Jacobians, 3–55 % fewer LU factorizations, 2–16 % more evaluations.

mod stiff_common;

use bgdsl_runtime::{Model, Radau5Options, Rodas4Options, Solver, Stats};
use stiff_common::*;

fn radau5(rtol: f64, atol: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol,
        ..Default::default()
    })
}

fn rodas4(rtol: f64, atol: f64) -> Solver {
    Solver::Rodas4(Rodas4Options {
        rtol,
        atol,
        ..Default::default()
    })
}

/// The counters in the order they are pinned.
fn counters(s: &Stats) -> [usize; 5] {
    [s.accepted, s.rejected, s.n_rhs, s.n_jac, s.n_lu]
}

/// Robertson to `t = 1e11`; reference: Bari test set, problem ROBER (computed with
/// RADAU5 in quadruple precision). `atol` is small because `y2` ends near 8e-14.
#[test]
fn robertson_to_1e11() {
    let (rtol, atol) = (1e-6, 1e-14);
    for solver in [radau5(rtol, atol), rodas4(rtol, atol)] {
        let (x, stats) = solve(&Robertson, solver, 1e11);
        let err = scaled_error(&x, &ROBERTSON_REF, rtol, atol);
        assert!(err <= 1.0, "{}: scaled error {err:e}, {x:?}", solver.name());
        // Mass is conserved: y1 + y2 + y3 = 1.
        assert!((x.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // Pinned: a change of the algorithm must be deliberate.
        let pinned = match solver.name() {
            "radau5" => [367, 2, 3021, 62, 338],
            _ => [459, 1, 2761, 459, 460],
        };
        assert_eq!(counters(&stats), pinned, "{}: {stats:?}", solver.name());
    }
}

/// Van der Pol with `μ = 1000` (`ε = 1e-6` in the scaled form) to `t = 2`, through a
/// steep jump of `y2`; reference: Bari test set, problem VDPOL.
#[test]
fn van_der_pol_mu_1000_to_2() {
    let (rtol, atol) = (1e-6, 1e-6);
    for solver in [radau5(rtol, atol), rodas4(rtol, atol)] {
        let (x, stats) = solve(&VanDerPol, solver, 2.0);
        let err = scaled_error(&x, &VDP_REF, rtol, atol);
        assert!(err <= 1.0, "{}: scaled error {err:e}, {x:?}", solver.name());
        // Pinned: a change of the algorithm must be deliberate.
        let pinned = match solver.name() {
            "radau5" => [596, 10, 5487, 112, 924],
            _ => [1061, 10, 6418, 1061, 1071],
        };
        assert_eq!(counters(&stats), pinned, "{}: {stats:?}", solver.name());
    }
}

/// HIRES to `t = 321.8122`; reference: Bari test set, problem HIRES.
#[test]
fn hires_to_321_8122() {
    let (rtol, atol) = (1e-6, 1e-9);
    for solver in [radau5(rtol, atol), rodas4(rtol, atol)] {
        let (x, stats) = solve(&Hires, solver, HIRES_T_END);
        let err = scaled_error(&x, &HIRES_REF, rtol, atol);
        assert!(err <= 1.0, "{}: scaled error {err:e}, {x:?}", solver.name());
        // Pinned: a change of the algorithm must be deliberate.
        let pinned = match solver.name() {
            "radau5" => [123, 7, 1190, 40, 158],
            _ => [272, 1, 1639, 272, 273],
        };
        assert_eq!(counters(&stats), pinned, "{}: {stats:?}", solver.name());
    }
}

/// The Oregonator to `t = 360`, through relaxation oscillations over six orders of
/// magnitude; reference: Bari test set, problem OREGO. Rodas4 needs a tighter `rtol`
/// than Radau5 for the same accuracy: its error estimate is not transformed, and
/// Rosenbrock methods lose order on stiff problems.
#[test]
fn oregonator_to_360() {
    let (rtol, atol) = (1e-6, 1e-6);
    for (solver, rtol, atol) in [
        (radau5(rtol, atol), rtol, atol),
        (rodas4(rtol / 10.0, atol / 10.0), rtol, atol),
    ] {
        let (x, stats) = solve(&Oregonator, solver, 360.0);
        let err = scaled_error(&x, &OREGO_REF, rtol, atol);
        assert!(err <= 1.0, "{}: scaled error {err:e}, {x:?}", solver.name());
        // Pinned: a change of the algorithm must be deliberate.
        let pinned = match solver.name() {
            "radau5" => [649, 41, 6519, 200, 992],
            _ => [2479, 6, 14906, 2479, 2485],
        };
        assert_eq!(counters(&stats), pinned, "{}: {stats:?}", solver.name());
    }
}

/// POLLU to `t = 60`; reference: Bari test set, problem POLLU (RADAU5 in quadruple
/// precision). `atol = rtol` as in the test set's runs. (With RADAU5's tolerance
/// transformation, before issue 15, Radau5 missed the tolerance here 135-fold: 22 steps,
/// two correct digits.)
#[test]
fn pollution_to_60() {
    let (rtol, atol) = (1e-6, 1e-6);
    for solver in [radau5(rtol, atol), rodas4(rtol, atol)] {
        let (x, stats) = solve(&Pollution, solver, 60.0);
        let err = scaled_error(&x, &POLLU_REF, rtol, atol);
        assert!(err <= 1.0, "{}: scaled error {err:e}, {x:?}", solver.name());
        // Pinned: a change of the algorithm must be deliberate.
        let pinned = match solver.name() {
            "radau5" => [24, 4, 227, 13, 52],
            _ => [22, 0, 134, 22, 22],
        };
        assert_eq!(counters(&stats), pinned, "{}: {stats:?}", solver.name());
    }
}

/// E5 to `t = 1e13`; reference: Bari test set, problem E5 (RADAU in quadruple
/// precision). `atol = 1e-24` because `y2` and `y3` end near 9e-23.
///
/// The linear invariant `y2 - y3 - y4 = 0` holds for the exact solution and, with the
/// Jacobian exact, for every Runge–Kutta and Rosenbrock step in exact arithmetic. In
/// floating point Radau5 keeps it to `4.8e-4 |y2|` at the end (measured; 1.2e-3 before
/// issue 15's tolerance change; asserted below 2e-3): the Newton iteration sees a
/// violation in its residual and removes it. Rodas4 is left out: it breaks the
/// invariant by 4e-2 to 1.3e6 times `y2` at rtol 1e-4…1e-8 (measured), and misses the
/// tolerance by 1.8–110x; its stages are single linear solves with
/// `1/(h γ) I - J` at steps near 1e8, whose rounding nothing corrects.
#[test]
fn e5_to_1e13() {
    let (rtol, atol) = (1e-6, 1e-24);
    let solver = radau5(rtol, atol);
    let (x, stats) = solve(&E5, solver, E5_T_END);
    let err = scaled_error(&x, &E5_REF, rtol, atol);
    assert!(err <= 1.0, "scaled error {err:e}, {x:?}");
    let invariant = (x[1] - x[2] - x[3]).abs() / x[1].abs();
    assert!(
        invariant <= 2e-3,
        "|y2 - y3 - y4| / |y2| = {invariant:e}, {x:?}"
    );
    // Pinned: a change of the algorithm must be deliberate.
    assert_eq!(counters(&stats), [466, 3, 3792, 90, 364], "{stats:?}");
}

/// The declared sparsity patterns of the problems are their Jacobians' structure: a
/// dependence missing from a declaration would make the solver's Jacobian wrong, one
/// too many only costs work. Observed by central differences at points where no term
/// is lost to rounding.
#[test]
fn declared_patterns_are_the_observed_ones() {
    fn check<M: Model>(model: &M, x: &[f64]) {
        let declared: Vec<Vec<usize>> = M::JACOBIAN_SPARSITY
            .unwrap()
            .iter()
            .map(|r| r.to_vec())
            .collect();
        assert_eq!(observed_pattern(model, x), declared, "{}", M::NAME);
    }
    check(&Robertson, &[0.5, 1e-5, 0.5]);
    check(&Hires, &HIRES_REF);
    check(&Oregonator, &[2.0, 3.0, 4.0]);
    check(&Pollution, &POLLU_REF);
    check(&E5, &[1e-3, 1e-9, 1e-9, 1e-9]);
}

/// Radau5 meets the tolerance asked for, within `k = 3`, at every `rtol` in 1e-4…1e-8 on
/// three problems of the Bari test set (references there), with `atol = c rtol`: POLLU
/// (`c = 1`), HIRES (`c = 1e-4`), VDPOL (`c = 1`). With RADAU5's transformation and
/// Newton stopping (before issue 15) POLLU failed at every `rtol` here (`k` = 9.6, 135,
/// 78 at 1e-4, 1e-6, 1e-8); HIRES and VDPOL passed (`k` <= 2.8 and <= 0.1): their
/// misses grew past 3 only below 1e-8 (HIRES 10 at 1e-10).
#[test]
fn radau5_meets_the_tolerance() {
    fn check<M: Model>(model: &M, t_end: f64, reference: &[f64], c: f64) {
        for rtol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let atol = c * rtol;
            let (x, _) = solve(model, radau5(rtol, atol), t_end);
            let k = scaled_error(&x, reference, rtol, atol);
            assert!(k <= 3.0, "{} at rtol {rtol:e}: k = {k:e}", M::NAME);
        }
    }
    check(&Pollution, 60.0, &POLLU_REF, 1.0);
    check(&Hires, HIRES_T_END, &HIRES_REF, 1e-4);
    check(&VanDerPol, 2.0, &VDP_REF, 1.0);
}
