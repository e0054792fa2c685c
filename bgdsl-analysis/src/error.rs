//! What can go wrong in an analysis: errors as data, each rendered by
//! [`Display`](core::fmt::Display) as one sentence that says what and why.

use core::fmt;

use bgdsl_runtime::SolverError;

/// Why an analysis could not produce its result.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum AnalysisError {
    /// A vector or index given to an analysis does not fit the model: a state vector of
    /// the wrong length, a parameter index past the end.
    Dimension {
        /// What was given (`state vector`, `parameter index`).
        what: &'static str,
        /// The length or index expected (an index: the exclusive bound).
        expected: usize,
        /// The length or index found.
        found: usize,
    },
    /// The model's derivatives or outputs were NaN or infinite where the analysis
    /// evaluated them.
    NonFinite {
        /// What was evaluated (`derivatives`, `outputs`).
        what: &'static str,
        /// The name of the first non-finite entry.
        name: String,
    },
    /// A simulation the analysis runs failed.
    Solver(SolverError),
}

impl fmt::Display for AnalysisError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AnalysisError::Dimension {
                what,
                expected,
                found,
            } => write!(
                f,
                "the {what} does not fit the model: expected {expected}, found {found}"
            ),
            AnalysisError::NonFinite { what, name } => write!(
                f,
                "the model's {what} are not finite at the point analysed (first: `{name}`)"
            ),
            AnalysisError::Solver(e) => write!(f, "a simulation the analysis needs failed: {e}"),
        }
    }
}

impl std::error::Error for AnalysisError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            AnalysisError::Solver(e) => Some(e),
            _ => None,
        }
    }
}

impl From<SolverError> for AnalysisError {
    fn from(e: SolverError) -> Self {
        AnalysisError::Solver(e)
    }
}
