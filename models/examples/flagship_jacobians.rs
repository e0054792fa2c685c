//! Writes the flagship's Jacobians for the LU bench of `bgdsl-runtime`
//! (`bgdsl-runtime/benches/lu.rs`), which cannot depend on `models`: the quick return
//! model's structural sparsity pattern and its exact Jacobian at the states of the
//! Radau5 run (rtol 1e-6) at t = 0.5, 1.5, 2.5, 3.5 and 4.5 s.
//!
//! `cargo run --release -p models --example flagship_jacobians -- [file]`
//! (default `bgdsl-runtime/benches/data/quick_return_jacobians.txt`)
//!
//! Format: `n <states>`, then one line of columns per row (`row <i>: <j> ...`), then
//! for each time `jacobian <t>` followed by the values in the pattern's order, one a
//! line, printed with Rust's shortest round-trip digits.

use std::fmt::Write as _;

use bgdsl_runtime::{Jacobian, JacobianEvaluator, Radau5Options, Solver, SparsityPattern, Stepper};
use models::quick_return::QuickReturn;

fn main() {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "bgdsl-runtime/benches/data/quick_return_jacobians.txt".into());
    let model = QuickReturn::default();
    let pattern = SparsityPattern::for_model::<QuickReturn>().expect("the model's pattern");
    let mut out = String::new();
    writeln!(out, "n {}", pattern.n()).unwrap();
    for i in 0..pattern.n() {
        let cols: Vec<String> = pattern.row(i).iter().map(|j| j.to_string()).collect();
        writeln!(out, "row {i}: {}", cols.join(" ")).unwrap();
    }
    let mut evaluator = JacobianEvaluator::new(&model);
    let mut jac = Jacobian::new(pattern.clone().into());
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-10,
        ..Default::default()
    });
    let mut stepper = Stepper::new(model.clone(), solver).expect("a stepper");
    for t in [0.5, 1.5, 2.5, 3.5, 4.5] {
        stepper.advance_to(t).expect("the run");
        let x = stepper.state().to_vec();
        evaluator.evaluate_sparse(&model, t, &x, &mut jac);
        writeln!(out, "jacobian {t}").unwrap();
        for v in jac.values() {
            writeln!(out, "{v:?}").unwrap();
        }
    }
    std::fs::write(&path, out).expect("write the file");
    println!("{} states, {} entries: {path}", pattern.n(), pattern.nnz());
}
