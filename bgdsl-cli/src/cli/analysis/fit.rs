//! `models fit`: least-squares fit of parameters to measured signals. Not yet in the
//! program: the library has it (`bgdsl_analysis::fit`).

use clap::Args;

use super::ModelArgs;
use crate::catalog::Catalogue;
use crate::cli::Failure;

/// The arguments of `models fit`.
#[derive(Clone, Debug, Default, Args)]
pub struct FitArgs {
    /// The model and its settings.
    #[command(flatten)]
    pub model: ModelArgs,
}

/// `models fit ...`.
pub(crate) fn fit(args: &FitArgs, _catalogue: &'static Catalogue) -> Result<(), Failure> {
    Err(Failure::Usage(format!(
        "`fit` ({}) is not in this version of the program yet; the library has it: \
         bgdsl_analysis::fit",
        args.model.target
    )))
}
