//! What a signal does to the program: SIGINT (Ctrl-C), SIGTERM and SIGHUP all count as
//! an interrupt.
//!
//! The first signal sets a process-wide flag ([`requested`]); runs stop at their next
//! sample, drawing stops before its next figure, and the run writes its partial set
//! (see [`crate::catalog`]). A second signal exits at once with status 130 after
//! removing every temporary file and folder that is registered ([`Temporary`]): the
//! staging folder a run writes into, or the previous set being removed after a swap.
//!
//! The registry is one lock: the exit path takes it, removes every path, and exits
//! while still holding it, so that a thread that registers, unregisters or renames a
//! registered folder ([`with_registry`]) either finishes first or never starts.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard};

/// The exit status after a second signal (128 + SIGINT's number, whatever the signal).
pub const FORCED_EXIT_STATUS: i32 = 130;

static REQUESTED: AtomicBool = AtomicBool::new(false);

static REGISTRY: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Whether an interrupt was requested (a first signal, or [`request`]).
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Requests an interrupt; returns whether one had been requested already.
pub fn request() -> bool {
    REQUESTED.swap(true, Ordering::SeqCst)
}

/// Installs the handler of SIGINT, SIGTERM and SIGHUP: the first signal calls
/// [`request`], a second one [`exit_now`]. Does nothing if a handler cannot be
/// installed (e.g. one is installed already).
pub fn install_handler() {
    let _ = ctrlc::set_handler(|| {
        if request() {
            exit_now(FORCED_EXIT_STATUS);
        }
    });
}

fn registry() -> MutexGuard<'static, Vec<PathBuf>> {
    REGISTRY
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Removes every registered path (a file, or a folder with its contents) and exits the
/// process with `status`, holding the registry's lock to the end.
pub fn exit_now(status: i32) -> ! {
    let paths = registry();
    for path in paths.iter() {
        remove_all(path);
    }
    std::process::exit(status)
}

/// Removes `path` whatever it is, retrying while another thread is still creating
/// files in it (a folder that is not empty yet).
fn remove_all(path: &Path) {
    for _ in 0..100 {
        let removed = match std::fs::symlink_metadata(path) {
            Err(_) => return,
            Ok(meta) if meta.is_dir() => std::fs::remove_dir_all(path),
            Ok(_) => std::fs::remove_file(path),
        };
        if removed.is_ok() && std::fs::symlink_metadata(path).is_err() {
            return;
        }
    }
}

/// A registered temporary path: removed by a forced exit while registered, and by
/// [`Temporary::remove`] or on drop unless [`Temporary::keep`] is called.
#[derive(Debug)]
pub struct Temporary {
    path: PathBuf,
    armed: bool,
}

impl Temporary {
    /// Registers `path` (which need not exist yet).
    pub fn register(path: PathBuf) -> Self {
        registry().push(path.clone());
        Temporary { path, armed: true }
    }

    /// The registered path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Unregisters the path without removing it (it was renamed into place). Call it
    /// inside [`with_registry`] together with the rename.
    pub fn keep(mut self, registry_locked: &mut Vec<PathBuf>) {
        registry_locked.retain(|p| p != &self.path);
        self.armed = false;
    }

    /// Registers `path` in a registry already locked by [`with_registry`].
    pub fn adopt(path: PathBuf, registry_locked: &mut Vec<PathBuf>) -> Self {
        registry_locked.push(path.clone());
        Temporary { path, armed: true }
    }

    /// Removes the path and unregisters it.
    pub fn remove(self) {
        drop(self);
    }
}

/// Runs `f` with the registry (the list of registered paths) locked and passed in, so
/// that no forced exit removes registered paths while `f` renames them; for
/// [`Temporary::keep`] and [`Temporary::adopt`].
pub fn with_registry<T>(f: impl FnOnce(&mut Vec<PathBuf>) -> T) -> T {
    let mut guard = registry();
    f(&mut guard)
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if self.armed {
            let mut paths = registry();
            remove_all(&self.path);
            paths.retain(|p| p != &self.path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn registered(path: &Path) -> bool {
        with_registry(|paths| paths.iter().any(|p| p == path))
    }

    #[test]
    fn a_temporary_is_removed_unless_kept() {
        let base = std::env::temp_dir().join(format!("bgdsl-interrupt-{}", std::process::id()));
        let (dropped, kept) = (base.join("dropped"), base.join("kept"));
        std::fs::create_dir_all(dropped.join("inner")).unwrap();
        std::fs::create_dir_all(&kept).unwrap();
        let temporary = Temporary::register(dropped.clone());
        assert!(registered(&dropped));
        drop(temporary);
        assert!(!dropped.exists() && !registered(&dropped));
        let temporary = Temporary::register(kept.clone());
        with_registry(|paths| temporary.keep(paths));
        assert!(kept.exists() && !registered(&kept));
        std::fs::remove_dir_all(&base).unwrap();
    }
}
