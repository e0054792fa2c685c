//! The FMUs checked by FMPy (PyPI), an FMI importer written by others.
//!
//! The test writes the FMUs of the mass-spring-damper, the DC motor, the DC servo (the
//! motor with its voltage and load torque as FMU inputs), the quick return
//! mechanism and the Butterworth filter (its source voltage an FMU input) with this crate's shared library (the `cdylib` that `cargo test`
//! builds beside the test, `target/<profile>/libbgdsl_fmi.so`; `BGDSL_FMI_LIBRARY`
//! overrides), then runs `tests/fmpy_check.py`, which
//!
//! 1. validates every FMU with `fmpy.validation.validate_fmu` (no problem allowed);
//! 2. simulates them with parameters (and the servo's inputs, and the oscillator's
//!    initial spring deflection) set through `start_values` (so through `fmi2SetReal`
//!    before initialisation): the oscillator,
//!    the DC motor, the servo and the filter as Model Exchange (FMPy's CVode integrates)
//!    and as Co-Simulation (our Radau5 integrates inside the FMU), the quick return as
//!    Co-Simulation, every 1 ms (the filter every 10 ms);
//! 3. calls one FMU wrongly through FMPy's own bindings and checks each call fails
//!    with fmi2Error and a logged reason.
//!
//! The results are compared here with the project's own runs of the same models with
//! the same parameters:
//!
//! - Co-Simulation against a [`Stepper`] stepped exactly as FMPy steps the FMU (the
//!   same communication points, the same arithmetic for them): the FMU runs this very
//!   code, so the results must agree to rounding (they are in fact identical);
//! - Co-Simulation against one uninterrupted [`Simulation`] with the model's default
//!   solver: the FMU restarts its solver at every communication point, so the two
//!   differ by the solvers' error, bounded by their tolerances (Radau5, rtol 1e-6,
//!   atol 1e-9): agreement to 1e-4 of each signal's range;
//! - Model Exchange (CVode, rtol 1e-10, its absolute tolerance 1e-10 from the nominal
//!   values 1) against a tight run of our own (Radau5, rtol 1e-11, atol 1e-13): two
//!   independent integrators, each to its tolerance: agreement to 1e-5 of each
//!   signal's range. (CVode's global error is some ten times its local tolerance: at
//!   rtol 1e-9 the oscillator deviates by 1.4e-5, at 1e-10 by 7e-7.)
//!
//! The filter's load voltage is also checked against its closed-form step response
//! ([`butterworth_step`]): to 1e-6 of the final value for Model Exchange, 1e-4 for
//! Co-Simulation (the solver tolerances above).
//!
//! The test skips, loudly, only when `python3` or the `fmpy` module is missing; `.ci/run`
//! installs FMPy so that in CI it always runs.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use bgdsl_fmi_core::{Exportable, ModelDescription, Role};
use bgdsl_runtime::{Radau5Options, Simulation, Solver, Stepper};
use models::dc_servo::DcServo;
use models::quick_return::QuickReturn;
use models::{Butterworth, DcMotor, Oscillator};

const SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fmpy_check.py");
const FMPY_VERSION: &str = "0.3.32";

/// FMPy's version, or why it cannot be used.
fn fmpy() -> Result<String, String> {
    let output = Command::new("python3")
        .args(["-c", "import fmpy; print(fmpy.__version__)"])
        .output()
        .map_err(|e| format!("python3 cannot be run ({e})"))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        return Err(format!("python3 has no fmpy module ({})", last.trim()));
    }
    Ok(String::from_utf8_lossy(&output.stdout).trim().to_string())
}

/// One simulation FMPy runs.
#[derive(Clone, Copy)]
struct Run {
    model: &'static str,
    fmi_type: &'static str,
    stop_time: f64,
    interval: f64,
    /// CVode's relative tolerance (Model Exchange); `None` leaves the FMU's solver at
    /// its own setting (Co-Simulation).
    rtol: Option<f64>,
    start_values: &'static [(&'static str, f64)],
}

impl Run {
    fn csv(&self, dir: &Path) -> PathBuf {
        let states = if self.sets_a_state() { "_state" } else { "" };
        dir.join(format!("{}_{}{states}.csv", self.model, self.fmi_type))
    }

