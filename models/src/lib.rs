//! Models written with `bond_graph!`, one module per model, each with its bond graph
//! drawn in its documentation:
//!
//! - [`Oscillator`]: mass, spring and damper pushed by a force.
//! - [`SeriesRlc`]: a series RLC circuit on a voltage source.
//! - [`DcMotor`]: a DC motor driving a geared, compliant, inertial load.
//! - [`QuarterCar`]: the quarter-car suspension model over a road profile.
//! - [`Duffing`]: the forced Duffing oscillator (a cubic spring).
//! - [`hybrid`]: models with events and modes (bouncing ball, rectifier, end stop,
//!   clutch).
//!
//! The hidden module `reference` holds hand-written equations of some of them, for
//! the tests and benchmarks that compare them with the generated code.

pub mod catalog;
pub mod cli;
pub mod control;
pub mod dc_motor;
pub mod dc_servo;
pub mod duffing;
pub mod hybrid;
pub mod interrupt;
pub mod oscillator;
pub mod plot;
pub mod provenance;
pub mod quarter_car;
pub mod quick_return;
pub mod quick_return_hybrid;
pub mod quick_return_rigid;
#[doc(hidden)]
pub mod reference;
pub mod report;
pub mod rlc;
pub mod scenario;

pub use dc_motor::{DcMotor, DcMotorOutputs, DcMotorParams, DcMotorState};
pub use duffing::{Duffing, DuffingOutputs, DuffingParams, DuffingState};
pub use oscillator::{Oscillator, OscillatorOutputs, OscillatorParams, OscillatorState};
pub use quarter_car::{QuarterCar, QuarterCarOutputs, QuarterCarParams, QuarterCarState};
pub use rlc::{SeriesRlc, SeriesRlcOutputs, SeriesRlcParams, SeriesRlcState};
