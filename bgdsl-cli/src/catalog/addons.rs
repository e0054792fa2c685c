//! The program's own add-ons to every run, whatever the model: each is an
//! [`ExtraRun`] started here with the typed model, beside the entry's extras (h2's
//! animation recorder, h5's energy recorder plug in here).

use bgdsl_runtime::FromParams;

use super::extras::{ExtraRun, RunContext};
use super::figures::generic::GenericRun;
use super::RunError;

/// The add-ons of one run of `model`: the generic figures' ([`GenericRun`]: energy
/// balance, phase portraits, the causal graph's section).
///
/// # Errors
///
/// [`RunError`] when an add-on cannot start.
pub(super) fn start<'a, M: FromParams>(
    model: &'a M,
    run: &RunContext<'a>,
) -> Result<Vec<Box<dyn ExtraRun + 'a>>, RunError> {
    let generic: Box<dyn ExtraRun + 'a> = Box::new(GenericRun::start(model, run));
    Ok(vec![generic])
}
