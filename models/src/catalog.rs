//! The models the `models` program knows, by name, and everything it needs to treat
//! them alike: their parameters (defaults, units, docs), overriding parameters by name,
//! physical validation, and running them into files.
//!
//! | name | model |
//! |---|---|
//! | `quick_return` | [`QuickReturn`]: the flagship, writes the spec's results file and the paper's figures |
//! | `quick_return_rigid` | [`QuickReturnRigid`]: the same mechanism with rigid joints, the crank driven by a flow source; the same results file and figures |
//! | `quick_return_rigid_coupled` | [`QuickReturnRigidCoupled`]: rigid joints, the crank driven through the compliant drive coupling |
//! | `quick_return_friction` | [`QuickReturnFriction`]: the flagship with Coulomb friction and stiction in its slides; the same results file and figures, the friction's columns and charts, and a comparison with the run without friction |
//! | `quick_return_end_stop` | [`QuickReturnEndStop`]: the flagship with an end stop on the output slider's guide; the same files, the stop's columns and charts, `events.csv`, and a comparison with the run without the stop |
//! | `bouncing_ball` | [`BouncingBall`]: impacts with restitution, a rest mode |
//! | `rectifier` | [`HalfWaveRectifier`]: an ideal diode switched by events |
//! | `rectifier_exp` | [`HalfWaveRectifierExp`]: the same with an exponential-law diode |
//! | `stick_slip` | [`BeltFriction`]: a mass on a belt, stick and slip |
//! | `end_stop` | [`EndStop`]: a mass hitting an end stop with restitution |
//! | `clutch` | [`ClutchEngagement`]: a clutch locking at a speed match |
//! | `oscillator` | [`Oscillator`] |
//! | `rlc` | [`SeriesRlc`] |
//! | `dc_motor` | [`DcMotor`] |
//! | `quarter_car` | [`QuarterCar`] |
//! | `duffing` | [`Duffing`] |
//! | `dc_servo` | [`DcServo`] |
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
//! - the results: `quick_return.csv` (the spec's file, always its 56 columns) for the
//!   quick return, `<name>.csv` (`t`, then the recorded states and outputs, all of them
//!   by default) for the other models, and `quick_return_extra.csv` when a quick return
//!   run records extra columns; beside each, `<stem>.units.csv`: one row per column of
//!   the results file (`column,unit,description`), the units and docs the model
//!   declares (the results file's header row stays plain names);
//! - the figures, unless plots are off, each as PNG and SVG (for the quick return, the
//!   paper's Figs. 3–19 and two more; for the other models, one chart per recorded
//!   output against time);
//! - for a model with events, `events.csv` (one row per state an event changed, with
//!   the event's time, name, values before and after, and energy change; see the
//!   private `events` module), and the summary counts the events by name and sums
//!   their energy; the quick return's energy balance (Fig. 21) adds that energy;
//! - for the flagship's hybrid variants, their own columns in `quick_return_extra.csv`
//!   ([`Entry::extra`], one chart each) and, in the summary, the comparison with the
//!   same run without the switching ([`Entry::compare`], [`compare`]);
//! - `index.html`: the run's summary and every figure it drew, self-contained;
//! - `run.yaml`: what produced the results ([`provenance`](crate::provenance)); a
//!   sweep writes one too.
//!
//! A sweep ([`run_sweep`]) runs every point of the grid over one or two parameters on
//! rayon's pool (one run per task, as many at once as there are cores, or
//! `RAYON_NUM_THREADS`) and writes `sweep.csv` (the parameters, then `peak_<name>` for
//! each metric: the largest magnitude over the window), one chart per metric
//! (`sweep_peak_<name>.png`, `.svg`) and `index.html`; no per-run results.
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
//! use models::catalog;
//!
//! let entry = catalog::find("quick_return").unwrap();
//! let mut params = entry.model.default_parameters();
//! catalog::set_parameter(entry, &mut params, "m1", serde_yaml::from_str("0").unwrap()).unwrap();
//! let problems = entry.model.check(&params);
//! assert_eq!(problems[0].keys, ["m1"]);
//! assert!(problems[0].message.contains("must be > 0"), "{}", problems[0].message);
//! ```

mod adapter;
mod checks;
mod columns;
pub mod compare;
mod events;
mod figures;
pub mod folder;
mod params;
mod physics;
mod run;
pub mod size;
mod study;
mod sweep;

