//! End-to-end tests of the `models` binary: its commands, every shipped scenario (with
//! a short end time), each kind of bad scenario (the error names the line; nothing is
//! written; exit status 2); runs that fail or are interrupted part-way are in
//! `results_sets.rs`. Outputs are checked for substance: the
//! results file's header is the spec's, its rows are the samples asked for, and every
//! image decodes, has the expected size and is not blank.

mod common;

use std::fs;
use std::path::Path;

use common::{assert_success, check_png, files, run, run_in, scenarios_dir, scratch, Csv};
use models::quick_return::figures::FIGURE_IDS;
use models::quick_return::results::header as spec_header;

/// The width of every chart.
const WIDTH: u32 = models::plot::WIDTH;
/// The height of a single chart (stacked ones are taller).
const HEIGHT: u32 = models::plot::HEIGHT;

#[test]
fn list_names_every_model_on_one_line() {
    let out = run(&["list"]);
    assert_success(&out);
    let names: Vec<&str> = out
        .stdout
        .lines()
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "quick_return",
            "quick_return_rigid",
            "quick_return_rigid_coupled",
            "quick_return_friction",
            "quick_return_end_stop",
            "bouncing_ball",
            "rectifier",
            "rectifier_exp",
            "stick_slip",
            "end_stop",
            "clutch",
            "oscillator",
            "rlc",
            "dc_motor",
            "quarter_car",
            "duffing",
            "dc_servo",
            "butterworth"
        ]
    );
    assert!(out.stdout.lines().all(|l| l.split_whitespace().count() > 3));
}

#[test]
fn params_shows_defaults_units_and_docs() {
    let out = run(&["params", "quick_return"]);
    assert_success(&out);
    let k01 = out
        .stdout
        .lines()
        .find(|l| l.trim_start().starts_with("K01 "))
        .expect("a line for K01");
    let words: Vec<&str> = k01.split_whitespace().collect();
    assert_eq!(&words[..3], ["K01", "100000", "N/m"], "{k01}");
    assert!(k01.contains("crank pivot O1 to ground"), "{k01}");
    let l1 = out
        .stdout
        .lines()
        .find(|l| l.trim_start().starts_with("l1 "))
        .unwrap();
    assert!(
        l1.contains("[0.2, 0.01, 0.01]") && l1.contains(" m "),
        "{l1}"
    );

    let states = run(&["params", "oscillator", "--states", "--outputs"]);
    assert_success(&states);
    assert!(
        states.stdout.contains("spring.q  0.05"),
        "{}",
        states.stdout
    );
    assert!(
        states
            .stdout
            .contains("\n  energy        J     Stored energy"),
        "{}",
        states.stdout
    );

    let unknown = run(&["params", "crank"]);
    assert_eq!(unknown.code, Some(2));
    assert_eq!(
        unknown.stderr.trim(),
        "error: unknown model `crank`; the models are: quick_return, quick_return_rigid, \
         quick_return_rigid_coupled, quick_return_friction, quick_return_end_stop, \
         bouncing_ball, rectifier, rectifier_exp, stick_slip, end_stop, clutch, oscillator, rlc, \
         dc_motor, quarter_car, duffing, dc_servo"
    );
}

#[test]
fn graph_prints_the_causal_graph_as_dot_or_svg() {
    let out = run(&["graph", "quick_return"]);
    assert_success(&out);
    assert!(
        out.stdout.starts_with("digraph \"QuickReturn\" {"),
        "{}",
        &out.stdout[..80]
    );
    assert!(out.stdout.trim_end().ends_with('}'));
    assert!(out.stdout.contains("cluster_crank"));

    let svg = run(&["graph", "oscillator", "--svg"]);
    let dot_installed = std::process::Command::new("dot").arg("-V").output().is_ok();
    if dot_installed {
        assert_success(&svg);
        assert!(svg.stdout.contains("<svg"), "{}", svg.stdout);
    } else {
        assert_eq!(svg.code, Some(MISSING_PREREQUISITE));
        assert!(svg.stderr.contains("Graphviz"), "{}", svg.stderr);
    }
}

