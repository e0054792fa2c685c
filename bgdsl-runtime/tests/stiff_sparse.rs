//! The stiff solvers on a model whose iteration matrices take the sparse path (a
//! fill-reducing order, static pivots checked for stability, the numerical pattern of
//! the Jacobians), against the same model declaring no pattern (banded linear algebra
//! with partial pivoting, full Jacobians): the same solution, and the fallback to
//! partial pivoting when the static pivots are unstable.

#[path = "support/pairs.rs"]
mod pairs;

#[path = "support/pair_runs.rs"]
mod pair_runs;

use bgdsl_runtime::{Solver, Stats};
use pair_runs::{run, scaled_difference, solvers};
use pairs::{Pairs, N};

/// With pivots that need no help, the sparse path reproduces the banded one to well
/// within the tolerance, with compressed Jacobians and no fallback; `a_k` follows its
/// forcing `sin(t + 0.3 k)` (up to the lag of the damped oscillator, `O(1 / ω)`).
#[test]
fn sparse_and_banded_paths_agree() {
    let (rtol, atol) = (1e-6, 1e-9);
    let t_end = 6.0;
    for solver in solvers(rtol, atol) {
        let (sparse, s) = run(&Pairs::<true>::new(1e3), solver, t_end);
        let (dense, d) = run(&Pairs::<false>::new(1e3), solver, t_end);
        let diff = scaled_difference(&sparse, &dense, rtol, atol);
        assert!(diff < 5.0, "{}: {diff:e}\n{s:?}\n{d:?}", solver.name());
        assert_eq!(s.n_lu_fallback, 0, "{}: {s:?}", solver.name());
        assert_eq!(d.n_lu_fallback, 0, "{}: {d:?}", solver.name());
        // The dense evaluator takes one direction per state; the sparse one a few per
        // Jacobian once the pattern is known.
        assert_eq!(d.n_jac_rhs - jacobian_f(&d, solver), N * d.n_jac);
        assert!(
            s.n_jac_rhs - jacobian_f(&s, solver) <= 6 * s.n_jac + 2 * N,
            "{}: {s:?}",
            solver.name()
        );
        for (k, a) in sparse[..pairs::PAIRS].iter().enumerate() {
            let forcing = (t_end + 0.3 * k as f64).sin();
            assert!((a - forcing).abs() < 1e-2, "a{k} = {a}, forcing {forcing}");
        }
    }
}

/// Rodas4 counts one `f64` evaluation per Jacobian for `∂f/∂t` in `n_jac_rhs`.
fn jacobian_f(s: &Stats, solver: Solver) -> usize {
    if solver.name() == "rodas4" {
        s.n_jac
    } else {
        0
    }
}

/// With `ω = 1e10` the elimination of an oscillator on its diagonal pivots grows like
/// `ω h` and fails its stability test once the steps are long: those factorizations are
/// done again with partial pivoting, counted, and the solution is that of the banded
/// path.
#[test]
fn unstable_static_pivots_fall_back_to_partial_pivoting() {
    let (rtol, atol) = (1e-6, 1e-8);
    let t_end = 6.0;
    for solver in solvers(rtol, atol) {
        let (sparse, s) = run(&Pairs::<true>::new(1e10), solver, t_end);
        let (dense, d) = run(&Pairs::<false>::new(1e10), solver, t_end);
        assert!(s.n_lu_fallback > 0, "{}: {s:?}", solver.name());
        assert!(s.n_lu_fallback <= s.n_lu);
        assert_eq!(d.n_lu_fallback, 0);
        let diff = scaled_difference(&sparse, &dense, rtol, atol);
        assert!(diff < 5.0, "{}: {diff:e}\n{s:?}\n{d:?}", solver.name());
    }
}
