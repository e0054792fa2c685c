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
        /// The free motions: a basis of the null space, each vector as its dominant
        /// states (one state when nothing couples it to the others, several for a
        /// motion they make together). `states` is their union.
        motions: Vec<Vec<String>>,
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
            AnalysisError::Singular {
                states,
                rates,
                motions,
            } => {
                write!(
                    f,
                    "the Jacobian ∂f/∂x is singular: the equilibrium does not determine {} \
                     (nothing pulls them back: a free rigid-body motion or an integrator)",
                    grouped(states)
                )?;
                let together: Vec<String> = motions
                    .iter()
                    .filter(|m| m.len() > 1)
                    .map(|m| list(m).replace(", ", " with "))
                    .collect();
                if !together.is_empty() {
                    write!(
                        f,
                        "; free motions of several states: {}",
                        capped(&together, MOTIONS_SHOWN, "motion")
                    )?;
                }
                write!(
                    f,
                    ", and no state cancels the rates of {}; hold the undetermined states \
                     at chosen values, or add what fixes them (a spring to ground, feedback)",
                    grouped(rates)
                )
            }
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

/// Elements shown by [`grouped`], free motions of several states by the singular
/// error; the rest are counted.
const ELEMENTS_SHOWN: usize = 8;
/// See [`ELEMENTS_SHOWN`].
const MOTIONS_SHOWN: usize = 4;

/// An element's name and its states: per component base, the names relative to the
/// element.
type Element<'a> = (&'a str, Vec<(&'a str, Vec<&'a str>)>);

/// State names grouped by element (the name's prefix before the first `.`), in their
/// order: `` `position` `` alone, `` crank: `R` (9 components), `r_x`, `r_y` `` for
/// the states of one element (a vector state's components, its name up to the last
/// `_`, counted when there are more than three); after [`ELEMENTS_SHOWN`] elements,
/// `and N more states`. A count leads a list of more than three states.
fn grouped(names: &[String]) -> String {
    if names.len() <= 3 {
        return list(names);
    }
    let mut elements: Vec<Element> = Vec::new();
    for name in names {
        let (element, rest) = name.split_once('.').unwrap_or((name.as_str(), ""));
        let base = rest.rsplit_once('_').map_or(rest, |(b, _)| b);
        let index = match elements.iter().position(|(e, _)| *e == element) {
            Some(i) => i,
            None => {
                elements.push((element, Vec::new()));
                elements.len() - 1
            }
        };
        let bases = &mut elements[index].1;
        match bases.iter_mut().find(|(b, _)| *b == base) {
            Some((_, parts)) => parts.push(rest),
            None => bases.push((base, vec![rest])),
        }
    }
    let shown: Vec<String> = elements
        .iter()
        .take(ELEMENTS_SHOWN)
        .map(|(element, bases)| {
            let parts: Vec<String> = bases
                .iter()
                .flat_map(|(base, parts)| match parts.as_slice() {
                    [""] => vec![format!("`{element}`")],
                    _ if parts.len() > 3 => {
                        vec![format!("`{base}` ({} components)", parts.len())]
                    }
                    _ => parts.iter().map(|p| format!("`{p}`")).collect(),
                })
                .collect();
            if bases.iter().all(|(_, parts)| parts == &[""]) {
                parts.join(", ")
            } else {
                format!("{element}: {}", parts.join(", "))
            }
        })
        .collect();
    let hidden: usize = elements
        .iter()
        .skip(ELEMENTS_SHOWN)
        .map(|(_, bases)| bases.iter().map(|(_, p)| p.len()).sum::<usize>())
        .sum();
    let mut text = format!("{} states ({}", names.len(), shown.join("; "));
    if hidden > 0 {
        text.push_str(&format!("; and {hidden} more state{}", plural(hidden)));
    }
    text.push(')');
    text
}

/// The first `shown` of `items` joined by `; `, then `and N more <what>s`.
fn capped(items: &[String], shown: usize, what: &str) -> String {
    let mut text = items
        .iter()
        .take(shown)
        .cloned()
        .collect::<Vec<_>>()
        .join("; ");
    if items.len() > shown {
        let more = items.len() - shown;
        text.push_str(&format!("; and {more} more {what}{}", plural(more)));
    }
    text
}

/// `s` for a count other than one.
fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}
