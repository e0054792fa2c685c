//! Proof that the variational equations' SDIRK stages allocate nothing: a
//! forward-sensitivity run of the flagship (117 states, sparse iteration matrices; 14
//! parameters) makes exactly as many heap allocations with 8 SDIRK steps per interval
//! as with 2, although it takes four times the stages (the state's run, the buffers and
//! the results are the same size in both). The sensitivities also converge as the
//! steps shrink (measured: differences 0.111 then 0.0080 of entries up to 2.16, 2 → 8
//! → 32 steps), so the stages did run.
//!
//! A global allocator is per binary, so this test has a binary of its own; it counts the
//! allocations made on the current thread (the runtime's `support/counting.rs`).

#[path = "../../bgdsl-runtime/tests/support/counting.rs"]
mod counting;

use bgdsl_analysis::sensitivity::{
    forward_sensitivities, parameter_index, Sensitivities, SensitivityOptions,
};
use counting::{allocations_in, Counting};
use models::quick_return::QuickReturn;

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn variational_stages_allocate_nothing() {
    let model = QuickReturn::default();
    let which: Vec<usize> = [
        "m1", "m2", "m3", "m4", "m5", "K01", "K12", "K03", "K3C[1]", "K23r", "K_C", "K34", "K45",
        "K5C[1]",
    ]
    .iter()
    .map(|n| parameter_index::<QuickReturn>(n).expect("a flagship parameter"))
    .collect();
    let times = [0.0, 0.01, 0.02];
    let run = |substeps: usize| {
        let options = SensitivityOptions {
            substeps,
            ..Default::default()
        };
        allocations_in(|| forward_sensitivities(&model, None, &which, &times, &options))
    };
    // A first run outside the count: thread-local buffers set up once per thread.
    run(1).1.expect("runs");
    let (few, coarse) = run(2);
    let (many, fine) = run(8);
    let (coarse, fine): (Sensitivities, Sensitivities) = (coarse.unwrap(), fine.unwrap());
    assert!(few > 0, "the counter counts in this binary");
    assert_eq!(
        many, few,
        "allocations with 8 SDIRK steps per interval against 2 (3 × 6 × 2 more stages)"
    );
    // The stages ran: the sensitivities converge as the steps shrink (order 3: the
    // differences 2 → 8 → 32 steps would shrink 64-fold; at least 4-fold is asked,
    // the flagship's stiff start keeping the coarse steps out of the asymptotic range).
    let (_, finest) = run(32);
    let last = |s: &Sensitivities| s.state_sensitivities[times.len() - 1].clone();
    let (a, b, c) = (last(&coarse), last(&fine), last(&finest.unwrap()));
    let (first, second) = ((&a - &b).amax(), (&b - &c).amax());
    assert!(
        second > 0.0 && second * 4.0 <= first,
        "{first} then {second}"
    );
    assert_eq!(c.nrows(), QuickReturn::N_STATES);
}
