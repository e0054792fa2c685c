//! The shared library an FMU carries: where to find it, and whether it serves a model.

use core::ffi::{c_int, CStr};
use std::ffi::CString;
use std::path::{Path, PathBuf};

use crate::description::ModelDescription;
use crate::fmi2::{Boolean, CallbackFunctions, Component, FmiString, FALSE};
use crate::package::FmuError;

/// The environment variable that names the shared library, overriding the search of
/// [`find_library`].
pub const LIBRARY_ENV: &str = "BGDSL_FMI_LIBRARY";

/// The file name of the shared library `cargo build -p bgdsl-fmi` makes on this
/// platform (`libbgdsl_fmi.so` on Linux).
pub fn library_file_name() -> String {
    dll_file_name("bgdsl_fmi")
}

/// The platform's file name of the shared library called `name`.
fn dll_file_name(name: &str) -> String {
    format!(
        "{}{name}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    )
}

/// Finds the shared library: the file named by `BGDSL_FMI_LIBRARY` if set; otherwise
/// [`library_file_name`] found by [`find_library_named`].
///
/// # Errors
///
/// [`FmuError::LibraryNotFound`], listing the paths tried.
pub fn find_library() -> Result<PathBuf, FmuError> {
    if let Some(path) = std::env::var_os(LIBRARY_ENV) {
        let path = PathBuf::from(path);
        return if path.is_file() {
            Ok(path)
        } else {
            Err(FmuError::LibraryNotFound { tried: vec![path] })
        };
    }
    find_library_named("bgdsl_fmi")
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
    Err(FmuError::LibraryNotFound { tried })
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
        })
    }
}
