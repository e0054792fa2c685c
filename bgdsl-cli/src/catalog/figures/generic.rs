//! The generic figures' add-on to every run ([`super::super::addons`]): the energy
//! recorder and its figure and summary line, the phase portraits asked for, and the
//! causal graph's section of `index.html`. An entry whose extras opt out of the generic
//! figures ([`Extras::generic_figures`](super::super::Extras::generic_figures), by
//! default when they draw their own, as the quick return's do) gets no energy figure
//! or line (its paper figures have their own balance); the graph and the phase
//! portraits asked for are for every model.

use std::path::Path;

use bgdsl_runtime::{EventRecord, FromParams, Model, Recorder};

use super::super::extras::{ExtraRun, Finished, RunContext};
use super::super::{Entry, Plots, RunError};
use super::energy::EnergyRecorder;
use super::energy_chart;
use super::phase::{self, PhaseRecorder};
use super::{graph, DrawnFigure};

/// One run's generic add-on.
pub(in crate::catalog) struct GenericRun<'a, M: Model> {
    entry: &'a Entry,
    energy: Option<EnergyRecorder<M>>,
    phase: Option<PhaseRecorder>,
    dot: Option<String>,
}

/// Whether the entry gets the generic figures
/// ([`Extras::generic_figures`](super::super::Extras::generic_figures)).
pub(in crate::catalog) fn generic_figures(entry: &Entry) -> bool {
    entry.extras.generic_figures()
}

impl<'a, M: FromParams> GenericRun<'a, M> {
    /// The add-on for a run of `model`.
    pub(in crate::catalog) fn start(model: &'a M, run: &RunContext<'a>) -> Self {
        let generic = generic_figures(run.entry);
        let plots = &run.plan.plots;
        GenericRun {
            entry: run.entry,
            // Kept with plots off too: the summary's line needs it.
            energy: generic
                .then(|| EnergyRecorder::new(M::from_params(model.params().clone()), run.capacity)),
            phase: (!run.plan.phase.is_empty() && *plots != Plots::None)
                .then(|| PhaseRecorder::new(&run.plan.phase, run.capacity)),
            dot: model.causal_graph().map(|g| g.to_dot()),
        }
    }
}

impl<M: Model> Recorder for GenericRun<'_, M> {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        if let Some(e) = self.energy.as_mut() {
            e.record(t, x, y);
        }
        if let Some(p) = self.phase.as_mut() {
            p.record(t, x, y);
        }
    }

    fn event(&mut self, record: &EventRecord<'_>) {
        if let Some(e) = self.energy.as_mut() {
            e.event(record);
        }
    }
}

impl<M: Model> ExtraRun for GenericRun<'_, M> {
    fn figures(&self, dir: &Path, plots: &Plots) -> Result<Vec<DrawnFigure>, RunError> {
        let mut drawn = Vec::new();
        let energy_wanted = match plots {
            Plots::None => false,
            Plots::All => true,
            Plots::Only(ids) => ids.iter().any(|id| id == energy_chart::FIGURE_ID),
        };
        if let (true, Some(balance)) = (
            energy_wanted,
            self.energy.as_ref().and_then(|e| e.balance()),
        ) {
            drawn.extend(energy_chart::draw(self.entry, balance, dir)?);
        }
        if let Some(p) = &self.phase {
            drawn.extend(phase::draw(self.entry, p, dir)?);
        }
        Ok(drawn)
    }

    fn summary_tail(&self, _run: &Finished<'_>) -> String {
        self.energy
            .as_ref()
            .and_then(|e| e.balance())
            .map(|b| b.summary_line())
            .unwrap_or_default()
    }

    fn sections(&self) -> Vec<String> {
        self.dot.iter().map(|dot| graph::section(dot)).collect()
    }
}
