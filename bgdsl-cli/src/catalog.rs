//! The catalogue: the models a program knows, by name, and everything it needs to
//! treat them alike: their parameters (defaults, units, docs), overriding parameters by
//! name, physical validation, and running them into files.
//!
//! A program builds a [`Catalogue`] of [`Entry`]s (usually with
//! [`catalogue!`](crate::catalogue)), each made from a model type by [`Entry::of`] with
//! defaults that its builder methods override; [`crate::main`] runs the command line
//! over it.
//!
//! Parameters are handled as YAML values ([`serde_yaml::Mapping`]): the defaults are the
//! model's `Params::default()` serialised, an override replaces one entry (after a check
//! that the name exists and the value has the default's shape: a number, or a list of as
//! many numbers), and the result is deserialised back into the model's parameter struct.
//! So one piece of code serves every model, and a scenario file, a `--set NAME=VALUE`
//! flag and a sweep all go through it.
//!
//! # Files
//!
//! A run ([`CatalogModel::run`]) writes into its output directory (created if needed):
//!
//! - the results: `<name>.csv` (`t`, then the recorded states and outputs, all of them
//!   by default, or the entry's [`EntryOf::record`]), and whatever the entry's
//!   [`Extras`] write (the quick return's `quick_return.csv`, its table then named
//!   `quick_return_extra.csv`); beside each, `<stem>.units.csv`: one row per column of
//!   the results file (`column,unit,description`), the units and docs the model
//!   declares (the results file's header row stays plain names);
//! - the figures, unless plots are off, each as PNG and SVG: the extras' own (the quick
//!   return's paper figures), and for an entry whose extras draw none
//!   ([`Extras::figure_ids`] is `None`) the generic ones: one chart per recorded output
//!   against time (`<output>.png`); one per state, a vector's components together
//!   (`state_<name>.png`; by default only for a model of at most
//!   [`STATE_CHART_LIMIT`] states, else those `plots` names); the energy balance
//!   (`energy_balance.png`, for a model with an energy account: the stored energy
//!   against `E(t0) + ∫ supplied − ∫ dissipated + Σ ΔE_events`, and their difference,
//!   [`EnergyBalance`]), with a line in the summary giving the largest difference
//!   relative to the energy scale; and for any entry, the phase portraits asked for
//!   (`phase_<x>_<y>.png`, [`PhasePair`]);
//! - for a model with events, `events.csv` (one row per state an event changed, with
//!   the event's time, name, values before and after, and energy change; see the
//!   private `events` module), and the summary counts the events by name and sums
//!   their energy; the extras are told each event's energy ([`ExtraRun::events`]);
//! - `index.html`: the run's summary, the extras' HTML sections ([`ExtraRun::sections`];
//!   for every model the causal bond graph, drawn by Graphviz's `dot` as inline SVG
//!   when it is on the `PATH`, else its DOT text), for a model with bodies
//!   (`Model::BODIES`, or an entry's [`EntryOf::poses`]) the animation of the run
//!   ([`crate::animation`]), and every figure it drew,
//!   self-contained;
//! - `run.yaml`: what produced the results ([`provenance`](crate::provenance)); a
//!   sweep writes one too.
//!
//! A sweep ([`run_sweep`]) runs every point of the grid over one or two parameters on
//! rayon's pool (one run per task, as many at once as there are cores, or
//! `RAYON_NUM_THREADS`) and writes `sweep.csv` (the parameters, then `peak_<name>` for
//! each metric: the largest magnitude over the window), one chart per metric
//! (`sweep_peak_<name>.png`, `.svg`) and `index.html`; no per-run results.
//!
//! A Monte Carlo study ([`run_study`]) runs every sample the same way and writes
//! `samples.csv`, `trajectories.csv`, `bands.csv`, one band chart per banded column
//! (`band_<name>.png`, `.svg`), `index.html` and `run.yaml` (see the scenario's
//! `monte_carlo:`). With `--shard K/N` a sweep or a study runs one block of its points
//! or samples into a shard folder with `shard.yaml` ([`crate::study::manifest`]), and
//! [`merge`] joins the N folders into the one-process files, bit for bit.
//!
//! # Results folders
//!
//! A run's files (its results CSVs, figures, `index.html`) form one set, and an output
//! folder only ever holds one complete set ([`folder::RunFolder`]):
//!
//! - The run writes the whole set into a fresh staging folder beside the destination,
//!   `.<name>.staging-<pid>` (created before the integration starts), and when every
//!   file is written and synced, swaps it in for the destination (on Linux atomically,
//!   with `renameat2(RENAME_EXCHANGE)`; elsewhere the old folder is renamed aside to
//!   `.<name>.old-<pid>` first and renamed back if the second rename fails), then removes
//!   the set it replaced. So no file of an earlier run survives beside the new one.
//! - A run that fails or is interrupted part-way (a solver error, its step or wall-time
//!   budget used up, a signal while integrating, writing or drawing) leaves the
//!   destination untouched and commits its partial set the same way to the sibling
//!   folder `<name>.partial/` (replacing an earlier partial set whole; a later successful
//!   run leaves it alone). Its figures are drawn from the samples it has (none if it
//!   was interrupted while drawing), and its summary (printed, and in `index.html`)
//!   starts with `PARTIAL RUN` and the reason; the [`Outcome`] carries the failure. A
//!   sweep with failed (or, after an interrupt, unrun) points writes them as `NaN`,
//!   lists them in its summary and is committed to `<name>.partial/` too.
//! - A run that cannot write its set (a full disk, a read-only folder) removes its
//!   staging folder and leaves both folders as they were.
//! - The program replaces only folders it wrote itself: each holds the marker file
//!   `.models-results` ([`folder::MARKER`]). An output folder that exists, is not empty
//!   and has no marker is refused before anything runs ([`RunError::NotOurs`]).
//! - Staging folders left by a process killed outright (SIGKILL) are removed by the
//!   next run into the same parent folder.
//!
//! Within the staging folder every file is also written whole or not at all: into a
//! temporary file, synced and renamed into place. What signals do is described in
//! [`crate::interrupt`].
//!
//! # Example
//!
//! ```
//! use bgdsl_cli::catalog::{self, Catalogue, Entry};
//! use bgdsl_runtime::bond_graph;
//!
//! bond_graph! {
//!     /// A mass on a spring.
//!     pub model Spring {
//!         /// mass
//!         param m = 1.0 in "kg";
//!         /// stiffness
//!         param k = 4.0 in "N/m";
//!         I mass = m, p in "kg·m/s";
//!         C spring = k, q in "m";
//!         1 v;
//!         v -> { mass, spring };
//!         init spring.q = 0.1;
//!         /// Position of the mass, m.
//!         output x = spring.q in "m";
//!     }
//! }
//!
//! let catalogue = Catalogue::new("doc").entry(
//!     Entry::of::<Spring>().checks(|p: &SpringParams, checks| checks.positive("m", p.m)),
//! );
//! let entry = catalogue.find("spring").unwrap();
//! let mut params = entry.model.default_parameters();
//! catalog::set_parameter(entry, &mut params, "m", serde_yaml::from_str("0").unwrap()).unwrap();
//! let problems = entry.model.check(&params);
//! assert_eq!(problems[0].keys, ["m"]);
//! assert!(problems[0].message.contains("must be > 0"), "{}", problems[0].message);
//! ```

