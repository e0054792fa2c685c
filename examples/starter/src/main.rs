//! The program: `list`, `params`, `run` (models and scenario files, sweeps), `graph`
//! and `fmu` for the models of this crate (see `starter --help`).

use std::process::ExitCode;

use bgdsl_cli::{Catalogue, Entry};
use starter::Scale;

fn main() -> ExitCode {
    // `bgdsl_cli::catalogue![Scale]` would do with the defaults (10 s, 1000 samples,
    // no checks beyond finite values); the first model is the one run without a command.
    let scale = Entry::of::<Scale>().t_end(1.0).checks(starter::check);
    bgdsl_cli::main(Catalogue::new(env!("CARGO_PKG_NAME")).entry(scale))
}
