//! Proof that the per-evaluation solve of implicit unknowns (`implicit::solve`,
//! `Solution::refine`, `ImplicitMemory`) allocates nothing, on success and on failure,
//! alone and inside a model's derivatives on `f64` and dual numbers.
//!
//! A global allocator is per binary, so this test has a binary of its own (see
//! `alloc_free.rs`).

use std::hint::black_box;

use bgdsl_runtime::implicit::{solve, ImplicitMemory};
use bgdsl_runtime::{Dual, DualN, Model, Scalar};

#[path = "support/counting.rs"]
mod counting;
#[path = "support/loop_model.rs"]
#[allow(dead_code)] // The failure modes this test does not use.
mod loop_model;

use counting::{allocations_in, Counting};
use loop_model::{DiodeLoop, Fails};

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Three unknowns, non-linear: `z_i + 0.1 sin(z_j) = b_i` around a ring.
fn ring<T: Scalar>(z: &[T; 3], shift: f64, r: &mut [T; 3]) {
    for i in 0..3 {
        let next = z[(i + 1) % 3];
        r[i] = z[i] + T::from_f64(0.1) * next.sin() - T::from_f64(shift + i as f64);
    }
}

/// One test, so that nothing else runs on this thread while counting.
#[test]
fn solving_refining_and_failing_allocate_nothing() {
    let memory = ImplicitMemory::<3>::new();
    let (n, ()) = allocations_in(|| {
        for k in 0..1_000 {
            let shift = black_box(k as f64 * 1e-3);
            let solution = solve(memory.guess(), false, |z, r| ring(z, shift, r)).unwrap();
            memory.remember(&solution.z);
            let constant = solution.z.map(Dual::constant);
            let mut r = [Dual::constant(0.0); 3];
            ring(&constant, shift, &mut r);
            r[0].eps = -1.0;
            black_box(solution.refine(&r));
            let linear = solve([0.0; 3], true, |z, r| {
                for i in 0..3 {
                    r[i] = z[i] * DualN::constant(2.0) - DualN::constant(shift);
                }
            })
            .unwrap();
            black_box(linear.refine(&[shift; 3]));
            // The failures: singular, non-finite, not converged.
            let singular = solve([0.0; 2], true, |z, r| {
                r[0] = z[0] + z[1];
                r[1] = z[0] + z[1];
            });
            let nan = solve([0.0], false, |z, r| {
                r[0] = (z[0] - DualN::constant(1.0)).ln()
            });
            let none = solve([0.0], false, |z, r| {
                r[0] = z[0] * z[0] + DualN::constant(1.0)
            });
            memory.record(black_box(singular.unwrap_err()));
            black_box((nan.unwrap_err(), none.unwrap_err(), memory.failure()));
            memory.clear_failure();
        }
    });
    assert_eq!(n, 0, "allocations in 1,000 solves");

    // Inside a model, on f64 and on the dual numbers of the Jacobians.
    let model = DiodeLoop::new(0.5, Fails::After);
    let (n, ()) = allocations_in(|| {
        for k in 0..1_000 {
            let t = k as f64 * 1e-3;
            let q = [black_box(1e-6 * (k % 5) as f64)];
            let mut dx = [0.0];
            model.derivatives::<f64>(t, &q, &mut dx);
            let mut dual = [Dual::constant(0.0)];
            model.derivatives::<Dual>(t, &[Dual::variable(q[0])], &mut dual);
            let mut lanes = [DualN::<4>::constant(0.0)];
            model.derivatives(t, &[DualN::new(q[0], [1.0, 0.0, 2.0, 0.0])], &mut lanes);
            black_box((dx, dual, lanes, model.evaluation_error()));
        }
    });
    assert_eq!(
        n, 0,
        "allocations in 1,000 evaluations of a model with a loop"
    );
    // The loop above ran past t_fail = 0.5: failures were met and reported.
    assert!(model.evaluation_error().is_some());
}
