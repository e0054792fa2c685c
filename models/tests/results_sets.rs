//! A results folder is a transaction: a successful run replaces the whole set, a run
//! that fails, is interrupted or cannot write leaves the previous set byte for byte as
//! it was (its partial set goes to `<out>.partial/`), no temporary file or folder
//! survives any signal the program catches, figures and pages stay small whatever the
//! run's length, and a run too large to write without asking is refused.

mod common;

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{assert_code, run_in, scratch, Csv, BIN};

/// Every file under `dir` (relative path → contents), hidden ones included.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for entry in fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let relative = path.strip_prefix(root).unwrap().to_path_buf();
                out.insert(relative, fs::read(&path).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Asserts that two snapshots are equal, naming the files that differ.
#[track_caller]
fn assert_same(after: &BTreeMap<PathBuf, Vec<u8>>, before: &BTreeMap<PathBuf, Vec<u8>>) {
    let differ: Vec<&PathBuf> = after
        .keys()
        .chain(before.keys())
        .filter(|k| after.get(*k) != before.get(*k))
        .collect();
    assert!(differ.is_empty(), "the previous set changed: {differ:?}");
}

/// The names in `dir`, sorted, hidden ones included.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn quick_run<'a>(out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["run", "quick_return", "--t-end", "0.05", "--out", out];
    args.extend_from_slice(extra);
    args
}

/// A quick return scenario whose step budget runs out at about 6 ms.
const BUDGET: &str = "model: quick_return\nsolver:\n  method: radau5\n  max_steps: 50\n";

#[test]
fn success_replaces_the_whole_set() {
    let dir = scratch("sets-success");
    let out = dir.join("out");
    let out_arg = out.to_str().unwrap();
    assert_code(&run_in(&dir, &quick_run(out_arg, &[])), 0);
    let plotted = names(&out);
    assert!(plotted.iter().any(|n| n.ends_with(".svg")), "{plotted:?}");
    // Files of an earlier run that this one would not write.
    fs::write(out.join("fig20_output_slider_vs_rigid.png"), b"stale").unwrap();
    fs::write(out.join("quick_return_extra.csv"), b"t\n0\n").unwrap();

    let again = run_in(&dir, &quick_run(out_arg, &["--no-plots"]));
    assert_code(&again, 0);
    assert_eq!(
        names(&out),
        [
            ".models-results",
            "index.html",
            "quick_return.csv",
            "quick_return.units.csv",
            "run.yaml"
        ]
    );
    assert_eq!(names(&dir), ["out"], "nothing temporary beside it");
    assert!(again.stdout.contains(&format!(
        "report         {}",
        out.join("index.html").display()
    )));
}

#[test]
fn a_failure_leaves_the_previous_set_untouched_and_writes_a_partial_one() {
    let dir = scratch("sets-failure");
    fs::write(dir.join("budget.yaml"), BUDGET).unwrap();
    let out = dir.join("out");
    let out_arg = out.to_str().unwrap();
    assert_code(&run_in(&dir, &quick_run(out_arg, &["--no-plots"])), 0);
    let before = snapshot(&out);

    let failed = run_in(&dir, &["run", "budget.yaml", "--out", out_arg]);
    assert_code(&failed, 1);
    assert_eq!(
        snapshot(&out),
        before,
        "the previous set is byte for byte intact"
    );
    let partial = dir.join("out.partial");
    assert_eq!(names(&dir), ["budget.yaml", "out", "out.partial"]);
    let csv = Csv::read(&partial.join("quick_return.csv"));
    assert!(
        csv.rows.len() > 1 && csv.rows.len() < 5001,
        "{}",
        csv.rows.len()
    );
    assert!(
        failed.stdout.starts_with("PARTIAL RUN"),
        "{}",
        failed.stdout
    );
    assert!(failed.stdout.contains(&format!(
        "{} ({} rows, 56 columns",
        partial.join("quick_return.csv").display(),
        csv.rows.len()
    )));
    let message = failed.stderr.trim();
    assert!(
        message.contains("the budget of 50 steps was used up"),
        "{message}"
    );
    assert!(
        message.contains(&format!(
            "partial results in {}",
            partial.join("quick_return.csv").display()
        )),
        "{message}"
    );
    let index = fs::read_to_string(partial.join("index.html")).unwrap();
    assert!(index.contains("PARTIAL RUN"));

    // The next failing run replaces the partial set whole.
    fs::write(partial.join("planted.txt"), b"x").unwrap();
    let failed_again = run_in(
        &dir,
        &["run", "budget.yaml", "--out", out_arg, "--no-plots"],
    );
    assert_code(&failed_again, 1);
    assert!(!partial.join("planted.txt").exists());
    assert_same(&snapshot(&out), &before);
    assert_eq!(names(&dir), ["budget.yaml", "out", "out.partial"]);
}

