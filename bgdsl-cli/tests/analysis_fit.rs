//! `models fit` in-process, on a catalogue of this test's own: a DC motor (armature
//! resistance and inductance, torque constant, rotor inertia and viscous friction) on
//! a 12 V step.
//!
//! - The measurements are the true motor's current and speed at 301 times over 0.3 s
//!   (Radau5 at rtol 1e-11), with seeded Gaussian noise ten times larger, relative to
//!   the column's RMS, on the current (5 %) than on the speed (0.5 %); the fit starts
//!   from a resistance 1.5 times and a friction 3 times the truth. Each true value must
//!   lie inside its reported 95 % interval, the interval must be narrower than the
//!   starting error, the cost must fall tenfold, and each column's estimated σ and
//!   residual RMS must equal the noise's σ to 15 % (the sample standard deviation of
//!   301 normal draws is within 15 % of σ with probability far above 0.999). The seed
//!   is fixed (2024); over seeds 1 to 40 both intervals held the truth in 37 runs
//!   (two 95 % intervals: about 90 %; one variance pooled over the columns, the method
//!   before session 25, held both in 33). The coverage itself is checked over 200
//!   seeds in `bgdsl-analysis/tests/fit_recovery.rs`.
//! - With `--sigma` (through the program's own command line parser) the σ given are
//!   used as they are, the intervals use the normal quantile, and the χ² check says
//!   "consistent" for the true σ and "larger" for a σ three times too small.
//! - `fitted.yaml` is a scenario `models run` accepts, and its run's final speed
//!   matches the measured one to 3 σ.
//! - Bad input is refused before any work, with a message naming what is wrong, and
//!   leaves a previous results folder as it was.

mod analysis_common;
mod common;

use std::fs;
use std::path::Path;
use std::sync::LazyLock;

use analysis_common::yaml;
use common::Scratch;

use bgdsl_cli::cli::analysis::fit::FitArgs;
use bgdsl_cli::cli::analysis::ModelArgs;
use bgdsl_cli::cli::{execute, Cli, Command, RunArgs};
use bgdsl_cli::Catalogue;
use bgdsl_runtime::{bond_graph, Model, Radau5Options, Simulation, Solver};

bond_graph! {
    /// A permanent-magnet DC motor with an inertial, viscously damped rotor on a
    /// constant supply voltage.
    pub model Motor {
        /// supply voltage
        param voltage = 12.0 in "V";
        /// armature resistance
        param resistance = 1.0 in "Ω";
        /// armature inductance
        param inductance = 0.5e-3 in "H";
        /// torque constant
        param torque_constant = 0.05 in "N·m/A";
        /// rotor inertia
        param inertia = 1.0e-4 in "kg·m²";
        /// rotor viscous friction
        param friction = 1.0e-4 in "N·m·s/rad";
        /// a list parameter, to be refused as a whole
        param spare: [f64; 2] = [1.0, 2.0] in "1";
        Se supply = voltage;
        1 armature;
        R winding = resistance;
        I coil = inductance, p in "Wb";
        GY motor = torque_constant;
        1 shaft;
        I rotor = inertia, p in "N·m·s";
        R bearing = friction;
        supply -> armature -> { winding, coil };
        armature -> motor -> shaft -> { rotor, bearing };
        /// Armature current, A.
        output current = armature.f in "A";
        /// Rotor speed, rad/s.
        output speed = shaft.f in "rad/s";
    }
}

static CATALOGUE: LazyLock<Catalogue> = LazyLock::new(|| bgdsl_cli::catalogue![Motor]);

/// Standard normal draws: SplitMix64 (Steele, Lea & Flood 2014) into the Box–Muller
/// transform; reproducible without a dependency.
struct Normal(u64);

impl Normal {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn draw(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (core::f64::consts::TAU * v).cos()
    }
}

/// The noise's standard deviation relative to each column's root mean square: ten
/// times larger on the current than on the speed (the fit estimates a variance per
/// column).
const RELATIVE_NOISE: [f64; 2] = [0.05, 0.005];

