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

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::OnceLock;

use common::quick_return::{self as qr, FlagshipRun};
use quick_return_hand::{QuickReturnHand, QuickReturnHandParams};

/// A global allocator that counts, per thread, the allocations made (as in
/// `alloc_generated.rs`), for `records_without_allocating`.
struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the allocator may be called while the thread's locals are torn down.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Heap allocations made by this thread while running `f`.
fn allocations_in(f: &mut dyn FnMut()) -> u64 {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

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
    qr::check_recording_allocates_nothing(&QuickReturnHand::default(), allocations_in);
}

#[test]
fn leaves_nothing_behind_when_it_fails() {
    qr::check_failure_leaves_nothing(&QuickReturnHand::default(), "hand_failure");
}
