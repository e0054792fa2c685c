//! The shared library an FMU carries: where to find it, and whether it serves a model.

use core::ffi::{c_int, CStr};
use std::ffi::CString;
use std::path::{Path, PathBuf};

use crate::description::ModelDescription;
use crate::fmi2::{Boolean, CallbackFunctions, Component, FmiString, FALSE};
use crate::package::FmuError;

/// The environment variable that names the shared library, overriding the search of
/// [`find_library`] and [`find_library_of`].
pub const LIBRARY_ENV: &str = "BGDSL_FMI_LIBRARY";

/// The package whose `cdylib` serves every model of the `models` catalogue
/// (`libbgdsl_fmi.so`), the library [`find_library`] finds.
pub const CATALOGUE_PACKAGE: &str = "bgdsl-fmi";

/// The file name of the shared library `cargo build -p bgdsl-fmi` makes on this
/// platform (`libbgdsl_fmi.so` on Linux).
pub fn library_file_name() -> String {
    dll_file_name(&library_name(CATALOGUE_PACKAGE))
}

/// The name of the library a package builds when its `Cargo.toml` does not set one:
/// the package's name with `-` turned into `_` (`my-pump` builds `libmy_pump.so`).
pub fn library_name(package: &str) -> String {
    package.replace('-', "_")
}

