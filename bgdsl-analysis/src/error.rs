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
    /// The Jacobian ∂f/∂x is singular where an equilibrium was sought: the
    /// equilibrium is not determined (a free rigid-body motion, an integrator in a
    /// loop).
    Singular {
        /// The states the equilibrium leaves undetermined (along the Jacobian's null
        /// space): a free body's position, an integrator's output.
        states: Vec<String>,
        /// The states whose rates no state can cancel (along the left null space): a
        /// free body's momentum under a net force.
        rates: Vec<String>,
    },
    /// Newton's method did not converge.
    NotConverged {
        /// Iterations taken.
        iterations: usize,
        /// The root-sum-square of the rates at the last iterate.
        residual: f64,
    },
    /// A name given to an analysis is not one of the model's.
    UnknownName {
        /// What was looked for (`input`, `output`, `parameter`, `state`).
        what: &'static str,
        /// The name given.
        name: String,
        /// The names there are.
        known: Vec<String>,
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
            AnalysisError::Singular { states, rates } => write!(
                f,
                "the Jacobian ∂f/∂x is singular: the equilibrium does not determine {} \
                 (nothing pulls them back: a free rigid-body motion or an integrator), and \
                 no state cancels the rates of {}; hold the undetermined states at chosen \
                 values, or add what fixes them (a spring to ground, feedback)",
                list(states),
                list(rates)
            ),
            AnalysisError::NotConverged {
                iterations,
                residual,
            } => write!(
                f,
                "Newton's method found no equilibrium in {iterations} iterations (rates \
                 still {residual:.3e}, root-sum-square): start from a better guess (a \
                 state reached by a run)"
            ),
            AnalysisError::UnknownName { what, name, known } => write!(
                f,
                "the model has no {what} `{name}`; its {what}s: {}",
                list(known)
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

/// `a, b, c` with each name in backquotes, or `(none)`.
fn list(names: &[String]) -> String {
    if names.is_empty() {
        return "(none)".to_string();
    }
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}