#[test]
fn a_failing_sweep_keeps_the_previous_sweep() {
    let dir = scratch("sets-sweep");
    let sweep = "model: quick_return\ntime:\n  end: 0.02\nsweep:\n  parameters:\n    \
                 - name: w_drive\n      values: [4.0, 5.0]\n  peaks: [Tc]\n";
    fs::write(dir.join("sweep.yaml"), sweep).unwrap();
    fs::write(
        dir.join("failing.yaml"),
        format!("{sweep}solver:\n  method: radau5\n  max_steps: 5\n"),
    )
    .unwrap();
    let out = dir.join("out");
    let out_arg = out.to_str().unwrap();
    assert_code(&run_in(&dir, &["run", "sweep.yaml", "--out", out_arg]), 0);
    assert!(out.join("sweep.csv").is_file());
    let before = snapshot(&out);
    let failed = run_in(&dir, &["run", "failing.yaml", "--out", out_arg]);
    assert_code(&failed, 1);
    assert_same(&snapshot(&out), &before);
    let table = fs::read_to_string(dir.join("out.partial/sweep.csv")).unwrap();
    assert!(table.contains("NaN"), "{table}");
    assert!(
        failed.stdout.starts_with("PARTIAL SWEEP"),
        "{}",
        failed.stdout
    );
}

#[test]
fn a_folder_with_foreign_content_is_refused() {
    let dir = scratch("sets-foreign");
    let mine = dir.join("mine");
    fs::create_dir_all(&mine).unwrap();
    fs::write(mine.join("notes.txt"), b"my notes").unwrap();
    let refused = run_in(&dir, &quick_run(mine.to_str().unwrap(), &[]));
    assert_code(&refused, 2);
    assert!(
        refused.stderr.contains("did not write"),
        "{}",
        refused.stderr
    );
    assert_eq!(names(&mine), ["notes.txt"]);
    assert_eq!(names(&dir), ["mine"]);
}

#[test]
fn a_full_disk_leaves_the_previous_set_and_nothing_temporary() {
    let dir = scratch("sets-full");
    let out = dir.join("out");
    let out_arg = out.to_str().unwrap();
    assert_code(&run_in(&dir, &quick_run(out_arg, &["--no-plots"])), 0);
    let before = snapshot(&out);
    // Files above 100 or 200 kB (512- or 1024-byte blocks) cannot be written (EFBIG):
    // the 35 kB of results can, some figures and the page (230 kB) cannot, which used
    // to leave the new results beside the old page.
    let full: common::Run = Command::new("sh")
        .args(["-c", "trap '' XFSZ; ulimit -f 200; exec \"$0\" \"$@\"", BIN])
        .args(["run", "quick_return", "--t-end", "0.05"])
        .args(["--out", out_arg])
        .current_dir(&dir)
        .output()
        .unwrap()
        .into();
    assert_code(&full, 1);
    assert!(full.stderr.contains("File too large"), "{}", full.stderr);
    assert_same(&snapshot(&out), &before);
    assert_eq!(names(&dir), ["out"]);
}

#[test]
fn an_unwritable_folder_changes_nothing() {
    let dir = scratch("sets-unwritable");
    // A parent that is a file: no one, root included, can create a folder in it.
    fs::write(dir.join("file"), b"x").unwrap();
    let failed = run_in(&dir, &quick_run("file/out", &["--no-plots"]));
    assert_code(&failed, 1);
    assert!(failed.stderr.contains("file"), "{}", failed.stderr);
    assert_eq!(names(&dir), ["file"]);
}

