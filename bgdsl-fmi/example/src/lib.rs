//! How to export your own bond-graph model as an FMI 2.0 FMU, as a crate of its own
//! (the README's "Export your own model as an FMU" walks through it).
//!
//! Three things make an FMU of a model:
//!
//! 1. the model, written with `bond_graph!` ([`Room`]; [`Kettle`] has an event);
//! 2. a shared library (this crate, built as a `cdylib`) that exports the FMI 2.0 C
//!    interface for it: a registry of the models it serves ([`MODELS`]) and one
//!    `export_fmi2!` invocation;
//! 3. a program that packs `modelDescription.xml` and that library into the `.fmu`
//!    file ([`write_fmu`], run by `src/main.rs`).
//!
//! ```sh
//! cargo run --release -p bgdsl-fmi-example -- room.fmu
//! ```
#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use bgdsl_fmi_core::{FmuError, ModelDescription, ModelEntry};
use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A room warmed by a heater the host switches, losing heat through its walls:
    /// efforts are temperatures above outdoors (K), flows heat flows (W).
    pub model Room {
        /// heat capacity of the air and furnishings
        param capacity = 5.0e5 in "J/K";
        /// thermal resistance of the walls
        param walls = 0.01 in "K/W";
        /// outdoor temperature
        param outdoor = 5.0 in "degC";
        /// the heater's power, which the host sets
        input heating = 1000.0 in "W";

        MSf heater = heating;
        C air = 1.0 / capacity;  // temperature rise e = q / capacity, q the heat stored
        R wall = walls;          // heat lost f = e / walls
        0 room;
        heater -> room -> { air, wall };

        /// the room's temperature
        output temperature = outdoor + air.e;
        /// the heat flowing out through the walls
        output loss = wall.f;
    }
}

bond_graph! {
    /// A kettle: a heater warms the water, which loses heat through the kettle's
    /// walls, and the kettle switches itself off at the boil, which ends the run (an
    /// event whose action is `stop`: the FMU asks its importer to terminate there).
    /// Efforts are temperatures above the room's (K), flows heat flows (W).
    pub model Kettle {
        /// heat capacity of the water (1.7 l)
        param capacity = 7100.0 in "J/K";
        /// thermal resistance from the water to the room
        param walls = 0.5 in "K/W";
        /// room temperature
        param room = 20.0 in "degC";
        /// boiling point
        param boil = 100.0 in "degC";
        /// the heater's power
        input heating = 2000.0 in "W";

        MSf heater = heating;
        C water = 1.0 / capacity;
        R wall = walls;
        0 node;
        heater -> node -> { water, wall };

        /// the water's temperature
        output temperature = room + water.e;

        /// At the boil the kettle switches off: the run ends.
        when water.e > boil - room { stop; }
    }
}

/// The models this library serves, each with its `modelIdentifier` (the FMU's binary
/// is `binaries/<platform>/<identifier>.so`). A library may serve several models;
/// `fmi2Instantiate` picks one by the GUID in the FMU's `modelDescription.xml`.
pub static MODELS: &[ModelEntry] = &[
    ModelEntry::new::<Room>("room")
        // Refuse a value the model cannot run with when the host sets it.
        .with_check(check_room),
    ModelEntry::new::<Kettle>("kettle"),
];

bgdsl_fmi_core::export_fmi2!(MODELS);

/// The room's rule for its parameters (in [`bgdsl_runtime::Model::parameter_values`]
/// order: capacity, walls, outdoor): a positive capacity and wall resistance.
///
/// # Errors
///
/// A message naming the parameter and the rule.
pub fn check_room(values: &[f64]) -> Result<(), String> {
    for (name, value) in [("capacity", values[0]), ("walls", values[1])] {
        if value <= 0.0 {
            return Err(format!("{name} must be > 0, found {value}"));
        }
    }
    Ok(())
}

/// The shared library this crate builds (`libroom_fmu.so`), found beside the running
/// program as `bgdsl-fmi-core` finds its own.
///
/// # Errors
///
/// [`FmuError::LibraryNotFound`], listing the paths tried.
pub fn find_library() -> Result<PathBuf, FmuError> {
    bgdsl_fmi_core::find_library_named("room_fmu")
}

/// Writes the room's FMU to `out` (a file, or a folder for `room.fmu`) with `library`
/// as its binary; returns the file written.
///
/// # Errors
///
/// The library is missing, does not serve the model, or the file cannot be written.
pub fn write_fmu(library: &Path, out: &Path) -> Result<PathBuf, FmuError> {
    bgdsl_fmi_core::write_fmu(&ModelDescription::of::<Room>(), "room", library, out)
}
