//! Proof that [`JacobianEvaluator::evaluate`], [`JacobianEvaluator::evaluate_ad`] and
//! [`JacobianEvaluator::jvp`] do not allocate once the evaluator is set up, compressed
//! or dense, on a hand-written and on a generated model.
//!
//! A global allocator is per binary, so this test has a binary of its own; it counts
//! the allocations (and reallocations) made on the current thread (`support/counting.rs`),
//! so neither the harness nor the tests running alongside on other threads are counted.

#[path = "support/chain.rs"]
mod chain;

use std::hint::black_box;

use bgdsl_runtime::{bond_graph, JacobianEvaluator, Model, SparsityPattern};

#[path = "support/counting.rs"]
mod counting;

use counting::{allocations_in, Counting};

#[global_allocator]
static GLOBAL: Counting = Counting;

bond_graph! {
    /// The Duffing oscillator: a generated model with a state-dependent Jacobian.
    model Duffing {
        param m = 1.0;
        param k = 1.0;
        param k3 = 1.0;
        param c = 0.1;
        param force = 0.5;
        param omega = 1.2;

        Se drive = force * (omega * t).cos();
        I  mass = m;
        C  spring { e = k * q + k3 * q.powi(3) };
        R  damper = c;
        1  v;

        drive -> v -> { mass, spring, damper };
        output x = spring.q;
    }
}

/// Evaluates Jacobians (by `evaluate` and `evaluate_ad`) and JVPs of `model` at a few
/// states with `evaluator`, counting allocations; returns the count and the
/// evaluations reported.
fn run<M: Model>(model: &M, evaluator: &mut JacobianEvaluator) -> (usize, usize) {
    let n = M::N_STATES;
    let mut x = vec![0.0; n];
    model.initial_state(&mut x);
    let mut jac = vec![0.0; n * n];
    let v = vec![1.0; n];
    let mut out = vec![0.0; n];
    // Warm up (nothing lazy should exist, but do not count it if it did).
    evaluator.evaluate(model, 0.0, &x, &mut jac);
    allocations_in(|| {
        let mut evaluations = 0;
        for step in 0..10 {
            let t = 0.01 * f64::from(step);
            x[0] += 1.0e-4;
            evaluations += evaluator.evaluate(model, t, &x, &mut jac);
            evaluations += evaluator.evaluate_ad(model, t, &x, &mut jac);
            evaluator.jvp(model, t, &x, &v, &mut out);
            black_box((&jac, &out));
        }
        evaluations
    })
}

#[test]
fn compressed_and_dense_evaluation_do_not_allocate() {
    let chain = chain::Chain::default();
    let mut compressed = JacobianEvaluator::new(&chain);
    let (allocations, evaluations) = run(&chain, &mut compressed);
    assert_eq!(allocations, 0, "compressed chain");
    assert_eq!(
        evaluations,
        10 * 2 * 5,
        "5 colours, evaluate and evaluate_ad, 10 times"
    );

    let mut dense = JacobianEvaluator::with_pattern(SparsityPattern::dense(chain::N_STATES));
    let (allocations, evaluations) = run(&chain, &mut dense);
    assert_eq!(allocations, 0, "dense chain");
    assert_eq!(evaluations, 10 * 2 * chain::N_STATES);

    let duffing = Duffing::default();
    let mut evaluator = JacobianEvaluator::new(&duffing);
    let (allocations, evaluations) = run(&duffing, &mut evaluator);
    assert_eq!(allocations, 0, "generated Duffing");
    assert_eq!(evaluations, 10 * 2 * 2);
}

/// The counter counts: the same harness sees the allocations of set-up.
#[test]
fn the_counter_sees_allocations() {
    let (allocations, evaluator) =
        allocations_in(|| JacobianEvaluator::new(&chain::Chain::default()));
    assert!(allocations > 0);
    black_box(evaluator);
}
