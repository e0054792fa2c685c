//! FMI 2.0 export of the shipped bgdsl models: one shared library that serves every
//! model of the `models` catalogue as a functional mock-up unit (Model Exchange, and
//! Co-Simulation with the model's own stiff solver inside), and the FMUs themselves.
//!
//! # Building an FMU
//!
//! ```sh
//! cargo build -p bgdsl-fmi --release      # target/release/libbgdsl_fmi.so: the FMUs' binary
//! ```
//!
//! then, from Rust, [`write_fmu`] (`models fmu <model>` does the same):
//!
//! ```no_run
//! let library = bgdsl_fmi::find_library()?; // next to the program, or $BGDSL_FMI_LIBRARY
//! let fmu = bgdsl_fmi::write_fmu("oscillator", &library, "oscillator.fmu".as_ref())?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The FMU holds `modelDescription.xml`, `binaries/linux64/oscillator.so` (this
//! library, renamed) and `documentation/index.html`. Any FMI 2.0 importer loads it:
//!
//! ```python
//! import fmpy
//! fmpy.simulate_fmu("oscillator.fmu", fmi_type="CoSimulation", stop_time=5.0,
//!                   start_values={"k": 200.0})
//! ```
//!
//! # One library, many models
//!
//! Every FMU of the catalogue carries the same binary. `fmi2Instantiate` receives the
//! GUID from the FMU's `modelDescription.xml` and picks the model whose description
//! hashes to it ([`MODELS`]); an unknown GUID (an FMU written with a library built from
//! other model code) is refused with a message that lists the GUIDs this library
//! serves. The FMI functions are the `extern "C"` items of [`fmi2`]; see
//! [`bgdsl_fmi_core`] for the variables, value references and state machine.
//!
//! # Hybrid models
//!
//! The catalogue's hybrid models (the bouncing ball, the rectifiers, the stick-slip
//! belt, the end stop, the clutch, the quick return with friction) have events and
//! modes: their FMUs declare event indicators for Model Exchange and handle the events
//! inside each Co-Simulation step (see [`bgdsl_fmi_core`], "Events and modes");
//! `tests/fmpy_events.rs` runs the ball and the ideal rectifier in FMPy against the
//! closed forms.
#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use bgdsl_fmi_core::{ModelDescription, ModelEntry};
use models::catalog::Catalogued;
use models::dc_servo::DcServo;
use models::hybrid::{
    BeltFriction, BouncingBall, ClutchEngagement, EndStop, HalfWaveRectifier, HalfWaveRectifierExp,
};
use models::quick_return::QuickReturn;
use models::quick_return_hybrid::QuickReturnFriction;
use models::{Butterworth, DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

pub use bgdsl_fmi_core::{find_library, library_file_name, FmuError};

/// The models this library serves, by `modelIdentifier`: the names of the `models`
/// catalogue. Each checks the parameter values an importer sets with the catalogue's
/// physical checks ([`catalogue_check`]), as `models run --set` does.
pub static MODELS: &[ModelEntry] = &[
    entry::<QuickReturn>("quick_return"),
    entry::<Oscillator>("oscillator"),
    entry::<SeriesRlc>("rlc"),
    entry::<DcMotor>("dc_motor"),
    entry::<QuarterCar>("quarter_car"),
    entry::<Duffing>("duffing"),
    entry::<DcServo>("dc_servo"),
    entry::<Butterworth>("butterworth"),
    // With events and modes.
    entry::<BouncingBall>("bouncing_ball"),
    entry::<HalfWaveRectifier>("rectifier"),
    entry::<HalfWaveRectifierExp>("rectifier_exp"),
    entry::<BeltFriction>("stick_slip"),
    entry::<EndStop>("end_stop"),
    entry::<ClutchEngagement>("clutch"),
    entry::<QuickReturnFriction>("quick_return_friction"),
];

const fn entry<M: Catalogued>(identifier: &'static str) -> ModelEntry {
    ModelEntry::new::<M>(identifier).with_check(catalogue_check::<M>)
}

/// The catalogue's physical checks of model `M` ([`Catalogued::check_params`]: a mass
/// of 0, a negative stiffness, a mechanism that cannot be assembled) on a whole set of
/// flat parameter values: `Err` with every problem found, each naming its parameter,
/// its meaning and unit, the rule and the value.
///
/// # Errors
///
/// The values break one of the model's rules.
pub fn catalogue_check<M: Catalogued>(values: &[f64]) -> Result<(), String> {
    bgdsl_cli::fmi::check_values::<M>(values, M::check_params)
}

bgdsl_fmi_core::export_fmi2!(MODELS);

/// The entry for the model called `name`.
///
/// # Errors
///
/// [`UnknownModel`] when the library serves no such model; it lists the ones it does.
pub fn model(name: &str) -> Result<&'static ModelEntry, UnknownModel> {
    bgdsl_fmi_core::registry::find(MODELS, name).ok_or_else(|| UnknownModel {
        name: name.to_string(),
    })
}

/// The description (`modelDescription.xml` content, GUID) of the model called `name`.
///
/// # Errors
///
/// As [`model`].
pub fn describe(name: &str) -> Result<ModelDescription, UnknownModel> {
    Ok(model(name)?.describe())
}

/// Writes the FMU of the model called `name` (a name of the catalogue, which becomes
/// the `modelIdentifier`) with `library` as its binary (this crate's shared library,
/// see [`find_library`]); `out` is the FMU file, or an existing folder to write
/// `<name>.fmu` into. Written whole or not at all; returns the file written.
///
/// # Errors
///
/// An unknown model, a library that cannot be read, or the file cannot be written.
pub fn write_fmu(name: &str, library: &Path, out: &Path) -> Result<PathBuf, ExportError> {
    let entry = model(name)?;
    let written = bgdsl_fmi_core::write_fmu(&entry.describe(), entry.identifier(), library, out)
        .map_err(|e| e.for_package(bgdsl_fmi_core::CATALOGUE_PACKAGE))?;
    Ok(written)
}

/// Why [`write_fmu`] failed.
#[derive(Debug)]
pub enum ExportError {
    /// No such model.
    UnknownModel(UnknownModel),
    /// The FMU could not be made or written.
    Fmu(FmuError),
}

impl core::fmt::Display for ExportError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ExportError::UnknownModel(e) => e.fmt(f),
            ExportError::Fmu(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ExportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ExportError::UnknownModel(e) => Some(e),
            ExportError::Fmu(e) => Some(e),
        }
    }
}

impl From<UnknownModel> for ExportError {
    fn from(e: UnknownModel) -> Self {
        ExportError::UnknownModel(e)
    }
}

impl From<FmuError> for ExportError {
    fn from(e: FmuError) -> Self {
        ExportError::Fmu(e)
    }
}

/// A model name this library does not serve.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownModel {
    /// The name asked for.
    pub name: String,
}

impl core::fmt::Display for UnknownModel {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let known: Vec<&str> = MODELS.iter().map(|e| e.identifier()).collect();
        write!(
            f,
            "no model called `{}` can be exported; the models are: {}",
            self.name,
            known.join(", ")
        )
    }
}

impl std::error::Error for UnknownModel {}
