//! Writing an FMU: `modelDescription.xml` and the shared library, zipped to the
//! standard's layout, written whole or not at all.
//!
//! ```text
//! oscillator.fmu
//! ├── modelDescription.xml
//! ├── binaries/linux64/oscillator.so     the shared library, renamed
//! └── documentation/index.html           the variables, as a table
//! ```
//!
//! The shared library is built separately (`cargo build -p bgdsl-fmi --release` builds
//! `target/release/libbgdsl_fmi.so`, which serves every shipped model);
//! [`find_library`](crate::find_library) locates it, [`write_fmu`] checks that it
//! serves the model and packs it.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::description::ModelDescription;
use crate::library::{check_serves, LIBRARY_ENV};
use crate::variables::Role;
use crate::xml::{escape, model_description_xml, xml_double};
use crate::zip::{ZipError, ZipWriter};

/// The FMI platform folder for binaries built for this machine (`linux64`,
/// `win64`, `darwin64`, ...), `None` on a platform FMI 2.0 does not name.
pub fn platform_folder() -> Option<&'static str> {
    let bits = if cfg!(target_pointer_width = "64") {
        "64"
    } else {
        "32"
    };
    let os = match std::env::consts::OS {
        "linux" => "linux",
        "windows" => "win",
        "macos" => "darwin",
        _ => return None,
    };
    Some(match (os, bits) {
        ("linux", "64") => "linux64",
        ("linux", _) => "linux32",
        ("win", "64") => "win64",
        ("win", _) => "win32",
        ("darwin", "64") => "darwin64",
        _ => "darwin32",
    })
}

