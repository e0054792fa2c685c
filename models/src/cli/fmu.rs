//! `models fmu`: a model as an FMI 2.0 functional mock-up unit.

use std::path::PathBuf;

use super::Failure;
use crate::catalog;

/// `models fmu <model> [--out FILE]`: writes the FMU and prints its path.
pub(super) fn fmu(name: &str, out: Option<PathBuf>) -> Result<(), Failure> {
    let entry = catalog::find(name).map_err(|e| Failure::Usage(e.to_string()))?;
    let library = bgdsl_fmi_core::find_library().map_err(|e| Failure::Usage(e.to_string()))?;
    let out = match out {
        Some(path) => path,
        None => {
            let folder = PathBuf::from("out/fmu");
            std::fs::create_dir_all(&folder)
                .map_err(|e| Failure::Other(format!("cannot create {}: {e}", folder.display())))?;
            folder
        }
    };
    let written = bgdsl_fmi_core::write_fmu(&entry.model.fmu_description(), name, &library, &out)
        .map_err(|e| Failure::Other(e.to_string()))?;
    println!("{}", written.display());
    Ok(())
}
