//! End-to-end tests of what a results set says produced it: `run.yaml` for a model run
//! with overrides, a scenario run, a sweep and a failed run; the round trip (the
//! record's values run the same run again, bit for bit); the default folder rule (runs
//! with different overrides land in different folders, `--out` is obeyed, the default
//! run's folder is unchanged); and the `overrides` line of the summary and index.html.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use common::{assert_success, files, run_in, scratch};
use models::provenance::{RunRecord, FILE_NAME};
use serde_yaml::{Mapping, Value};

/// Reads `dir/run.yaml`.
fn record(dir: &Path) -> RunRecord {
    let path = dir.join(FILE_NAME);
    let text =
        fs::read_to_string(&path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    serde_yaml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}\n{text}", path.display()))
}

/// Whether `text` is a git commit hash.
fn is_commit(text: &str) -> bool {
    text.len() == 40 && text.chars().all(|c| c.is_ascii_hexdigit())
}

#[test]
fn a_model_run_records_its_overrides_parameters_state_and_solver() {
    let dir = scratch("provenance_model");
    let out = run_in(
        &dir,
        &[
            "run",
            "quick_return",
            "--set",
            "g=1.5",
            "--set",
            "w_drive=4",
            "--t-end",
            "0.05",
            "--no-plots",
            "--out",
            "results",
        ],
    );
    assert_success(&out);
    let results = dir.join("results");
    assert_eq!(
        files(&results),
        [
            "index.html",
            "quick_return.csv",
            "quick_return.units.csv",
            "run.yaml"
        ]
    );
    let r = record(&results);

    assert_eq!(r.program.name, "models");
    assert_eq!(r.program.version, env!("CARGO_PKG_VERSION"));
    assert!(
        is_commit(&r.program.commit) || r.program.commit == "unknown",
        "{}",
        r.program.commit
    );
    let started = humantime::parse_rfc3339(&r.started).expect("RFC 3339, UTC");
    let age = std::time::SystemTime::now()
        .duration_since(started)
        .expect("started in the past");
    assert!(age.as_secs() < 600, "{}", r.started);
    assert!(r.started.ends_with('Z'), "{}", r.started);
    assert_eq!(
        &r.command_line[1..],
        [
            "run",
            "quick_return",
            "--set",
            "g=1.5",
            "--set",
            "w_drive=4",
            "--t-end",
            "0.05",
            "--no-plots",
            "--out",
            "results"
        ]
    );
    assert_eq!(r.outcome.status, "complete");
    assert_eq!(r.outcome.reason, None);
    assert_eq!(
        (r.model.name.as_str(), r.model.type_name.as_str()),
        ("quick_return", "QuickReturn")
    );
    assert!(r.scenario.is_none());

    let overrides: Vec<(&str, f64, f64, &str)> = r
        .overrides
        .iter()
        .map(|o| {
            (
                o.name.as_str(),
                o.value.as_f64().unwrap(),
                o.default.as_f64().unwrap(),
                o.from.as_str(),
            )
        })
        .collect();
    assert_eq!(
        overrides,
        [
            ("g", 1.5, 9.81, "--set g=1.5"),
            ("w_drive", 4.0, 5.0, "--set w_drive=4"),
        ]
    );

    let entry = models::catalog::find("quick_return").unwrap();
    let defaults = entry.model.default_parameters();
    assert_eq!(r.parameters.len(), defaults.len());
    for (name, default) in &defaults {
        let value = r.parameters.get(name).expect("every parameter");
        match name.as_str().unwrap() {
            "g" => assert_eq!(value.as_f64(), Some(1.5)),
            "w_drive" => assert_eq!(value.as_f64(), Some(4.0)),
            _ => assert_eq!(value, default, "{name:?}"),
        }
    }

    let states = entry.model.state_names();
    let names: Vec<&str> = r.initial.keys().map(|k| k.as_str().unwrap()).collect();
    assert_eq!(names, states, "every state, by name, in order");
    assert!(r.initial_overridden.is_empty());

    assert_eq!((r.time.start, r.time.end), (0.0, 0.05));
    assert_eq!(r.output.interval, Some(0.001));
    assert_eq!(r.samples, 51);
    assert_eq!(r.plots, Value::from("none"));
    assert_eq!(r.solver.method, "radau5");
    assert_eq!((r.solver.rtol, r.solver.atol), (Some(1e-6), Some(1e-10)));
    assert_eq!(r.solver.max_steps, 100_000);
    assert!(r.solver_options.contains("newton"), "{}", r.solver_options);
    assert_eq!(r.results, ["quick_return.csv"]);
    assert!(r.sweep.is_none());
}

