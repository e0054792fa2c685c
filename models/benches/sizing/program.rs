//! The sizing benchmark's program (run.sh copies it into each throwaway crate, as
//! `main.rs`, next to the generated `model.rs`): times one right-hand side, one
//! Jacobian and a short solve of the model, with a hand-written chain's right-hand
//! side as the anchor, and prints them as `key=value` lines for run.sh.

mod model;

use std::hint::black_box;
use std::sync::Arc;
use std::time::{Duration, Instant};

use bgdsl_runtime::{simulate, Jacobian, JacobianEvaluator, Model, Solver};
use model::Subject;

/// Seconds per call of `f`, repeated for at least `budget`.
fn per_call(budget: Duration, mut f: impl FnMut()) -> f64 {
    f();
    let start = Instant::now();
    let mut calls = 0u32;
    while calls < 3 || start.elapsed() < budget {
        f();
        calls += 1;
    }
    start.elapsed().as_secs_f64() / f64::from(calls)
}

/// A hand-written chain of `n / 2` unit masses and springs: the anchor, a right-hand
/// side with the same number of states and about the work per state of the scalar chain.
fn hand_chain(x: &[f64], dx: &mut [f64]) {
    let cells = x.len() / 2;
    for i in 0..cells {
        let v = x[2 * i];
        let next = if i + 1 < cells { x[2 * i + 2] } else { 0.0 };
        let force = 100.0 * x[2 * i + 1] + 0.5 * (v - next);
        let before = if i == 0 { 0.0 } else { 100.0 * x[2 * i - 1] };
        dx[2 * i] = before - force;
        dx[2 * i + 1] = v - next;
    }
}

fn main() {
    let budget = Duration::from_millis(300);
    let model = Subject::default();
    let n = Subject::N_STATES;
    let mut x = vec![0.0; n];
    model.initial_state(&mut x);
    // A state away from rest, the same every run.
    for (i, v) in x.iter_mut().enumerate() {
        *v += 1e-3 * ((i % 13) as f64 - 6.0);
    }
    let mut dx = vec![0.0; n];
    let rhs = per_call(budget, || {
        model.derivatives::<f64>(black_box(0.1), black_box(&x), &mut dx)
    });
    let anchor = per_call(budget, || hand_chain(black_box(&x), &mut dx));
    println!("states={n}");
    println!("rhs_us={:.3}", rhs * 1e6);
    println!("anchor_us={:.3}", anchor * 1e6);
    let power = per_call(budget, || {
        black_box(model.power_balance::<f64>(black_box(0.1), black_box(&x)));
    });
    println!("power_us={:.3}", power * 1e6);
    let mut y = vec![0.0; Subject::N_OUTPUTS];
    let outputs = per_call(budget, || model.outputs::<f64>(0.1, black_box(&x), &mut y));
    println!("outputs_us={:.3}", outputs * 1e6);
    let jac_max: usize = std::env::var("SIZING_JACOBIAN_MAX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000);
    if n <= jac_max {
        let mut evaluator = JacobianEvaluator::new(&model);
        // The solvers' path: only the pattern's entries (no n x n matrix).
        let mut jac = Jacobian::new(Arc::new(evaluator.pattern().clone()));
        let jacobian = per_call(budget, || {
            evaluator.evaluate_sparse(&model, 0.1, black_box(&x), &mut jac);
        });
        println!("colours={}", evaluator.n_colours());
        println!("jacobian_us={:.3}", jacobian * 1e6);
    }
    let t_end: f64 = std::env::var("SIZING_T_END")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.01);
    let start = Instant::now();
    let run = simulate(&model, Solver::dopri5(), 0.0, t_end, 2);
    println!("dopri5_ms={:.3}", start.elapsed().as_secs_f64() * 1e3);
    if let Err(e) = run {
        println!("dopri5_error={e}");
    }
    let stiff_max: usize = std::env::var("SIZING_STIFF_MAX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2_000);
    if n <= stiff_max {
        let start = Instant::now();
        let run = simulate(&model, Solver::stiff(), 0.0, t_end, 2);
        println!("radau5_ms={:.3}", start.elapsed().as_secs_f64() * 1e3);
        if let Err(e) = run {
            println!("radau5_error={e}");
        }
    }
}
