//! The program: `list`, `params`, `run` (models and scenario files, sweeps), `graph`
//! and `fmu` for the models of this crate (see `starter --help`).

use std::process::ExitCode;

use bgdsl_cli::Entry;
use starter::Scale;

fn main() -> ExitCode {
    // `catalogue![Scale]` alone would take the defaults (10 s, 1000 samples, no rules
    // beyond finite numbers). The first model is what the program runs without a command.
    let scale = Entry::of::<Scale>()
        .description("a kitchen scale: a load set down on a pan on a spring and a dashpot")
        .t_end(1.0)
        .checks(starter::check);
    bgdsl_cli::main(bgdsl_cli::catalogue![].entry(scale))
}