use core::fmt;
use core::marker::PhantomData;

use bgdsl_runtime::{CausalGraph, DormandPrinceOptions, ParameterInfo, Radau5Options, Solver};
use serde_yaml::Mapping;

pub use checks::{Checks, Problem};
pub use columns::{resolve_columns, Column};
pub use figures::figure_ids;
pub(crate) use params::format_number;
pub use params::{
    describe_value, format_value, overflow_message, overflowing_number, parse_value, set_parameter,
};
pub use physics::Catalogued;
pub use run::{
    create_dir as create_output_dir, Observer, Outcome, Plots, RunError, RunPlan, Silent,
};
pub use study::{all_outputs, merge, run_study, DrawnParameter, StudyOutcome, StudyPlan};
pub use sweep::{metric_unit, run_sweep, Axis, Metric, SweepOutcome, SweepPlan};

use crate::dc_servo::DcServo;
use crate::hybrid::{
    BeltFriction, BouncingBall, ClutchEngagement, EndStop, HalfWaveRectifier, HalfWaveRectifierExp,
};
use crate::quick_return::QuickReturn;
use crate::quick_return_hybrid::{QuickReturnEndStop, QuickReturnFriction};
use crate::quick_return_rigid::{QuickReturnRigid, QuickReturnRigidCoupled};
use crate::{DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

/// What a model's run writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResultsKind {
    /// `<name>.csv`: `t`, then the recorded states and outputs (all by default).
    Trajectory,
    /// The quick return spec's results file `quick_return.csv` (its 56 columns, always),
    /// the paper's figures, and optionally `quick_return_extra.csv` with other states
    /// and outputs.
    QuickReturn,
}

/// A model the program knows.
pub struct Entry {
    /// The name on the command line and in scenario files, e.g. `quick_return`.
    pub name: &'static str,
    /// One line saying what it is.
    pub description: &'static str,
    /// The model itself, behind an object-safe interface.
    pub model: &'static dyn CatalogModel,
    /// What a run writes.
    pub results: ResultsKind,
    /// The default end of the time span, s (runs start at 0).
    pub t_end: f64,
    /// The default sampling interval, s.
    pub interval: f64,
    /// The solver a run uses unless told otherwise.
    pub solver: fn() -> Solver,
    /// For a quick return model: outputs and states recorded by default into
    /// `quick_return_extra.csv`, one chart each (empty: no such file).
    pub extra: &'static [&'static str],
    /// For a quick return model: the run its summary compares with (the same with
    /// some parameters set), or `None`.
    pub compare: Option<&'static compare::Compare>,
}

impl fmt::Debug for Entry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Entry")
            .field("name", &self.name)
            .field("model", &self.model.type_name())
            .finish_non_exhaustive()
    }
}

/// A model of the catalogue behind an object-safe interface, so that the program can
/// hold them in one list. Implemented for every [`Catalogued`] model; parameters are
/// passed as the YAML mapping of all of them (see the [module documentation](self)).
pub trait CatalogModel: Sync {
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
    /// What an FMI 2.0 FMU of the model declares (`models fmu`).
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
}

/// The adapter that makes a [`Catalogued`] model a [`CatalogModel`].
struct Adapter<M>(PhantomData<fn() -> M>);

/// The flagship's solver: Radau IIA at rtol 1e-6; atol 1e-10 resolves the joint
/// deflections (~1e-4 m).
pub fn flagship_solver() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-10,
        ..Default::default()
    })
}

/// The rigid quick return's solver: DOPRI5 at rtol 1e-6 (with rigid joints the
/// mechanism is not stiff; measured in `benches/quick_return_rigid.rs`).
pub fn rigid_solver() -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-6,
        atol: 1e-9,
        ..Default::default()
    })
}

/// The rigid quick return on its compliant drive coupling: Radau IIA at rtol 1e-6. The
/// coupling's damper (R_C = 100 N·m·s/rad) on the mechanism's small inertia is a fast
/// mode (time constant ~1e-3 s) that limits an explicit method's step: DOPRI5 takes
/// 5545 steps over 0–5 s, Radau5 278.
pub fn coupled_solver() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-9,
        ..Default::default()
    })
}

fn stiff_default() -> Solver {
    Solver::stiff()
}

