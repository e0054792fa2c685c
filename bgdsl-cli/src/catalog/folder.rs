//! A results folder as a transaction: a run writes its whole set into a fresh staging
//! folder beside the destination and, once everything is written and synced, swaps it
//! in whole ([`RunFolder`]). The rule is described in the
//! [catalogue's documentation](crate::catalog#results-folders).

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};

use super::RunError;
use crate::interrupt::{self, Temporary};

/// The marker file in every folder the program writes; only a folder holding it (or an
/// empty one) is ever replaced.
pub const MARKER: &str = ".models-results";

/// The marker's contents.
const MARKER_TEXT: &str = "This folder was written by the `models` program of bgdsl, \
    which replaces it whole at the next run into it.\n";

/// The sibling folder a failed or interrupted run commits to: `<destination>.partial`.
pub fn partial_path(destination: &Path) -> PathBuf {
    let mut name = destination.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

/// A run's results set being written: a staging folder
/// `<parent>/.<name>.staging-<pid>`, registered with [`crate::interrupt`] so that a
/// forced exit removes it, and removed when dropped uncommitted.
#[derive(Debug)]
pub struct RunFolder {
    destination: PathBuf,
    staging: Temporary,
}

impl RunFolder {
    /// Checks that `destination` and its `.partial` sibling are the program's to
    /// replace (absent, empty, or holding [`MARKER`]), creates the parent folders, removes
    /// staging folders that processes no longer running left there, and creates a new
    /// staging folder with the marker in it.
    ///
    /// # Errors
    ///
    /// [`RunError::NotOurs`] for a folder with foreign content or a path that is not a
    /// folder; [`RunError::Io`] when the folders cannot be created.
    pub fn begin(destination: &Path) -> Result<Self, RunError> {
        check_replaceable(destination)?;
        check_replaceable(&partial_path(destination))?;
        let (parent, name) = split(destination)?;
        super::run::create_dir(&parent)?;
        remove_abandoned(&parent, &name);
        remove_abandoned(&parent, &format!("{name}.partial"));
        let staging_path = parent.join(format!(".{name}.staging-{}", std::process::id()));
        let staging = Temporary::register(staging_path.clone());
        let io_error = |action, source| RunError::Io {
            path: staging_path.clone(),
            action,
            source,
        };
        if fs::symlink_metadata(&staging_path).is_ok() {
            // Left by an earlier process with the same id.
            fs::remove_dir_all(&staging_path)
                .map_err(|e| io_error("removing an abandoned staging folder", e))?;
        }
        fs::create_dir(&staging_path).map_err(|e| io_error("creating the staging folder", e))?;
        let marker = staging_path.join(MARKER);
        fs::write(&marker, MARKER_TEXT)
            .and_then(|()| File::open(&marker)?.sync_all())
            .map_err(|e| io_error("writing the marker file", e))?;
        Ok(RunFolder {
            destination: destination.to_path_buf(),
            staging,
        })
    }

    /// The staging folder to write the set into.
    pub fn path(&self) -> &Path {
        self.staging.path()
    }

    /// The destination folder.
    pub fn destination(&self) -> &Path {
        &self.destination
    }

    /// Where the set ends up: the destination, or its `.partial` sibling.
    pub fn target(&self, partial: bool) -> PathBuf {
        if partial {
            partial_path(&self.destination)
        } else {
            self.destination.clone()
        }
    }

    /// Syncs the staging folder and swaps it in for [`RunFolder::target`]`(partial)`,
    /// then removes the set it replaced; returns the target.
    ///
    /// # Errors
    ///
    /// [`RunError::NotOurs`] if the target was given foreign content meanwhile,
    /// [`RunError::Io`] if the swap fails (the target is then left as it was).
    pub fn commit(self, partial: bool) -> Result<PathBuf, RunError> {
        let target = self.target(partial);
        check_replaceable(&target)?;
        let staging_path = self.staging.path().to_path_buf();
        File::open(&staging_path)
            .and_then(|dir| dir.sync_all())
            .map_err(|source| RunError::Io {
                path: staging_path.clone(),
                action: "syncing the staging folder",
                source,
            })?;
        let (parent, name) = split(&target)?;
        // On an error the staging folder is dropped (removed) after the lock is released.
        let mut staging = Some(self.staging);
        let replaced = interrupt::with_registry(|registry| {
            let old = swap_in(&staging_path, &target, &parent, &name, registry)?;
            // The staging path now holds the replaced set (after an exchange) or
            // nothing; the replaced set is registered until it is removed.
            if let Some(staging) = staging.take() {
                staging.keep(registry);
            }
            Ok::<_, RunError>(old.map(|old| Temporary::adopt(old, registry)))
        })?;
        if let Ok(dir) = File::open(&parent) {
            let _ = dir.sync_all();
        }
        if let Some(old) = replaced {
            old.remove();
        }
        Ok(target)
    }
}

/// Moves `staging` onto `target`; returns where the replaced set now is, if there was
/// one. Linux exchanges the two atomically; elsewhere (or on a file system without
/// the exchange), the old set is renamed aside first and renamed back if the second
/// rename fails.
fn swap_in(
    staging: &Path,
    target: &Path,
    parent: &Path,
    name: &str,
    registry: &mut Vec<PathBuf>,
) -> Result<Option<PathBuf>, RunError> {
    let io_error = |action, source| RunError::Io {
        path: target.to_path_buf(),
        action,
        source,
    };
    if fs::symlink_metadata(target).is_err() {
        fs::rename(staging, target).map_err(|e| io_error("renaming the staging folder", e))?;
        return Ok(None);
    }
    match exchange(staging, target) {
        Ok(()) => return Ok(Some(staging.to_path_buf())),
        Err(e) if !exchange_unsupported(&e) => {
            return Err(io_error("swapping the staging folder in", e))
        }
        Err(_) => {}
    }
    let aside = parent.join(format!(".{name}.old-{}", std::process::id()));
    registry.push(aside.clone());
    let forget = |registry: &mut Vec<PathBuf>| registry.retain(|p| p != &aside);
    if let Err(e) = fs::rename(target, &aside) {
        forget(registry);
        return Err(io_error("moving the previous set aside", e));
    }
    if let Err(e) = fs::rename(staging, target) {
        let restored = fs::rename(&aside, target);
        if restored.is_ok() {
            forget(registry);
        }
        return Err(io_error("renaming the staging folder", e));
    }
    forget(registry);
    Ok(Some(aside))
}

/// Exchanges two paths atomically (Linux's `renameat2` with `RENAME_EXCHANGE`).
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| {
        CString::new(p.as_os_str().as_bytes())
            .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "a NUL in the path"))
    };
    let (a, b) = (c(a)?, c(b)?);
    // SAFETY: both pointers are valid NUL-terminated strings for the call's duration.
    let status = unsafe {
        libc::syscall(
            libc::SYS_renameat2,
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if status == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> io::Result<()> {
    Err(io::Error::from(io::ErrorKind::Unsupported))
}

/// Whether the exchange failed only because the system or file system lacks it.
fn exchange_unsupported(e: &io::Error) -> bool {
    #[cfg(target_os = "linux")]
    {
        matches!(
            e.raw_os_error(),
            Some(libc::EINVAL | libc::ENOSYS | libc::EOPNOTSUPP)
        )
    }
    #[cfg(not(target_os = "linux"))]
    {
        e.kind() == io::ErrorKind::Unsupported
    }
}

/// The parent folder (`.` for a bare name) and the file name of `path`.
fn split(path: &Path) -> Result<(PathBuf, String), RunError> {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .filter(|n| !n.is_empty())
        .ok_or_else(|| RunError::NotOurs {
            path: path.to_path_buf(),
            reason: "does not end in a folder name".to_owned(),
        })?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((parent, name.to_owned()))
}

/// Whether the program may replace `dir`: absent, an empty folder, or a folder holding
/// [`MARKER`].
fn check_replaceable(dir: &Path) -> Result<(), RunError> {
    let not_ours = |reason: &str| RunError::NotOurs {
        path: dir.to_path_buf(),
        reason: reason.to_owned(),
    };
    let meta = match fs::symlink_metadata(dir) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(source) => {
            return Err(RunError::Io {
                path: dir.to_path_buf(),
                action: "inspecting the output folder",
                source,
            })
        }
        Ok(meta) => meta,
    };
    if meta.file_type().is_symlink() {
        return Err(not_ours("is a symbolic link; give the folder it points to"));
    }
    if !meta.is_dir() {
        return Err(not_ours("is not a folder"));
    }
    let mut entries = fs::read_dir(dir).map_err(|source| RunError::Io {
        path: dir.to_path_buf(),
        action: "reading the output folder",
        source,
    })?;
    let empty = entries.next().is_none();
    if empty || dir.join(MARKER).is_file() {
        Ok(())
    } else {
        Err(not_ours(&format!(
            "holds files the program did not write (it has no `{MARKER}`), and a run \
             replaces its output folder whole; give another --out, or empty or remove it"
        )))
    }
}

/// Removes `.<name>.staging-<pid>` and `.<name>.old-<pid>` folders in `parent` whose
/// process is no longer running (killed by a signal no program can catch). Best effort.
fn remove_abandoned(parent: &Path, name: &str) {
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    let own = std::process::id();
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(file_name) = file_name.to_str() else {
            continue;
        };
        let pid = [".staging-", ".old-"].iter().find_map(|kind| {
            file_name
                .strip_prefix('.')?
                .strip_prefix(name)?
                .strip_prefix(kind)?
                .parse::<u32>()
                .ok()
        });
        if let Some(pid) = pid {
            if pid != own && !process_exists(pid) {
                let _ = fs::remove_dir_all(entry.path());
            }
        }
    }
}

