//! The program's own add-ons to every run, whatever the model: each is an
//! [`ExtraRun`] started here with the typed model, beside the entry's extras: the
//! animation of its bodies and the generic figures (energy balance, phase portraits, graph).

use bgdsl_runtime::FromParams;

use super::extras::{ExtraRun, RunContext};
use super::figures::generic::GenericRun;
use super::RunError;

/// The add-ons of one run of `model`: the animation of its bodies, if it has any, and
/// the generic figures' ([`GenericRun`]: energy balance, phase portraits, the causal
/// graph's section).
///
/// # Errors
///
/// [`RunError`] when an add-on cannot start.
pub(super) fn start<'a, M: FromParams + 'static>(
    model: &'a M,
    run: &RunContext<'a>,
) -> Result<Vec<Box<dyn ExtraRun + 'a>>, RunError> {
    let mut addons: Vec<Box<dyn ExtraRun + 'a>> = Vec::new();
    if let Some(animation) = crate::animation::start(model, run.entry) {
        addons.push(Box::new(animation));
    }
    addons.push(Box::new(GenericRun::start(model, run)));
    Ok(addons)
}
