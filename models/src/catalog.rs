//! The models the `models` program knows, by name ([`catalogue`]), with their physical
//! parameter checks ([`Catalogued`]) and the quick return family's extras
//! ([`QuickReturnExtras`]: the spec's results file, the paper's figures, the
//! comparison run). The machinery (parameters as YAML, runs, sweeps, results folders)
//! is [`bgdsl_cli::catalog`], re-exported here.
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
//! | `butterworth` | [`Butterworth`]: the third-order Butterworth ladder filter |

pub mod compare;
mod extras;
mod physics;

use std::sync::LazyLock;

use bgdsl_runtime::{DormandPrinceOptions, Model, Radau5Options, Solver};

pub use bgdsl_cli::catalog::*;
pub use compare::Compare;
pub use extras::QuickReturnExtras;
pub use physics::Catalogued;

use crate::dc_servo::DcServo;
use crate::hybrid::{
    BeltFriction, BouncingBall, ClutchEngagement, EndStop, HalfWaveRectifier, HalfWaveRectifierExp,
};
use crate::quick_return::QuickReturn;
use crate::quick_return_hybrid::{QuickReturnEndStop, QuickReturnFriction};
use crate::quick_return_rigid::{QuickReturnRigid, QuickReturnRigidCoupled};
use crate::{Butterworth, DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

/// The flagship's solver: Radau IIA at rtol 1e-6; atol 1e-10 resolves the joint
/// deflections (~1e-4 m).
///
/// Its Jacobian costs about 90 derivative evaluations (30 directions on 117 states) and
/// a factorization about 45, so the work is reused more boldly than Radau5's defaults
/// do (they suit small models, whose Jacobians cost a few evaluations): the Jacobian is
/// kept while the Newton iteration contracts faster than 0.2, and with it a step size
/// the controller would change by a factor in [0.6, 2] is kept, and its factors too.
/// Measured (`models/examples/flagship_profile.rs`, `docs/flagship-speed.md`): half the
/// Jacobians, a third of the factorizations, 15 % less CPU at rtol 1e-6 with an error
/// as small (3.1e-6 against 3.8e-6 of the column peaks) and 7–27 % less at rtol
/// 1e-4…1e-8. On the Bari test set's small problems the same settings cost up to 40 %
/// more evaluations, so they are not the defaults.
///
/// The Newton iteration stops at 0.03 of the (transformed) tolerance, RADAU5's upper
/// value for its stopping tolerance (its default takes `min(0.03, sqrt(rtol'))`,
/// 2.2e-3 here): the flagship's error is its discretization error, not the
/// iteration's (3.9e-6 of the column peaks at rtol 1e-6 against 3.1e-6, within ±5 %
/// at rtol 1e-4, 1e-5 and 1e-7, smaller at 1e-8), for 20 % fewer evaluations and
/// solves. On the Bari set it costs up to two digits, so it is not the default either.
pub fn flagship_solver() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-10,
        reuse_jacobian_below: 0.2,
        hold_step_min: 0.6,
        hold_step_max: 2.0,
        newton_tol: Some(0.03),
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

/// The exponential-law rectifier's solver: Radau IIA at its default tolerances with
/// steps of at most 0.1 ms (a two-hundredth of the 50 Hz source's period). Without the
/// limit it steps over the short conduction pulses (39–66 steps over 0.1 s), and the
/// run's energy balance misses 40 % of the energy scale: the capacitor discharges
/// through pulses that should recharge it.
fn rectifier_exp_solver() -> Solver {
    Solver::Radau5(Radau5Options {
        max_step: 1e-4,
        ..Default::default()
    })
}

/// The friction variant's comparison: the same run without friction.
static WITHOUT_FRICTION: Compare = Compare {
    label: "without friction",
    set: &[("mu", 0.0), ("mu_s", 0.0)],
};

/// The end stop variant's comparison: the same run with the stop beyond the stroke.
static WITHOUT_STOP: Compare = Compare {
    label: "without the stop",
    set: &[("x_stop", 1.0)],
};

/// What the end stop variant records beside the spec's columns, and draws.
const STOP_COLUMNS: &[&str] = &["F_stop", "gap", "resting"];

/// What the friction variant records beside the spec's columns, and draws.
const FRICTION_COLUMNS: &[&str] = &[
    "Ff_3C", "N_3C", "u_3C", "mode_3C", "Ff_5C", "N_5C", "u_5C", "mode_5C", "P_fric",
];

/// The quick return's links as the animation draws them: boxes of the spec's edge
/// lengths (Table 1) about each link's centre of mass.
fn link_boxes(l: [[f64; 3]; 5]) -> Vec<(&'static str, bgdsl_cli::animation::Shape)> {
    ["crank", "slider", "rocker", "rod", "output_slider"]
        .into_iter()
        .zip(l)
        .map(|(name, size)| (name, bgdsl_cli::animation::Shape::Box { size }))
        .collect()
}

/// The quick return's pivots on the ground: the crank's O1 at the origin, the
/// rocker's O3 at (0, −d, 0).
fn pivots(d: f64) -> Vec<[f64; 3]> {
    vec![[0.0, 0.0, 0.0], [0.0, -d, 0.0]]
}

/// The rigid quick return's links at a sample: the mechanism assembled at the run's
/// crank angle (output `crank_angle`), where rigid joints hold it.
fn rigid_poses(theta: f64, d: f64, l: [f64; 3]) -> Vec<bgdsl_cli::animation::BodyPose> {
    let pose = crate::quick_return::assembly(theta, d, l[0], l[1], l[2]);
    pose.orientation
        .iter()
        .zip(pose.position)
        .map(|(r, p)| {
            let mut columns = [0.0; 9];
            columns.copy_from_slice(r.as_slice());
            ([p.x, p.y, p.z], columns)
        })
        .collect()
}

/// The output `crank_angle` among `names` at outputs `y` (NaN, which draws nothing,
/// were there none).
fn crank_angle(names: &[&str], y: &[f64]) -> f64 {
    names
        .iter()
        .position(|n| *n == "crank_angle")
        .and_then(|i| y.get(i).copied())
        .unwrap_or(f64::NAN)
}

/// The quick return's links, by name, in the order of its `assembly`.
const LINKS: &[&str] = &["crank", "slider", "rocker", "rod", "output_slider"];

/// The `models` program's catalogue: every model, in the order `models list` prints
/// them, the flagship first (what `models` runs without a command).
pub fn catalogue() -> Catalogue {
    Catalogue::new("models")
        .version(env!("CARGO_PKG_VERSION"))
        .commit(env!("MODELS_GIT_COMMIT"), env!("MODELS_GIT_DIRTY"))
        .about("Run the bond-graph models of bgdsl: the quick return mechanism and friends.")
        .default_help(
            "Without a command, runs the flagship (the quick return mechanism, 0-5 s) and \
             writes out/quick_return/.",
        )
        .fmi_library(bgdsl_fmi_core::CATALOGUE_PACKAGE)
        .entry(
            Entry::of::<QuickReturn>()
                .name("quick_return")
                .description(
                    "the quick return mechanism of Vaz & Thommen (2010): five links in 3-D, \
                     compliant joints, the crank driven at a constant speed",
                )
                .t_end(5.0)
                .interval(1e-3)
                .solver(flagship_solver())
                .checks(QuickReturn::check_params)
                .shapes(|p| link_boxes([p.l1, p.l2, p.l3, p.l4, p.l5]))
                .ground(|p| pivots(p.d))
                .record(&[])
                .extras(QuickReturnExtras::<QuickReturn>::new()),
        )
        .entry(
            Entry::of::<QuickReturnRigid>()
                .name("quick_return_rigid")
                .description(
                    "the quick return mechanism with rigid joints, in the plane, the crank \
                     driven by a flow source: the inverse dynamics as a bond graph",
                )
                .t_end(5.0)
                .interval(1e-3)
                .solver(rigid_solver())
                .checks(QuickReturnRigid::check_params)
                .poses(LINKS, |p, _, _, y| {
                    let theta = crank_angle(<QuickReturnRigid as Model>::OUTPUT_NAMES, y);
                    rigid_poses(theta, p.d, [p.l1[0], p.l3[0], p.l4[0]])
                })
                .shapes(|p| link_boxes([p.l1, p.l2, p.l3, p.l4, p.l5]))
                .ground(|p| pivots(p.d))
                .record(&[])
                .extras(QuickReturnExtras::<QuickReturnRigid>::new()),
        )
        .entry(
            Entry::of::<QuickReturnRigidCoupled>()
                .name("quick_return_rigid_coupled")
                .description(
                    "the quick return mechanism with rigid joints, the crank driven through \
                     the compliant drive coupling",
                )
                .t_end(5.0)
                .interval(1e-3)
                .solver(coupled_solver())
                .checks(QuickReturnRigidCoupled::check_params)
                .poses(LINKS, |p, _, _, y| {
                    let theta = crank_angle(<QuickReturnRigidCoupled as Model>::OUTPUT_NAMES, y);
                    rigid_poses(theta, p.d, [p.l1[0], p.l3[0], p.l4[0]])
                })
                .shapes(|p| link_boxes([p.l1, p.l2, p.l3, p.l4, p.l5]))
                .ground(|p| pivots(p.d))
                .record(&[])
                .extras(QuickReturnExtras::<QuickReturnRigidCoupled>::new()),
        )
        .entry(
            Entry::of::<QuickReturnFriction>()
                .name("quick_return_friction")
                .description(
                    "the quick return mechanism with Coulomb friction and stiction in its two \
                     slides (mu on the normal force) beside the viscous 20 N·s/m",
                )
                .t_end(5.0)
                .interval(1e-3)
                .solver(flagship_solver())
                .checks(QuickReturnFriction::check_params)
                .shapes(|p| link_boxes([p.l1, p.l2, p.l3, p.l4, p.l5]))
                .ground(|p| pivots(p.d))
                .record(FRICTION_COLUMNS)
                .extras(QuickReturnExtras::<QuickReturnFriction>::compared_with(
                    &WITHOUT_FRICTION,
                )),
        )
        .entry(
            Entry::of::<QuickReturnEndStop>()
                .name("quick_return_end_stop")
                .description(
                    "the quick return mechanism with an end stop on the output slider's guide \
                     inside its stroke: impacts with restitution, a rest mode",
                )
                .t_end(5.0)
                .interval(1e-3)
                .solver(flagship_solver())
                .checks(QuickReturnEndStop::check_params)
                .shapes(|p| link_boxes([p.l1, p.l2, p.l3, p.l4, p.l5]))
                .ground(|p| pivots(p.d))
                .record(STOP_COLUMNS)
                .extras(QuickReturnExtras::<QuickReturnEndStop>::compared_with(
                    &WITHOUT_STOP,
                )),
        )
        .entry(
            Entry::of::<BouncingBall>()
                .name("bouncing_ball")
                .description(
                    "a ball dropped on a floor: impacts with restitution, at rest after the \
                     bounces fall below a rest speed",
                )
                .t_end(5.0)
                .interval(1e-3)
                .solver(event_solver())
                .checks(BouncingBall::check_params),
        )
        .entry(
            Entry::of::<HalfWaveRectifier>()
                .name("rectifier")
                .description(
                    "a half-wave rectifier: a sine source, an ideal diode (switched at zero \
                     voltage) and an RC load",
                )
                .t_end(0.1)
                .interval(1e-5)
                .solver(rectifier_solver())
                .checks(HalfWaveRectifier::check_params),
        )
        .entry(
            Entry::of::<HalfWaveRectifierExp>()
                .name("rectifier_exp")
                .description(
                    "the half-wave rectifier with an exponential-law diode (smooth, stiff)",
                )
                .t_end(0.1)
                .interval(1e-5)
                .solver(rectifier_exp_solver())
                .checks(HalfWaveRectifierExp::check_params),
        )
        .entry(
            Entry::of::<BeltFriction>()
                .name("stick_slip")
                .description(
                    "a mass on a spring riding a moving belt: Coulomb friction with \
                     stiction, stick and slip",
                )
                .t_end(20.0)
                .interval(1e-3)
                .solver(event_solver())
                .checks(BeltFriction::check_params),
        )
        .entry(
            Entry::of::<EndStop>()
                .name("end_stop")
                .description("a mass on a spring hitting an end stop with restitution")
                .t_end(5.0)
                .interval(1e-3)
                .solver(event_solver())
                .checks(EndStop::check_params),
        )
        .entry(
            Entry::of::<ClutchEngagement>()
                .name("clutch")
                .description(
                    "two shafts joined by a friction clutch that locks when their speeds match",
                )
                .t_end(5.0)
                .interval(1e-3)
                .solver(event_solver())
                .checks(ClutchEngagement::check_params),
        )
        .entry(
            Entry::of::<Oscillator>()
                .name("oscillator")
                .description("a mass on a spring with a damper, pushed by a constant force")
                .t_end(10.0)
                .interval(1e-2)
                .solver(Solver::stiff())
                .checks(Oscillator::check_params),
        )
        .entry(
            Entry::of::<SeriesRlc>()
                .name("rlc")
                .description("a series RLC circuit switched onto a voltage source")
                .t_end(0.01)
                .interval(1e-5)
                .solver(Solver::stiff())
                .checks(SeriesRlc::check_params),
        )
        .entry(
            Entry::of::<DcMotor>()
                .name("dc_motor")
                .description(
                    "a DC motor driving an inertial load through a gearbox and a compliant \
                     shaft",
                )
                .t_end(1.0)
                .interval(1e-3)
                .solver(Solver::stiff())
                .checks(DcMotor::check_params),
        )
        .entry(
            Entry::of::<QuarterCar>()
                .name("quarter_car")
                .description("the quarter-car suspension model driving over a bump")
                .t_end(3.0)
                .interval(1e-3)
                .solver(road_solver())
                .checks(QuarterCar::check_params),
        )
        .entry(
            Entry::of::<Duffing>()
                .name("duffing")
                .description("the forced Duffing oscillator: a mass on a cubic hardening spring")
                .t_end(100.0)
                .interval(1e-2)
                .solver(Solver::stiff())
                .checks(Duffing::check_params),
        )
        .entry(
            Entry::of::<DcServo>()
                .name("dc_servo")
                .description(
                    "the DC motor with its voltage and load torque as inputs, for a host's \
                     controller (run alone: the inputs stay at their defaults)",
                )
                .t_end(1.0)
                .interval(1e-3)
                .solver(Solver::stiff())
                .checks(DcServo::check_params),
        )
        .entry(
            Entry::of::<Butterworth>()
                .name("butterworth")
                .description(
                    "the third-order Butterworth ladder filter (Rs = RL = 1 Ω, L = 1 H, \
                     C = 2 F), its step response; `models bode` gives its frequency response",
                )
                .t_end(20.0)
                .interval(1e-2)
                .solver(Solver::stiff())
                .checks(Butterworth::check_params),
        )
}

/// The catalogue, built once (for the tests, the benches and the FMI library).
static CATALOGUE: LazyLock<Catalogue> = LazyLock::new(catalogue);

/// The catalogue's entries, in order.
pub fn entries() -> &'static [Entry] {
    CATALOGUE.entries()
}

/// The model names, comma-separated.
pub fn names() -> String {
    CATALOGUE.names().join(", ")
}

/// The model called `name`.
///
/// # Errors
///
/// [`UnknownModel`], whose message lists the models.
pub fn find(name: &str) -> Result<&'static Entry, UnknownModel> {
    CATALOGUE.find(name)
}

/// The catalogue, built once.
pub fn shared() -> &'static Catalogue {
    &CATALOGUE
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_has_described_parameters_and_valid_defaults() {
        for entry in entries() {
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
             rectifier_exp, stick_slip, end_stop, clutch, oscillator, rlc, dc_motor, quarter_car, duffing, dc_servo, \
             butterworth"
        );
    }
}