/// Radau5 with steps of at most 1 ms, so that it cannot step over the quarter car's
/// bump (0.2 s long at 10 m/s) between two samples.
fn road_solver() -> Solver {
    Solver::Radau5(Radau5Options {
        max_step: 1e-3,
        ..Default::default()
    })
}

/// The hybrid models' solver: DOPRI5 at rtol 1e-9, atol 1e-12 (their flights, slips
/// and swings are not stiff; the events are located on its dense output).
pub fn event_solver() -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-9,
        atol: 1e-12,
        ..Default::default()
    })
}

/// The ideal rectifier's solver: Radau IIA at rtol 1e-8 (while the diode conducts the
/// source charges the capacitor with the time constant `r_on C` = 1 ms, beside the
/// load's 0.1 s).
fn rectifier_solver() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-8,
        atol: 1e-10,
        ..Default::default()
    })
}

/// The friction variant's comparison: the same run without friction.
static WITHOUT_FRICTION: compare::Compare = compare::Compare {
    label: "without friction",
    set: &[("mu", 0.0), ("mu_s", 0.0)],
};

/// The end stop variant's comparison: the same run with the stop beyond the stroke.
static WITHOUT_STOP: compare::Compare = compare::Compare {
    label: "without the stop",
    set: &[("x_stop", 1.0)],
};

/// What the end stop variant records beside the spec's columns, and draws.
const STOP_COLUMNS: &[&str] = &["F_stop", "gap", "resting"];

/// What the friction variant records beside the spec's columns, and draws.
const FRICTION_COLUMNS: &[&str] = &[
    "Ff_3C", "N_3C", "u_3C", "mode_3C", "Ff_5C", "N_5C", "u_5C", "mode_5C", "P_fric",
];

/// Every model, in the order `models list` prints them.
pub static MODELS: &[Entry] = &[
    Entry {
        name: "quick_return",
        description: "the quick return mechanism of Vaz & Thommen (2010): five links in 3-D, \
                      compliant joints, the crank driven at a constant speed",
        model: &Adapter::<QuickReturn>(PhantomData),
        results: ResultsKind::QuickReturn,
        t_end: 5.0,
        interval: 1e-3,
        solver: flagship_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "quick_return_rigid",
        description: "the quick return mechanism with rigid joints, in the plane, the crank \
                      driven by a flow source: the inverse dynamics as a bond graph",
        model: &Adapter::<QuickReturnRigid>(PhantomData),
        results: ResultsKind::QuickReturn,
        t_end: 5.0,
        interval: 1e-3,
        solver: rigid_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "quick_return_rigid_coupled",
        description: "the quick return mechanism with rigid joints, the crank driven through \
                      the compliant drive coupling",
        model: &Adapter::<QuickReturnRigidCoupled>(PhantomData),
        results: ResultsKind::QuickReturn,
        t_end: 5.0,
        interval: 1e-3,
        solver: coupled_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "quick_return_friction",
        description: "the quick return mechanism with Coulomb friction and stiction in its two \
                      slides (mu on the normal force) beside the viscous 20 N·s/m",
        model: &Adapter::<QuickReturnFriction>(PhantomData),
        results: ResultsKind::QuickReturn,
        t_end: 5.0,
        interval: 1e-3,
        solver: flagship_solver,
        extra: FRICTION_COLUMNS,
        compare: Some(&WITHOUT_FRICTION),
    },
    Entry {
        name: "quick_return_end_stop",
        description: "the quick return mechanism with an end stop on the output slider's guide \
                      inside its stroke: impacts with restitution, a rest mode",
        model: &Adapter::<QuickReturnEndStop>(PhantomData),
        results: ResultsKind::QuickReturn,
        t_end: 5.0,
        interval: 1e-3,
        solver: flagship_solver,
        extra: STOP_COLUMNS,
        compare: Some(&WITHOUT_STOP),
    },
    Entry {
        name: "bouncing_ball",
        description: "a ball dropped on a floor: impacts with restitution, at rest after the \
                      bounces fall below a rest speed",
        model: &Adapter::<BouncingBall>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 5.0,
        interval: 1e-3,
        solver: event_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "rectifier",
        description: "a half-wave rectifier: a sine source, an ideal diode (switched at zero \
                      voltage) and an RC load",
        model: &Adapter::<HalfWaveRectifier>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 0.1,
        interval: 1e-5,
        solver: rectifier_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "rectifier_exp",
        description: "the half-wave rectifier with an exponential-law diode (smooth, stiff)",
        model: &Adapter::<HalfWaveRectifierExp>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 0.1,
        interval: 1e-5,
        solver: stiff_default,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "stick_slip",
        description: "a mass on a spring riding a moving belt: Coulomb friction with \
                      stiction, stick and slip",
        model: &Adapter::<BeltFriction>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 20.0,
        interval: 1e-3,
        solver: event_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "end_stop",
        description: "a mass on a spring hitting an end stop with restitution",
        model: &Adapter::<EndStop>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 5.0,
        interval: 1e-3,
        solver: event_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "clutch",
        description: "two shafts joined by a friction clutch that locks when their speeds match",
        model: &Adapter::<ClutchEngagement>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 5.0,
        interval: 1e-3,
        solver: event_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "oscillator",
        description: "a mass on a spring with a damper, pushed by a constant force",
        model: &Adapter::<Oscillator>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 10.0,
        interval: 1e-2,
        solver: stiff_default,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "rlc",
        description: "a series RLC circuit switched onto a voltage source",
        model: &Adapter::<SeriesRlc>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 0.01,
        interval: 1e-5,
        solver: stiff_default,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "dc_motor",
        description: "a DC motor driving an inertial load through a gearbox and a compliant \
                      shaft",
        model: &Adapter::<DcMotor>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 1.0,
        interval: 1e-3,
        solver: stiff_default,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "quarter_car",
        description: "the quarter-car suspension model driving over a bump",
        model: &Adapter::<QuarterCar>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 3.0,
        interval: 1e-3,
        solver: road_solver,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "duffing",
        description: "the forced Duffing oscillator: a mass on a cubic hardening spring",
        model: &Adapter::<Duffing>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 100.0,
        interval: 1e-2,
        solver: stiff_default,
        extra: &[],
        compare: None,
    },
    Entry {
        name: "dc_servo",
        description: "the DC motor with its voltage and load torque as inputs, for a host's \
                      controller (run alone: the inputs stay at their defaults)",
        model: &Adapter::<DcServo>(PhantomData),
        results: ResultsKind::Trajectory,
        t_end: 1.0,
        interval: 1e-3,
        solver: stiff_default,
        extra: &[],
        compare: None,
    },
];