/// The true motor's current and speed with noise, as a measurements CSV, and each
/// column's noise standard deviation.
fn measurements() -> (String, [f64; 2]) {
    let motor = Motor::default();
    let times: Vec<f64> = (0..=300).map(|k| 1e-3 * k as f64).collect();
    let mut x0 = vec![0.0; Motor::N_STATES];
    motor.initial_state(&mut x0);
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-11,
        atol: 1e-13,
        ..Default::default()
    });
    let mut sim = Simulation::new(&motor, solver).unwrap();
    let mut rows = Vec::new();
    sim.run(0.0, &x0, &times, &mut |t: f64, _x: &[f64], y: &[f64]| {
        rows.push((t, [y[0], y[1]]))
    })
    .unwrap();
    let rms =
        |c: usize| (rows.iter().map(|r| r.1[c] * r.1[c]).sum::<f64>() / rows.len() as f64).sqrt();
    let sigma = [RELATIVE_NOISE[0] * rms(0), RELATIVE_NOISE[1] * rms(1)];
    let mut noise = Normal(2024);
    let mut text = String::from("t,current,speed\n");
    for (t, [current, speed]) in rows {
        let current = current + sigma[0] * noise.draw();
        let speed = speed + sigma[1] * noise.draw();
        text.push_str(&format!("{t},{current},{speed}\n"));
    }
    (text, sigma)
}

fn args(data: &Path, out: &Path) -> FitArgs {
    FitArgs {
        model: ModelArgs {
            target: "motor".to_owned(),
            out: Some(out.to_path_buf()),
            set: vec!["resistance=1.5".to_owned(), "friction=3e-4".to_owned()],
            no_plots: true,
            ..ModelArgs::default()
        },
        data: data.to_path_buf(),
        fit: vec!["resistance,friction".to_owned()],
        bound: vec!["resistance=0:10".to_owned(), "friction=0:1".to_owned()],
        ..FitArgs::default()
    }
}

fn fit(args: FitArgs) -> Result<(), bgdsl_cli::cli::Failure> {
    execute(
        Cli {
            command: Some(Command::Fit(Box::new(args))),
        },
        &CATALOGUE,
    )
}

#[test]
fn resistance_and_friction_are_recovered_and_the_fitted_scenario_runs() {
    let scratch = Scratch::new("fit-recover");
    let data = scratch.join("step.csv");
    let (csv, sigma) = measurements();
    fs::write(&data, csv).unwrap();
    let out = scratch.join("fit");
    let mut a = args(&data, &out);
    a.model.no_plots = false;
    fit(a).unwrap();
    for name in ["fit_current.svg", "fit_speed.png", "index.html", "run.yaml"] {
        assert!(out.join(name).is_file(), "{name} missing");
    }

    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("fit.json")).unwrap()).unwrap();
    assert_eq!(summary["converged"], true, "{summary:#}");
    let truth = [("resistance", 1.0), ("friction", 1.0e-4)];
    let parameters = summary["parameters"].as_array().unwrap();
    for (p, (name, value)) in parameters.iter().zip(truth) {
        assert_eq!(p["name"], name);
        let low = p["interval_95"][0].as_f64().unwrap();
        let high = p["interval_95"][1].as_f64().unwrap();
        assert!(
            low <= value && value <= high,
            "{name}: {value} not in [{low}, {high}]"
        );
        let initial = p["initial"].as_f64().unwrap();
        assert!(
            high - low < (initial - value).abs(),
            "{name}: interval not informative"
        );
    }
    let correlation = &summary["correlation"];
    assert_eq!(correlation[0][0].as_f64().unwrap(), 1.0);
    let r = correlation[0][1].as_f64().unwrap();
    assert!(r.abs() < 1.0 && r == correlation[1][0].as_f64().unwrap());
    let before = summary["cost_before"].as_f64().unwrap();
    let after = summary["cost_after"].as_f64().unwrap();
    assert!(after < 0.1 * before, "cost {before} → {after}");
    // Each column's σ estimated: it and the residual RMS equal the noise's σ.
    for (column, sigma) in summary["columns"].as_array().unwrap().iter().zip(sigma) {
        assert_eq!(column["sigma_given"], false, "{column}");
        for key in ["sigma", "rms"] {
            let value = column[key].as_f64().unwrap();
            assert!(
                (value / sigma - 1.0).abs() < 0.15,
                "{}: {key} {value} vs σ {sigma}",
                column["column"]
            );
        }
        let weight = column["weight"].as_f64().unwrap();
        let estimated = column["sigma"].as_f64().unwrap();
        assert!((weight * estimated * estimated - 1.0).abs() < 1e-12);
    }
    assert_eq!(summary["columns"][0]["unit"], "A");
    assert!(summary["chi_square"].is_null(), "no σ given: no χ² check");
    assert_eq!(summary["noise"], "per column");
    assert_eq!(summary["weights_settled"], true);
    // fit.yaml says the same as fit.json.
    let yaml: serde_yaml::Value =
        serde_yaml::from_str(&fs::read_to_string(out.join("fit.yaml")).unwrap()).unwrap();
    // (serde_json's default parser may miss the nearest double by an ulp.)
    let from_yaml = yaml["parameters"][0]["estimate"].as_f64().unwrap();
    let from_json = parameters[0]["estimate"].as_f64().unwrap();
    assert!((from_yaml - from_json).abs() <= 1e-15 * from_json.abs());

    // fitted.csv: measured, model and residual per column; the residuals' RMS as said.
    let text = fs::read_to_string(out.join("fitted.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,current_measured,current_model,current_residual,speed_measured,speed_model,speed_residual"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 301);
    for row in &rows {
        assert!((row[1] - row[2] - row[3]).abs() <= 1e-12 * row[1].abs().max(1.0));
    }

    // The fitted scenario runs, and its run ends at the measured speed (to 3 σ).
    let scenario = out.join("fitted.yaml");
    let run_out = scratch.join("rerun");
    execute(
        Cli {
            command: Some(Command::Run(Box::new(RunArgs {
                model: ModelArgs {
                    target: scenario.to_string_lossy().into_owned(),
                    out: Some(run_out.clone()),
                    no_plots: true,
                    ..ModelArgs::default()
                },
                ..RunArgs::default()
            }))),
        },
        &CATALOGUE,
    )
    .unwrap();
    let run = fs::read_to_string(run_out.join("motor.csv")).unwrap();
    let header: Vec<&str> = run.lines().next().unwrap().split(',').collect();
    let speed = header.iter().position(|h| *h == "speed").unwrap();
    let last: Vec<f64> = run
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert!((last[0] - 0.3).abs() < 1e-12, "the measured span");
    let measured_end = rows[300][4];
    assert!(
        (last[speed] - measured_end).abs() < 3.0 * sigma[1],
        "{} vs {measured_end}",
        last[speed]
    );
}

