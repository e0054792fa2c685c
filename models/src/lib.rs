//! Models written with `bond_graph!`, one module per model, each with its bond graph
//! drawn in its documentation, and the catalogue of the `models` program
//! ([`catalog::catalogue`]), which [`bgdsl_cli`] runs:
//!
//! - [`Oscillator`]: mass, spring and damper pushed by a force.
//! - [`SeriesRlc`]: a series RLC circuit on a voltage source.
//! - [`DcMotor`]: a DC motor driving a geared, compliant, inertial load.
//! - [`QuarterCar`]: the quarter-car suspension model over a road profile.
//! - [`Duffing`]: the forced Duffing oscillator (a cubic spring).
//! - [`Butterworth`]: the third-order Butterworth ladder filter (a frequency-response
//!   reference).
//! - [`hybrid`]: models with events and modes (bouncing ball, rectifier, end stop,
//!   clutch).
//!
//! The program's generic modules live in `bgdsl-cli` and are re-exported here under
//! their old paths ([`cli`], [`scenario`], [`provenance`], [`plot`], [`report`],
//! [`interrupt`]). The hidden module `reference` holds hand-written equations of some
//! of the models, for the tests and benchmarks that compare them with the generated
//! code.

pub mod butterworth;
pub mod catalog;
pub mod control;
pub mod dc_motor;
pub mod dc_servo;
pub mod duffing;
pub mod hybrid;
pub mod oscillator;
pub mod quarter_car;
pub mod quick_return;
pub mod quick_return_hybrid;
pub mod quick_return_rigid;
#[doc(hidden)]
pub mod reference;
pub mod rlc;

pub use bgdsl_cli::{cli, interrupt, plot, provenance, report, scenario};
pub use butterworth::{Butterworth, ButterworthOutputs, ButterworthParams, ButterworthState};
pub use catalog::catalogue;
pub use dc_motor::{DcMotor, DcMotorOutputs, DcMotorParams, DcMotorState};
pub use duffing::{Duffing, DuffingOutputs, DuffingParams, DuffingState};
pub use oscillator::{Oscillator, OscillatorOutputs, OscillatorParams, OscillatorState};
pub use quarter_car::{QuarterCar, QuarterCarOutputs, QuarterCarParams, QuarterCarState};
pub use rlc::{SeriesRlc, SeriesRlcOutputs, SeriesRlcParams, SeriesRlcState};
