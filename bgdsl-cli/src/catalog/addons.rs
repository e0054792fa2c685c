//! The program's own add-ons to every run, whatever the model: each is an
//! [`ExtraRun`] started here with the typed model, beside the entry's extras (h2's
//! animation recorder, h5's energy recorder plug in here).

use bgdsl_runtime::Model;

use super::extras::{ExtraRun, RunContext};
use super::RunError;

/// The add-ons of one run of `model` (none yet).
///
/// # Errors
///
/// [`RunError`] when an add-on cannot start.
pub(super) fn start<'a, M: Model>(
    model: &'a M,
    run: &RunContext<'a>,
) -> Result<Vec<Box<dyn ExtraRun + 'a>>, RunError> {
    let _ = (model, run);
    Ok(Vec::new())
}
