//! The hybrid models' FMUs checked by FMPy (PyPI), an FMI importer written by others:
//! the bouncing ball (impacts with restitution, then a rest mode) and the half-wave
//! rectifier (an ideal diode switching on and off), each as Model Exchange (FMPy's
//! CVode integrates and locates the events through `fmi2GetEventIndicators`; the FMU
//! applies the actions in `fmi2NewDiscreteStates`) and as Co-Simulation (the FMU's own
//! solver locates and handles the events inside each `fmi2DoStep`).
//!
//! `tests/fmpy_check.py` validates the FMUs of every hybrid model of the library and
//! runs the ball's and the rectifier's; FMPy records every grid point and, in Model
//! Exchange, the state on both sides of every event it handled (`record_events`, its
//! default). The results are compared here with the project's own runs of the same
//! models:
//!
//! - Co-Simulation against a [`Stepper`] stepped exactly as FMPy steps the FMU: the
//!   same code, so identical to rounding (tolerance 1e-12 of each signal's range);
//! - Co-Simulation against one uninterrupted tight run of our own (Radau5, rtol 1e-11,
//!   atol 1e-13, events located to 1e-12 s): the FMU's solver has the model's default
//!   tolerances (rtol 1e-6) and restarts at every communication point: 1e-5 of each
//!   signal's range (measured: 8e-12 for the ball, whose flights Radau5 integrates
//!   exactly, 4e-8 for the rectifier). Not the default solver uninterrupted: on the
//!   rectifier it steps over the diode's turn-on (the state decays slowly while the
//!   diode is off, so Radau5 takes steps longer than the 20 ms period, and the
//!   indicator has the same sign at both ends), where the FMU's steps end every 0.1 ms;
//! - Model Exchange (CVode, rtol 1e-10) against the same tight run: agreement at the
//!   grid points to 1e-5 of each signal's range (measured: 4e-7 and 2e-6);
//! - the event times FMPy's Model Exchange run found against the closed form (the
//!   ball: impact k at `t1 + (2 u1 / g)(e + ... + e^(k-1))`, `u1 = sqrt(2 g h0)`,
//!   `t1 = u1 / g`; the ball comes to rest at the first impact whose rebound speed
//!   `e^k u1` would be below `v_rest`) and against our tight run's event times (the
//!   rectifier, whose switching times are only implicit): the first ten to 1e-8 s,
//!   all to 1e-6 s (measured: 3e-9 s and 3.2e-7 s for the ball, 2.7e-9 s for the
//!   rectifier). CVode locates a root to about 100 ulps of t, but its state carries
//!   its integration error, and its absolute tolerance (rtol times the nominal value
//!   1: 1e-10 m) is coarse against the ball's last bounces (peaks of a few µm), so the
//!   later impacts drift ahead of the closed form, by 3e-7 s at the 28th.
//!
//! Where a comparison is at the grid points, those within 1e-6 s of an event of ours
//! are left out: a sample there may fall between the two runs' event times.
//!
//! The test skips, loudly, only when `python3` or the `fmpy` module is missing; `.ci/run`
//! installs FMPy so that in CI it always runs.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use bgdsl_fmi_core::{Exportable, ModelDescription, Role};
use bgdsl_runtime::{EventRecord, Radau5Options, Recorder, Simulation, Solver, Stepper};
use models::hybrid::{BouncingBall, HalfWaveRectifier};

const SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fmpy_check.py");
const BALL: &str = "bouncing_ball";
const RECTIFIER: &str = "rectifier";
/// The library's models with events and modes.
const HYBRID: &[&str] = &[
    BALL,
    RECTIFIER,
    "rectifier_exp",
    "stick_slip",
    "end_stop",
    "clutch",
    "quick_return_friction",
];

/// One simulation FMPy runs.
#[derive(Clone, Copy, Debug)]
struct Run {
    model: &'static str,
    fmi_type: &'static str,
    stop_time: f64,
    interval: f64,
    /// CVode's relative tolerance (Model Exchange); `None` leaves the FMU's solver at
    /// its own setting (Co-Simulation).
    rtol: Option<f64>,
}

impl Run {
    fn csv(&self, dir: &Path) -> PathBuf {
        dir.join(format!("{}_{}.csv", self.model, self.fmi_type))
    }
}