mod adapter;
mod addons;
pub mod analysis;
mod checks;
mod columns;
mod entry;
mod events;
mod extras;
mod figures;
pub mod folder;
mod params;
mod run;
pub mod size;
mod study;
mod sweep;

use bgdsl_runtime::{CausalGraph, ParameterInfo};
use serde_yaml::Mapping;

pub use checks::{Checks, Problem};
pub use columns::{column_unit, resolve_columns, units_path, write_units, Column};
pub use entry::{Catalogue, Entry, EntryOf, UnknownModel};
pub use extras::{ExtraRun, Extras, Finished, NoExtras, RunContext, Written};
pub use figures::energy::{EnergyBalance, EnergyRecorder, FIGURE_ID as ENERGY_FIGURE_ID};
pub use figures::graph::{dot_svg, DotError, DOT_TIMEOUT};
pub use figures::phase::{PhasePair, PhaseRecorder};
pub use figures::plot_error;
pub use figures::states::{state_groups, StateGroup, STATE_CHART_LIMIT};
pub use params::{
    describe_value, format_value, overflow_message, overflowing_number, parse_value, set_parameter,
};
pub use params::{format_number, format_significant};
pub use run::{
    create_dir as create_output_dir, initial_state, params_from, Observer, Outcome, Plots,
    RunError, RunPlan, Silent, SolverSettings,
};
pub use study::{all_outputs, merge, run_study, DrawnParameter, StudyOutcome, StudyPlan};
pub use sweep::{metric_unit, run_sweep, Axis, Metric, SweepOutcome, SweepPlan};

