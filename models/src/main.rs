//! `cargo run --release`: the flagship, the quick return mechanism of the seed paper
//! written with `bond_graph!`, over 0–5 s with its default parameters; writes
//! `out/quick_return/quick_return.csv` (the spec's results file) and prints a summary.

use std::error::Error;
use std::path::Path;

use bgdsl_runtime::{Radau5Options, Solver};
use models::quick_return::run::run_flagship;
use models::quick_return::QuickReturn;

fn main() -> Result<(), Box<dyn Error>> {
    let model = QuickReturn::default();
    // Radau IIA at rtol 1e-6; atol 1e-10 resolves the joint deflections (~1e-4 m).
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-10,
        ..Default::default()
    });
    let summary = run_flagship(&model, solver, Path::new("out/quick_return"))?;
    println!("{summary}");
    Ok(())
}