/// The ball to rest and on (it rests at 4.07 s); the rectifier over three periods of
/// its 50 Hz source.
const RUNS: &[Run] = &[
    Run {
        model: BALL,
        fmi_type: "ModelExchange",
        stop_time: 5.0,
        interval: 1e-2,
        rtol: Some(1e-10),
    },
    Run {
        model: BALL,
        fmi_type: "CoSimulation",
        stop_time: 5.0,
        interval: 1e-2,
        rtol: None,
    },
    Run {
        model: RECTIFIER,
        fmi_type: "ModelExchange",
        stop_time: 0.06,
        interval: 1e-4,
        rtol: Some(1e-10),
    },
    Run {
        model: RECTIFIER,
        fmi_type: "CoSimulation",
        stop_time: 0.06,
        interval: 1e-4,
        rtol: None,
    },
];

/// FMPy's version, or why it cannot be used.
fn fmpy() -> Result<String, String> {
    let output = Command::new("python3")
        .args(["-c", "import fmpy; print(fmpy.__version__)"])
        .output()
        .map_err(|e| format!("python3 cannot be run ({e})"))?;
    if !output.status.success() {
        return Err("python3 has no fmpy module".to_string());
    }
    Ok(String::from_utf8_lossy(&output.stdout).trim().to_string())
}

/// The names FMPy records: every state (the modes included) and every output.
fn recorded(description: &ModelDescription) -> Vec<String> {
    description
        .variables
        .all()
        .iter()
        .filter(|v| matches!(v.role, Role::State(_) | Role::Output(_)))
        .map(|v| v.name.clone())
        .collect()
}

/// A string as JSON (the names and paths here have no character to escape but these).
fn json_string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

fn config(dir: &Path, fmus: &[(&str, PathBuf)]) -> String {
    let path_of = |model: &str| {
        let (_, path) = fmus.iter().find(|(m, _)| *m == model).unwrap();
        json_string(&path.to_string_lossy())
    };
    let runs: Vec<String> = RUNS
        .iter()
        .map(|run| {
            let names: Vec<String> = recorded(&bgdsl_fmi::describe(run.model).unwrap())
                .iter()
                .map(|n| json_string(n))
                .collect();
            format!(
                "{{\"fmu\": {}, \"fmi_type\": \"{}\", \"stop_time\": {:?}, \
                 \"output_interval\": {:?}, \"relative_tolerance\": {}, \"start_values\": {{}}, \
                 \"outputs\": [{}], \"csv\": {}}}",
                path_of(run.model),
                run.fmi_type,
                run.stop_time,
                run.interval,
                run.rtol.map_or("null".to_string(), |r| format!("{r:?}")),
                names.join(", "),
                json_string(&run.csv(dir).to_string_lossy()),
            )
        })
        .collect();
    let validate: Vec<String> = fmus
        .iter()
        .map(|(_, p)| json_string(&p.to_string_lossy()))
        .collect();
    format!(
        "{{\"validate\": [{}], \"runs\": [{}], \"misuse\": []}}",
        validate.join(", "),
        runs.join(", ")
    )
}

/// A CSV the script wrote: the header (less `time`), the times and the rows.
fn read_csv(path: &Path) -> (Vec<String>, Vec<f64>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .skip(1)
        .map(str::to_string)
        .collect();
    let (times, rows) = lines
        .map(|line| {
            let values: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
            (values[0], values[1..].to_vec())
        })
        .unzip();
    (header, times, rows)
}

/// States then outputs at `(t, x)`, in the order of [`recorded`].
fn row<M: Exportable>(model: &M, t: f64, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; M::N_OUTPUTS];
    model.outputs::<f64>(t, x, &mut y);
    x.iter().chain(&y).copied().collect()
}

/// A run of our own: rows (states then outputs) at the sample times, and the events'
/// times and names.
#[derive(Default)]
struct Own {
    rows: Vec<Vec<f64>>,
    events: Vec<(f64, &'static str)>,
}

impl Recorder for Own {
    fn record(&mut self, _t: f64, x: &[f64], y: &[f64]) {
        self.rows.push(x.iter().chain(y).copied().collect());
    }