/// A quick return scenario setting a parameter, an initial state, the span, the
/// sampling and the solver.
const SCENARIO: &str = "model: quick_return\n\
    parameters:\n  w_drive: 4\n\
    initial:\n  crank.rotation.p_z: 0.001\n\
    time: {end: 0.08}\n\
    output: {interval: 0.002}\n\
    solver: {method: radau5, rtol: 1.0e-5, max_step: 0.01}\n";

#[test]
fn a_scenario_run_records_the_file_and_where_each_value_came_from() {
    let dir = scratch("provenance_scenario");
    fs::write(dir.join("spin.yaml"), SCENARIO).unwrap();
    let out = run_in(&dir, &["run", "spin.yaml", "--set", "g=1.5", "--no-plots"]);
    assert_success(&out);
    let results = dir.join("out/spin-g=1.5");
    let r = record(&results);
    let scenario = r.scenario.expect("the scenario file");
    assert_eq!(scenario.path, "spin.yaml");
    assert_eq!(scenario.text, SCENARIO, "the whole text");
    let from: Vec<(&str, &str)> = r
        .overrides
        .iter()
        .map(|o| (o.name.as_str(), o.from.as_str()))
        .collect();
    assert_eq!(from, [("g", "--set g=1.5"), ("w_drive", "spin.yaml:3:3")]);
    assert_eq!(r.initial_overridden, ["crank.rotation.p_z"]);
    assert_eq!(
        r.initial.get("crank.rotation.p_z").and_then(Value::as_f64),
        Some(0.001)
    );
    assert_eq!(r.output.interval, Some(0.002));
    assert_eq!(r.samples, 41);
    assert_eq!(r.solver.rtol, Some(1e-5));
    assert_eq!(r.solver.max_step, Some(0.01));
    assert!(
        out.stdout
            .contains("initial        crank.rotation.p_z = 0.001 (declared 0)\n"),
        "{}",
        out.stdout
    );
}

/// The scenario that `run.yaml`'s scenario keys make, with the model's name.
fn replay_scenario(record_path: &Path) -> String {
    let text = fs::read_to_string(record_path).unwrap();
    let record: Mapping = serde_yaml::from_str(&text).unwrap();
    let mut scenario = Mapping::new();
    let model = record
        .get("model")
        .and_then(|m| m.get("name"))
        .cloned()
        .unwrap();
    scenario.insert("model".into(), model);
    for key in [
        "parameters",
        "initial",
        "time",
        "output",
        "plots",
        "solver",
        "sweep",
    ] {
        if let Some(value) = record.get(key) {
            scenario.insert(key.into(), value.clone());
        }
    }
    serde_yaml::to_string(&scenario).unwrap()
}

#[test]
fn the_record_runs_the_same_run_again_bit_for_bit() {
    let dir = scratch("provenance_round_trip");
    fs::write(dir.join("spin.yaml"), SCENARIO).unwrap();
    let first = run_in(
        &dir,
        &[
            "run",
            "spin.yaml",
            "--set",
            "g=1.5",
            "--no-plots",
            "--out",
            "first",
        ],
    );
    assert_success(&first);
    fs::write(
        dir.join("replay.yaml"),
        replay_scenario(&dir.join("first/run.yaml")),
    )
    .unwrap();
    let again = run_in(&dir, &["run", "replay.yaml", "--out", "again"]);
    assert_success(&again);

    let a = fs::read(dir.join("first/quick_return.csv")).unwrap();
    let b = fs::read(dir.join("again/quick_return.csv")).unwrap();
    assert_eq!(a.len(), b.len());
    assert!(a == b, "the replayed results differ");
    // The run with the defaults differs: the comparison can fail.
    let plain = run_in(
        &dir,
        &[
            "run",
            "quick_return",
            "--t-end",
            "0.08",
            "--no-plots",
            "--out",
            "plain",
        ],
    );
    assert_success(&plain);
    let c = fs::read(dir.join("plain/quick_return.csv")).unwrap();
    assert!(a != c);

    let (r1, r2) = (record(&dir.join("first")), record(&dir.join("again")));
    assert_eq!(r1.parameters, r2.parameters);
    assert_eq!(r1.initial, r2.initial);
    assert_eq!(r1.solver, r2.solver);
    assert_eq!(r1.solver_options, r2.solver_options);
    assert_eq!(r1.output, r2.output);
    // The replay sets every state, so every one counts as overridden there.
    assert_eq!(r2.initial_overridden.len(), r2.initial.len());
}

