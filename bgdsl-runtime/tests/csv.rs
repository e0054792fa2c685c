//! Writing a [`Trajectory`] as CSV: names in the header, values that read back exactly,
//! and atomic replacement of the file.

use std::fs;
use std::path::{Path, PathBuf};

use bgdsl_runtime::{CsvStage, Model, Recorder, Scalar, Trajectory};

struct TwoStates;

impl Model for TwoStates {
    type Params = ();
    const NAME: &'static str = "two_states";
    const STATE_NAMES: &'static [&'static str] = &["spring.q", "mass.p"];
    const OUTPUT_NAMES: &'static [&'static str] = &["energy, total"];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, _x: &[T], dx: &mut [T]) {
        dx.fill(T::from_f64(0.0));
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], y: &mut [T]) {
        y.fill(T::from_f64(0.0));
    }
}

/// A fresh, empty directory for one test.
fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("csv-{name}"));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

/// Values chosen to break lossy formatting: thirds, tiny and huge magnitudes, negative
/// zero, subnormals, and neighbours of round numbers.
fn awkward_trajectory() -> Trajectory {
    let mut traj = Trajectory::for_model::<TwoStates>(4);
    traj.record(0.0, &[1.0 / 3.0, -2.0 / 3.0], &[1e-300]);
    traj.record(0.1, &[-0.0, 1e300], &[f64::MIN_POSITIVE / 3.0]);
    traj.record(
        0.30000000000000004,
        &[123456789.12345679, 1e-7],
        &[6.02214076e23],
    );
    traj.record(1e20, &[f64::EPSILON, f64::MAX], &[-1.5e-5]);
    traj
}

/// Splits one line of the simple CSV this crate writes (quoted fields may contain
/// commas; no line breaks inside fields).
fn split_csv(line: &str) -> Vec<String> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut field)),
            _ => field.push(c),
        }
    }
    fields.push(field);
    fields
}

#[test]
fn header_and_values_round_trip() {
    let dir = scratch_dir("round-trip");
    let path = dir.join("out.csv");
    let traj = awkward_trajectory();
    traj.write_csv(&path).unwrap();

    let text = fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "t,spring.q,mass.p,\"energy, total\"");
    assert_eq!(
        split_csv("t,spring.q,mass.p,\"energy, total\""),
        ["t", "spring.q", "mass.p", "energy, total"]
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| split_csv(l).iter().map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), traj.len());
    for (row, values) in rows.iter().enumerate() {
        for (col, name) in traj.names().iter().enumerate() {
            let expected = traj.value(row, name).unwrap();
            // Bit-identical, so -0.0 and subnormals survive too.
            assert_eq!(
                values[col].to_bits(),
                expected.to_bits(),
                "{name} row {row}"
            );
        }
    }
    // Readable: moderate numbers in plain notation, extreme ones in scientific.
    assert!(text.contains("\n0.1,-0,1e300,"), "{text}");
    assert_eq!(entries(&dir), ["out.csv"]);
}

#[test]
fn rewriting_replaces_the_file_whole() {
    let dir = scratch_dir("replace");
    let path = dir.join("out.csv");
    fs::write(
        &path,
        "old contents that are longer than the header line\n".repeat(100),
    )
    .unwrap();
    let traj = Trajectory::for_model::<TwoStates>(0);
    traj.write_csv(&path).unwrap();
    assert_eq!(
        fs::read_to_string(&path).unwrap(),
        "t,spring.q,mass.p,\"energy, total\"\n"
    );
    assert_eq!(entries(&dir), ["out.csv"]);
}

#[test]
fn missing_directory_is_an_error_and_leaves_nothing() {
    let dir = scratch_dir("missing");
    let path = dir.join("no-such-dir").join("out.csv");
    let err = awkward_trajectory().write_csv(&path).unwrap_err();
    assert_eq!(err.stage, CsvStage::CreateTemporary);
    assert_eq!(err.path, path);
    assert_eq!(err.source.kind(), std::io::ErrorKind::NotFound);
    assert!(err.to_string().starts_with("could not write CSV file `"));
    assert!(entries(&dir).is_empty());
}

#[test]
fn failed_rename_removes_the_temporary_file() {
    // The destination is a non-empty directory: the temporary file is written, the
    // rename onto it fails, and the temporary file must be cleaned up.
    let dir = scratch_dir("rename");
    let target = dir.join("taken");
    fs::create_dir(&target).unwrap();
    fs::write(target.join("keep"), "x").unwrap();
    let err = awkward_trajectory().write_csv(&target).unwrap_err();
    assert_eq!(err.stage, CsvStage::Rename);
    assert_eq!(entries(&dir), ["taken"]);
    assert_eq!(entries(&target), ["keep"]);
}

#[test]
fn accessors_find_columns_by_name() {
    let traj = awkward_trajectory();
    assert_eq!(traj.names(), ["t", "spring.q", "mass.p", "energy, total"]);
    assert_eq!(traj.times()[2], 0.30000000000000004);
    assert_eq!(traj.column("mass.p").unwrap()[1], 1e300);
    assert_eq!(traj.column_index("energy, total"), Some(3));
    assert_eq!(traj.value(3, "t"), Some(1e20));
    assert_eq!(traj.state(0, 1), Some(-2.0 / 3.0));
    assert_eq!(traj.state(0, 2), None);
    assert_eq!(traj.value(4, "t"), None);
    assert!(traj.column("nope").is_none());
    assert_eq!(traj.capacity(), 4);
}