#[cfg(unix)]
#[test]
fn a_read_only_parent_changes_nothing() {
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } == 0 {
        return; // root writes anywhere; the test above covers it
    }
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("sets-read-only");
    let parent = dir.join("parent");
    fs::create_dir_all(&parent).unwrap();
    fs::set_permissions(&parent, fs::Permissions::from_mode(0o555)).unwrap();
    let failed = run_in(
        &dir,
        &quick_run(parent.join("out").to_str().unwrap(), &["--no-plots"]),
    );
    fs::set_permissions(&parent, fs::Permissions::from_mode(0o755)).unwrap();
    assert_code(&failed, 1);
    assert!(names(&parent).is_empty());
}

/// Starts a flagship run to `t_end` into `out` (in `dir`) and waits until it integrates
/// (its staging folder exists); returns the child and its staging folder.
#[cfg(unix)]
fn start_run(dir: &Path, out: &Path, t_end: &str, plots: bool) -> (Child, PathBuf) {
    let mut command = Command::new(BIN);
    command.args(["run", "quick_return", "--t-end", t_end, "--yes", "--out"]);
    command.arg(out);
    if !plots {
        command.arg("--no-plots");
    }
    let child = command
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let staging = dir.join(format!(".out.staging-{}", child.id()));
    wait_for(|| staging.exists(), "the staging folder");
    (child, staging)
}