/// An oscillator sweep over the damping.
const SWEEP: &str = "model: oscillator\n\
    parameters:\n  force: 2\n\
    time: {end: 1.0}\n\
    output: {count: 101}\n\
    sweep:\n  parameters:\n    - name: c\n      values: [1, 4, 16]\n  peaks: [x, speed]\n";

#[test]
fn a_sweep_records_its_grid_and_metrics_and_shows_its_overrides() {
    let dir = scratch("provenance_sweep");
    fs::write(dir.join("damping.yaml"), SWEEP).unwrap();
    let out = run_in(&dir, &["run", "damping.yaml", "--set", "k=50"]);
    assert_success(&out);
    let results = dir.join("out/damping-k=50");
    let r = record(&results);
    let sweep = r.sweep.expect("the sweep");
    assert_eq!(sweep.parameters.len(), 1);
    assert_eq!(sweep.parameters[0].name, "c");
    assert_eq!(sweep.parameters[0].values, [1.0, 4.0, 16.0]);
    assert_eq!(sweep.peaks, ["x", "speed"]);
    assert_eq!((sweep.window.from, sweep.window.to), (0.5, 1.0));
    let names: Vec<&str> = r.overrides.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["k", "force"], "the swept c is not an override");
    assert_eq!((r.output.count, r.output.interval), (Some(101), None));
    assert_eq!(r.samples, 101);
    assert_eq!(r.results, ["sweep.csv"]);
    assert_eq!(r.outcome.status, "complete");

    let line = "overrides      k = 50 (default 100), force = 2 (default 1)\n";
    assert!(out.stdout.contains(line), "{}", out.stdout);
    let index = fs::read_to_string(results.join("index.html")).unwrap();
    assert!(index.contains(line.trim_end()), "{index}");
}

#[test]
fn the_summary_and_index_show_the_overrides_or_none() {
    let dir = scratch("provenance_summary");
    let out = run_in(
        &dir,
        &[
            "run",
            "quick_return",
            "--set",
            "d=0.3",
            "--set",
            "w_drive=4",
            "--t-end",
            "0.05",
            "--no-plots",
            "--out",
            "qr",
        ],
    );
    assert_success(&out);
    let line = "overrides      d = 0.3 (default 0.4), w_drive = 4 (default 5)";
    assert!(out.stdout.contains(line), "{}", out.stdout);
    let index = fs::read_to_string(dir.join("qr/index.html")).unwrap();
    assert!(index.contains(line), "{index}");

    // A model other than the quick return (the trajectory summary).
    let out = run_in(
        &dir,
        &[
            "run",
            "rlc",
            "--set",
            "resistance=5",
            "--no-plots",
            "--out",
            "rlc",
        ],
    );
    assert_success(&out);
    assert!(
        out.stdout
            .contains("overrides      resistance = 5 (default 10)\n"),
        "{}",
        out.stdout
    );
    let out = run_in(&dir, &["run", "rlc", "--no-plots", "--out", "rlc"]);
    assert_success(&out);
    assert!(
        out.stdout.contains("overrides      none\n"),
        "{}",
        out.stdout
    );
    let index = fs::read_to_string(dir.join("rlc/index.html")).unwrap();
    assert!(index.contains("overrides      none"), "{index}");
}

/// The CSV files under `dir/out`, relative to it, sorted.
fn results_under(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for folder in fs::read_dir(dir.join("out")).unwrap() {
        let folder = folder.unwrap().path();
        for name in files(&folder) {
            if name.ends_with(".csv") && !name.ends_with(".units.csv") {
                found.push(folder.strip_prefix(dir).unwrap().join(name));
            }
        }
    }
    found.sort();
    found
}