/// Why an FMU could not be written.
#[derive(Debug)]
pub enum FmuError {
    /// The `modelIdentifier` is not a C identifier.
    BadIdentifier {
        /// The identifier.
        identifier: String,
    },
    /// The shared library could not be found: where it was looked for.
    LibraryNotFound {
        /// The file looked for (`libbgdsl_fmi.so`).
        file: String,
        /// The package that builds it, when known (see [`FmuError::for_package`]).
        package: Option<String>,
        /// The paths tried, in order.
        tried: Vec<PathBuf>,
    },
    /// The shared library could not be read.
    ReadLibrary {
        /// Its path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not an FMI 2.0 library: it does not export `fmi2Instantiate` and
    /// `fmi2DoStep`.
    NotAnFmiLibrary {
        /// Its path.
        path: PathBuf,
    },
    /// The library could not be loaded to check it.
    LoadLibrary {
        /// Its path.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The library does not serve the model: `fmi2Instantiate` refuses its GUID (it
    /// was built from other model code than the description; rebuild it).
    WrongLibrary {
        /// Its path.
        path: PathBuf,
        /// The model.
        model: String,
        /// The model's GUID.
        guid: String,
        /// The package that builds the library, when known (see
        /// [`FmuError::for_package`]).
        package: Option<String>,
    },
    /// This platform has no FMI 2.0 binaries folder.
    UnsupportedPlatform,
    /// The archive could not be built.
    Zip(ZipError),
    /// The FMU file could not be written (nothing was left behind).
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl core::fmt::Display for FmuError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FmuError::BadIdentifier { identifier } => write!(
                f,
                "`{identifier}` cannot be a modelIdentifier: it must be a C identifier \
                 (letters, digits, `_`, not starting with a digit)"
            ),
            FmuError::LibraryNotFound {
                file,
                package,
                tried,
            } => {
                write!(
                    f,
                    "the FMI shared library {file} was not found; build it with {} or name \
                     it in {LIBRARY_ENV}. Looked at:",
                    build_advice(package.as_deref())
                )?;
                for path in tried {
                    write!(f, " {}", path.display())?;
                }
                Ok(())
            }
            FmuError::ReadLibrary { path, source } => {
                write!(
                    f,
                    "cannot read the shared library {}: {source}",
                    path.display()
                )
            }
            FmuError::NotAnFmiLibrary { path } => write!(
                f,
                "{} is not an FMI 2.0 library: it does not export fmi2Instantiate and \
                 fmi2DoStep",
                path.display()
            ),
            FmuError::LoadLibrary { path, reason } => {
                write!(
                    f,
                    "cannot load the shared library {}: {reason}",
                    path.display()
                )
            }
            FmuError::WrongLibrary {
                path,
                model,
                guid,
                package,
            } => write!(
                f,
                "the shared library {} does not serve model {model} (GUID {guid}): it was \
                 built from other model code; rebuild it with {}",
                path.display(),
                build_advice(package.as_deref())
            ),
            FmuError::UnsupportedPlatform => write!(
                f,
                "FMI 2.0 names no binaries folder for this platform ({} {})",
                std::env::consts::OS,
                std::env::consts::ARCH
            ),
            FmuError::Zip(e) => write!(f, "cannot build the FMU archive: {e}"),
            FmuError::Write { path, source } => {
                write!(f, "cannot write {}: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for FmuError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            FmuError::ReadLibrary { source, .. } | FmuError::Write { source, .. } => Some(source),
            FmuError::Zip(e) => Some(e),
            _ => None,
        }
    }
}

impl FmuError {
    /// The same error naming `package` as the crate that builds the shared library, so
    /// that its message says `cargo build -p <package> --release`: for a library that
    /// is missing or built from other model code (other errors are returned as they
    /// are, and so is one that names a package already).
    #[must_use]
    pub fn for_package(self, package: &str) -> Self {
        match self {
            FmuError::LibraryNotFound {
                file,
                package: None,
                tried,
            } => FmuError::LibraryNotFound {
                file,
                package: Some(package.to_string()),
                tried,
            },
            FmuError::WrongLibrary {
                path,
                model,
                guid,
                package: None,
            } => FmuError::WrongLibrary {
                path,
                model,
                guid,
                package: Some(package.to_string()),
            },
            other => other,
        }
    }
}

/// How to build a package's shared library: the command when the package is known.
fn build_advice(package: Option<&str>) -> String {
    match package {
        Some(package) => format!("`cargo build -p {package} --release`"),
        None => "`cargo build --release` in the crate that invokes `export_fmi2!`".to_string(),
    }
}

impl From<ZipError> for FmuError {
    fn from(e: ZipError) -> Self {
        FmuError::Zip(e)
    }
}

/// Whether `identifier` can be a `modelIdentifier` (a C identifier, also a file name).
pub fn is_c_identifier(identifier: &str) -> bool {
    let mut chars = identifier.chars();
    matches!(chars.next(), Some(c) if c == '_' || c.is_ascii_alphabetic())
        && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
}

/// Writes the FMU of `description` with `modelIdentifier` `identifier`, its binary
/// being the shared library at `library` (which must serve this model: build the two
/// together). `out` is the FMU file, or an existing folder to write
/// `<identifier>.fmu` into. Returns the file written.
///
/// The file is written whole or not at all: into a temporary file beside it, synced,
/// then renamed over it.
///
/// # Errors
///
/// A bad identifier, a library that cannot be read, exports no FMI functions or does
/// not serve the model ([`check_serves`]: it was built from other model code), or
/// the file cannot be written; nothing is left behind then.
pub fn write_fmu(
    description: &ModelDescription,
    identifier: &str,
    library: &Path,
    out: &Path,
) -> Result<PathBuf, FmuError> {
    let bytes = fmu_bytes(description, identifier, library)?;
    let path = if out.is_dir() {
        out.join(format!("{identifier}.fmu"))
    } else {
        out.to_path_buf()
    };
    write_atomically(&path, &bytes).map_err(|source| FmuError::Write {
        path: path.clone(),
        source,
    })?;
    Ok(path)
}

/// The bytes of the FMU [`write_fmu`] writes.
///
/// # Errors
///
/// As [`write_fmu`], but for writing.
pub fn fmu_bytes(
    description: &ModelDescription,
    identifier: &str,
    library: &Path,
) -> Result<Vec<u8>, FmuError> {
    if !is_c_identifier(identifier) {
        return Err(FmuError::BadIdentifier {
            identifier: identifier.to_string(),
        });
    }
    let platform = platform_folder().ok_or(FmuError::UnsupportedPlatform)?;
    let binary = std::fs::read(library).map_err(|source| FmuError::ReadLibrary {
        path: library.to_path_buf(),
        source,
    })?;
    let exports = |symbol: &[u8]| binary.windows(symbol.len()).any(|w| w == symbol);
    if !(exports(b"fmi2Instantiate\0") && exports(b"fmi2DoStep\0")) {
        return Err(FmuError::NotAnFmiLibrary {
            path: library.to_path_buf(),
        });
    }
    check_serves(library, description)?;
    let xml = model_description_xml(description, identifier);
    let mut zip = ZipWriter::new();
    zip.add("modelDescription.xml", xml.as_bytes(), false)?;
    let binary_name = format!(
        "binaries/{platform}/{identifier}{}",
        std::env::consts::DLL_SUFFIX
    );
    zip.add(&binary_name, &binary, true)?;
    zip.add(
        "documentation/index.html",
        documentation(description, identifier).as_bytes(),
        false,
    )?;
    Ok(zip.finish()?)
}

/// `bytes` into `path` through a temporary file in the same folder, synced and renamed
/// into place; the temporary file is removed on failure.
fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "fmu".to_string());
    let temp = dir.join(format!(".{file_name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut file = std::fs::File::create(&temp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    result
}

/// `documentation/index.html`: the model's variables with their value references,
/// units and start values.
fn documentation(d: &ModelDescription, identifier: &str) -> String {
    let mut h = String::new();
    let name = escape(d.model_name);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{name}</title></head>\n\
         <body>\n<h1>{name}</h1>\n<p>{}. FMI 2.0 Model Exchange and Co-Simulation \
         (<code>{}</code>), GUID <code>{}</code>.</p>\n",
        escape(&d.description),
        escape(identifier),
        escape(&d.guid)
    );
    h.push_str(
        "<table>\n<tr><th>value reference</th><th>name</th><th>kind</th><th>unit</th>\
         <th>start</th><th>description</th></tr>\n",
    );
    for v in d.variables.all() {
        let start = v.start.map(xml_double).unwrap_or_default();
        let kind = match v.role {
            Role::Parameter(_) => "parameter (tunable)",
            other => other.kind(),
        };
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{kind}</td><td>{}</td><td>{start}</td><td>{}</td></tr>",
            v.value_reference,
            escape(&v.name),
            escape(&v.unit),
            escape(&v.description)
        );
    }
    h.push_str("</table>\n</body></html>\n");
    h
}
