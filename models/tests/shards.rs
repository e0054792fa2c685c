//! Monte Carlo studies, `run --shard K/N` and `merge`, end to end through the `models`
//! binary: shards merged equal the one-process run byte for byte (samples.csv,
//! trajectories.csv, bands.csv, sweep.csv), a shard run again is the same, merge
//! refuses wrong sets naming the folders, the Slurm and Kubernetes recipes of
//! docs/recipes run their shards (a dry run with the variables the engines set; a real
//! array job when a Slurm cluster answers here), and a study's scenario errors point
//! at their line and column.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::{
    assert_code, assert_success, check_png, files, run, run_in, scenarios_dir, scratch, Csv, BIN,
};

/// The example study, shortened to keep the test quick (2 s of 0.01 s samples stays).
fn study() -> PathBuf {
    scenarios_dir().join("quarter_car_monte_carlo.yaml")
}

fn sweep() -> PathBuf {
    scenarios_dir().join("quarter_car_speed.yaml")
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn run_ok(args: &[&str]) -> common::Run {
    let out = run(args);
    assert_success(&out);
    out
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The bytes of `dir/name`.
fn bytes(dir: &Path, name: &str) -> Vec<u8> {
    fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{}: {e}", dir.join(name).display()))
}

fn assert_same_files(a: &Path, b: &Path, names: &[&str]) {
    for name in names {
        assert!(
            bytes(a, name) == bytes(b, name),
            "{name} differs between {} and {}",
            a.display(),
            b.display()
        );
    }
}

const STUDY_FILES: [&str; 3] = ["samples.csv", "trajectories.csv", "bands.csv"];

#[test]
fn a_study_writes_samples_bands_and_band_charts() {
    let dir = scratch("study_files");
    let out = dir.join("full");
    run_ok(&["run", s(&study()), "--out", s(&out)]);
    let samples = Csv::read(&out.join("samples.csv"));
    assert_eq!(samples.rows.len(), 40);
    assert_eq!(
        samples.column("index"),
        (0..40).map(f64::from).collect::<Vec<_>>()
    );
    // The drawn values lie in their distributions' support.
    assert!(samples
        .column("sprung_mass")
        .iter()
        .all(|m| (250.0..400.0).contains(m)));
    assert!(samples
        .column("suspension_damping")
        .iter()
        .all(|c| *c > 0.0));
    // The median of a type-7 quantile over the samples, recomputed from
    // trajectories.csv at the last time, is bands.csv's.
    let traces = Csv::read(&out.join("trajectories.csv"));
    let bands = Csv::read(&out.join("bands.csv"));
    let t_end = *bands.column("t").last().unwrap();
    assert_eq!(t_end, 2.0);
    let mut last: Vec<f64> = traces
        .column("t")
        .iter()
        .zip(traces.column("tyre_force"))
        .filter(|(t, _)| **t == t_end)
        .map(|(_, f)| f)
        .collect();
    assert_eq!(last.len(), 40);
    last.sort_by(f64::total_cmp);
    let median = 0.5 * (last[19] + last[20]);
    assert_eq!(*bands.column("tyre_force_q50").last().unwrap(), median);
    // final_<c> of samples.csv is the trajectory's last value.
    let mut finals = samples.column("final_tyre_force");
    finals.sort_by(f64::total_cmp);
    assert_eq!(finals, last);
    // The bands are ordered at every time.
    for i in 0..bands.rows.len() {
        let q: Vec<f64> = ["q05", "q25", "q50", "q75", "q95"]
            .iter()
            .map(|s| bands.column(&format!("body_height_{s}"))[i])
            .collect();
        assert!(q.windows(2).all(|w| w[0] <= w[1]), "{q:?}");
    }
    for column in [
        "body_height",
        "body_acceleration",
        "suspension_travel",
        "tyre_force",
    ] {
        check_png(&out.join(format!("band_{column}.png")), 1024, 640);
    }
    let index = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(index.contains("band_tyre_force"));
    // run.yaml's keys, with the model, are a scenario that draws the same numbers.
    let record: serde_yaml::Mapping =
        serde_yaml::from_str(&fs::read_to_string(out.join("run.yaml")).unwrap()).unwrap();
    let mut scenario = serde_yaml::Mapping::new();
    scenario.insert("model".into(), "quarter_car".into());
    for key in [
        "parameters",
        "initial",
        "time",
        "output",
        "plots",
        "solver",
        "monte_carlo",
    ] {
        scenario.insert(key.into(), record[key].clone());
    }
    assert_eq!(
        serde_yaml::to_string(&record["monte_carlo"]).unwrap(),
        "samples: 40\nseed: 2024\nparameters:\n  sprung_mass:\n    uniform:\n    - 250.0\n    - 400.0\n  \
         suspension_stiffness:\n    normal:\n      mean: 20000.0\n      sd: 2000.0\n  \
         suspension_damping:\n    lognormal:\n      mu: 7.3\n      sigma: 0.2\n"
    );
    let again = dir.join("again.yaml");
    fs::write(&again, serde_yaml::to_string(&scenario).unwrap()).unwrap();
    run_ok(&[
        "run",
        s(&again),
        "--no-plots",
        "--out",
        s(&dir.join("again")),
    ]);
    assert_same_files(&out, &dir.join("again"), &STUDY_FILES);
}

/// Shards 1/3, 2/3, 3/3 (run in another order), merged in yet another, equal the
/// one-process run byte for byte; a shard run again is byte for byte the same.
#[test]
fn merged_shards_equal_the_one_process_study() {
    let dir = scratch("study_shards");
    let full = dir.join("full");
    run_ok(&["run", s(&study()), "--out", s(&full)]);
    for k in [3, 1, 2] {
        let shard = format!("{k}/3");
        run_ok(&[
            "run",
            s(&study()),
            "--shard",
            &shard,
            "--out",
            s(&dir.join(format!("s{k}"))),
        ]);
    }
    let manifest = fs::read_to_string(dir.join("s2/shard.yaml")).unwrap();
    assert!(
        manifest.contains("shard: 2\nshards: 3\nitems: 40\nfirst: 13\nend: 26\ncomplete: true"),
        "{manifest}"
    );
    let merged = dir.join("merged");
    let out = run_ok(&[
        "merge",
        s(&dir.join("s2")),
        s(&dir.join("s3")),
        s(&dir.join("s1")),
        "--out",
        s(&merged),
    ]);
    assert!(
        out.stdout.contains("40 samples merged from 3 shards"),
        "{}",
        out.stdout
    );
    assert_same_files(&full, &merged, &STUDY_FILES);
    check_png(&merged.join("band_tyre_force.png"), 1024, 640);
    assert!(merged.join("index.html").is_file());
    // Any shard can be run again, anywhere: the same bytes.
    let again = dir.join("s2-again");
    run_ok(&["run", s(&study()), "--shard", "2/3", "--out", s(&again)]);
    assert_same_files(
        &dir.join("s2"),
        &again,
        &["samples.csv", "trajectories.csv", "shard.yaml"],
    );
}

#[test]
fn merged_sweep_shards_equal_the_one_process_sweep() {
    let dir = scratch("sweep_shards");
    let full = dir.join("full");
    run_ok(&["run", s(&sweep()), "--t-end", "1.0", "--out", s(&full)]);
    for k in 1..=3 {
        let shard = format!("{k}/3");
        run_ok(&[
            "run",
            s(&sweep()),
            "--t-end",
            "1.0",
            "--shard",
            &shard,
            "--out",
            s(&dir.join(format!("s{k}"))),
        ]);
    }
    let merged = dir.join("merged");
    run_ok(&[
        "merge",
        s(&dir.join("s1")),
        s(&dir.join("s2")),
        s(&dir.join("s3")),
        "--out",
        s(&merged),
    ]);
    assert_same_files(&full, &merged, &["sweep.csv"]);
    check_png(&merged.join("sweep_peak_tyre_force.png"), 1024, 640);
    // Without --out: shards go to out/<name>-shard-K-of-N, the merge to out/<name>.
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let o = run_in(
            &dir,
            &["run", s(&sweep()), "--t-end", "1.0", "--shard", &shard],
        );
        assert_success(&o);
    }
    let o = run_in(
        &dir,
        &[
            "merge",
            "out/quarter_car_speed-t_end=1-shard-1-of-3",
            "out/quarter_car_speed-t_end=1-shard-2-of-3",
            "out/quarter_car_speed-t_end=1-shard-3-of-3",
        ],
    );
    assert_success(&o);
    assert_same_files(
        &full,
        &dir.join("out/quarter_car_speed-t_end=1"),
        &["sweep.csv"],
    );
    // A shard of a different sweep (another end time) is another study.
    let other = dir.join("other");
    run_ok(&[
        "run",
        s(&sweep()),
        "--t-end",
        "0.9",
        "--shard",
        "3/3",
        "--out",
        s(&other),
    ]);
    let out = run(&[
        "merge",
        s(&dir.join("s1")),
        s(&dir.join("s2")),
        s(&other),
        "--out",
        s(&dir.join("no")),
    ]);
    assert_code(&out, 2);
    assert!(
        out.stderr
            .contains("are not shards of one study: study hash"),
        "{}",
        out.stderr
    );
    assert!(!dir.join("no").exists());
}

/// Merge says what is wrong with a set of folders, naming them, and writes nothing.
#[test]
fn merge_refuses_gaps_duplicates_other_studies_and_stray_folders() {
    let dir = scratch("merge_refusals");
    for k in 1..=3 {
        let shard = format!("{k}/3");
        run_ok(&[
            "run",
            s(&study()),
            "--shard",
            &shard,
            "--no-plots",
            "--out",
            s(&dir.join(format!("s{k}"))),
        ]);
    }
    run_ok(&[
        "run",
        s(&sweep()),
        "--t-end",
        "0.5",
        "--shard",
        "2/3",
        "--out",
        s(&dir.join("sweep2")),
    ]);
    let refused = |args: &[&str], expected: &str| {
        let mut all = vec!["merge"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["--out", "merged"]);
        let out = run_in(&dir, &all);
        assert_code(&out, 2);
        assert_eq!(out.stderr.trim_end(), expected);
        assert!(!dir.join("merged").exists());
    };
    refused(
        &["s1", "s3"],
        "error: missing shard 2/3 of the study (given: 1/3 in s1, 3/3 in s3)",
    );
    refused(
        &["s1", "s2", "s3", "s2"],
        "error: s2 and s2 are both shard 2/3; give each shard once",
    );
    let out = run_in(&dir, &["merge", "s1", "sweep2", "s3", "--out", "merged"]);
    assert_code(&out, 2);
    assert!(
        out.stderr
            .starts_with("error: s1 and sweep2 are not shards of one study: study hash "),
        "{}",
        out.stderr
    );
    let out = run_in(&dir, &["merge", "s1", "s2", "s3", "--out", "s2"]);
    assert_code(&out, 2);
    assert_eq!(
        out.stderr.trim_end(),
        "error: the output folder s2 is one of the shards: the merge would replace it; choose \
         another --out"
    );
    assert!(dir.join("s2/shard.yaml").is_file());
    fs::create_dir_all(dir.join("stray")).unwrap();
    refused(&["s1", "stray"], "error: stray: not a shard folder (no shard.yaml); give the folders that `run ... --shard K/N` wrote");
    // --shard itself is checked.
    let out = run_in(&dir, &["run", s(&study()), "--shard", "0/3"]);
    assert_code(&out, 2);
    assert!(
        out.stderr.contains("shards are numbered from 1"),
        "{}",
        out.stderr
    );
    let out = run_in(&dir, &["run", "oscillator", "--shard", "1/2"]);
    assert_code(&out, 2);
    assert!(
        out.stderr
            .contains("--shard splits a sweep or a Monte Carlo study"),
        "{}",
        out.stderr
    );
    let out = run_in(&dir, &["run", s(&sweep()), "--shard", "1/4"]);
    assert_code(&out, 2);
    assert!(
        out.stderr.contains("4 shards but only 3 sweep points"),
        "{}",
        out.stderr
    );
}

/// The Slurm recipe's script run as a job array's tasks would run it (the variables
/// Slurm sets), and the Kubernetes Job's command as its pods would (JOB_COMPLETION_INDEX
/// from 0), then merged: the one-process result.
#[test]
fn the_recipes_run_their_shards_and_merge() {
    let dir = scratch("recipes");
    let full = dir.join("full");
    run_ok(&["run", s(&study()), "--no-plots", "--out", s(&full)]);
    // Slurm: `sbatch --array=1-4 slurm-array.sbatch`.
    let script = repo().join("docs/recipes/slurm-array.sbatch");
    for k in 1..=4 {
        let status = Command::new("bash")
            .arg(&script)
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "4")
            .env("MODELS", BIN)
            .env("STUDY", study())
            .env("RESULTS", dir.join("slurm"))
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
    }
    merge_and_compare(&dir.join("slurm"), 4, &full);
    // Kubernetes: the Indexed Job's container command, with the Job's environment.
    let job: serde_yaml::Value = serde_yaml::from_str(
        &fs::read_to_string(repo().join("docs/recipes/k8s-indexed-job.yaml")).unwrap(),
    )
    .unwrap();
    let completions = job["spec"]["completions"].as_u64().unwrap();
    let container = &job["spec"]["template"]["spec"]["containers"][0];
    let command: Vec<&str> = container["command"]
        .as_sequence()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    let args = container["args"][0].as_str().unwrap();
    assert_eq!(command, ["/bin/sh", "-c"]);
    let shards = container["env"]
        .as_sequence()
        .unwrap()
        .iter()
        .find(|e| e["name"] == "SHARDS")
        .unwrap()["value"]
        .as_str()
        .unwrap();
    assert_eq!(
        shards,
        completions.to_string(),
        "SHARDS must equal completions"
    );
    for index in 0..completions {
        let status = Command::new(command[0])
            .args(&command[1..])
            .arg(args)
            .env("JOB_COMPLETION_INDEX", index.to_string())
            .env("SHARDS", shards)
            .env("MODELS", BIN)
            .env("STUDY", study())
            .env("RESULTS", dir.join("k8s"))
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
    }
    merge_and_compare(&dir.join("k8s"), completions as usize, &full);
}