/// The platform's file name of the shared library called `name`.
fn dll_file_name(name: &str) -> String {
    format!(
        "{}{name}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    )
}

/// Finds the shared library of the `models` catalogue ([`CATALOGUE_PACKAGE`]):
/// [`find_library_of`] for it.
///
/// # Errors
///
/// [`FmuError::LibraryNotFound`], listing the paths tried.
pub fn find_library() -> Result<PathBuf, FmuError> {
    find_library_of(CATALOGUE_PACKAGE)
}

/// Finds the FMI shared library that the package `package` builds (its `cdylib`,
/// `lib<package>.so` with `-` as `_`, see [`library_name`]): the file named by
/// `BGDSL_FMI_LIBRARY` if set; otherwise the library found by [`find_library_named`]
/// beside the running program. A user's program (`cargo build --release` builds both
/// `target/release/<program>` and `target/release/lib<package>.so`) finds its own
/// library with it. The errors name the package, so that they say what to build.
///
/// # Errors
///
/// [`FmuError::LibraryNotFound`], listing the paths tried.
pub fn find_library_of(package: &str) -> Result<PathBuf, FmuError> {
    let found = match std::env::var_os(LIBRARY_ENV) {
        Some(path) => {
            let path = PathBuf::from(path);
            if path.is_file() {
                Ok(path)
            } else {
                Err(FmuError::LibraryNotFound {
                    file: dll_file_name(&library_name(package)),
                    package: None,
                    tried: vec![path],
                })
            }
        }
        None => find_library_named(&library_name(package)),
    };
    found.map_err(|e| e.for_package(package))
}

/// Finds the shared library of the crate whose library is called `name` (the
/// platform's file name, `lib<name>.so` on Linux): next to the running program, or one
/// folder up (so that `target/release/models`, tests in `target/debug/deps/` and
/// examples in `target/debug/examples/` all find `target/<profile>/`), or in `deps/`
/// beside the program (where `cargo test` leaves a library without copying it up; a
/// library built from other model code is refused later by [`check_serves`]). A crate
/// exporting its own model's FMU finds its library with it.
///
/// # Errors
///
/// [`FmuError::LibraryNotFound`], listing the paths tried.
pub fn find_library_named(name: &str) -> Result<PathBuf, FmuError> {
    let file = dll_file_name(name);
    let mut tried = Vec::new();
    if let Ok(exe) = std::env::current_exe() {
        let beside = exe.ancestors().skip(1).take(2).map(Path::to_path_buf);
        let in_deps = exe.parent().map(|dir| dir.join("deps"));
        for dir in beside.chain(in_deps) {
            let candidate = dir.join(&file);
            if candidate.is_file() {
                return Ok(candidate);
            }
            tried.push(candidate);
        }
    }
    Err(FmuError::LibraryNotFound {
        file,
        package: None,
        tried,
    })
}

/// `fmi2Instantiate`'s signature.
type Instantiate = unsafe extern "C" fn(
    FmiString,
    c_int,
    FmiString,
    FmiString,
    *const CallbackFunctions,
    Boolean,
    Boolean,
) -> Component;
/// `fmi2FreeInstance`'s signature.
type FreeInstance = unsafe extern "C" fn(Component);

/// Checks that the library at `library` serves the model of `description`: loads it and
/// asks its `fmi2Instantiate` for a Co-Simulation instance with the model's GUID (which
/// is then freed). A library built from other model code refuses the GUID.
///
/// The library stays loaded for the rest of the process (unloading a Rust library
/// that may have registered thread-local destructors is not safe).
///
/// # Errors
///
/// [`FmuError::LoadLibrary`] when it cannot be loaded or lacks the functions,
/// [`FmuError::WrongLibrary`] when it refuses the GUID.
pub fn check_serves(library: &Path, description: &ModelDescription) -> Result<(), FmuError> {
    let load_error = |reason: String| FmuError::LoadLibrary {
        path: library.to_path_buf(),
        reason,
    };
    let guid = CString::new(description.guid.as_str()).map_err(|e| load_error(e.to_string()))?;
    // SAFETY: loading runs the library's initialisers; an FMI library (its exports were
    // checked by the caller) has none beyond the C runtime's.
    let loaded =
        unsafe { libloading::Library::new(library) }.map_err(|e| load_error(e.to_string()))?;
    // SAFETY: the symbols are the standard's functions, with the standard's signatures.
    let (instantiate, free) = unsafe {
        let instantiate = loaded.get::<Instantiate>(b"fmi2Instantiate\0");
        let free = loaded.get::<FreeInstance>(b"fmi2FreeInstance\0");
        match (instantiate, free) {
            (Ok(i), Ok(f)) => (*i, *f),
            (Err(e), _) | (_, Err(e)) => return Err(load_error(e.to_string())),
        }
    };
    // Never unloaded: the function pointers above stay valid.
    core::mem::forget(loaded);
    let callbacks = CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: core::ptr::null_mut(),
    };
    let name: &CStr = c"bgdsl-fmi-check";
    // SAFETY: valid NUL-terminated strings and callbacks, as the standard asks; the
    // instance, if made, is freed once and not used otherwise.
    let made = unsafe {
        let c = instantiate(
            name.as_ptr(),
            1,
            guid.as_ptr(),
            core::ptr::null(),
            &callbacks,
            FALSE,
            FALSE,
        );
        let made = !c.is_null();
        if made {
            free(c);
        }
        made
    };
    if made {
        Ok(())
    } else {
        Err(FmuError::WrongLibrary {
            path: library.to_path_buf(),
            model: description.model_name.to_string(),
            guid: description.guid.clone(),
            package: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_package_builds_the_library_named_after_it_with_underscores() {
        assert_eq!(library_name("my-pump"), "my_pump");
        assert_eq!(library_name("starter"), "starter");
        assert_eq!(library_file_name(), dll_file_name("bgdsl_fmi"));
        if cfg!(target_os = "linux") {
            assert_eq!(dll_file_name(&library_name("my-pump")), "libmy_pump.so");
        }
    }

    #[test]
    fn a_library_not_found_says_which_package_to_build_and_where_it_looked() {
        let error = find_library_named("no_such_library_anywhere")
            .unwrap_err()
            .for_package("no-such-library-anywhere");
        let message = error.to_string();
        assert!(
            message.contains(&dll_file_name("no_such_library_anywhere")),
            "{message}"
        );
        assert!(
            message.contains("`cargo build -p no-such-library-anywhere --release`"),
            "{message}"
        );
        let FmuError::LibraryNotFound { tried, .. } = &error else {
            panic!("{error:?}");
        };
        // Beside the test program, one folder up, and in `deps/` beside it.
        assert_eq!(tried.len(), 3, "{tried:?}");
        for path in tried {
            assert!(message.contains(&path.display().to_string()), "{message}");
        }
    }

    #[test]
    fn without_a_package_the_advice_names_the_crate_that_exports() {
        let message = find_library_named("no_such_library_anywhere")
            .unwrap_err()
            .to_string();
        assert!(message.contains("`export_fmi2!`"), "{message}");
        // A package named once is not renamed by a second call.
        let twice = find_library_named("x")
            .unwrap_err()
            .for_package("first")
            .for_package("second")
            .to_string();
        assert!(twice.contains("-p first "), "{twice}");
    }
}