    fn event(&mut self, record: &EventRecord<'_>) {
        self.events.push((record.t, record.name));
    }
}

/// One uninterrupted run of the project's own from the default state, sampled at
/// `times`.
fn own_run<M: Exportable>(times: &[f64], solver: Solver) -> Own {
    let model = M::default();
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(&model, solver).unwrap();
    let mut own = Own::default();
    sim.run(0.0, &x0, times, &mut own).unwrap();
    own
}

/// The FMU stepped as FMPy steps it (`fmpy.simulation.simulateCS`): communication
/// point `t_n = n * interval`, each step `doStep(t_n, t_{n+1} - t_n)`.
fn stepped_like_fmpy<M: Exportable>(run: &Run, steps: usize) -> Vec<Vec<f64>> {
    let model = M::default();
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let solver = model.default_solver();
    let mut stepper = Stepper::starting_at(model, solver, 0.0, &x0).unwrap();
    let mut rows = vec![row(stepper.model(), 0.0, &x0)];
    let mut time = 0.0;
    for n in 0..steps {
        let next = (n + 1) as f64 * run.interval;
        let end = time + (next - time);
        stepper.advance_to(end).unwrap();
        rows.push(row(stepper.model(), end, stepper.state()));
        time = next;
    }
    rows
}

/// The largest deviation of any column over the rows `keep` allows, relative to that
/// column's largest magnitude in the reference (1e-12 for a column zero throughout):
/// the relative and absolute deviation, the column and the row.
fn worst(
    names: &[String],
    fmu: &[Vec<f64>],
    reference: &[Vec<f64>],
    keep: impl Fn(usize) -> bool,
) -> (f64, String, f64, usize) {
    assert_eq!(fmu.len(), reference.len(), "row counts differ");
    let mut worst = (0.0, String::new(), 0.0, 0);
    for (j, name) in names.iter().enumerate() {
        let scale = reference.iter().map(|r| r[j].abs()).fold(1e-12, f64::max);
        for i in (0..fmu.len()).filter(|&i| keep(i)) {
            let dev = (fmu[i][j] - reference[i][j]).abs();
            if dev / scale > worst.0 || worst.1.is_empty() {
                worst = (dev / scale, name.clone(), dev, i);
            }
        }
    }
    worst
}

/// The times at which FMPy's Model Exchange run handled an event that changed a state
/// (the pairs of rows with the same time that differ): FMPy records the state before
/// and after each event.
fn fmpy_event_times(times: &[f64], rows: &[Vec<f64>], states: usize) -> Vec<f64> {
    (1..times.len())
        .filter(|&i| times[i] == times[i - 1] && rows[i][..states] != rows[i - 1][..states])
        .map(|i| times[i])
        .collect()
}

/// The ball's impact times in closed form, up to the one that brings it to rest.
fn ball_impacts() -> Vec<f64> {
    let p = models::hybrid::BouncingBallParams::default();
    let u1 = (2.0 * p.g * p.h0).sqrt();
    let mut t = u1 / p.g;
    let mut impacts = vec![t];
    let mut k = 1;
    while p.restitution.powi(k) * u1 >= p.v_rest {
        t += 2.0 * p.restitution.powi(k) * u1 / p.g;
        impacts.push(t);
        k += 1;
    }
    impacts
}

fn check(failures: &mut Vec<String>, line: String, ok: bool) {
    eprintln!("{line}");
    if !ok {
        failures.push(line);
    }
}

/// Compares one run's CSV with the project's runs.
fn compare<M: Exportable>(run: &Run, dir: &Path, failures: &mut Vec<String>) {
    let (names, times, rows) = read_csv(&run.csv(dir));
    assert_eq!(
        names,
        recorded(&ModelDescription::of::<M>()),
        "{run:?}: columns"
    );
    let steps = (run.stop_time / run.interval).round() as usize;
    let label = format!("{} {}", run.model, run.fmi_type);
    // The grid points, as FMPy computes them, and where they are in the CSV.
    let grid: Vec<f64> = (0..=steps).map(|n| n as f64 * run.interval).collect();
    let on_grid: Vec<usize> = (0..times.len())
        .filter(|&i| {
            let n = (times[i] / run.interval).round();
            (times[i] - n * run.interval).abs() <= 1e-9 * run.interval
                && (i + 1 == times.len() || times[i + 1] != times[i])
        })
        .collect();
    assert_eq!(on_grid.len(), grid.len(), "{label}: grid rows");
    let fmu: Vec<Vec<f64>> = on_grid.iter().map(|&i| rows[i].clone()).collect();

    let tight = Solver::Radau5(Radau5Options {
        rtol: 1e-11,
        atol: 1e-13,
        ..Radau5Options::default()
    });
    let own = own_run::<M>(&grid, tight);
    let near_event = |i: usize| own.events.iter().any(|(t, _)| (grid[i] - t).abs() < 1e-6);
    if run.fmi_type == "CoSimulation" {
        let (rel, column, abs, at) =
            worst(&names, &fmu, &stepped_like_fmpy::<M>(run, steps), |_| true);
        check(
            failures,
            format!("{label} vs our Stepper stepped as FMPy steps: {rel:.2e} of the range ({abs:.2e} in {column} at t = {}); tolerance 1e-12", grid[at]),
            rel <= 1e-12,
        );
        let (rel, column, abs, at) = worst(&names, &fmu, &own.rows, |i| !near_event(i));
        check(
            failures,
            format!("{label} vs our tight run (Radau5, rtol 1e-11): {rel:.2e} of the range ({abs:.2e} in {column} at t = {}); tolerance 1e-5", grid[at]),
            rel <= 1e-5,
        );
        return;
    }
    let (rel, column, abs, at) = worst(&names, &fmu, &own.rows, |i| !near_event(i));
    check(
        failures,
        format!("{label} vs our tight run (Radau5, rtol 1e-11): {rel:.2e} of the range ({abs:.2e} in {column} at t = {}); tolerance 1e-5", grid[at]),
        rel <= 1e-5,
    );
    let found = fmpy_event_times(&times, &rows, M::N_STATES);
    let expected: Vec<f64> = if run.model == BALL {
        ball_impacts()
    } else {
        own.events.iter().map(|(t, _)| *t).collect()
    };
    let source = if run.model == BALL {
        "the closed form"
    } else {
        "our tight run"
    };
    let worst_time = found
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    // The first ten events, before CVode's absolute tolerance (1e-10, its rtol times
    // the nominal 1) becomes large against the ball's last bounces (peaks of a few µm).
    let worst_first = found
        .iter()
        .zip(&expected)
        .take(10)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    check(
        failures,
        format!(
            "{label}: {} events handled, {} in {source}; event times off by {worst_first:.2e} s \
             at most over the first ten (tolerance 1e-8 s), {worst_time:.2e} s over all \
             (tolerance 1e-6 s)",
            found.len(),
            expected.len()
        ),
        found.len() == expected.len() && worst_first <= 1e-8 && worst_time <= 1e-6,
    );
}

#[test]
fn fmpy_runs_the_hybrid_fmus_and_finds_their_events_where_the_project_does() {
    let version = match fmpy() {
        Ok(version) => version,
        Err(reason) => {
            let _ = writeln!(
                std::io::stderr(),
                "\n!!!!!!!!\n!!! SKIPPED: the FMPy check of the hybrid FMUs did not run: \
                 {reason}.\n!!! Install it with `pip install fmpy==0.3.32` (`.ci/run` does).\n\
                 !!!!!!!!\n"
            );
            return;
        }
    };
    eprintln!("FMPy {version}");
    let library = bgdsl_fmi::find_library().unwrap();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("fmpy-events-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Every hybrid model's FMU is validated; the ball and the rectifier are run.
    let fmus: Vec<(&str, PathBuf)> = HYBRID
        .iter()
        .copied()
        .map(|model| (model, bgdsl_fmi::write_fmu(model, &library, &dir).unwrap()))
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
            "{stdout}"
        );
    }
    let mut failures = Vec::new();
    for run in RUNS {
        match run.model {
            BALL => compare::<BouncingBall>(run, &dir, &mut failures),
            RECTIFIER => compare::<HalfWaveRectifier>(run, &dir, &mut failures),
            other => unreachable!("no comparison for {other}"),
        }
    }
    assert!(
        failures.is_empty(),
        "beyond tolerance:\n{}",
        failures.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