/// Whether a process with id `pid` exists.
#[cfg(unix)]
fn process_exists(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return true;
    };
    // SAFETY: signal 0 checks only that the process exists; it sends nothing.
    let status = unsafe { libc::kill(pid, 0) };
    status == 0 || io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

#[cfg(not(unix))]
fn process_exists(_: u32) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("bgdsl-folder-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_commit_replaces_the_whole_set_and_leaves_nothing_temporary() {
        let root = scratch("commit");
        let out = root.join("out");
        let first = RunFolder::begin(&out).unwrap();
        fs::write(first.path().join("a.csv"), "1").unwrap();
        fs::write(first.path().join("old.png"), "x").unwrap();
        assert_eq!(first.commit(false).unwrap(), out);
        let second = RunFolder::begin(&out).unwrap();
        fs::write(second.path().join("a.csv"), "2").unwrap();
        second.commit(false).unwrap();
        assert_eq!(names(&out), [MARKER, "a.csv"]);
        assert_eq!(fs::read_to_string(out.join("a.csv")).unwrap(), "2");
        assert_eq!(names(&root), ["out"]);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_dropped_or_partial_set_leaves_the_previous_one_alone() {
        let root = scratch("partial");
        let out = root.join("out");
        let first = RunFolder::begin(&out).unwrap();
        fs::write(first.path().join("a.csv"), "1").unwrap();
        first.commit(false).unwrap();
        let dropped = RunFolder::begin(&out).unwrap();
        fs::write(dropped.path().join("a.csv"), "2").unwrap();
        drop(dropped);
        let partial = RunFolder::begin(&out).unwrap();
        fs::write(partial.path().join("a.csv"), "3").unwrap();
        assert_eq!(partial.commit(true).unwrap(), root.join("out.partial"));
        assert_eq!(fs::read_to_string(out.join("a.csv")).unwrap(), "1");
        assert_eq!(
            fs::read_to_string(root.join("out.partial/a.csv")).unwrap(),
            "3"
        );
        assert_eq!(names(&root), ["out", "out.partial"]);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_folder_with_foreign_content_is_refused() {
        let root = scratch("foreign");
        let out = root.join("mine");
        fs::create_dir_all(&out).unwrap();
        fs::write(out.join("notes.txt"), "keep me").unwrap();
        let err = RunFolder::begin(&out).unwrap_err();
        assert!(matches!(err, RunError::NotOurs { .. }), "{err}");
        assert!(err.to_string().contains("did not write"), "{err}");
        assert_eq!(names(&root), ["mine"]);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn abandoned_staging_folders_of_dead_processes_are_removed() {
        let root = scratch("abandoned");
        // Process ids are below 2^22 on Linux; this one cannot be running.
        let dead = root.join(".out.staging-4294967");
        fs::create_dir_all(&dead).unwrap();
        let folder = RunFolder::begin(&root.join("out")).unwrap();
        assert!(!dead.exists());
        drop(folder);
        assert!(names(&root).is_empty());
        fs::remove_dir_all(&root).unwrap();
    }
}