/// A model name the catalogue does not have.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownModel {
    /// The name asked for.
    pub name: String,
}

impl fmt::Display for UnknownModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown model `{}`; the models are: {}",
            self.name,
            names()
        )
    }
}

impl std::error::Error for UnknownModel {}

/// The model names, comma-separated.
pub fn names() -> String {
    MODELS.iter().map(|e| e.name).collect::<Vec<_>>().join(", ")
}

/// The model called `name`.
///
/// # Errors
///
/// [`UnknownModel`], whose message lists the models.
pub fn find(name: &str) -> Result<&'static Entry, UnknownModel> {
    MODELS
        .iter()
        .find(|e| e.name == name)
        .ok_or_else(|| UnknownModel {
            name: name.to_owned(),
        })
}

/// The summary's last line: where the run's page is, `report         out/x/index.html`.
pub(crate) fn report_line(index: &std::path::Path) -> String {
    format!("report         {}\n", index.display())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_has_described_parameters_and_valid_defaults() {
        for entry in MODELS {
            let params = entry.model.default_parameters();
            assert_eq!(
                params.len(),
                entry.model.parameters().len(),
                "{}",
                entry.name
            );
            assert!(entry.model.check(&params).is_empty(), "{}", entry.name);
            let x0 = entry.model.initial_state(&params).unwrap();
            assert_eq!(x0.len(), entry.model.state_names().len());
            assert!(entry.model.causal_graph().is_some());
        }
    }

    #[test]
    fn unknown_names_list_the_models() {
        let err = find("crank").unwrap_err();
        assert_eq!(
            err.to_string(),
            "unknown model `crank`; the models are: quick_return, quick_return_rigid, \
             quick_return_rigid_coupled, quick_return_friction, quick_return_end_stop, bouncing_ball, rectifier, \
             rectifier_exp, stick_slip, end_stop, clutch, oscillator, rlc, dc_motor, quarter_car, duffing, dc_servo"
        );
    }
}
