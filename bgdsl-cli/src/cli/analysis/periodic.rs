//! `models periodic`: the periodic steady state of a periodically driven model
//! (`orbit.csv`, `floquet.json`). Not yet in the program: the library has it
//! (`bgdsl_analysis::periodic`).

use clap::Args;

use super::ModelArgs;
use crate::catalog::Catalogue;
use crate::cli::Failure;

/// The arguments of `models periodic`.
#[derive(Clone, Debug, Default, Args)]
pub struct PeriodicArgs {
    /// The model and its settings.
    #[command(flatten)]
    pub model: ModelArgs,
}

/// `models periodic ...`.
pub(crate) fn periodic(args: &PeriodicArgs, _catalogue: &'static Catalogue) -> Result<(), Failure> {
    Err(Failure::Usage(format!(
        "`periodic` ({}) is not in this version of the program yet; the library has it: \
         bgdsl_analysis::periodic",
        args.model.target
    )))
}