/// The fit of `models fit motor --data DATA --fit resistance,friction --sigma SIGMA
/// --out OUT`, through the program's own command line parser; returns `fit.json`.
fn fit_with_sigma(data: &Path, out: &Path, sigma: &str) -> serde_yaml::Value {
    let (data, out) = (data.to_str().unwrap(), out.to_str().unwrap());
    let args = [
        "fit",
        "motor",
        "--data",
        data,
        "--fit",
        "resistance,friction",
        "--set",
        "resistance=1.5",
        "--set",
        "friction=3e-4",
        "--sigma",
        sigma,
        "--no-plots",
        "--out",
        out,
    ];
    analysis_common::run(&CATALOGUE, &args).unwrap();
    yaml(&Path::new(out).join("fit.json"))
}

#[test]
fn given_sigma_is_used_as_it_is_and_checked_by_chi_square() {
    let scratch = Scratch::new("fit-sigma");
    let data = scratch.join("step.csv");
    let (csv, sigma) = measurements();
    fs::write(&data, csv).unwrap();

    // The true σ: used as given, the intervals ± 1.96 standard errors, χ² consistent.
    let flag = format!("current={},speed={}", sigma[0], sigma[1]);
    let given = fit_with_sigma(&data, &scratch.join("true"), &flag);
    for (column, s) in given["columns"].as_sequence().unwrap().iter().zip(sigma) {
        assert_eq!(column["sigma_given"].as_bool(), Some(true), "{column:?}");
        assert_eq!(column["sigma"].as_f64(), Some(s));
    }
    let truth = [1.0, 1.0e-4];
    for (p, value) in given["parameters"].as_sequence().unwrap().iter().zip(truth) {
        assert!(p["degrees_of_freedom"].is_null(), "{p:?}");
        assert_eq!(p["t_quantile"].as_f64(), Some(1.959_963_984_540_054));
        let interval = analysis_common::numbers(&p["interval_95"]);
        assert!(interval[0] <= value && value <= interval[1], "{p:?}");
    }
    let chi = &given["chi_square"];
    let p_value = chi["p_value"].as_f64().unwrap();
    assert!((0.01..=0.99).contains(&p_value), "{chi:?}");
    assert!(chi["verdict"].as_str().unwrap().starts_with("consistent"));
    assert_eq!(chi["degrees_of_freedom"].as_f64(), Some(2.0 * 301.0 - 2.0));

    // The current's σ three times too small: χ² says the residuals are larger.
    let flag = format!("current={},speed={}", sigma[0] / 3.0, sigma[1]);
    let small = fit_with_sigma(&data, &scratch.join("small"), &flag);
    let chi = &small["chi_square"];
    assert!(chi["p_value"].as_f64().unwrap() < 1e-6, "{chi:?}");
    // About (9 ν_current + ν_speed)/(ν_current + ν_speed) ≈ 5.
    assert!(chi["reduced"].as_f64().unwrap() > 3.0, "{chi:?}");
    assert!(chi["verdict"].as_str().unwrap().starts_with("larger"));
}