/// A model of the catalogue behind an object-safe interface, so that the program can
/// hold them in one list. Implemented for every model [`Entry::of`] accepts; parameters are
/// passed as the YAML mapping of all of them (see the [module documentation](self)).
pub trait CatalogModel: Send + Sync {
    /// The model's type name (`Model::NAME`), e.g. `QuickReturn`.
    fn type_name(&self) -> &'static str;
    /// The parameters in declaration order, with units and docs.
    fn parameters(&self) -> &'static [ParameterInfo];
    /// Every parameter with its default value, in declaration order.
    fn default_parameters(&self) -> Mapping;
    /// The state names, in the order of the state vector.
    fn state_names(&self) -> &'static [&'static str];
    /// The output names, in the order of the output vector.
    fn output_names(&self) -> &'static [&'static str];
    /// The states with their units and docs (`Model::STATES`), in the order of the
    /// state vector.
    fn states(&self) -> &'static [bgdsl_runtime::SignalInfo];
    /// The outputs with their units and docs (`Model::OUTPUTS`), in the order of the
    /// output vector.
    fn outputs(&self) -> &'static [bgdsl_runtime::SignalInfo];
    /// What is wrong with `params` (which must hold every parameter, each of the right
    /// shape, as [`set_parameter`] keeps them): non-finite numbers and the model's
    /// physical checks. Empty when the model can run with them.
    fn check(&self, params: &Mapping) -> Vec<Problem>;
    /// The declared initial state for `params`.
    ///
    /// # Errors
    ///
    /// When `params` do not deserialise into the model's parameters.
    fn initial_state(&self, params: &Mapping) -> Result<Vec<f64>, RunError>;
    /// The causal bond graph the model was generated from.
    fn causal_graph(&self) -> Option<&'static CausalGraph>;
    /// The inputs a host sets between steps (none for most models).
    fn inputs(&self) -> &'static [bgdsl_runtime::InputInfo];
    /// What an FMI 2.0 FMU of the model declares (the `fmu` command).
    fn fmu_description(&self) -> bgdsl_fmi_core::ModelDescription;
    /// Runs `plan` and writes its files (see [`RunPlan`] and [`Outcome`]).
    ///
    /// # Errors
    ///
    /// [`RunError`] when nothing could be written; a run that fails part-way is an
    /// [`Outcome`] with a failure.
    fn run(
        &self,
        entry: &Entry,
        plan: &RunPlan,
        observer: &dyn Observer,
    ) -> Result<Outcome, RunError>;
    /// Runs one point of a sweep and returns each metric's value (`NaN` where the
    /// window holds no sample).
    ///
    /// # Errors
    ///
    /// [`RunError`] when the run fails or is stopped.
    fn sweep_point(
        &self,
        plan: &RunPlan,
        metrics: &[Metric],
        window: [f64; 2],
        observer: &dyn Observer,
    ) -> Result<Vec<f64>, RunError>;
    /// Runs one sample of a study and returns `columns` at every sample time, row-major
    /// (times, then columns).
    ///
    /// # Errors
    ///
    /// [`RunError`] when the run fails or is stopped.
    fn trajectory(
        &self,
        plan: &RunPlan,
        columns: &[Column],
        observer: &dyn Observer,
    ) -> Result<Vec<f64>, RunError>;
    /// The equilibrium of the model with `plan`'s parameters, from its initial state
    /// (with `request`'s guess) at its start time (`models steady`; see
    /// [`analysis::steady`]).
    ///
    /// # Errors
    ///
    /// [`AnalysisFailure`](analysis::AnalysisFailure): a singular Jacobian naming the
    /// states, no convergence.
    fn steady(
        &self,
        plan: &RunPlan,
        request: &analysis::steady::SteadyRequest,
    ) -> Result<analysis::steady::SteadyResult, analysis::AnalysisFailure>;
    /// The linear model of the model with `plan`'s parameters at `request`'s operating
    /// point (`models linearize`, `models bode`; see [`analysis::linear`]).
    ///
    /// # Errors
    ///
    /// [`AnalysisFailure`](analysis::AnalysisFailure): an unknown input or output (a
    /// usage error), a failed equilibrium or run to the operating point.
    fn linearize(
        &self,
        plan: &RunPlan,
        request: &analysis::linear::LinearRequest,
    ) -> Result<bgdsl_analysis::LinearModel, analysis::AnalysisFailure>;
    /// The periodic orbit of the model with `plan`'s parameters near its initial state,
    /// from its start time, with `columns` sampled over one period (`models periodic`;
    /// see [`analysis::periodic`]).
    ///
    /// # Errors
    ///
    /// [`AnalysisFailure`](analysis::AnalysisFailure): a bad period, a failed run, no
    /// convergence.
    fn periodic(
        &self,
        plan: &RunPlan,
        columns: &[Column],
        request: &analysis::periodic::PeriodicRequest,
    ) -> Result<analysis::periodic::PeriodicFound, analysis::AnalysisFailure>;
    /// The least-squares fit of `parameters` of the model, from `plan`'s values, to
    /// `data` (`models fit`; see [`analysis::fit`]).
    ///
    /// # Errors
    ///
    /// [`AnalysisFailure`](analysis::AnalysisFailure): an unknown parameter or column, a
    /// failed run, parameters the data do not determine.
    fn fit(
        &self,
        plan: &RunPlan,
        data: &bgdsl_analysis::fit::Measurements,
        parameters: &[analysis::fit::FitBound],
        options: &bgdsl_analysis::fit::FitOptions,
    ) -> Result<analysis::fit::FitFound, analysis::AnalysisFailure>;
}

/// The summary's last line: where the run's page is, `report         out/x/index.html`.
pub(crate) fn report_line(index: &std::path::Path) -> String {
    format!("report         {}\n", index.display())
}
