//! The flagship run: a quick return model integrated from its initial state over
//! 0–5 s, sampled every 1 ms into the results file's columns, written to
//! `<out_dir>/quick_return.csv` and summarised; and the one error type of this module.

use core::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use bgdsl_runtime::{Model, Simulation, Solver, SolverError, Stats};

use super::results::{sample_times, Results, FILE_NAME, N_ROWS};
use super::summary::Summary;

/// What went wrong in a quick return run. Nothing is half-written: the results file is
/// written whole or not at all, and only after the run succeeded.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The model has no output named like some of the results file's columns.
    MissingOutputs {
        /// The model's name.
        model: &'static str,
        /// The missing column names, in the file's order.
        missing: Vec<&'static str>,
    },
    /// The solver could not be set up or could not reach the last sample time.
    Solver {
        /// The model's name.
        model: &'static str,
        /// The solver's name.
        solver: &'static str,
        /// What the solver reported.
        source: SolverError,
    },
    /// The results file or its directory could not be written.
    Io {
        /// The file (or directory) that was to be written.
        path: PathBuf,
        /// The operation that failed.
        stage: IoStage,
        /// The underlying error.
        source: io::Error,
    },
}

/// The operation that failed in an [`Error::Io`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IoStage {
    /// Creating the output directory.
    CreateDirectory,
    /// Creating the temporary file next to the destination.
    CreateTemporary,
    /// Writing, flushing or syncing the temporary file.
    Write,
    /// Renaming the temporary file onto the destination.
    Rename,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::MissingOutputs { model, missing } => {
                write!(
                    f,
                    "model `{model}` cannot produce the quick return results file: it has no \
                     output named "
                )?;
                for (i, name) in missing.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    f.write_str(name)?;
                }
                f.write_str(" (the file's columns are read from the outputs by name)")
            }
            Error::Solver {
                model,
                solver,
                source,
            } => write!(f, "the {solver} run of model `{model}` failed: {source}"),
            Error::Io {
                path,
                stage,
                source,
            } => {
                let what = match stage {
                    IoStage::CreateDirectory => "creating the directory failed",
                    IoStage::CreateTemporary => "creating a temporary file in its directory failed",
                    IoStage::Write => "writing the temporary file failed",
                    IoStage::Rename => "renaming the temporary file onto it failed",
                };
                write!(f, "could not write `{}`: {what}: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::MissingOutputs { .. } => None,
            Error::Solver { source, .. } => Some(source),
            Error::Io { source, .. } => Some(source),
        }
    }
}

/// A finished run in memory: the results-file columns and what the run cost.
#[derive(Clone, Debug)]
pub struct Recorded {
    /// The samples.
    pub results: Results,
    /// The solver's counters.
    pub stats: Stats,
    /// The solver used.
    pub solver: Solver,
    /// Wall time of the integration (including the recording of the samples, excluding
    /// the set-up of the workspace).
    pub wall: Duration,
}

/// Integrates `model` with `solver` from its initial state at `t = times[0]` (or 0 when
/// `times` is empty) through `times`, recording the results-file columns at each.
///
/// # Errors
///
/// [`Error::MissingOutputs`] before anything runs; [`Error::Solver`] if the options are
/// invalid or the run fails.
pub fn record<M: Model>(model: &M, solver: Solver, times: &[f64]) -> Result<Recorded, Error> {
    let mut results = Results::for_model::<M>(times.len())?;
    let solver_error = |source| Error::Solver {
        model: M::NAME,
        solver: solver.name(),
        source,
    };
    let mut sim = Simulation::new(model, solver).map_err(solver_error)?;
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let t0 = times.first().copied().unwrap_or(0.0);
    let started = Instant::now();
    let stats = sim
        .run(t0, &x0, times, &mut results)
        .map_err(solver_error)?;
    let wall = started.elapsed();
    Ok(Recorded {
        results,
        stats,
        solver,
        wall,
    })
}

/// The flagship run: `model` with `solver` from its initial state over 0–5 s, sampled
/// at `t = k / 1000` s, `k = 0..=5000`; writes the results file
/// `out_dir/quick_return.csv` (creating `out_dir` if needed) and returns the
/// [`Summary`] of the run.
///
/// The file is written only after the run has succeeded, atomically (a temporary file
/// in `out_dir`, renamed onto the destination): on any error no file is left behind
/// and an existing results file is unchanged.
///
/// # Errors
///
/// [`Error::MissingOutputs`] if the model lacks a column; [`Error::Solver`] if the run
/// fails (including a wall-time limit in the solver's options); [`Error::Io`] if the
/// directory or the file cannot be written.
pub fn run_flagship<M: Model>(model: &M, solver: Solver, out_dir: &Path) -> Result<Summary, Error> {
    let times = sample_times();
    debug_assert_eq!(times.len(), N_ROWS);
    let recorded = record(model, solver, &times)?;
    std::fs::create_dir_all(out_dir).map_err(|source| Error::Io {
        path: out_dir.to_path_buf(),
        stage: IoStage::CreateDirectory,
        source,
    })?;
    let path = out_dir.join(FILE_NAME);
    let started = Instant::now();
    recorded.results.write_csv(&path)?;
    let write_time = started.elapsed();
    let mut summary = Summary::of(&recorded);
    if let Some(params) = quick_return_params(model) {
        summary = summary.with_params(&params);
    }
    summary.file = Some((path, write_time));
    Ok(summary)
}

/// The parameters of `model` as the quick return's, read by name from its declared
/// parameters (`None` for a model that lacks one of them).
fn quick_return_params<M: Model>(model: &M) -> Option<super::QuickReturnParams> {
    use serde_yaml::{Mapping, Value};
    let mut values = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    let mut params = Mapping::new();
    let mut at = 0;
    for p in M::PARAMETERS {
        let numbers = values.get(at..at + p.len)?;
        at += p.len;
        let value = match numbers {
            [one] => Value::from(*one),
            many => Value::Sequence(many.iter().map(|v| Value::from(*v)).collect()),
        };
        params.insert(Value::from(p.name), value);
    }
    serde_yaml::from_value(Value::Mapping(params)).ok()
}
