//! The LU kernels of the stiff solvers on the Jacobians they meet: the flagship quick
//! return model's (117 states; `benches/data/quick_return_jacobians.txt`, written by
//! `cargo run --release -p models --example flagship_jacobians`) and the Bari test
//! set's POLLU (20 states), with Radau IIA's shifts for a step of the flagship's mean
//! size (5 s / 1166 steps).
//!
//! `cargo bench -p bgdsl-runtime --bench lu`
//!
//! Prints, per matrix, the thread CPU time of one call (best of 30 batches of about
//! 2 ms; wall time is meaningless on the shared build machine): Radau5's factorization
//! of the pair `γ/h I - J`, `(α + iβ)/h I - J` after a new Jacobian (the numerical
//! pattern's values taken in) and with the same Jacobian (a new step size),
//! `solve_both` and `solve_real`; and as the anchor, in the same run, a dense LU with
//! partial pivoting of the same real matrix (nalgebra) and its solve. Ratios to the
//! anchor are what compares across runs. Results: `docs/flagship-speed.md`.

#[path = "../tests/stiff_common/mod.rs"]
mod stiff_common;

use std::hint::black_box;

use bgdsl_runtime::__bench::Matrices;
use bgdsl_runtime::{Jacobian, JacobianEvaluator, Model, SparsityPattern};
use nalgebra::{DMatrix, DVector};

/// Radau IIA (3 stages)'s real eigenvalue `γ` and complex pair `α ± iβ` of the inverse
/// of its coefficient matrix (Hairer & Wanner, *Solving ODEs II*, Sect. IV.8).
const GAMMA: f64 = 3.637_834_252_744_496;
const ALPHA: f64 = 2.681_082_873_627_752;
const BETA: f64 = 3.050_430_199_247_41;

/// The flagship's mean step, s.
const H: f64 = 5.0 / 1166.0;

/// The flagship's pattern and its Jacobians along the run.
fn flagship() -> (SparsityPattern, Vec<Jacobian>) {
    let text = include_str!("data/quick_return_jacobians.txt");
    let mut lines = text.lines();
    let n: usize = lines.next().unwrap()["n ".len()..].parse().unwrap();
    let rows: Vec<Vec<usize>> = (0..n)
        .map(|_| {
            let line = lines.next().unwrap();
            let cols = line.split_once(':').unwrap().1;
            cols.split_whitespace()
                .map(|c| c.parse().unwrap())
                .collect()
        })
        .collect();
    let pattern = SparsityPattern::from_rows(&rows).unwrap();
    let mut jacobians = Vec::new();
    let mut line = lines.next();
    while let Some(header) = line {
        assert!(header.starts_with("jacobian "), "{header}");
        let mut jac = Jacobian::new(pattern.clone().into());
        for v in jac.values_mut() {
            *v = lines.next().unwrap().parse().unwrap();
        }
        jacobians.push(jac);
        line = lines.next();
    }
    (pattern, jacobians)
}

/// POLLU's pattern and its Jacobian at the initial state.
fn pollution() -> (SparsityPattern, Vec<Jacobian>) {
    let model = stiff_common::Pollution;
    let pattern = SparsityPattern::for_model::<stiff_common::Pollution>().unwrap();
    let mut x = vec![0.0; stiff_common::Pollution::N_STATES];
    model.initial_state(&mut x);
    let mut jac = Jacobian::new(pattern.clone().into());
    JacobianEvaluator::new(&model).evaluate_sparse(&model, 0.0, &x, &mut jac);
    (pattern, vec![jac])
}

/// This thread's CPU time, s: a busy shared machine inflates it far less than wall
/// time.
fn cpu_time() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid timespec for the call to fill.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The least CPU time of one call of `f`, µs: the best of 30 batches of about 2 ms.
fn time(mut f: impl FnMut()) -> f64 {
    let start = cpu_time();
    let mut calls = 0;
    while cpu_time() - start < 2e-3 {
        f();
        calls += 1;
    }
    (0..30)
        .map(|_| {
            let start = cpu_time();
            for _ in 0..calls {
                f();
            }
            (cpu_time() - start) / calls as f64 * 1e6
        })
        .fold(f64::INFINITY, f64::min)
}

/// Times the kernels on the Jacobians of one model and prints a table: CPU µs per
/// call and the ratio to the anchor (a dense LU of the same real matrix).
fn bench(name: &str, h: f64, (pattern, jacobians): (SparsityPattern, Vec<Jacobian>)) {
    let n = pattern.n();
    let shifts = [GAMMA / h, ALPHA / h, BETA / h];
    let mut m = Matrices::new(&pattern);
    // The numerical pattern: the union of the run's Jacobians.
    for jac in &jacobians {
        assert!(m.factor_pair(shifts, jac, true), "{name}: static pivots");
    }
    let jac = jacobians.last().unwrap();
    let nonzero = jac.values().iter().filter(|v| **v != 0.0).count();
    println!(
        "{name}: {n} states, {} structural entries, {nonzero} non-zero; {}",
        pattern.nnz(),
        match m.sparse_size() {
            Some((nnz, flops)) => {
                format!("sparse, {nnz} entries in the factors, {flops} multiply-adds")
            }
            None => "banded".into(),
        }
    );
    let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
    // The anchor: a dense LU with partial pivoting of `γ/h I - J` and its solve.
    let mut dense = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            dense[i * n + j] = -jac.get(i, j);
        }
        dense[i * n + i] += shifts[0];
    }
    let a = DMatrix::from_row_slice(n, n, &dense);
    let anchor = time(|| {
        black_box(black_box(&a).clone().lu());
    });
    let lu = a.clone().lu();
    let rhs = DVector::from_column_slice(&b);
    let mut xd = rhs.clone();
    let anchor_solve = time(|| {
        xd.copy_from(&rhs);
        lu.solve_mut(&mut xd);
        black_box(&xd);
    });
    let factor_new = time(|| {
        black_box(m.factor_pair(black_box(shifts), black_box(jac), true));
    });
    let factor = time(|| {
        black_box(m.factor_pair(black_box(shifts), black_box(jac), false));
    });
    let (mut x, mut y_re, mut y_im) = (b.clone(), b.clone(), b.clone());
    let solve_both = time(|| {
        x.copy_from_slice(&b);
        y_re.copy_from_slice(&b);
        y_im.copy_from_slice(&b);
        m.solve_both(&mut x, &mut y_re, &mut y_im);
        black_box(&x);
    });
    let solve_real = time(|| {
        x.copy_from_slice(&b);
        m.solve_real(&mut x);
        black_box(&x);
    });
    let rows = [
        ("factor pair, new Jacobian", factor_new),
        ("factor pair", factor),
        ("solve_both", solve_both),
        ("solve_real", solve_real),
        ("anchor: dense LU (real)", anchor),
        ("anchor: dense solve (real)", anchor_solve),
    ];
    for (what, t) in rows {
        println!(
            "  {what:<28} {t:>9.3} µs cpu   {:>8.4} x anchor",
            t / anchor
        );
    }
}

fn main() {
    // `cargo bench` passes `--bench`: no filters, the whole table.
    bench("quick_return", H, flagship());
    bench("pollu", 1e-2, pollution());
}
