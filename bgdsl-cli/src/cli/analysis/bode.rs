//! `models bode`: frequency responses from inputs to outputs at an operating point.

use clap::Args;

use super::linearize::PointArgs;
use super::ModelArgs;
use crate::catalog::Catalogue;
use crate::cli::Failure;

/// The arguments of `models bode`.
#[derive(Clone, Debug, Default, Args)]
pub struct BodeArgs {
    /// The model and its settings.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The operating point.
    #[command(flatten)]
    pub point: PointArgs,
}

/// `models bode ...`.
pub(crate) fn bode(args: &BodeArgs, _catalogue: &'static Catalogue) -> Result<(), Failure> {
    Err(Failure::Usage(format!(
        "`bode` ({}) is not in this version of the program yet",
        args.model.target
    )))
}
