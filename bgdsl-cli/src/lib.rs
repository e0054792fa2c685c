//! The bgdsl program as a library: the command line, scenario files, sweeps, run folders,
//! figures, `index.html` and FMU packaging, over any model written with `bond_graph!`.
//!
//! A program is a catalogue of models and one call:
//!
//! ```no_run
//! use std::process::ExitCode;
//!
//! bgdsl_runtime::bond_graph! {
//!     /// A mass on a spring.
//!     pub model MySpring {
//!         /// mass
//!         param m = 1.0 in "kg";
//!         /// stiffness
//!         param k = 4.0 in "N/m";
//!         I mass = m, p in "kg·m/s";
//!         C spring = k, q in "m";
//!         1 v;
//!         v -> { mass, spring };
//!         init spring.q = 0.1;
//!         /// Position of the mass, m.
//!         output x = spring.q in "m";
//!     }
//! }
//!
//! fn main() -> ExitCode {
//!     bgdsl_cli::main(bgdsl_cli::catalogue![MySpring])
//! }
//! ```
//!
//! [`main`] parses the command line (`list`, `params`, `run`, `graph`, `fmu`, and the
//! analyses `steady`, `linearize`, `bode`; see [`cli`]), runs it and maps failures to the exit statuses of [`cli`]. The
//! [`catalog`] module holds the catalogue ([`Catalogue`], [`Entry`]) and the generic
//! run; an entry's [`Extras`](catalog::Extras) add files, figures and summary lines of
//! its own.
#![warn(missing_docs)]

pub mod animation;
pub mod catalog;
pub mod cli;
pub mod fmi;
pub mod interrupt;
pub mod plot;
pub mod provenance;
pub mod report;
pub mod scenario;
pub mod study;

use std::process::ExitCode;

pub use catalog::{Catalogue, Entry, EntryOf};

/// A [`Catalogue`] of the calling package with these models, each with the defaults of
/// [`Entry::of`]: `catalogue![A, B]` is
/// `Catalogue::new(env!("CARGO_PKG_NAME")).version(env!("CARGO_PKG_VERSION")).model::<A>().model::<B>()`,
/// with the git commit from the environment variables `BGDSL_GIT_COMMIT` and
/// `BGDSL_GIT_DIRTY` when the package's build script sets them (else `unknown`).
#[macro_export]
macro_rules! catalogue {
    ($($model:ty),* $(,)?) => {
        $crate::Catalogue::new(env!("CARGO_PKG_NAME"))
            .version(env!("CARGO_PKG_VERSION"))
            .commit(
                match option_env!("BGDSL_GIT_COMMIT") {
                    Some(commit) => commit,
                    None => "unknown",
                },
                match option_env!("BGDSL_GIT_DIRTY") {
                    Some(dirty) => dirty,
                    None => "unknown",
                },
            )
            $(.model::<$model>())*
    };
}

/// Runs the program over `catalogue`: parses `std::env::args`, runs the command (without
/// one, the catalogue's first model), prints errors as `error: …` lines on stderr and
/// returns the exit status ([`cli`]: 0, 1, 2, 69 or 130).
pub fn main(catalogue: Catalogue) -> ExitCode {
    // The catalogue lives as long as the program (runs and sweeps borrow it).
    let catalogue: &'static Catalogue = Box::leak(Box::new(catalogue));
    let cli = cli::parse(catalogue);
    match cli::execute(cli, catalogue) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            for line in failure.to_string().lines() {
                eprintln!("error: {line}");
            }
            ExitCode::from(failure.exit_code())
        }
    }
}
