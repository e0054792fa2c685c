//! What a model's run does beyond the generic files: the hook through which a catalogue
//! adds its own results files, figures, summary and `index.html` sections (the quick
//! return's spec file and paper figures are one), and through which the program's own
//! add-ons ([`super::addons`]) plug into every run.
//!
//! An entry's [`Extras`] is asked once per run for an [`ExtraRun`]: a [`Recorder`]
//! that sees every sample and event, then writes its files, draws its figures and
//! adds to the summary and the page, in this order, all into the run's staging folder.

use std::path::{Path, PathBuf};
use std::time::Duration;

use bgdsl_runtime::{Recorder, Stats};

use super::{Entry, Plots, RunError, RunPlan};
use crate::report::DrawnFigure;

/// What a run is, for the extras starting on it.
#[derive(Clone, Copy, Debug)]
pub struct RunContext<'a> {
    /// The entry run.
    pub entry: &'a Entry,
    /// The validated plan.
    pub plan: &'a RunPlan,
    /// Room to reserve for samples (the plan's count, at most a million).
    pub capacity: usize,
}

/// What a run came to, for the extras' summary.
#[derive(Clone, Copy, Debug)]
pub struct Finished<'a> {
    /// The entry run.
    pub entry: &'a Entry,
    /// The plan.
    pub plan: &'a RunPlan,
    /// The solver's counts.
    pub stats: Stats,
    /// Wall time of the integration.
    pub wall: Duration,
    /// Wall time of writing the results files.
    pub write_time: Duration,
    /// Why the run stopped early, when it did.
    pub failure: Option<&'a str>,
    /// Every results file, where it will be once the set is committed: the extras'
    /// first, in the order they were started, then `<table>.csv`, then `events.csv`.
    pub results: &'a [PathBuf],
}

/// The files an [`ExtraRun`] wrote into the staging folder.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Written {
    /// The results files, by name (listed in `run.yaml` and the outcome, results first).
    pub results: Vec<String>,
    /// Other files (units side files), by path.
    pub others: Vec<PathBuf>,
}

/// What an entry adds to its runs. Every method has a default that adds nothing, so
/// [`NoExtras`] is `impl Extras for NoExtras {}`.
pub trait Extras: Send + Sync {
    /// Called once per run before integrating: a recorder of its own, or `None`.
    ///
    /// # Errors
    ///
    /// [`RunError`] when the model cannot have these extras (nothing is written).
    fn start<'a>(
        &'a self,
        run: &RunContext<'a>,
    ) -> Result<Option<Box<dyn ExtraRun + 'a>>, RunError> {
        let _ = run;
        Ok(None)
    }

    /// The figure ids `plots:` may name when the extras draw their own figures in
    /// place of the generic charts (`None`: the generic charts, named by output). When
    /// `Some`, the table `<stem>.csv` is charted only for the columns the entry records
    /// by default.
    fn figure_ids(&self) -> Option<&'static [&'static str]> {
        None
    }

    /// Whether the generic figures are drawn for this entry (by default when the
    /// extras have no figures of their own, see [`figure_ids`](Self::figure_ids)).
    fn generic_figures(&self) -> bool {
        self.figure_ids().is_none()
    }

    /// The stem of the file of recorded columns, by default the entry's name (the quick
    /// return's is `quick_return_extra`, beside its own `quick_return.csv`).
    fn table_stem(&self, entry: &Entry) -> String {
        entry.name.clone()
    }

    /// The columns its own results files hold per sample, for the size guard.
    fn result_columns(&self) -> u64 {
        0
    }
}

/// An entry without extras.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoExtras;

impl Extras for NoExtras {}

/// One run's extras: a [`Recorder`] (every sample and event), then its files, figures,
/// summary and page sections. Every method but the recorder's has a default that does
/// nothing.
pub trait ExtraRun: Recorder {
    /// The run's events, in order, with each one's change of stored energy (J; 0 where
    /// not known), once the integration ended.
    fn events(&mut self, energies: &[(f64, f64)]) {
        let _ = energies;
    }

    /// Writes its results files into `dir` (the staging folder).
    ///
    /// # Errors
    ///
    /// [`RunError`] when a file cannot be written.
    fn write(&mut self, dir: &Path) -> Result<Written, RunError> {
        let _ = dir;
        Ok(Written::default())
    }

    /// Draws its figures into `dir` (asked only when plots are on).
    ///
    /// # Errors
    ///
    /// [`RunError::Io`] for a file that cannot be written (the set is abandoned), any
    /// other error leaves the run without figures.
    fn figures(&self, dir: &Path, plots: &Plots) -> Result<Vec<DrawnFigure>, RunError> {
        let _ = (dir, plots);
        Ok(Vec::new())
    }

    /// The summary in place of the generic one (the first extra run that has one
    /// wins), or `None`.
    fn summary(&self, run: &Finished<'_>) -> Option<String> {
        let _ = run;
        None
    }

    /// Lines added to the summary after the events' lines.
    fn summary_tail(&self, run: &Finished<'_>) -> String {
        let _ = run;
        String::new()
    }

    /// HTML fragments for `index.html`, shown after the summary (self-contained: no
    /// external file or network).
    fn sections(&self) -> Vec<String> {
        Vec::new()
    }
}
