//! Proof that [`JacobianEvaluator::evaluate`], [`JacobianEvaluator::evaluate_ad`] and
//! [`JacobianEvaluator::jvp`] do not allocate once the evaluator is set up, compressed
//! or dense, on a hand-written and on a generated model.
//!
//! A global allocator is per binary, so this test has a binary of its own. It counts
//! allocations (and reallocations) made on the current thread while a thread-local flag
//! is set, in a thread-local counter, so neither the harness nor the tests running
//! alongside on other threads are counted.

#[path = "support/chain.rs"]
mod chain;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::hint::black_box;

use bgdsl_runtime::{bond_graph, JacobianEvaluator, Model, SparsityPattern};

struct CountingAllocator;

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn note_allocation() {
    // `try_with`: the allocator may run while thread-locals are being torn down.
    if COUNTING.try_with(Cell::get).unwrap_or(false) {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
    }
}

// SAFETY: every call is forwarded unchanged to the system allocator; counting has no
// effect on the memory handed out.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        // SAFETY: the caller's contract for `layout` is passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        // SAFETY: as above.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note_allocation();
        // SAFETY: as above; `ptr` was allocated by `System` through this allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// The number of heap allocations `f` makes on this thread.
fn allocations_in<T>(f: impl FnOnce() -> T) -> (usize, T) {
    let before = ALLOCATIONS.with(Cell::get);
    COUNTING.with(|c| c.set(true));
    let value = f();
    COUNTING.with(|c| c.set(false));
    (ALLOCATIONS.with(Cell::get) - before, value)
}

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
