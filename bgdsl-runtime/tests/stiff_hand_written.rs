//! Hand-written Jacobians on the stiff solvers' sparse path: a dense
//! [`Model::jacobian`] without a declared pattern is factored over its detected
//! pattern (the issue: POLLU was 2x slower when only the Jacobian was written), and a
//! sparse [`Model::jacobian_sparse`] needs no `n × n` storage at all.
//!
//! The "hand-written" Jacobians here are those of the `Pairs` oscillators
//! (`support/pairs.rs`) computed by the runtime's own automatic differentiation, so
//! they are exact; what is tested is which path they take. Only the sparse path can
//! fall back to partial pivoting (`Stats::n_lu_fallback`): with `ω = 1e10` its static
//! pivots fail, so a fallback count above zero proves the sparse LU was used, where the
//! banded path of a model declaring no pattern has none.

#[path = "support/pair_runs.rs"]
mod pair_runs;
#[path = "support/pairs.rs"]
mod pairs;

use std::cell::{Cell, RefCell};

use bgdsl_runtime::{Jacobian, JacobianEvaluator, Model, Scalar, Solver, SparsityPattern, Stats};
use pair_runs::{run, scaled_difference, solvers};
use pairs::{Pairs, N};

/// `Pairs<true>` with its Jacobian written densely and no declared pattern.
struct Dense {
    inner: Pairs<true>,
    evaluator: RefCell<JacobianEvaluator>,
    calls: Cell<usize>,
}

/// `Pairs<true>` with its Jacobian written sparsely, in the declared pattern's order.
struct Sparse {
    inner: Pairs<true>,
    evaluator: RefCell<JacobianEvaluator>,
    jac: RefCell<Jacobian>,
    calls: Cell<usize>,
}

impl Dense {
    fn new(omega: f64) -> Self {
        let inner = Pairs::<true>::new(omega);
        Dense {
            evaluator: RefCell::new(JacobianEvaluator::new(&inner)),
            inner,
            calls: Cell::new(0),
        }
    }
}

impl Sparse {
    fn new(omega: f64) -> Self {
        let inner = Pairs::<true>::new(omega);
        let pattern = SparsityPattern::for_model::<Pairs<true>>().unwrap();
        Sparse {
            evaluator: RefCell::new(JacobianEvaluator::new(&inner)),
            jac: RefCell::new(Jacobian::new(pattern.into())),
            inner,
            calls: Cell::new(0),
        }
    }
}

impl Model for Dense {
    type Params = ();
    const NAME: &'static str = "pairs_dense_jacobian";
    const STATE_NAMES: &'static [&'static str] = Pairs::<true>::STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        self.inner.initial_state(x0);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.inner.derivatives(t, x, dx);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    fn jacobian(&self, t: f64, x: &[f64], jac: &mut [f64]) -> bool {
        self.calls.set(self.calls.get() + 1);
        self.evaluator
            .borrow_mut()
            .evaluate_ad(&self.inner, t, x, jac);
        true
    }
}

impl Model for Sparse {
    type Params = ();
    const NAME: &'static str = "pairs_sparse_jacobian";
    const STATE_NAMES: &'static [&'static str] = Pairs::<true>::STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Pairs::<true>::JACOBIAN_SPARSITY;
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        self.inner.initial_state(x0);
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.inner.derivatives(t, x, dx);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    fn jacobian_sparse(&self, t: f64, x: &[f64], values: &mut [f64]) -> bool {
        self.calls.set(self.calls.get() + 1);
        let mut jac = self.jac.borrow_mut();
        self.evaluator
            .borrow_mut()
            .evaluate_sparse(&self.inner, t, x, &mut jac);
        values.copy_from_slice(jac.values());
        true
    }
}

/// Directional derivatives of automatic differentiation in a run: `n_jac_rhs` less
/// Rodas4's one `f64` evaluation per Jacobian for `∂f/∂t`.
fn ad_directions(s: &Stats, solver: Solver) -> usize {
    s.n_jac_rhs
        - if solver.name() == "rodas4" {
            s.n_jac
        } else {
            0
        }
}

/// A dense hand-written Jacobian without a declared pattern takes the sparse path (it
/// falls back to partial pivoting where the static pivots fail, which only the sparse
/// path does), is the only Jacobian used (no directional derivative), and gives the
/// solution of the automatically differentiated model with a declared pattern, to
/// within the tolerance (5 `atol + rtol |x|`, as `stiff_sparse.rs`).
#[test]
fn a_dense_hand_written_jacobian_takes_the_sparse_path() {
    let (rtol, atol) = (1e-6, 1e-8);
    for solver in solvers(rtol, atol) {
        let model = Dense::new(1e10);
        let (x, s) = run(&model, solver, 6.0);
        let (reference, r) = run(&Pairs::<true>::new(1e10), solver, 6.0);
        let (_, banded) = run(&Pairs::<false>::new(1e10), solver, 6.0);
        assert!(s.n_lu_fallback > 0, "{}: {s:?}", solver.name());
        assert_eq!(banded.n_lu_fallback, 0, "{}: {banded:?}", solver.name());
        assert_eq!(ad_directions(&s, solver), 0, "{}: {s:?}", solver.name());
        // Set-up evaluates it three times to find its pattern; the run once per
        // Jacobian.
        assert_eq!(model.calls.get(), 3 + s.n_jac, "{}", solver.name());
        let diff = scaled_difference(&x, &reference, rtol, atol);
        assert!(diff < 5.0, "{}: {diff:e}\n{s:?}\n{r:?}", solver.name());
    }
}

/// A sparse hand-written Jacobian is used in place of automatic differentiation (once
/// at set-up to find it, then once per Jacobian), and gives the same solution.
#[test]
fn a_sparse_hand_written_jacobian_is_used() {
    let (rtol, atol) = (1e-6, 1e-9);
    for solver in solvers(rtol, atol) {
        let model = Sparse::new(1e3);
        let (x, s) = run(&model, solver, 6.0);
        let (reference, r) = run(&Pairs::<true>::new(1e3), solver, 6.0);
        assert_eq!(ad_directions(&s, solver), 0, "{}: {s:?}", solver.name());
        assert!(ad_directions(&r, solver) > 0);
        assert_eq!(model.calls.get(), 1 + s.n_jac, "{}", solver.name());
        let diff = scaled_difference(&x, &reference, rtol, atol);
        assert!(diff < 5.0, "{}: {diff:e}\n{s:?}\n{r:?}", solver.name());
    }
    assert_eq!(N, Sparse::STATE_NAMES.len());
}
