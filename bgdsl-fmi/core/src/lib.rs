//! FMI 2.0 export for bgdsl models: the C interface of a functional mock-up unit (Model
//! Exchange and Co-Simulation), its `modelDescription.xml`, and the FMU archive,
//! generic over any model `bond_graph!` generates.
//!
//! This crate does not know the shipped models. The `bgdsl-fmi` crate does: it lists
//! them in a registry and invokes [`export_fmi2!`] to build the one shared library that
//! serves them all. A program that writes FMUs (the `models fmu` command) needs only
//! this crate, the model type and that library's path:
//!
//! ```no_run
//! use bgdsl_fmi_core::{find_library, write_fmu, ModelDescription};
//! # bgdsl_runtime::bond_graph! {
//! #     /// A mass on a spring.
//! #     pub model Spring { param k = 1.0; I mass = 1.0; C spring = k; 1 v;
//! #         v -> { mass, spring }; init spring.q = 1.0; output x = spring.q; }
//! # }
//! let library = find_library()?; // target/release/libbgdsl_fmi.so, or $BGDSL_FMI_LIBRARY
//! let description = ModelDescription::of::<Spring>();
//! let written = write_fmu(&description, "spring", &library, "spring.fmu".as_ref())?;
//! # Ok::<(), bgdsl_fmi_core::FmuError>(())
//! ```
//!
//! # How the pieces fit
//!
//! - [`fmi2`]: the standard's C types. [`ffi`]: each FMI function over C arguments,
//!   the only `unsafe` code; [`export_fmi2!`] makes them the library's symbols.
//! - [`Instance`]: one instantiated model and what each call does to it, in safe Rust,
//!   following the state machine of [`machine`].
//! - [`FmuModel`]: the object-safe face of a model, implemented for every
//!   [`Exportable`] model by [`Adapter`]; Co-Simulation integrates with the model's own
//!   solver through a [`Stepper`](bgdsl_runtime::Stepper).
//! - [`ModelEntry`]: a model a library serves; `fmi2Instantiate` picks it by the GUID
//!   of its [`ModelDescription`] (a hash of the model's name and variables).
//! - [`variables`]: the value references. [`xml`]: `modelDescription.xml`. [`zip`] and
//!   [`package`]: the FMU file. [`library`]: finding the shared library and checking
//!   that it serves a model.
//!
//! # Behaviour towards the importer
//!
//! Bad calls (an unknown value reference, a wrong array length, a call the state
//! machine does not allow now, a NULL or freed component, a parameter value the
//! model's [`ParameterCheck`] rejects) return `fmi2Error` with a message through the
//! importer's logger, and change nothing; a panic in model code is caught at the
//! boundary and becomes `fmi2Error` with the instance in its error state. Each call is
//! logged once, after it, with its outcome: failures always, whatever `loggingOn`
//! says; successes in category `logCalls` when it is on.
//!
//! The host sets parameters, inputs and, before initialisation ends, the initial
//! states (`initial="exact"`; see [`variables`]).
//!
//! # Events and modes
//!
//! A model's events ([`Model::EVENTS`](bgdsl_runtime::Model::EVENTS)) are the FMU's
//! event indicators (`numberOfEventIndicators`), in Model Exchange: the importer
//! locates their sign changes, and in Event Mode `fmi2NewDiscreteStates` applies the
//! actions of those that crossed in their direction (a `stop` action sets
//! `terminateSimulation`). Its discrete modes are discrete variables the FMU keeps, not
//! continuous states: `nx` counts the continuous states only. In Co-Simulation the
//! model's own solver handles the events inside each `fmi2DoStep`, and a `stop` ends
//! the step early with `fmi2Discard` and `fmi2Terminated`. See [`instance`] and
//! [`variables`].
//!
//! # Your own model as an FMU
//!
//! A crate that builds as a `cdylib`, lists its models in a `static` registry of
//! [`ModelEntry`] (optionally [`ModelEntry::with_check`]), invokes [`export_fmi2!`] once,
//! and packs the FMU with [`write_fmu`]: `bgdsl-fmi/example/` in the repository is a
//! complete, tested one. A program made with `bgdsl-cli` does the packing itself
//! (`<program> fmu <model>`), with the library of its package that
//! [`find_library_of`] finds beside it (`examples/starter/` in the repository).
#![warn(missing_docs)]

pub mod description;
pub mod exports;
pub mod ffi;
pub mod fmi2;
pub mod instance;
pub mod library;
pub mod logger;
pub mod machine;
pub mod model;
pub mod package;
pub mod registry;
pub mod variables;
pub mod xml;
pub mod zip;

pub use description::{guid, ModelDescription, NamingConvention};
pub use fmi2::Status;
pub use instance::{CallError, Instance};
pub use library::{
    check_serves, find_library, find_library_named, find_library_of, library_file_name,
    library_name, CATALOGUE_PACKAGE, LIBRARY_ENV,
};
pub use machine::{Call, Phase};
pub use model::{finite_only, Adapter, Exportable, FmuModel, ParameterCheck, Sizes, Stopped};
pub use package::{fmu_bytes, platform_folder, write_fmu, FmuError};
pub use registry::ModelEntry;
pub use variables::{Role, Variable, Variables};
pub use xml::model_description_xml;