fn merge_and_compare(results: &Path, n: usize, full: &Path) {
    let shards: Vec<String> = (1..=n)
        .map(|k| s(&results.join(format!("shard-{k}-of-{n}"))).to_owned())
        .collect();
    let merged = results.join("merged");
    let mut args: Vec<&str> = vec!["merge"];
    args.extend(shards.iter().map(String::as_str));
    args.extend(["--out", s(&merged)]);
    run_ok(&args);
    assert_same_files(full, &merged, &STUDY_FILES);
}

/// A real job array on a Slurm cluster, when one answers here with a node ready
/// (`sinfo`; set one up on one machine with docs/recipes/slurm-one-node.sh); otherwise
/// it says so and passes. The array gets two minutes, then it is cancelled and the
/// test fails.
#[test]
fn a_slurm_job_array_runs_the_shards_when_slurm_is_here() {
    let states = Command::new("sinfo").args(["-h", "-o", "%T"]).output();
    let ready = states.is_ok_and(|o| {
        o.status.success()
            && String::from_utf8_lossy(&o.stdout)
                .lines()
                .any(|l| ["idle", "mixed", "allocated"].contains(&l.trim()))
    });
    if !ready {
        eprintln!("skipped: no Slurm cluster with a ready node answers `sinfo` here");
        return;
    }
    let dir = scratch("slurm_real");
    let full = dir.join("full");
    run_ok(&["run", s(&study()), "--no-plots", "--out", s(&full)]);
    let results = dir.join("results");
    let submitted = Command::new("sbatch")
        .args(["--parsable", "--array=1-3", "--time=5"])
        .arg(format!("--output={}/slurm-%a.out", dir.display()))
        .arg(format!(
            "--export=ALL,MODELS={BIN},STUDY={},RESULTS={}",
            study().display(),
            results.display()
        ))
        .arg(repo().join("docs/recipes/slurm-array.sbatch"))
        .output()
        .unwrap();
    assert!(submitted.status.success(), "{submitted:?}");
    let job = String::from_utf8_lossy(&submitted.stdout).trim().to_owned();
    let started = std::time::Instant::now();
    loop {
        let queued = Command::new("squeue")
            .args(["-h", "-j", &job])
            .output()
            .unwrap();
        if queued.stdout.is_empty() {
            break;
        }
        if started.elapsed() > std::time::Duration::from_secs(120) {
            let _ = Command::new("scancel").arg(&job).status();
            panic!(
                "the array job {job} did not finish in 2 minutes; see {}",
                dir.display()
            );
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    merge_and_compare(&results, 3, &full);
}

/// A study whose samples fail commits what it has to `<out>.partial/` and leaves
/// `<out>` alone (the results-set rule); its shard folder says it is partial, and merge
/// refuses it.
#[test]
fn failed_samples_make_a_partial_set_that_merge_refuses() {
    let dir = scratch("study_partial");
    let out = dir.join("study");
    run_ok(&["run", s(&study()), "--no-plots", "--out", s(&out)]);
    let before = bytes(&out, "samples.csv");
    // Ten steps cannot cover 2 s with steps of at most 1 ms: every sample fails.
    let failed = run(&[
        "run",
        s(&study()),
        "--max-steps",
        "10",
        "--no-plots",
        "--out",
        s(&out),
    ]);
    assert_code(&failed, 1);
    assert!(
        failed
            .stdout
            .starts_with("PARTIAL STUDY 40 of 40 samples failed"),
        "{}",
        failed.stdout
    );
    assert_eq!(
        bytes(&out, "samples.csv"),
        before,
        "the complete set is untouched"
    );
    let partial = dir.join("study.partial");
    let samples = Csv::read(&partial.join("samples.csv"));
    assert!(samples
        .column("final_tyre_force")
        .iter()
        .all(|v| v.is_nan()));
    // A partial shard.
    let scenario = study();
    for k in 1..=2 {
        let shard = format!("{k}/2");
        let extra: &[&str] = if k == 2 { &["--max-steps", "10"] } else { &[] };
        let mut args = vec!["run", s(&scenario), "--shard", &shard, "--no-plots"];
        args.extend_from_slice(extra);
        let o = dir.join(format!("s{k}"));
        args.extend(["--out", s(&o)]);
        let _ = run(&args);
    }
    let m = fs::read_to_string(dir.join("s2.partial/shard.yaml")).unwrap();
    assert!(m.contains("complete: false"), "{m}");
    let out = run_in(&dir, &["merge", "s1", "s2.partial", "--out", "merged"]);
    assert_code(&out, 2);
    // Its solver's step budget makes it another study, and it is partial: both said.
    let lines: Vec<&str> = out.stderr.lines().collect();
    assert_eq!(lines.len(), 2, "{}", out.stderr);
    assert!(lines[0].starts_with("error: s1 and s2.partial are not shards of one study"));
    assert_eq!(
        lines[1],
        "error: s2.partial: shard 2/2 is partial (some of its items failed or did not run); run \
         it again"
    );
}

/// Each kind of mistake in a study is reported at its key, all in one go.
#[test]
fn study_errors_point_at_their_line() {
    let dir = scratch("study_errors");
    fs::write(dir.join("masses.csv"), "m,other\n300,1\n310,2\n").unwrap();
    // Flow mappings (`{...}`) put the error at the parameter's key; block mappings at
    // the distribution's key or its setting.
    let text = "model: quarter_car\n\
                monte_carlo:\n  samples: 3\n  seed: 1\n  parameters:\n\
                \x20   sprung_mass: {uniform: [400, 250]}\n\
                \x20   unsprung_mass:\n      normal:\n        mean: 40\n        sd: -1\n\
                \x20   suspension_damping: {lognormal: {mu: 7}}\n\
                \x20   tyre_stiffness: {csv: {file: masses.csv, column: m}}\n\
                \x20   speed: {triangle: [1, 2]}\n\
                \x20   wheels: {uniform: [1, 2]}\n";
    fs::write(dir.join("bad.yaml"), text).unwrap();
    let out = run_in(&dir, &["run", "bad.yaml", "--out", "out"]);
    assert_code(&out, 2);
    let lines: Vec<&str> = out.stderr.lines().collect();
    let expected = [
        "error: bad.yaml:6:5: a uniform range [lo, hi] needs lo < hi, found [400, 250]",
        "error: bad.yaml:8:7: `sd` must be >= 0, found -1",
        "error: bad.yaml:11:5: `lognormal` needs `sigma`",
        "error: bad.yaml:12:5: the column has 2 values, fewer than the 3 samples",
        "error: bad.yaml:13:5: unknown distribution `triangle`; use `uniform: [lo, hi]`, \
         `normal: {mean: M, sd: S}`, `lognormal: {mu: M, sigma: S}`, `csv: {file: F, column: C}` \
         or `values: [x0, x1, ...]`",
        "error: bad.yaml:14:5: unknown parameter `wheels`; the parameters of quarter_car are: \
         sprung_mass, unsprung_mass, suspension_stiffness, suspension_damping, tyre_stiffness, g, \
         speed, bump_distance, bump_height, bump_length, wave_amplitude, wavelength",
    ];
    assert_eq!(lines, expected, "{}", out.stderr);
    assert!(!dir.join("out").exists());
    // A drawn sample that is not physical names the sample and the distribution.
    fs::write(
        dir.join("negative.yaml"),
        "model: quarter_car\nmonte_carlo:\n  samples: 50\n  seed: 3\n  parameters:\n    sprung_mass: {normal: {mean: 10, sd: 10}}\n",
    )
    .unwrap();
    let out = run_in(&dir, &["run", "negative.yaml"]);
    assert_code(&out, 2);
    assert!(
        out.stderr.starts_with("error: negative.yaml:6:5: sample "),
        "{}",
        out.stderr
    );
    assert!(
        out.stderr
            .contains("narrow the distribution or change the seed"),
        "{}",
        out.stderr
    );
    // The size guard counts the trajectories: 20,000 samples of 10,001 times.
    fs::write(
        dir.join("large.yaml"),
        "model: quarter_car\ntime: {end: 10}\noutput: {interval: 0.001}\nmonte_carlo:\n  samples: 20000\n  seed: 1\n  parameters:\n    g: {uniform: [9.7, 9.9]}\n",
    )
    .unwrap();
    let out = run_in(&dir, &["run", "large.yaml"]);
    assert_code(&out, 2);
    assert!(
        out.stderr.starts_with(
            "error: this study would write up to 52.8 GB of trajectories (20,000 samples × \
             10,001 times × 11 columns)"
        ),
        "{}",
        out.stderr
    );
    // A listed figure must be a banded column's; only those are drawn.
    let listed = |plots: &str| {
        format!(
            "model: quarter_car\noutput: {{interval: 0.05, record: [tyre_force, body_height]}}\n\
             plots: {plots}\nmonte_carlo:\n  samples: 3\n  seed: 1\n  parameters:\n    \
             g: {{uniform: [9, 10]}}\n"
        )
    };
    fs::write(dir.join("plots.yaml"), listed("[tyre_force, damper_power]")).unwrap();
    let out = run_in(&dir, &["run", "plots.yaml"]);
    assert_code(&out, 2);
    assert_eq!(
        out.stderr.trim_end(),
        "error: plots.yaml:3:1: figure `damper_power` would draw nothing: a study draws the \
         band of each banded column (tyre_force, body_height); name one of those, or band \
         `damper_power` with `output.record`"
    );
    fs::write(dir.join("plots.yaml"), listed("[tyre_force]")).unwrap();
    assert_success(&run_in(&dir, &["run", "plots.yaml", "--out", "listed"]));
    let drawn: Vec<String> = files(&dir.join("listed"))
        .into_iter()
        .filter(|f| f.ends_with(".png"))
        .collect();
    assert_eq!(drawn, ["band_tyre_force.png"]);
    fs::remove_dir_all(dir.join("listed")).unwrap();
    fs::remove_file(dir.join("plots.yaml")).unwrap();
    // The section's own keys are checked like every scenario key.
    fs::write(
        dir.join("shape.yaml"),
        "model: quarter_car\nmonte_carlo:\n  samples: 10\n  parameters: {g: {uniform: [9, 10]}}\n  draws: 3\n",
    )
    .unwrap();
    let out = run_in(&dir, &["run", "shape.yaml"]);
    assert_code(&out, 2);
    assert_eq!(
        out.stderr.lines().collect::<Vec<_>>(),
        [
            "error: shape.yaml:2:1: monte_carlo: missing field `seed`",
            "error: shape.yaml:5:3: monte_carlo: unknown field `draws`, expected one of `samples`, `seed`, `parameters`"
        ]
    );
    // Nothing was written: the folder holds only what the test put there.
    assert_eq!(
        files(&dir),
        [
            "bad.yaml",
            "large.yaml",
            "masses.csv",
            "negative.yaml",
            "shape.yaml"
        ]
    );
}

/// SIGINT during a study stops it: the samples not yet run are NaN in the partial set
/// committed to `<out>.partial/`, and `<out>` (a previous complete study) is untouched.
#[cfg(unix)]
#[test]
fn an_interrupted_study_commits_a_partial_set() {
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let dir = scratch("study_interrupted");
    let scenario = dir.join("long.yaml");
    // 400 samples of 20 s at 1 ms: tens of seconds, interrupted after a moment.
    fs::write(
        &scenario,
        "model: quarter_car\ntime: {end: 20}\noutput: {interval: 0.001, record: [tyre_force]}\n\
         monte_carlo:\n  samples: 400\n  seed: 5\n  parameters:\n    sprung_mass: {uniform: [250, 400]}\n",
    )
    .unwrap();
    let out = dir.join("out");
    run_ok(&["run", s(&study()), "--no-plots", "--out", s(&out)]);
    let before = bytes(&out, "samples.csv");
    let child = Command::new(BIN)
        .args(["run", s(&scenario), "--no-plots", "--out", s(&out)])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let staging = dir.join(format!(".out.staging-{}", child.id()));
    let started = Instant::now();
    while !staging.exists() {
        assert!(
            started.elapsed() < Duration::from_secs(30),
            "no staging folder"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    std::thread::sleep(Duration::from_millis(300));
    let pid = libc::pid_t::try_from(child.id()).unwrap();
    // SAFETY: sends a signal to our own child.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGINT) }, 0);
    let run: common::Run = child.wait_with_output().unwrap().into();
    assert_code(&run, 1);
    assert!(run.stdout.starts_with("PARTIAL STUDY "), "{}", run.stdout);
    assert_eq!(
        bytes(&out, "samples.csv"),
        before,
        "the complete set is untouched"
    );
    let samples = Csv::read(&dir.join("out.partial/samples.csv"));
    assert_eq!(samples.rows.len(), 400, "every sample has its row");
    let finals = samples.column("final_tyre_force");
    assert!(
        finals.iter().any(|v| v.is_nan()),
        "some samples did not run"
    );
    assert!(!staging.exists());
}