#[test]
fn runs_with_different_overrides_do_not_share_a_folder() {
    let dir = scratch("provenance_folders");
    for args in [
        &["run", "rlc", "--no-plots"][..],
        &["run", "rlc", "--set", "resistance=1", "--no-plots"],
        &["run", "rlc", "--set", "resistance=2", "--no-plots"],
        &["run", "rlc", "--set", "resistance=2.0", "--no-plots"],
        &[
            "run",
            "rlc",
            "--set",
            "resistance=2",
            "--solver",
            "dopri5",
            "--rtol",
            "1e-8",
            "--no-plots",
        ],
    ] {
        assert_success(&run_in(&dir, args));
    }
    assert_eq!(
        results_under(&dir),
        [
            "out/rlc/rlc.csv",
            "out/rlc-resistance=1/rlc.csv",
            "out/rlc-resistance=2/rlc.csv",
            "out/rlc-resistance=2,solver=dopri5,rtol=1e-8/rlc.csv",
        ]
        .map(PathBuf::from)
    );
    let r1 = fs::read(dir.join("out/rlc-resistance=1/rlc.csv")).unwrap();
    let r2 = fs::read(dir.join("out/rlc-resistance=2/rlc.csv")).unwrap();
    assert!(r1 != r2, "each folder holds its own run");
    let last = record(&dir.join("out/rlc-resistance=2"));
    assert!(
        last.command_line.iter().any(|a| a == "resistance=2.0"),
        "--set resistance=2.0 and --set resistance=2 are the same run, in the same folder: {:?}",
        last.command_line
    );
}

#[test]
fn out_is_obeyed_and_scenarios_are_named_after_their_file() {
    let dir = scratch("provenance_out");
    fs::write(
        dir.join("soft.yaml"),
        "model: oscillator\nparameters: {k: 10}\n",
    )
    .unwrap();
    for args in [
        &[
            "run",
            "rlc",
            "--set",
            "resistance=1",
            "--no-plots",
            "--out",
            "mine",
        ][..],
        &["run", "soft.yaml", "--no-plots"],
        &["run", "soft.yaml", "--set", "c=3", "--no-plots"],
    ] {
        assert_success(&run_in(&dir, args));
    }
    assert_eq!(
        files(&dir.join("mine")),
        ["index.html", "rlc.csv", "rlc.units.csv", "run.yaml"]
    );
    assert_eq!(files(&dir.join("out")), ["soft", "soft-c=3"]);
    assert_eq!(
        files(&dir.join("out/soft-c=3")),
        [
            "index.html",
            "oscillator.csv",
            "oscillator.units.csv",
            "run.yaml"
        ]
    );
}

#[test]
fn the_default_run_still_writes_the_specs_folder() {
    let dir = scratch("provenance_default");
    let out = run_in(&dir, &["run", "quick_return", "--no-plots"]);
    assert_success(&out);
    assert_eq!(files(&dir.join("out")), ["quick_return"]);
    assert_eq!(
        files(&dir.join("out/quick_return")),
        [
            "index.html",
            "quick_return.csv",
            "quick_return.units.csv",
            "run.yaml"
        ]
    );
    assert!(
        out.stdout.contains("overrides      none\n"),
        "{}",
        out.stdout
    );
    let r = record(&dir.join("out/quick_return"));
    assert!(r.overrides.is_empty());
    assert_eq!(r.time.end, 5.0);
    assert_eq!(r.samples, 5001);
}

#[test]
fn a_failed_run_records_why() {
    let dir = scratch("provenance_partial");
    fs::write(
        dir.join("budget.yaml"),
        "model: quick_return\nsolver:\n  method: radau5\n  max_steps: 50\n",
    )
    .unwrap();
    let out = run_in(&dir, &["run", "budget.yaml", "--no-plots"]);
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    let r = record(&dir.join("out/budget.partial"));
    assert_eq!(r.outcome.status, "partial");
    let reason = r.outcome.reason.unwrap_or_default();
    assert!(reason.contains("budget of 50 steps"), "{reason}");
    assert_eq!(r.solver.max_steps, 50);
    assert_eq!(r.results, ["quick_return.csv"]);
    assert_eq!(r.output.interval, Some(0.001));
}