    fn sets_a_state(&self) -> bool {
        self.start_values
            .iter()
            .any(|(name, _)| name.contains(".q"))
    }
}

const RUNS: &[Run] = &[
    // An initial state set by the importer (the states are initial="exact"), other
    // than the declared one (0.05 m).
    Run {
        model: "oscillator",
        fmi_type: "ModelExchange",
        stop_time: 1.0,
        interval: 1e-3,
        rtol: Some(1e-10),
        start_values: &[("spring.q", 0.08)],
    },
    Run {
        model: "oscillator",
        fmi_type: "CoSimulation",
        stop_time: 1.0,
        interval: 1e-3,
        rtol: None,
        start_values: &[("spring.q", 0.08)],
    },
    Run {
        model: "oscillator",
        fmi_type: "ModelExchange",
        stop_time: 2.0,
        interval: 1e-3,
        rtol: Some(1e-10),
        start_values: &[("k", 200.0), ("force", 3.0)],
    },
    Run {
        model: "oscillator",
        fmi_type: "CoSimulation",
        stop_time: 2.0,
        interval: 1e-3,
        rtol: None,
        start_values: &[("k", 200.0), ("force", 3.0)],
    },
    Run {
        model: "dc_motor",
        fmi_type: "ModelExchange",
        stop_time: 0.5,
        interval: 1e-3,
        rtol: Some(1e-10),
        start_values: &[("voltage", 6.0), ("load_torque", 0.05)],
    },
    Run {
        model: "dc_motor",
        fmi_type: "CoSimulation",
        stop_time: 0.5,
        interval: 1e-3,
        rtol: None,
        start_values: &[("voltage", 6.0), ("load_torque", 0.05)],
    },
    // Inputs (the supply voltage, the load torque) set through the FMU as an importer
    // sets them, with a parameter tuned beside them.
    Run {
        model: "dc_servo",
        fmi_type: "ModelExchange",
        stop_time: 0.5,
        interval: 1e-3,
        rtol: Some(1e-10),
        start_values: &[
            ("voltage", 12.0),
            ("load_torque", 0.05),
            ("gear_ratio", 8.0),
        ],
    },
    Run {
        model: "dc_servo",
        fmi_type: "CoSimulation",
        stop_time: 0.5,
        interval: 1e-3,
        rtol: None,
        start_values: &[
            ("voltage", 12.0),
            ("load_torque", 0.05),
            ("gear_ratio", 8.0),
        ],
    },
    Run {
        model: "quick_return",
        fmi_type: "CoSimulation",
        stop_time: 0.5,
        interval: 1e-3,
        rtol: None,
        // A scalar and one number of a vector parameter (`R3C[1]` is `R3C[0]` in Rust).
        start_values: &[("w_drive", 4.0), ("R3C[1]", 30.0)],
    },
    // A step of the source voltage (an input) into the filter at rest.
    Run {
        model: "butterworth",
        fmi_type: "ModelExchange",
        stop_time: 10.0,
        interval: 1e-2,
        rtol: Some(1e-10),
        start_values: &[("voltage", 3.0)],
    },
    Run {
        model: "butterworth",
        fmi_type: "CoSimulation",
        stop_time: 10.0,
        interval: 1e-2,
        rtol: None,
        start_values: &[("voltage", 3.0)],
    },
];

/// The load voltage of the catalogue's Butterworth filter (`H(s) = 1 / (2 (s + 1)(s² +
/// s + 1))`, see `models::butterworth`) at rest until a step of the source voltage to
/// `v` at `t = 0`: the inverse Laplace transform of `H(s) v / s`, by partial fractions
/// `1/s − 1/(s + 1) − 1/(s² + s + 1)`.
fn butterworth_step(v: f64, t: f64) -> f64 {
    let w = 0.75f64.sqrt();
    0.5 * v * (1.0 - (-t).exp() - (-0.5 * t).exp() * (w * t).sin() / w)
}

/// The names FMPy records: every state and every output.
fn recorded(description: &ModelDescription) -> Vec<String> {
    description
        .variables
        .all()
        .iter()
        .filter(|v| matches!(v.role, Role::State(_) | Role::Output(_)))
        .map(|v| v.name.clone())
        .collect()
}

fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn json_list(items: impl IntoIterator<Item = String>) -> String {
    format!("[{}]", items.into_iter().collect::<Vec<_>>().join(", "))
}

/// The script's configuration, as JSON.
fn config(dir: &Path, fmus: &[(&str, PathBuf)]) -> String {
    let path_of = |model: &str| {
        let (_, path) = fmus.iter().find(|(m, _)| *m == model).unwrap();
        json_string(&path.to_string_lossy())
    };
    let runs = RUNS.iter().map(|run| {
        let description = bgdsl_fmi::describe(run.model).unwrap();
        let starts = run
            .start_values
            .iter()
            .map(|(name, value)| format!("{}: {value:?}", json_string(name)))
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "{{\"fmu\": {}, \"fmi_type\": \"{}\", \"stop_time\": {:?}, \"output_interval\": {:?}, \
             \"relative_tolerance\": {}, \"start_values\": {{{starts}}}, \"outputs\": {}, \"csv\": {}}}",
            path_of(run.model),
            run.fmi_type,
            run.stop_time,
            run.interval,
            run.rtol.map_or("null".to_string(), |r| format!("{r:?}")),
            json_list(recorded(&description).iter().map(|n| json_string(n))),
            json_string(&run.csv(dir).to_string_lossy()),
        )
    });
    format!(
        "{{\"validate\": {}, \"runs\": {}, \"misuse\": [{}]}}",
        json_list(fmus.iter().map(|(_, p)| json_string(&p.to_string_lossy()))),
        json_list(runs),
        path_of("oscillator"),
    )
}

/// A CSV the script wrote: the header and the rows.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|line| line.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

/// Model `M` with `start_values` set as the FMU sets them: by FMI variable name,
/// through the flat parameter and input values.
fn tuned<M: Exportable>(start_values: &[(&str, f64)]) -> M {
    started::<M>(start_values).0
}

/// Model `M` with `start_values` set as the FMU sets them, and its initial state: the
/// declared one for those parameters, but for the states `start_values` sets.
fn started<M: Exportable>(start_values: &[(&str, f64)]) -> (M, Vec<f64>) {
    let description = ModelDescription::of::<M>();
    let mut model = M::default();
    let mut p = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut p);
    let mut u = vec![0.0; M::INPUTS.len()];
    model.input_values(&mut u);
    let mut states = Vec::new();
    for (name, value) in start_values {
        match description.variables.find(name).map(|v| v.role) {
            Some(Role::Parameter(i)) => p[i] = *value,
            Some(Role::Input(i)) => u[i] = *value,
            Some(Role::State(i)) => states.push((i, *value)),
            other => panic!("{name} is not a parameter, an input or a state ({other:?})"),
        }
    }
    model.set_parameter_values(&p);
    model.set_input_values(&u);
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    for (i, value) in states {
        x0[i] = value;
    }
    (model, x0)
}

/// States then outputs at `(t, x)`, in the order of [`recorded`].
fn row<M: Exportable>(model: &M, t: f64, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; M::N_OUTPUTS];
    model.outputs::<f64>(t, x, &mut y);
    x.iter().chain(&y).copied().collect()
}

/// The FMU stepped as FMPy steps it (`fmpy.simulation.simulateCS`): communication
/// point `t_n = n * interval`, each step `doStep(t_n, t_{n+1} - t_n)`, which the FMU
/// integrates to `t_n + (t_{n+1} - t_n)`, from where the last step ended.
fn stepped_like_fmpy<M: Exportable>(run: &Run, times: &[f64]) -> Vec<Vec<f64>> {
    let (model, x0) = started::<M>(run.start_values);
    let solver = model.default_solver();
    let mut stepper = Stepper::starting_at(model, solver, 0.0, &x0).unwrap();
    let mut rows = vec![row(stepper.model(), 0.0, &x0)];
    let mut time = 0.0;
    for n in 0..times.len() - 1 {
        let next = (n + 1) as f64 * run.interval;
        let end = time + (next - time);
        stepper.advance_to(end).unwrap();
        rows.push(row(stepper.model(), end, stepper.state()));
        time = next;
    }
    rows
}