/// Runs the fit with `edit` applied to the arguments and `csv` as the data; returns
/// the error message.
fn refused(scratch: &Path, csv: &str, edit: impl FnOnce(&mut FitArgs)) -> String {
    let data = scratch.join("bad.csv");
    fs::write(&data, csv).unwrap();
    let mut a = args(&data, &scratch.join("fit"));
    edit(&mut a);
    fit(a).unwrap_err().to_string()
}

#[test]
fn bad_data_and_bad_parameters_are_refused_and_leave_the_previous_set() {
    let scratch = Scratch::new("fit-refused");
    let good = "t,current,speed\n0,0,0\n0.1,5,100\n0.2,4,150\n0.3,3,180\n";
    // A previous set in the output folder, from a fit that succeeds.
    let data = scratch.join("good.csv");
    fs::write(&data, measurements().0).unwrap();
    let out = scratch.join("fit");
    fit(args(&data, &out)).unwrap();
    let previous = fs::read_to_string(out.join("fit.json")).unwrap();

    let cases: Vec<(String, &str)> = vec![
        (
            refused(
                &scratch,
                "t,current,torque\n0,0,0\n0.1,1,1\n0.2,1,1\n",
                |_| {},
            ),
            "`torque` is not an output of the model",
        ),
        (
            refused(&scratch, "t,current\n0,0\n0.2,1\n0.1,2\n", |_| {}),
            "line 4",
        ),
        (
            refused(&scratch, "t,current\n0,0\n0.1,inf\n0.2,2\n", |_| {}),
            "not a finite number",
        ),
        (
            refused(
                &scratch,
                "t,current,speed\n0,,0\n0.1,nan,1\n0.2,,2\n",
                |_| {},
            ),
            "`current` has no measured value",
        ),
        (
            refused(&scratch, good, |a| a.fit = vec!["resistanse".to_owned()]),
            "no parameter `resistanse`",
        ),
        (
            refused(&scratch, good, |a| a.fit = vec!["spare".to_owned()]),
            "spare[0]",
        ),
        (
            refused(&scratch, good, |a| {
                a.bound = vec!["resistance=2:1".to_owned()]
            }),
            "empty",
        ),
        (
            refused(&scratch, good, |a| a.bound = vec!["inertia=0:1".to_owned()]),
            "`inertia` is not fitted",
        ),
        (
            refused(&scratch, good, |a| a.columns = vec!["voltage".to_owned()]),
            "no column `voltage`",
        ),
        (refused(&scratch, good, |a| a.fit = Vec::new()), "--fit"),
        (
            refused(&scratch, good, |a| a.sigma = vec!["voltage=1".to_owned()]),
            "no column `voltage`",
        ),
        (
            refused(&scratch, good, |a| {
                a.sigma = vec!["current=-0.1".to_owned()]
            }),
            "not a positive number",
        ),
        (
            refused(&scratch, good, |a| a.sigma = vec!["current".to_owned()]),
            "give C=SIGMA",
        ),
        (
            refused(&scratch, good, |a| {
                a.sigma = vec!["current=1,current=2".to_owned()]
            }),
            "given twice",
        ),
        (
            refused(&scratch, good, |a| {
                a.columns = vec!["current".to_owned()];
                a.sigma = vec!["speed=1".to_owned()];
            }),
            "no column `speed`",
        ),
    ];
    for (message, expected) in cases {
        assert!(message.contains(expected), "`{expected}` not in: {message}");
    }
    assert_eq!(fs::read_to_string(out.join("fit.json")).unwrap(), previous);
    let leftovers: Vec<String> = fs::read_dir(&*scratch)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}