/// The exit status of a missing external prerequisite (`EX_UNAVAILABLE`).
const MISSING_PREREQUISITE: i32 = 69;

/// Graphviz missing for `graph --svg` and the FMI library missing for `fmu`: the same
/// status, and a message that says what to install or build.
#[test]
fn a_missing_prerequisite_has_one_exit_status() {
    let dir = scratch("missing_prerequisite");
    let empty = dir.join("empty_path");
    fs::create_dir_all(&empty).unwrap();
    let no_dot = std::process::Command::new(env!("CARGO_BIN_EXE_models"))
        .args(["graph", "oscillator", "--svg"])
        .env("PATH", &empty)
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&no_dot.stderr);
    assert_eq!(no_dot.status.code(), Some(MISSING_PREREQUISITE), "{stderr}");
    assert!(stderr.contains("Graphviz"), "{stderr}");
    let no_library = std::process::Command::new(env!("CARGO_BIN_EXE_models"))
        .args(["fmu", "oscillator", "--out"])
        .arg(dir.join("fmu"))
        .env("BGDSL_FMI_LIBRARY", dir.join("no-such-library.so"))
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&no_library.stderr);
    assert_eq!(
        no_library.status.code(),
        Some(MISSING_PREREQUISITE),
        "{stderr}"
    );
    assert!(stderr.contains("cargo build -p bgdsl-fmi"), "{stderr}");
    assert!(
        !dir.join("fmu").exists(),
        "nothing is created without the library"
    );
}

/// `fmu --out` creates the folders it needs, as `run --out` does: for a `.fmu` file,
/// its folder; for any other path, that folder.
#[test]
fn fmu_creates_missing_folders_as_run_does() {
    let program = Path::new(env!("CARGO_BIN_EXE_models"));
    let library = program.with_file_name(bgdsl_fmi_core::library_file_name());
    let in_deps = program
        .with_file_name("deps")
        .join(bgdsl_fmi_core::library_file_name());
    if !library.is_file() && !in_deps.is_file() {
        // `cargo test --workspace` builds it; `cargo test -p models` alone does not.
        use std::io::Write as _;
        let _ = writeln!(
            std::io::stderr(),
            "\n!!! SKIPPED: no FMI library at {} (build it with `cargo build -p bgdsl-fmi`)\n",
            library.display()
        );
        return;
    }
    let dir = scratch("fmu_folders");
    let file = dir.join("a/b/c.fmu");
    let out = run(&["fmu", "oscillator", "--out", file.to_str().unwrap()]);
    // A library older than the model code (left by an earlier build, when only this
    // crate is tested) fails here with its rebuild advice: `cargo test --workspace`
    // builds it fresh. Not skipped, so that a library and program that disagree fail.
    assert_success(&out);
    assert!(file.is_file(), "{}", file.display());
    assert_eq!(out.stdout.trim(), file.display().to_string());
    let folder = dir.join("x/y");
    let out = run(&["fmu", "oscillator", "--out", folder.to_str().unwrap()]);
    assert_success(&out);
    assert!(folder.join("oscillator.fmu").is_file());
    let results = dir.join("r/s/t");
    let out = run(&[
        "run",
        "oscillator",
        "--t-end",
        "0.2",
        "--no-plots",
        "--out",
        results.to_str().unwrap(),
    ]);
    assert_success(&out);
    assert!(results.join("oscillator.csv").is_file());
}

/// Checks a quick return results file: the spec's header, one row per ms from 0 to
/// `t_end`, finite values, the crank angle starting at π/2.
fn check_results(path: &Path, t_end: f64) -> Csv {
    let csv = Csv::read(path);
    assert_eq!(csv.header.join(","), spec_header());
    let rows = (t_end * 1000.0).round() as usize + 1;
    assert_eq!(csv.rows.len(), rows, "{}", path.display());
    for (k, t) in csv.column("t").iter().enumerate() {
        assert_eq!(*t, k as f64 / 1000.0);
    }
    assert!(csv.rows.iter().flatten().all(|v| v.is_finite()));
    let angle = csv.column("crank_angle");
    assert!((angle[0] - core::f64::consts::FRAC_PI_2).abs() < 1e-9);
    csv
}