/// One uninterrupted run of the project's own, sampled at `times`.
fn own_run<M: Exportable>(run: &Run, times: &[f64], solver: Solver) -> Vec<Vec<f64>> {
    let (model, x0) = started::<M>(run.start_values);
    let mut sim = Simulation::new(&model, solver).unwrap();
    let mut rows = Vec::new();
    let mut record = |t: f64, x: &[f64], _: &[f64]| rows.push(row(&model, t, x));
    sim.run(0.0, &x0, times, &mut record).unwrap();
    rows
}

/// The largest deviation of any column, relative to that column's range in the
/// reference (its largest magnitude; 1e-12 for a column that is zero throughout), and
/// the column where it occurs.
fn worst(names: &[String], fmu: &[Vec<f64>], reference: &[Vec<f64>]) -> (f64, String, f64) {
    assert_eq!(fmu.len(), reference.len(), "row counts differ");
    let mut worst = (0.0, String::new(), 0.0);
    for (j, name) in names.iter().enumerate() {
        let scale = reference.iter().map(|r| r[j].abs()).fold(1e-12, f64::max);
        let dev = fmu
            .iter()
            .zip(reference)
            .map(|(a, b)| (a[j] - b[j]).abs())
            .fold(0.0, f64::max);
        if dev / scale > worst.0 || worst.1.is_empty() {
            worst = (dev / scale, name.clone(), dev);
        }
    }
    worst
}

/// Compares one run's CSV with the project's runs; returns lines for the report and
/// the failures.
fn compare<M: Exportable>(
    run: &Run,
    dir: &Path,
    report: &mut Vec<String>,
    failures: &mut Vec<String>,
) {
    let (header, data) = read_csv(&run.csv(dir));
    let names: Vec<String> = header[1..].to_vec();
    assert_eq!(
        names,
        recorded(&ModelDescription::of::<M>()),
        "{}: columns",
        run.model
    );
    let times: Vec<f64> = data.iter().map(|r| r[0]).collect();
    let expected_rows = (run.stop_time / run.interval).round() as usize + 1;
    assert_eq!(
        times.len(),
        expected_rows,
        "{} {}: rows",
        run.model,
        run.fmi_type
    );
    let values: Vec<Vec<f64>> = data.iter().map(|r| r[1..].to_vec()).collect();
    let column = |name: &str| -> Vec<f64> {
        let j = names.iter().position(|n| n == name).unwrap();
        values.iter().map(|r| r[j]).collect()
    };
    // A state the importer set is where the run starts.
    for (name, value) in run.start_values {
        if name.contains(".q") {
            let first = column(name)[0];
            if first != *value {
                failures.push(format!(
                    "{} {}: {name} starts at {first}, not at the start value {value}",
                    run.model, run.fmi_type
                ));
            }
        }
    }
    // The crank angle is the program's: unwrapped (no jump between samples), so past π
    // after the crank has turned through it.
    if run.model == "quick_return" {
        let angle = column("crank_angle");
        let jump = angle
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        let last = angle[angle.len() - 1];
        if !(jump < 0.1 && last > core::f64::consts::PI) {
            failures.push(format!(
                "quick_return {}: crank_angle is not unwrapped: largest step {jump} rad between \
                 samples, {last} rad at the end",
                run.fmi_type
            ));
        }
    }
    if run.model == "butterworth" {
        let v = run.start_values[0].1;
        let tolerance = if run.fmi_type == "CoSimulation" {
            1e-4
        } else {
            1e-6
        };
        let dev = times
            .iter()
            .zip(column("load_voltage"))
            .map(|(&t, y)| (y - butterworth_step(v, t)).abs())
            .fold(0.0, f64::max)
            / (0.5 * v);
        let line = format!(
            "butterworth {} vs the closed-form step response: {dev:.2e} of the final value; \
             tolerance {tolerance:.0e}",
            run.fmi_type
        );
        eprintln!("{line}");
        if dev.is_nan() || dev > tolerance {
            failures.push(line.clone());
        }
        report.push(line);
    }
    // The tuned parameters took effect: the results are far from the defaults'.
    let default_run = Run {
        start_values: &[],
        ..*run
    };
    let model: M = M::default();
    // Relative to the tuned run's range (the default oscillator sits still).
    let defaults = own_run::<M>(&default_run, &times, model.default_solver());
    let (rel, column, _) = worst(&names, &defaults, &values);
    let line = format!(
        "{} {} vs the default parameters: {rel:.2e} of the signal's range in {column} (the \
         tuning took effect: must be over 1e-2)",
        run.model, run.fmi_type
    );
    eprintln!("{line}");
    if rel.is_nan() || rel <= 1e-2 {
        failures.push(line);
    }
    let mut check = |what: &str, reference: Vec<Vec<f64>>, tolerance: f64| {
        let (rel, column, abs) = worst(&names, &values, &reference);
        let line = format!(
            "{} {} vs {what}: max deviation {rel:.2e} of the signal's range ({abs:.2e} in {column}); tolerance {tolerance:.0e}",
            run.model, run.fmi_type
        );
        eprintln!("{line}");
        if rel.is_nan() || rel > tolerance {
            failures.push(line.clone());
        }
        report.push(line);
    };
    if run.fmi_type == "CoSimulation" {
        check(
            "our Stepper stepped as FMPy steps",
            stepped_like_fmpy::<M>(run, &times),
            1e-12,
        );
        let model: M = tuned(run.start_values);
        check(
            "our uninterrupted run",
            own_run::<M>(run, &times, model.default_solver()),
            1e-4,
        );
    } else {
        let tight = Solver::Radau5(Radau5Options {
            rtol: 1e-11,
            atol: 1e-13,
            ..Radau5Options::default()
        });
        check(
            "our tight run (Radau5, rtol 1e-11)",
            own_run::<M>(run, &times, tight),
            1e-5,
        );
    }
}

