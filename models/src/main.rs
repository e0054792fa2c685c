//! `models`: runs the bond-graph models of bgdsl (see `models --help` and the
//! [`models::cli`] module). Without a command (`cargo run --release`) it runs the
//! flagship, the quick return mechanism of the seed paper, over 0–5 s with its default
//! parameters: writes `out/quick_return/quick_return.csv` (the spec's results file),
//! the paper's figures and `index.html`, and prints a summary.
//!
//! Exit status: 0 success; 1 a run failed or was interrupted part-way (its partial set
//! written to `<out>.partial/`, `<out>` untouched) or output could not be written; 2 a
//! usage or validation error (nothing written); 130 a second signal (see
//! [`models::cli`]).

use std::process::ExitCode;

use clap::Parser;
use models::cli::{execute, Cli};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match execute(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            for line in failure.to_string().lines() {
                eprintln!("error: {line}");
            }
            ExitCode::from(failure.exit_code())
        }
    }
}