/// Runs a shipped scenario to 0.3 s into a scratch directory, with the extra flags.
fn run_scenario(stem: &str, extra: &[&str]) -> (std::path::PathBuf, common::Run) {
    let dir = scratch(stem);
    let scenario = scenarios_dir().join(format!("{stem}.yaml"));
    let out_dir = dir.join("out");
    let mut args = vec![
        "run",
        scenario.to_str().unwrap(),
        "--t-end",
        "0.3",
        "--out",
        out_dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let out = run(&args);
    assert_success(&out);
    (out_dir, out)
}

/// The shipped study is tested in `shards.rs`.
#[test]
fn every_shipped_scenario_is_tested() {
    let mut stems: Vec<String> = fs::read_dir(scenarios_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    stems.sort();
    assert_eq!(
        stems,
        [
            "quarter_car_monte_carlo",
            "quarter_car_speed",
            "quick_return_default",
            "quick_return_g0",
            "quick_return_speed_sweep",
            "quick_return_stiff_limit"
        ]
    );
}

#[test]
fn scenario_default_writes_the_results_figures_and_index() {
    let (dir, out) = run_scenario("quick_return_default", &[]);
    assert!(
        out.stdout.contains("(301 rows, 56 columns)"),
        "{}",
        out.stdout
    );
    check_results(&dir.join("quick_return.csv"), 0.3);
    let names = files(&dir);
    let mut drawn = 0;
    for id in FIGURE_IDS {
        let Some(png) = names
            .iter()
            .find(|n| n.starts_with(&format!("{id}_")) && n.ends_with(".png"))
        else {
            // One steady crank revolution against the rigid kinematics needs a run
            // longer than a revolution; 0.3 s is not.
            assert_eq!(*id, "fig20", "no PNG of {id} in {names:?}");
            continue;
        };
        let svg = png.replace(".png", ".svg");
        assert!(names.contains(&svg), "no {svg}");
        check_png(&dir.join(png), WIDTH, HEIGHT);
        let text = fs::read_to_string(dir.join(&svg)).unwrap();
        assert!(text.contains("<svg") && text.trim_end().ends_with("</svg>"));
        drawn += 1;
    }
    assert!(drawn >= 18);
    let index = fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(
        index.contains("output-slider stroke"),
        "the summary is in index.html"
    );
    assert!(index.contains("fig05"));
    // Nothing else (the CSV, its units, run.yaml, index.html): no temporary files left behind.
    assert_eq!(names.len(), 4 + 2 * drawn, "{names:?}");
}

#[test]
fn scenario_g0_runs_without_gravity() {
    let (dir, _) = run_scenario("quick_return_g0", &["--no-plots"]);
    let csv = check_results(&dir.join("quick_return.csv"), 0.3);
    assert_eq!(
        files(&dir),
        [
            "index.html",
            "quick_return.csv",
            "quick_return.units.csv",
            "run.yaml"
        ]
    );
    // Without gravity the mechanism starts with no load at all.
    assert_eq!(csv.column("F_O1_y")[0], 0.0);
}

#[test]
fn scenario_stiff_limit_runs() {
    let (dir, out) = run_scenario("quick_return_stiff_limit", &["--no-plots"]);
    check_results(&dir.join("quick_return.csv"), 0.3);
    assert!(
        out.stdout.contains("rtol 1e-7, atol 1e-11"),
        "{}",
        out.stdout
    );
}

#[test]
fn scenario_speed_sweep_reports_peaks_against_speed() {
    let (dir, out) = run_scenario("quick_return_speed_sweep", &[]);
    let csv = Csv::read(&dir.join("sweep.csv"));
    assert_eq!(csv.header, ["w_drive", "peak_Tc", "peak_F_O1"]);
    assert_eq!(csv.rows.len(), 17);
    let speeds = csv.column("w_drive");
    assert_eq!(speeds[0], 2.0);
    assert_eq!(speeds[16], 10.0);
    for row in &csv.rows {
        assert!(row[1] > 0.0 && row[2] > 0.0, "{row:?}");
    }
    assert!(out.stdout.contains("17 runs"), "{}", out.stdout);
    for stem in ["sweep_peak_Tc", "sweep_peak_F_O1"] {
        check_png(&dir.join(format!("{stem}.png")), WIDTH, HEIGHT);
        assert!(dir.join(format!("{stem}.svg")).is_file());
    }
    assert!(dir.join("index.html").is_file());
}

#[test]
fn scenario_quarter_car_sweep_runs() {
    let (dir, _) = run_scenario("quarter_car_speed", &["--no-plots"]);
    let csv = Csv::read(&dir.join("sweep.csv"));
    assert_eq!(
        csv.header,
        ["speed", "peak_body_acceleration", "peak_tyre_force"]
    );
    assert_eq!(csv.column("speed"), [5.0, 10.0, 20.0]);
}

#[test]
fn other_models_write_their_trajectory() {
    let dir = scratch("oscillator");
    let out = run(&[
        "run",
        "oscillator",
        "--set",
        "force=5",
        "--set",
        "c=20",
        "--solver",
        "dopri5",
        "--rtol",
        "1e-8",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    let csv = Csv::read(&dir.join("oscillator.csv"));
    assert_eq!(
        csv.header,
        [
            "t",
            "mass.p",
            "spring.q",
            "x",
            "speed",
            "spring_force",
            "damper_power",
            "input_power",
            "energy"
        ]
    );
    assert_eq!(csv.rows.len(), 1001);
    // Pushed by 5 N from x = 0.01, critically damped, it settles at force / k = 0.05 m.
    let x = csv.column("x");
    assert!((x[1000] - 0.05).abs() < 1e-4, "{}", x[1000]);
    assert!(out.stdout.contains("dopri5 (rtol 1e-8"), "{}", out.stdout);
    check_png(&dir.join("x.png"), WIDTH, HEIGHT);
}

/// Writes `text` as `name` in a scratch directory and runs it with `--out` there;
/// checks exit status 2, that the message starts with `name:line:` and contains
/// `expected`, and that no file was written. Returns stderr.
fn rejects(name: &str, text: &str, line: usize, expected: &str) -> String {
    let dir = scratch(&format!("bad_{name}"));
    let file = dir.join(format!("{name}.yaml"));
    fs::write(&file, text).unwrap();
    let out_dir = dir.join("out");
    let out = run_in(
        &dir,
        &[
            "run",
            &format!("{name}.yaml"),
            "--out",
            out_dir.to_str().unwrap(),
        ],
    );
    assert_eq!(out.code, Some(2), "stderr:\n{}", out.stderr);
    let first = out.stderr.lines().next().unwrap_or("");
    let prefix = format!("error: {name}.yaml:{line}:");
    assert!(
        first.starts_with(&prefix),
        "expected {prefix}... got:\n{}",
        out.stderr
    );
    assert!(
        out.stderr.contains(expected),
        "expected {expected:?} in:\n{}",
        out.stderr
    );
    assert!(
        !out_dir.exists(),
        "an invalid scenario wrote {:?}",
        files(&out_dir)
    );
    assert_eq!(files(&dir), [format!("{name}.yaml")]);
    assert!(out.stdout.is_empty());
    out.stderr
}

#[test]
fn rejects_an_unknown_key_listing_the_valid_ones() {
    let stderr = rejects(
        "unknown_key",
        "model: quick_return\nsolver:\n  method: radau5\n  tolerance: 1e-6\n",
        4,
        "solver: unknown field `tolerance`, expected one of `method`, `rtol`, `atol`",
    );
    assert!(
        stderr.starts_with("error: unknown_key.yaml:4:3: "),
        "{stderr}"
    );
}

#[test]
fn rejects_an_unknown_top_level_key() {
    rejects(
        "top_key",
        "model: quick_return\n\nparams:\n  m1: 1\n",
        3,
        "unknown field `params`, expected one of `model`, `description`, `parameters`",
    );
}

#[test]
fn rejects_an_unknown_parameter_listing_the_models() {
    rejects(
        "unknown_parameter",
        "model: quick_return\nparameters:\n  m1: 0.5\n  # the drive\n  omega: 5\n",
        5,
        "unknown parameter `omega`; the parameters of quick_return are: m1, m2, m3",
    );
}

#[test]
fn rejects_wrong_types() {
    rejects(
        "wrong_type",
        "model: quick_return\ntime:\n  end: soon\n",
        3,
        "time.end: invalid type: string \"soon\", expected f64",
    );
    rejects(
        "wrong_shape",
        "model: quick_return\nparameters:\n  g: 9.81\n  l1: [0.2, 0.01]\n",
        4,
        "parameter `l1` must be a list of 3 numbers",
    );
}

#[test]
fn rejects_a_zero_mass() {
    rejects(
        "zero_mass",
        "model: quick_return\nparameters:\n  g: 9.81\n  m4: 0\n",
        4,
        "parameter `m4` (connecting-rod mass (Table 1), kg) must be > 0, found 0",
    );
}

#[test]
fn rejects_a_negative_time_span() {
    rejects(
        "negative_span",
        "model: quick_return\ntime:\n  start: 0.0\n  end: -2.0\n",
        4,
        "the time span must be positive",
    );
}

#[test]
fn rejects_tolerances_out_of_range() {
    let stderr = rejects(
        "bad_tolerance",
        "model: quick_return\nsolver:\n  method: radau5\n  rtol: 0.5\n  atol: -1e-9\n",
        4,
        "rtol must be in [1e-14, 0.1], found 0.5",
    );
    assert!(
        stderr.contains("bad_tolerance.yaml:5:3: atol must be a finite number > 0"),
        "both errors are reported: {stderr}"
    );
}

#[test]
fn rejects_an_inertia_that_is_not_positive_definite() {
    rejects(
        "inertia",
        "model: quick_return\nparameters:\n  m2: 0.1\n  l2: [0.01, 0.0, 0.0]\n",
        4,
        "the slider's inertia is not positive definite",
    );
}

#[test]
fn rejects_a_sweep_point_that_makes_no_sense() {
    rejects(
        "sweep_point",
        "model: quick_return\nsweep:\n  parameters:\n    - name: m1\n      values: [0.5, 0]\n  peaks: [Tc]\n",
        4,
        "at the sweep point m1 = 0: parameter `m1`",
    );
}

#[test]
fn rejects_bad_flags_without_writing() {
    let dir = scratch("bad_flags");
    let out_dir = dir.join("out");
    let out = run(&[
        "run",
        "quick_return",
        "--set",
        "m1=0",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(2));
    assert_eq!(
        out.stderr.trim(),
        "error: --set m1=0: parameter `m1` (crank mass (Table 1), kg) must be > 0, found 0"
    );
    let out = run(&[
        "run",
        "quick_return",
        "--rtol",
        "1",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(2));
    assert!(
        out.stderr
            .contains("--rtol 1: rtol must be in [1e-14, 0.1]"),
        "{}",
        out.stderr
    );
    let out = run(&[
        "run",
        "quick_return",
        "--t-end",
        "0",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(2));
    assert!(
        out.stderr
            .contains("--t-end 0: the time span must be positive"),
        "{}",
        out.stderr
    );
    let out = run(&["run", "slider_crank"]);
    assert_eq!(out.code, Some(2));
    assert!(
        out.stderr.contains("unknown model `slider_crank`"),
        "{}",
        out.stderr
    );
    let out = run(&["frobnicate"]);
    assert_eq!(out.code, Some(2), "clap's usage errors exit with 2");
    assert!(!out_dir.exists());
}

#[test]
fn without_a_command_it_runs_the_flagship() {
    let dir = scratch("flagship");
    let out = run_in(&dir, &[]);
    assert_success(&out);
    assert!(
        out.stdout.starts_with("model          QuickReturn"),
        "{}",
        out.stdout
    );
    assert!(
        out.stdout.contains("quick-return time ratio    1.9"),
        "{}",
        out.stdout
    );
    let results = dir.join("out/quick_return");
    check_results(&results.join("quick_return.csv"), 5.0);
    let names = files(&results);
    let pngs: Vec<&String> = names.iter().filter(|n| n.ends_with(".png")).collect();
    assert_eq!(pngs.len(), FIGURE_IDS.len(), "{names:?}");
    for png in pngs {
        check_png(&results.join(png), WIDTH, HEIGHT);
    }
    assert!(results.join("index.html").is_file());
}

#[test]
fn fmu_says_how_to_build_the_library_it_needs_and_writes_nothing_without_it() {
    let dir = scratch("fmu_without_library");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_models"))
        .args(["fmu", "oscillator", "--out"])
        .arg(&dir)
        .env("BGDSL_FMI_LIBRARY", dir.join("no-such-library.so"))
        .output()
        .expect("the binary runs");
    assert_eq!(out.status.code(), Some(MISSING_PREREQUISITE), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no-such-library.so"), "{stderr}");
    assert!(files(&dir).is_empty(), "{:?}", files(&dir));
}

#[test]
fn fmu_of_an_unknown_model_lists_the_known_ones() {
    let out = run(&["fmu", "pendulum"]);
    assert_eq!(out.code, Some(2), "{out:?}");
    assert!(out.stderr.contains("quick_return"), "{}", out.stderr);
}

#[test]
fn params_lists_a_models_inputs() {
    let out = run(&["params", "dc_servo"]);
    assert_success(&out);
    let (_, inputs) = out
        .stdout
        .split_once("\ninputs")
        .expect("an inputs section");
    let voltage = inputs
        .lines()
        .find(|l| l.trim_start().starts_with("voltage "))
        .expect("a line for voltage");
    let words: Vec<&str> = voltage.split_whitespace().collect();
    assert_eq!(&words[..2], ["voltage", "V"], "{voltage}");
    assert!(!run(&["params", "oscillator"]).stdout.contains("\ninputs"));
}

/// A run of a model with events writes `events.csv` (the header, one row per state an
/// event changed) and its summary counts the events and sums their energy, which
/// equals the sum over the file's events; a model without events writes no such file
/// and no such lines.
#[test]
fn a_run_with_events_writes_them_and_counts_them() {
    let dir = scratch("events_file");
    let out = run(&[
        "run",
        "bouncing_ball",
        "--no-plots",
        "--out",
        dir.join("ball").to_str().unwrap(),
    ]);
    assert_success(&out);
    let text = fs::read_to_string(dir.join("ball").join("events.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("t,event,state,before,after,event_energy")
    );
    // One energy per event (rows of one event repeat it), keyed by its time.
    let mut events: Vec<(String, f64)> = Vec::new();
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), 6, "{line}");
        assert_eq!(fields[1], "floor.hit", "{line}");
        let before: f64 = fields[3].parse().unwrap();
        let after: f64 = fields[4].parse().unwrap();
        assert_ne!(
            before.to_bits(),
            after.to_bits(),
            "only changed states: {line}"
        );
        if events.last().map(|e| e.0.as_str()) != Some(fields[0]) {
            events.push((fields[0].to_owned(), fields[5].parse().unwrap()));
        }
    }
    let count_line = out
        .stdout
        .lines()
        .find(|l| l.starts_with("events "))
        .expect("an events line");
    assert_eq!(
        count_line.split_whitespace().nth(1),
        Some(events.len().to_string().as_str()),
        "{count_line}"
    );
    let total: f64 = events.iter().map(|e| e.1).sum();
    let energy_line = out
        .stdout
        .lines()
        .find(|l| l.starts_with("event energy"))
        .expect("an event energy line");
    let printed: f64 = energy_line
        .split_whitespace()
        .nth(2)
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        (printed - total).abs() <= 1e-5 * total.abs(),
        "{energy_line} vs {total}"
    );
    // The ball comes to rest: every joule of its drop went in the impacts.
    assert!((total + 9.81).abs() < 1e-6, "{total}");

    let plain = run(&[
        "run",
        "oscillator",
        "--no-plots",
        "--out",
        dir.join("oscillator").to_str().unwrap(),
    ]);
    assert_success(&plain);
    assert!(!dir.join("oscillator").join("events.csv").exists());
    assert!(!plain.stdout.contains("events "), "{}", plain.stdout);
}