#[test]
fn fmpy_validates_and_simulates_the_fmus_like_the_project_does() {
    let version = match fmpy() {
        Ok(version) => version,
        Err(reason) => {
            // Straight to the process's stderr: the test harness captures `eprintln!`
            // of passing tests, and this must be seen.
            let _ = writeln!(
                std::io::stderr(),
                "\n!!!!!!!!\n!!! SKIPPED: the FMPy check of the FMUs did not run: {reason}.\n\
                 !!! Install it with `pip install fmpy=={FMPY_VERSION}` (`.ci/run` does).\n!!!!!!!!\n"
            );
            return;
        }
    };
    eprintln!("FMPy {version}");
    let library = bgdsl_fmi::find_library().unwrap_or_else(|e| {
        panic!("{e}\n(`cargo test -p bgdsl-fmi` builds the library beside the test binaries)")
    });
    eprintln!("library: {}", library.display());

    let dir =
        PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("fmpy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fmus: Vec<(&str, PathBuf)> = [
        "oscillator",
        "dc_motor",
        "dc_servo",
        "quick_return",
        "butterworth",
    ]
    .into_iter()
    .map(|model| {
        let path = bgdsl_fmi::write_fmu(model, &library, &dir).unwrap();
        (model, path)
    })
    .collect();
    let config_path = dir.join("config.json");
    std::fs::write(&config_path, config(&dir, &fmus)).unwrap();

    let output = Command::new("python3")
        .arg(SCRIPT)
        .arg(&config_path)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "fmpy_check.py failed:\n{stdout}");
    for (_, fmu) in &fmus {
        assert!(
            stdout.contains(&format!("VALID {}", fmu.display())),
            "validate_fmu did not pass {}",
            fmu.display()
        );
    }
    assert_eq!(stdout.matches("REFUSED").count(), 4, "every misuse refused");

    let mut report = Vec::new();
    let mut failures = Vec::new();
    for run in RUNS {
        match run.model {
            "oscillator" => compare::<Oscillator>(run, &dir, &mut report, &mut failures),
            "dc_motor" => compare::<DcMotor>(run, &dir, &mut report, &mut failures),
            "dc_servo" => compare::<DcServo>(run, &dir, &mut report, &mut failures),
            "quick_return" => compare::<QuickReturn>(run, &dir, &mut report, &mut failures),
            "butterworth" => compare::<Butterworth>(run, &dir, &mut report, &mut failures),
            other => unreachable!("no comparison for {other}"),
        }
    }
    assert!(
        failures.is_empty(),
        "deviations beyond tolerance:\n{}",
        failures.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
