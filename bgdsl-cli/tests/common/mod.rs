//! What the program's test binaries share: a scratch folder per test. Included by
//! path (`mod common;`), so it adds no test binary.
#![allow(dead_code)]

use std::fs;
use std::ops::Deref;
use std::path::{Path, PathBuf};

/// A fresh folder for one test, `target/tmp/bgdsl-cli-<name>-<pid>` (a previous run's
/// removed first). Removed when dropped after the test passed; kept when it is dropped
/// while the test panics (a failed assertion), and its path printed, so that the files
/// can be inspected. Dereferences to its path.
pub struct Scratch(PathBuf);

impl Scratch {
    /// The folder for test `name`, created empty.
    pub fn new(name: &str) -> Self {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("bgdsl-cli-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
}

impl Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!(
                "the test failed: its files are kept in {}",
                self.0.display()
            );
        } else {
            let _ = fs::remove_dir_all(&self.0);
        }
    }
}
