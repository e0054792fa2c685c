//! `models fmu`: a model as an FMI 2.0 functional mock-up unit.

use std::path::{Path, PathBuf};

use bgdsl_fmi_core::FmuError;

use super::Failure;
use crate::catalog::{self, Catalogue};

/// `models fmu <model> [--out PATH]`: writes the FMU and prints its path.
///
/// `PATH` ending in `.fmu` is the file; anything else is a folder to write
/// `<model>.fmu` into (default `out/fmu`). Missing folders are created by the rule
/// `run --out` follows ([`catalog::create_output_dir`]), once the library has been
/// found, so a command that fails for want of it creates nothing.
pub(super) fn fmu(catalogue: &Catalogue, name: &str, out: Option<PathBuf>) -> Result<(), Failure> {
    let entry = catalogue
        .find(name)
        .map_err(|e| Failure::Usage(e.to_string()))?;
    let library = bgdsl_fmi_core::find_library().map_err(library_failure)?;
    let out = out.unwrap_or_else(|| PathBuf::from("out/fmu"));
    catalog::create_output_dir(folder_of(&out)).map_err(Failure::Run)?;
    let written = bgdsl_fmi_core::write_fmu(&entry.model.fmu_description(), name, &library, &out)
        .map_err(library_failure)?;
    println!("{}", written.display());
    Ok(())
}

/// The folder the FMU goes into: `out` itself, or the folder of a `.fmu` file.
fn folder_of(out: &Path) -> &Path {
    if out.extension().is_some_and(|e| e == "fmu") {
        match out.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        }
    } else {
        out
    }
}

/// A library that is missing, or that cannot serve the model (not an FMI library,
/// built from other model code), is a missing prerequisite; the rest (writing the
/// file) a failure.
fn library_failure(error: FmuError) -> Failure {
    match error {
        FmuError::LibraryNotFound { .. }
        | FmuError::ReadLibrary { .. }
        | FmuError::NotAnFmiLibrary { .. }
        | FmuError::LoadLibrary { .. }
        | FmuError::WrongLibrary { .. } => Failure::Prerequisite(error.to_string()),
        other => Failure::Other(other.to_string()),
    }
}
