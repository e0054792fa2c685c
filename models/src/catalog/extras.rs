//! The quick return family's extras ([`Extras`]): what a run of the flagship or one of
//! its variants writes beyond the generic files. The spec's results file
//! `quick_return.csv` (always its 56 columns, with its units side file), the paper's
//! figures (Figs. 3–19 and two more, ids [`FIGURE_IDS`]), the flagship's summary
//! (measurements beside the rigid mechanism's), and for the hybrid variants the
//! comparison with the same run without the switching ([`Compare`]). The generic table
//! of recorded columns becomes `quick_return_extra.csv`.

use core::marker::PhantomData;
use std::path::Path;

use bgdsl_cli::catalog::{
    params_from, plot_error, write_units, ExtraRun, Extras, Finished, Plots, RunContext, RunError,
    Written,
};
use bgdsl_cli::report::DrawnFigure;
use bgdsl_runtime::{EventRecord, Recorder};

use super::compare::{self, Compare};
use super::{Catalogued, Entry, RunPlan};
use crate::quick_return::figures::{draw_figures, FigureOptions, FIGURE_IDS};
use crate::quick_return::results::{Results, COLUMNS, FILE_NAME, N_COLUMNS};
use crate::quick_return::run::Recorded;
use crate::quick_return::summary::Summary;
use crate::quick_return_rigid::DrivenMechanism;

/// The extras of quick return model `M`: the spec's results file `quick_return.csv`
/// with its units, the paper's figures, the flagship's summary and, for a hybrid
/// variant, the comparison run; the table of recorded columns becomes
/// `quick_return_extra.csv`.
pub struct QuickReturnExtras<M> {
    compare: Option<&'static Compare>,
    model: PhantomData<fn() -> M>,
}

impl<M> QuickReturnExtras<M> {
    /// The results file, the figures and the summary.
    pub const fn new() -> Self {
        QuickReturnExtras {
            compare: None,
            model: PhantomData,
        }
    }

    /// As [`new`](Self::new), and the summary compares the run with `compare`'s.
    pub const fn compared_with(compare: &'static Compare) -> Self {
        QuickReturnExtras {
            compare: Some(compare),
            model: PhantomData,
        }
    }
}

impl<M> Default for QuickReturnExtras<M> {
    fn default() -> Self {
        Self::new()
    }
}

impl<M: Catalogued> Extras for QuickReturnExtras<M>
where
    M::Params: serde::de::DeserializeOwned,
{
    fn start<'a>(
        &'a self,
        run: &RunContext<'a>,
    ) -> Result<Option<Box<dyn ExtraRun + 'a>>, RunError> {
        let results =
            Results::for_model::<M>(run.capacity).map_err(|e| RunError::Results(Box::new(e)))?;
        Ok(Some(Box::new(QuickReturnRun::<M> {
            results,
            entry: run.entry,
            plan: run.plan,
            compare: self.compare,
            model: PhantomData,
        })))
    }

    fn figure_ids(&self) -> Option<&'static [&'static str]> {
        Some(FIGURE_IDS)
    }

    fn table_stem(&self, _entry: &Entry) -> String {
        format!("{}_extra", FILE_NAME.trim_end_matches(".csv"))
    }

    fn result_columns(&self) -> u64 {
        N_COLUMNS as u64
    }
}

/// One run's quick return results.
struct QuickReturnRun<'a, M> {
    results: Results,
    entry: &'a Entry,
    plan: &'a RunPlan,
    compare: Option<&'static Compare>,
    model: PhantomData<fn() -> M>,
}

/// The rigid mechanism a quick return model's parameters describe, for its figures and
/// summary.
fn mechanism<M: Catalogued>(params: &M::Params) -> Result<DrivenMechanism, RunError> {
    M::mechanism(params).ok_or_else(|| {
        RunError::Params(format!(
            "{} writes the quick return's results but describes no rigid mechanism",
            M::NAME
        ))
    })
}

impl<M> Recorder for QuickReturnRun<'_, M> {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        self.results.record(t, x, y);
    }

    fn event(&mut self, record: &EventRecord<'_>) {
        self.results.event(record);
    }
}

impl<M: Catalogued> ExtraRun for QuickReturnRun<'_, M>
where
    M::Params: serde::de::DeserializeOwned,
{
    fn events(&mut self, energies: &[(f64, f64)]) {
        for &(t, change) in energies {
            self.results.push_event_energy(t, change);
        }
    }

    fn write(&mut self, dir: &Path) -> Result<Written, RunError> {
        let path = dir.join(FILE_NAME);
        self.results
            .write_csv(&path)
            .map_err(|e| RunError::Results(Box::new(e)))?;
        let units = write_units(&*self.entry.model, &path, &COLUMNS)?;
        Ok(Written {
            results: vec![FILE_NAME.to_owned()],
            others: vec![units],
        })
    }

    fn figures(&self, dir: &Path, plots: &Plots) -> Result<Vec<DrawnFigure>, RunError> {
        let params = params_from::<M::Params>(&self.plan.params)?;
        let mechanism = mechanism::<M>(&params)?;
        let options = FigureOptions {
            only: match plots {
                Plots::Only(ids) => Some(ids.clone()),
                _ => None,
            },
            ..FigureOptions::default()
        };
        draw_figures(&self.results, &mechanism, dir, &options).map_err(plot_error)
    }

    fn summary(&self, run: &Finished<'_>) -> Option<String> {
        let recorded = Recorded {
            results: self.results.clone(),
            stats: run.stats,
            solver: run.plan.solver,
            wall: run.wall,
        };
        // The second half of the span recorded (of the plan's, for a complete run).
        let t = self.results.times();
        let (t0, t_end) = match (t.first(), t.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (0.0, 0.0),
        };
        let mut summary = Summary::over(&recorded, [0.5 * (t0 + t_end), t_end]);
        if let Ok(mechanism) =
            params_from::<M::Params>(&run.plan.params).and_then(|p| mechanism::<M>(&p))
        {
            summary = summary.with_params(&mechanism);
        }
        summary.file = run
            .results
            .first()
            .map(|path| (path.clone(), run.write_time));
        summary.failure = run.failure.map(str::to_owned);
        summary.overrides = Some(bgdsl_cli::provenance::summary_lines(
            run.entry,
            run.plan,
            &[],
        ));
        Some(summary.to_string())
    }

    fn summary_tail(&self, run: &Finished<'_>) -> String {
        let mut s = String::new();
        // A partial run has nothing settled to compare (and an interrupt asked to stop).
        if let (Some(other), None) = (self.compare, run.failure) {
            s.push_str(&compare::summary::<M>(
                run.entry,
                other,
                run.plan,
                Some(&self.results),
            ));
        }
        if let Some(extra) = run
            .results
            .iter()
            .rfind(|p| p.to_string_lossy().ends_with("_extra.csv"))
        {
            s.push_str(&format!("extra columns  {}\n", extra.display()));
        }
        s
    }
}
