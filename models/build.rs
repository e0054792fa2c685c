//! Build script of `models`: records which git commit the program is built from, for
//! the provenance record every run writes (`bgdsl_cli::provenance`, through
//! `Catalogue::commit` in `models::catalogue`).
//!
//! Sets `MODELS_GIT_COMMIT` (the commit hash, or `unknown` without git or outside a
//! repository) and `MODELS_GIT_DIRTY` (`true` when tracked files differ from that
//! commit, as `git describe --dirty` counts them; `false`; or `unknown`).
//!
//! It reruns when HEAD moves (`HEAD`, the branch's ref, `packed-refs`), when the index
//! changes (a commit, a `git add`), and when a source file of the crates the program is
//! built from changes, so that the dirty flag follows edits; not on every build.

use std::path::{Path, PathBuf};
use std::process::Command;

/// `git ARGS` in the crate's directory: its trimmed output, or `None` when git is
/// missing or fails (no repository).
fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    Some(String::from_utf8(out.stdout).ok()?.trim().to_owned())
}

/// Asks cargo to rerun this script when `path` changes; only for paths that exist (a
/// missing one would rerun it on every build).
fn watch(path: &Path) {
    if path.exists() {
        println!("cargo:rerun-if-changed={}", path.display());
    }
}

fn main() {
    let crate_dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    println!("cargo:rerun-if-changed=build.rs");
    let commit = git(&crate_dir, &["rev-parse", "HEAD"]);
    let dirty = commit.as_ref().and_then(|_| {
        git(
            &crate_dir,
            &["status", "--porcelain", "--untracked-files=no"],
        )
        .map(|s| !s.is_empty())
    });
    println!(
        "cargo:rustc-env=MODELS_GIT_COMMIT={}",
        commit.as_deref().unwrap_or("unknown")
    );
    println!(
        "cargo:rustc-env=MODELS_GIT_DIRTY={}",
        dirty.map_or("unknown", |d| if d { "true" } else { "false" })
    );

    let absolute = |what: &str| {
        git(&crate_dir, &["rev-parse", "--path-format=absolute", what]).map(PathBuf::from)
    };
    if let (Some(git_dir), Some(common_dir)) = (absolute("--git-dir"), absolute("--git-common-dir"))
    {
        watch(&git_dir.join("HEAD"));
        watch(&git_dir.join("index"));
        if let Some(reference) = git(&crate_dir, &["symbolic-ref", "-q", "HEAD"]) {
            watch(&common_dir.join(reference));
        }
        watch(&common_dir.join("packed-refs"));
        if let Some(workspace) = crate_dir.parent() {
            for member in [
                "models",
                "bgdsl-cli",
                "bgdsl-runtime",
                "bgdsl-macros",
                "bgdsl-fmi/core",
            ] {
                watch(&workspace.join(member).join("src"));
                watch(&workspace.join(member).join("Cargo.toml"));
            }
        }
    }
}
