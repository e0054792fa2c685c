//! End-to-end tests of what the `models` program accepts and what its outputs claim:
//! summaries computed from the run's own parameters, sweeps and scenarios validated
//! whole (every error, in line order), the run flags, stiff-model advice, figures that
//! draw something, and default runs that show each model's behaviour.

mod common;

use std::fs;
use std::path::Path;

use common::{assert_success, files, run, run_in, scratch, Csv};

/// The `rigid links` column of a summary row starting with `quantity`.
fn rigid_column(stdout: &str, quantity: &str) -> String {
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with(quantity))
        .unwrap_or_else(|| panic!("no row {quantity:?} in:\n{stdout}"));
    // `  quantity (26) measured (16) rigid (12) detail`
    line.chars().skip(2 + 27 + 17).take(12).collect::<String>()
}

/// The reference column is the rigid mechanism with the run's own geometry and drive
/// speed. For a crank shaper (crank r < d) the rocker's extremes are where O3–A is
/// tangent to the crank circle, at α = asin(r/d) from the vertical: stroke 2 L3 r/d,
/// ratio (π + 2α)/(π − 2α); the period is 2π/w_drive.
#[test]
fn the_rigid_reference_follows_the_parameters() {
    let dir = scratch("rigid_reference");
    let out = run(&[
        "run",
        "quick_return",
        "--set",
        "d=0.3",
        "--set",
        "w_drive=4",
        "--t-end",
        "0.2",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    let (r, d, l3, w) = (0.2f64, 0.3f64, 0.7f64, 4.0f64);
    let alpha = (r / d).asin();
    let pi = core::f64::consts::PI;
    let expected = [
        ("output-slider stroke", format!("{:.5} m", 2.0 * l3 * r / d)),
        (
            "quick-return time ratio",
            format!("{:.5}", (pi + 2.0 * alpha) / (pi - 2.0 * alpha)),
        ),
        ("period", format!("{:.5} s", 2.0 * pi / w)),
    ];
    for (quantity, value) in expected {
        assert_eq!(
            rigid_column(&out.stdout, quantity).trim(),
            value,
            "{quantity}:\n{}",
            out.stdout
        );
    }

    // An undriven crank has no cycle: no rigid value, and the summary says why.
    let out = run(&[
        "run",
        "quick_return",
        "--set",
        "w_drive=0",
        "--t-end",
        "0.05",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    for quantity in ["output-slider stroke", "quick-return time ratio", "period"] {
        assert_eq!(rigid_column(&out.stdout, quantity).trim(), "n/a");
    }
    assert!(
        out.stdout
            .contains("(rigid links n/a: the crank is not driven (w_drive = 0 rad/s))"),
        "{}",
        out.stdout
    );
}

/// `--set` of a parameter the sweep varies used to be ignored without a word.
#[test]
fn set_of_a_swept_parameter_is_refused() {
    let dir = scratch("set_swept");
    let out_dir = dir.join("out");
    let scenario = common::scenarios_dir().join("quick_return_speed_sweep.yaml");
    let out = run(&[
        "run",
        scenario.to_str().unwrap(),
        "--set",
        "w_drive=3",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
    assert_eq!(
        out.stderr.trim(),
        "error: --set w_drive=3: `w_drive` is swept by the scenario (sweep.parameters[0]), \
         so a value set here would be ignored; drop the --set, or the sweep's axis"
    );
    assert!(!out_dir.exists());
}

/// The flags the messages tell users to set exist, and do what the scenario keys do.
#[test]
fn run_flags_set_the_step_budget_span_and_sampling() {
    let dir = scratch("run_flags");
    let out = run(&[
        "run",
        "oscillator",
        "--solver",
        "rk4",
        "--step",
        "1e-3",
        "--t-start",
        "0.5",
        "--t-end",
        "1",
        "--interval",
        "0.1",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    assert!(out.stdout.contains("rk4 (step 1e-3 s)"), "{}", out.stdout);
    assert!(out.stdout.contains("steps          500 "), "{}", out.stdout);
    let csv = Csv::read(&dir.join("oscillator.csv"));
    let t = csv.column("t");
    assert_eq!(t.len(), 6, "{t:?}");
    for (k, t) in t.iter().enumerate() {
        assert!((t - (0.5 + 0.1 * k as f64)).abs() < 1e-12, "{t}");
    }

    let out = run(&[
        "run",
        "oscillator",
        "--max-steps",
        "3",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    assert!(
        out.stderr.contains("the budget of 3 steps was used up"),
        "{}",
        out.stderr
    );

    // The same checks as the scenario's keys, placed at the flags, all reported.
    let out = run(&[
        "run",
        "oscillator",
        "--step",
        "0.001",
        "--interval",
        "-1",
        "--max-steps",
        "0",
        "--t-start",
        "nan",
        "--out",
        dir.join("never").to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
    let lines: Vec<&str> = out.stderr.lines().collect();
    assert_eq!(
        lines,
        [
            "error: --t-start NaN: the start time must be a finite number of seconds, found NaN",
            "error: --step 0.001: `step` applies only to the fixed-step solvers rk4 and \
             dopri5-fixed, not radau5",
            "error: --max-steps 0: max_steps must be an integer > 0, found 0",
        ],
        "{}",
        out.stderr
    );
    assert!(!dir.join("never").exists());
}

/// A plot of something not recorded used to draw nothing and exit 0 with an empty
/// "Figures" heading.
#[test]
fn a_plot_of_something_not_recorded_is_refused() {
    let dir = scratch("plot_not_recorded");
    fs::write(
        dir.join("s.yaml"),
        "model: oscillator\noutput:\n  record: [x]\nplots: [speed]\n",
    )
    .unwrap();
    let out = run_in(&dir, &["run", "s.yaml", "--out", "out"]);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
    assert_eq!(
        out.stderr.trim(),
        "error: s.yaml:4:1: figure `speed` would draw nothing: `speed` is not recorded; add \
         it to `output.record`"
    );
    assert_eq!(files(&dir), ["s.yaml"]);
}

/// The summary ends by saying where the run's page is, for a run and for a sweep.
#[test]
fn the_summary_says_where_index_html_is() {
    let dir = scratch("report_line");
    let out = run(&[
        "run",
        "oscillator",
        "--t-end",
        "0.2",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    let index = dir.join("index.html");
    assert!(index.is_file());
    assert_eq!(
        out.stdout.lines().last(),
        Some(format!("report         {}", index.display()).as_str()),
        "{}",
        out.stdout
    );

    let sweep_dir = dir.join("sweep");
    fs::write(
        dir.join("sweep.yaml"),
        "model: oscillator\ntime: {end: 0.2}\nplots: none\nsweep:\n  parameters:\n    - name: k\n      values: [50, 100]\n  peaks: [x]\n",
    )
    .unwrap();
    let out = run_in(&dir, &["run", "sweep.yaml", "--out", "sweep"]);
    assert_success(&out);
    assert!(sweep_dir.join("index.html").is_file());
    assert_eq!(
        out.stdout.lines().last(),
        Some(
            format!(
                "report         {}",
                Path::new("sweep").join("index.html").display()
            )
            .as_str()
        ),
        "{}",
        out.stdout
    );
}

/// Whether a quick return column may stay constant: the mechanism moves in the X0-Y0
/// plane, so the z components of positions, momenta and forces (not the rotation about
/// z: `h1_z`, `Tc_z`), the x and y components
/// of the crank's angular momentum and of the drive torque, and the orientation entries
/// that couple z with x and y stay as they start.
fn out_of_plane(column: &str) -> bool {
    let orientation_z = column.len() == 5
        && (column.starts_with("R1_") || column.starts_with("R4_"))
        && (column.contains('3'));
    let rotation_about_z = ["h1_z", "Tc_z"].contains(&column);
    (column.ends_with("_z") && !rotation_about_z)
        || ["h1_x", "h1_y", "Tc_x", "Tc_y"].contains(&column)
        || orientation_z
}

/// `models run oscillator` used to start at equilibrium (every figure flat) and `models
/// run dc_servo` with 0 V in (all zeros): every model's default run now shows its
/// behaviour, every state and output moving (but the planar mechanisms' out-of-plane
/// columns, the rigid guide's, and the crank's angular momentum where a flow source
/// turns it).
#[test]
fn every_default_run_shows_its_behaviour() {
    let dir = scratch("default_runs");
    let list = run(&["list"]);
    assert_success(&list);
    let names: Vec<&str> = list
        .stdout
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert_eq!(names.len(), 18, "{}", list.stdout);
    for name in names {
        let out_dir = dir.join(name);
        let out = run(&[
            "run",
            name,
            "--no-plots",
            "--out",
            out_dir.to_str().unwrap(),
        ]);
        assert_success(&out);
        let quick_return = name.starts_with("quick_return");
        let file = if quick_return {
            "quick_return.csv".to_owned()
        } else {
            format!("{name}.csv")
        };
        let csv = Csv::read(&out_dir.join(file));
        assert!(csv.rows.len() > 100, "{name}: {} rows", csv.rows.len());
        for column in &csv.header[1..] {
            let values = csv.column(column);
            let (lo, hi) = values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            let moves = hi - lo > 1e-9 * hi.abs().max(lo.abs()).max(1e-12);
            // With rigid joints the output slider stays on its guide (y = 0), and the
            // flow-driven crank turns at the drive's constant speed.
            let rigid = name.starts_with("quick_return_rigid")
                && ["r_C5_y", "p5_y"].contains(&column.as_str());
            let prescribed = name == "quick_return_rigid" && column == "h1_z";
            // Modes the default run has no occasion to switch: the end stop's mass is
            // always pulled off the stop (never rests), the clutch's engine shaft stays
            // the faster until it locks.
            let unswitched = [
                ("end_stop", "wall.resting"),
                ("clutch", "clutch.plates.forward"),
            ]
            .contains(&(name, column.as_str()));
            let exception =
                unswitched || quick_return && (out_of_plane(column) || rigid || prescribed);
            assert!(
                moves != exception,
                "{name}: `{column}` ranges over [{lo}, {hi}] ({})",
                if exception {
                    "out of plane, expected constant"
                } else {
                    "constant in the default run"
                }
            );
        }
    }
}

/// `--solver rk4` on the stiff flagship said only "evaluated to -inf".
#[test]
fn rk4_on_the_stiff_flagship_says_it_is_stiff() {
    let dir = scratch("rk4_stiff");
    let out = run(&[
        "run",
        "quick_return",
        "--solver",
        "rk4",
        "--t-end",
        "0.2",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    assert!(
        out.stderr.contains("The model is probably stiff")
            && out.stderr.contains("use a stiff solver, radau5 or rodas4")
            && out.stderr.contains("(the step was 0.001 s)"),
        "{}",
        out.stderr
    );
}

/// Numbers in messages are written as a user would write them: `1e300`, not a
/// 301-digit integer (Rust's `{}` for a large `f64`).
#[test]
fn large_numbers_in_messages_are_written_short() {
    let dir = scratch("large_numbers");
    let out_dir = dir.join("out");
    let out = run(&[
        "run",
        "oscillator",
        "--t-end",
        "1e300",
        "--interval",
        "1e-300",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
    assert_eq!(
        out.stderr.trim(),
        "error: --interval 1e-300: a sampling interval of 1e-300 s over 1e300 s gives more \
         than 10000001 samples; choose a larger interval"
    );
    assert!(!out_dir.exists());
}