/// Polls `ready` every millisecond, for at most 30 s.
fn wait_for(ready: impl Fn() -> bool, what: &str) {
    let started = Instant::now();
    while !ready() {
        assert!(started.elapsed() < Duration::from_secs(30), "no {what}");
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Whether `dir` holds a file whose name satisfies `pick`.
fn holds(dir: &Path, pick: impl Fn(&str) -> bool) -> bool {
    fs::read_dir(dir).is_ok_and(|entries| {
        entries
            .flatten()
            .any(|e| pick(&e.file_name().to_string_lossy()))
    })
}

#[cfg(unix)]
fn signal(child: &Child, signal: i32) {
    let pid = libc::pid_t::try_from(child.id()).unwrap();
    // SAFETY: sends a signal to our own child.
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
}

/// A previous complete set in `dir/out`, and its snapshot.
fn previous_set(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let out = dir.join("out");
    assert_code(
        &run_in(dir, &quick_run(out.to_str().unwrap(), &["--no-plots"])),
        0,
    );
    snapshot(&out)
}

#[cfg(unix)]
fn interrupted_once(name: &str, sig: i32) {
    let dir = scratch(name);
    let before = previous_set(&dir);
    let out = dir.join("out");
    let (child, _) = start_run(&dir, &out, "5000", false);
    std::thread::sleep(Duration::from_millis(700));
    signal(&child, sig);
    let run: common::Run = child.wait_with_output().unwrap().into();
    assert_code(&run, 1);
    assert!(
        run.stderr.contains("interrupted after the sample at t = "),
        "{}",
        run.stderr
    );
    assert!(
        run.stdout.starts_with("PARTIAL RUN   interrupted"),
        "{}",
        run.stdout
    );
    assert_same(&snapshot(&out), &before);
    assert_eq!(names(&dir), ["out", "out.partial"]);
    let csv = Csv::read(&dir.join("out.partial/quick_return.csv"));
    assert!(csv.rows.len() > 1);
}

#[cfg(unix)]
#[test]
fn sigint_stops_the_run_and_writes_a_partial_set() {
    interrupted_once("sets-sigint", libc::SIGINT);
}

#[cfg(unix)]
#[test]
fn sigterm_is_handled_like_sigint() {
    interrupted_once("sets-sigterm", libc::SIGTERM);
}

#[cfg(unix)]
#[test]
fn a_second_signal_while_writing_exits_at_once_leaving_nothing_temporary() {
    let dir = scratch("sets-two-signals");
    let before = previous_set(&dir);
    let out = dir.join("out");
    let (child, staging) = start_run(&dir, &out, "5000", false);
    // Long enough that the results take a while to write after the first signal.
    std::thread::sleep(Duration::from_millis(2500));
    signal(&child, libc::SIGINT);
    // The second signal while the results file is being written (its temporary file
    // exists): the case that left a 108 MB temporary file.
    wait_for(
        || {
            holds(&staging, |n| {
                n.starts_with(".quick_return.csv.") && n.ends_with(".tmp")
            })
        },
        "temporary results file",
    );
    signal(&child, libc::SIGTERM);
    let run: common::Run = child.wait_with_output().unwrap().into();
    assert_code(&run, 130);
    assert_same(&snapshot(&out), &before);
    assert_eq!(names(&dir), ["out"], "no staging folder, no partial set");
}

#[cfg(unix)]
#[test]
fn a_signal_while_drawing_stops_it_and_writes_a_partial_set() {
    let dir = scratch("sets-drawing");
    let before = previous_set(&dir);
    let out = dir.join("out");
    let (child, staging) = start_run(&dir, &out, "60", true);
    // The first figure file (or its temporary file) appears once drawing has begun.
    wait_for(
        || holds(&staging, |n| n.ends_with(".png") || n.ends_with(".svg")),
        "figure",
    );
    signal(&child, libc::SIGINT);
    let run: common::Run = child.wait_with_output().unwrap().into();
    assert_code(&run, 1);
    assert!(
        run.stderr
            .contains("interrupted while writing the results and drawing the figures"),
        "{}",
        run.stderr
    );
    assert_same(&snapshot(&out), &before);
    assert_eq!(names(&dir), ["out", "out.partial"]);
    let partial = dir.join("out.partial");
    let csv = Csv::read(&partial.join("quick_return.csv"));
    assert_eq!(csv.rows.len(), 60_001, "the data are whole, the set is not");
    let index = fs::read_to_string(partial.join("index.html")).unwrap();
    assert!(index.contains("PARTIAL RUN"));
    let figures = names(&partial)
        .iter()
        .filter(|n| n.ends_with(".png"))
        .count();
    assert!(figures < 19, "{figures} figures drawn after the signal");
}

#[test]
fn long_runs_draw_small_decimated_figures_and_pages() {
    let dir = scratch("sets-decimated");
    // 1,000,001 samples of the forced Duffing oscillator.
    fs::write(
        dir.join("long.yaml"),
        "model: duffing\ntime:\n  end: 100\noutput:\n  interval: 1.0e-4\n  record: [x]\n\
         plots: [x]\n",
    )
    .unwrap();
    let started = Instant::now();
    let run = run_in(&dir, &["run", "long.yaml", "--out", "out"]);
    assert_code(&run, 0);
    let elapsed = started.elapsed();
    let out = dir.join("out");
    let csv = fs::read_to_string(out.join("duffing.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 1_000_001, "the CSV stays whole");
    let svg = fs::read_to_string(out.join("x.svg")).unwrap();
    let index = fs::metadata(out.join("index.html")).unwrap().len();
    assert!(svg.len() < 1_000_000, "{} bytes of SVG", svg.len());
    assert!(index < 2_000_000, "{index} bytes of index.html");
    assert!(
        svg.contains("of 1,000,001 points (min/max per pixel column)"),
        "the figure says it was decimated"
    );
    eprintln!(
        "1,000,001 samples: {} B of SVG, {index} B of index.html, {:.1} s in all",
        svg.len(),
        elapsed.as_secs_f64()
    );
}

#[test]
fn the_size_guard_refuses_a_huge_run_without_yes() {
    let dir = scratch("sets-guard");
    let refused = run_in(
        &dir,
        &["run", "quick_return", "--t-end", "9000", "--out", "out"],
    );
    assert_code(&refused, 2);
    assert!(refused.stderr.contains("--yes"), "{}", refused.stderr);
    assert!(
        refused
            .stderr
            .contains("would write up to 12.1 GB of results (9,000,001 rows × 56 columns)"),
        "{}",
        refused.stderr
    );
    assert!(names(&dir).is_empty(), "nothing written");

    let sweep = "model: oscillator\nsweep:\n  parameters:\n    - name: k\n      from: 1\n      \
                 to: 100\n      steps: 1001\n  peaks: [x]\n";
    fs::write(dir.join("sweep.yaml"), sweep).unwrap();
    let refused = run_in(&dir, &["run", "sweep.yaml", "--out", "out"]);
    assert_code(&refused, 2);
    assert!(
        refused.stderr.contains(
            "this sweep has 1,001 runs of 1,001 samples each, 1,002,001 samples to \
             integrate in all, about "
        ),
        "{}",
        refused.stderr
    );
    assert!(refused.stderr.contains(" threads"), "{}", refused.stderr);
    assert_eq!(names(&dir), ["sweep.yaml"]);
}
