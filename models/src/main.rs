//! `models`: runs the bond-graph models of bgdsl (see `models --help` and the
//! [`bgdsl_cli::cli`] module) over the catalogue [`models::catalogue`]. Without a
//! command (`cargo run --release`) it runs the flagship, the quick return mechanism of
//! the seed paper, over 0–5 s with its default parameters: writes
//! `out/quick_return/quick_return.csv` (the spec's results file), the paper's figures
//! and `index.html`, and prints a summary.
//!
//! Exit status: 0 success; 1 a run failed or was interrupted part-way (its partial set
//! written to `<out>.partial/`, `<out>` untouched) or output could not be written; 2 a
//! usage or validation error (nothing written); 69 a missing prerequisite; 130 a second
//! signal (see [`bgdsl_cli::cli`]).

use std::process::ExitCode;

fn main() -> ExitCode {
    bgdsl_cli::main(models::catalogue())
}
