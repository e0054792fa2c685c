//! The flagship run (`models::quick_return`: results file, summary, run) on the
//! hand-written quick return mechanism (`models/benches/quick_return_hand/model.rs`),
//! with the generic checks of `common/quick_return.rs`, which say what each checks and
//! why its tolerance is what it is. The model written in the bond-graph language gets
//! the same checks with one line each.
//!
//! Solver: Radau5 at rtol 1e-6, atol 1e-10 (`quick_return::flagship_solver`, which says
//! why); the energy balance at rtol 1e-8.

mod common;

#[path = "../../models/benches/quick_return_hand/model.rs"]
#[allow(dead_code)]
mod quick_return_hand;

use std::sync::OnceLock;

use common::quick_return::{self as qr, FlagshipRun};
use quick_return_hand::{QuickReturnHand, QuickReturnHandParams};

#[global_allocator]
static GLOBAL: common::counting::Counting = common::counting::Counting;

/// The default model's flagship run, shared by the checks (it is the expensive part).
fn default_run() -> &'static FlagshipRun {
    static RUN: OnceLock<FlagshipRun> = OnceLock::new();
    RUN.get_or_init(|| qr::flagship_run(&QuickReturnHand::default(), "hand_default"))
}

#[test]
fn writes_the_specs_results_file() {
    qr::check_results_file(default_run());
}

#[test]
fn shows_the_papers_findings() {
    qr::check_default_scenario(default_run());
}

#[test]
fn gives_forces_and_torques_the_specs_signs() {
    let p = QuickReturnHandParams::default();
    let weight = p.masses().iter().sum::<f64>() * p.g;
    qr::check_signs(default_run(), weight);
}

#[test]
fn stays_in_the_plane() {
    qr::check_planar(default_run());
}

#[test]
fn lets_the_start_up_transients_die_out() {
    qr::check_transients_decay(default_run());
}

#[test]
fn keeps_orientations_orthonormal() {
    qr::check_orthonormal(default_run());
}

#[test]
fn summarises_the_run() {
    qr::check_summary(default_run());
}

#[test]
fn runs_without_gravity() {
    let model = QuickReturnHand::new(QuickReturnHandParams {
        g: 0.0,
        ..Default::default()
    });
    qr::check_runs(&model, "hand_no_gravity");
}

#[test]
fn balances_energy() {
    qr::check_energy_balance(&QuickReturnHand::default());
}

#[test]
fn records_without_allocating() {
    qr::check_recording_allocates_nothing(&QuickReturnHand::default());
}

#[test]
fn leaves_nothing_behind_when_it_fails() {
    qr::check_failure_leaves_nothing(&QuickReturnHand::default(), "hand_failure");
}
