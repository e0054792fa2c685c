//! Helpers of the end-to-end tests of the `models` binary: running it, scratch
//! directories, reading CSV files back and checking images.

#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_models");

/// The shipped scenarios' directory.
pub fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

/// An empty scratch directory for test `name` (emptied if it exists).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli")
        .join(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// What a run of the binary gave.
#[derive(Debug)]
pub struct Run {
    /// Its exit code (`None` if killed by a signal).
    pub code: Option<i32>,
    /// stdout.
    pub stdout: String,
    /// stderr.
    pub stderr: String,
}

impl From<Output> for Run {
    fn from(out: Output) -> Self {
        Run {
            code: out.status.code(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        }
    }
}

/// Asserts that `run` exited with `code`, showing its output if not.
pub fn assert_code(run: &Run, code: i32) {
    assert_eq!(
        run.code,
        Some(code),
        "stdout:\n{}\nstderr:\n{}",
        run.stdout,
        run.stderr
    );
}

/// Asserts that `run` succeeded (exit status 0), showing its output if not.
pub fn assert_success(run: &Run) {
    assert_code(run, 0);
}

/// Runs the binary with `args` in directory `cwd`.
pub fn run_in(cwd: &Path, args: &[&str]) -> Run {
    Command::new(BIN)
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the binary runs")
        .into()
}

/// Runs the binary with `args` in the models crate's directory.
pub fn run(args: &[&str]) -> Run {
    run_in(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// A CSV file read back: the header and the rows of numbers.
#[derive(Debug)]
pub struct Csv {
    /// The header's names.
    pub header: Vec<String>,
    /// The rows.
    pub rows: Vec<Vec<f64>>,
}

impl Csv {
    /// Reads `path`; every row must have as many numbers as the header has names.
    pub fn read(path: &Path) -> Csv {
        let text =
            fs::read_to_string(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .expect("a header")
            .split(',')
            .map(str::to_owned)
            .collect();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| {
                let row: Vec<f64> = l
                    .split(',')
                    .map(|v| v.parse().unwrap_or_else(|_| panic!("a number: {v:?}")))
                    .collect();
                assert_eq!(row.len(), header.len(), "row {l:?} of {}", path.display());
                row
            })
            .collect();
        Csv { header, rows }
    }

    /// Column `name`.
    pub fn column(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        self.rows.iter().map(|r| r[i]).collect()
    }
}

/// The files in `dir`, sorted by name, hidden ones included but for the marker of a
/// results folder (`.models-results`).
pub fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|name| name != models::catalog::folder::MARKER)
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// Decodes the PNG at `path` and checks that it is `width` pixels wide, at least
/// `min_height` high, and not blank: more than 1 % of its pixels differ from the
/// corner's (the background) and it has at least 3 colours.
pub fn check_png(path: &Path, width: u32, min_height: u32) {
    let file = fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let decoder = png::Decoder::new(file);
    let mut reader = decoder
        .read_info()
        .unwrap_or_else(|e| panic!("{} does not decode: {e}", path.display()));
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader
        .next_frame(&mut buf)
        .unwrap_or_else(|e| panic!("{} does not decode: {e}", path.display()));
    assert_eq!(info.width, width, "{}", path.display());
    assert!(
        info.height >= min_height,
        "{}: height {}",
        path.display(),
        info.height
    );
    let channels = info.color_type.samples();
    let pixels: Vec<&[u8]> = buf[..info.buffer_size()].chunks(channels).collect();
    let background = pixels[0];
    let different = pixels.iter().filter(|p| **p != background).count();
    assert!(
        different * 100 > pixels.len(),
        "{} is blank: {different} of {} pixels differ from the background",
        path.display(),
        pixels.len()
    );
    let mut colours: Vec<&[u8]> = pixels.iter().step_by(7).copied().collect();
    colours.sort();
    colours.dedup();
    assert!(
        colours.len() >= 3,
        "{}: {} colours",
        path.display(),
        colours.len()
    );
}
