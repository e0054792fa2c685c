//! `models steady` in-process: the DC motor's steady speed and current against their
//! closed form (with the defaults and with `--set`), a user's own models through the
//! program library (a damped spring's static deflection, a held position), and the
//! failures: a singular Jacobian names the states, exits with status 1 and leaves an
//! existing results folder byte-identical; an unknown state is a usage error.

mod analysis_common;
mod common;

use std::fs;
use std::sync::LazyLock;

use analysis_common::{close, contents, names, run, yaml, MODELS};
use bgdsl_cli::{catalogue, Catalogue};
use bgdsl_runtime::bond_graph;
use common::Scratch;
use models::dc_motor::DcMotorParams;

bond_graph! {
    /// A mass hanging on a damped spring: at rest the spring stretches by m g / k.
    pub model Hanging {
        /// mass
        param m = 2.0 in "kg";
        /// stiffness
        param k = 50.0 in "N/m";
        /// damping
        param c = 3.0 in "N·s/m";
        /// gravity
        param g = 9.81 in "m/s²";
        Se weight = m * g;
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        R damper = c;
        1 v;
        weight -> v -> { mass, spring, damper };
        /// The spring's stretch, m.
        output stretch = spring.q in "m";
    }
}

bond_graph! {
    /// A mass pushed by a constant force against viscous drag, its position
    /// integrated: the speed settles at F / b, nothing fixes the position.
    pub model Pushed {
        /// mass
        param m = 2.0 in "kg";
        /// force
        param force = 3.0 in "N";
        /// drag coefficient
        param b = 0.5 in "N·s/m";
        Se push = force;
        I mass = m, p in "kg·m/s";
        R drag = b;
        1 v;
        push -> v -> { mass, drag };
        state position: f64 = 0.0;
        der position = v.f;
        /// The mass's speed, m/s.
        output speed = v.f in "m/s";
    }
}

bond_graph! {
    /// A free mass under a constant force: no equilibrium at all.
    pub model Falling {
        /// mass
        param m = 1.0 in "kg";
        /// force
        param force = 1.0 in "N";
        Se push = force;
        I mass = m, p in "kg·m/s";
        1 v;
        push -> v -> mass;
        state position: f64 = 0.0;
        der position = v.f;
    }
}

/// A user's own program, as `catalogue!` makes it.
static OWN: LazyLock<Catalogue> = LazyLock::new(|| catalogue![Hanging, Pushed, Falling]);

/// The value of `name` in a list of `{name, value, unit}` of `steady.yaml`.
fn value(file: &serde_yaml::Value, list: &str, name: &str) -> (f64, String) {
    let row = file[list]
        .as_sequence()
        .unwrap()
        .iter()
        .find(|r| r["name"].as_str() == Some(name))
        .unwrap_or_else(|| panic!("no {name} in {list}"));
    (
        row["value"].as_f64().unwrap(),
        row["unit"].as_str().unwrap().to_owned(),
    )
}

/// The DC motor's steady speed and current: with `b = b_m + b_L/N²`,
/// `ω_m = (V − R τ_L/(N k_t)) / (R b / k_t + k_t)` and `i = (b ω_m + τ_L/N) / k_t`
/// (torque balance on the rotor with the load reflected through the gearbox, and
/// Kirchhoff's law on the armature with the back-EMF `k_t ω_m`).
fn dc_motor_closed_form(p: &DcMotorParams) -> (f64, f64) {
    let n = p.gear_ratio;
    let b = p.rotor_friction + p.load_friction / (n * n);
    let speed = (p.voltage - p.resistance * p.load_torque / (n * p.torque_constant))
        / (p.resistance * b / p.torque_constant + p.torque_constant);
    let current = (b * speed + p.load_torque / n) / p.torque_constant;
    (speed, current)
}

#[test]
fn the_dc_motor_settles_at_its_closed_form_speed_and_current() {
    let dir = Scratch::new("steady-dc-motor");
    for (voltage, set) in [(12.0, None), (24.0, Some("voltage=24"))] {
        let out = dir.join(format!("v{voltage}"));
        let mut args = vec!["steady", "dc_motor", "--out", out.to_str().unwrap()];
        if let Some(set) = set {
            args.extend(["--set", set]);
        }
        run(&MODELS, &args).unwrap();
        let p = DcMotorParams {
            voltage,
            ..DcMotorParams::default()
        };
        let (speed, current) = dc_motor_closed_form(&p);
        let file = yaml(&out.join("steady.yaml"));
        let (found, unit) = value(&file, "outputs", "motor_speed");
        assert!(close(found, speed, 1e-12), "{found} vs {speed}");
        assert_eq!(unit, "rad/s");
        let (found, unit) = value(&file, "outputs", "current");
        assert!(close(found, current, 1e-12), "{found} vs {current}");
        assert_eq!(unit, "A");
        let (found, _) = value(&file, "outputs", "load_speed");
        assert!(close(found, speed / p.gear_ratio, 1e-12));
        assert!(file["residual"].as_f64().unwrap() <= 1e-9);
        assert_eq!(file["jacobian"].as_str(), Some("exact (dual numbers)"));
        assert!(file["iterations"].as_u64().unwrap() >= 1);
        // The set: the data, the record (with what was asked) and the page.
        assert_eq!(
            names(&out),
            [".models-results", "index.html", "run.yaml", "steady.yaml"]
        );
        let record = yaml(&out.join("run.yaml"));
        assert_eq!(record["analysis"]["command"].as_str(), Some("steady"));
        assert_eq!(record["parameters"]["voltage"].as_f64(), Some(voltage));
        let page = fs::read_to_string(out.join("index.html")).unwrap();
        assert!(
            page.contains("motor_speed"),
            "the page shows the equilibrium"
        );
    }
}

/// A user's own model through the program library: the static deflection `m g / k`
/// with zero momentum, in the default folder `out/hanging-steady` (relative to the
/// working directory, so the test names it with `--out` to stay in its scratch).
#[test]
fn a_users_own_model_hangs_at_its_static_deflection() {
    let dir = Scratch::new("steady-own");
    let out = dir.join("hanging");
    run(
        &OWN,
        &[
            "steady",
            "hanging",
            "--set",
            "m=3",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let file = yaml(&out.join("steady.yaml"));
    let (stretch, unit) = value(&file, "states", "spring.q");
    assert!(close(stretch, 3.0 * 9.81 / 50.0, 1e-13), "{stretch}");
    assert_eq!(unit, "m");
    let (momentum, _) = value(&file, "states", "mass.p");
    assert!(momentum.abs() <= 1e-12, "{momentum}");
    let (output, _) = value(&file, "outputs", "stretch");
    assert_eq!(output, stretch);
}

/// Holding the position of a pushed mass: the speed settles at F / b (momentum
/// `m F / b`), the position stays at its guess and its rate is that speed.
#[test]
fn a_held_position_leaves_the_speed_at_force_over_drag() {
    let dir = Scratch::new("steady-held");
    let out = dir.join("pushed");
    run(
        &OWN,
        &[
            "steady",
            "pushed",
            "--hold",
            "position",
            "--guess",
            "position=7",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let file = yaml(&out.join("steady.yaml"));
    let (p, _) = value(&file, "states", "mass.p");
    assert!(close(p, 2.0 * 3.0 / 0.5, 1e-12), "{p}");
    let (x, _) = value(&file, "states", "position");
    assert_eq!(x, 7.0);
    let held = file["states"]
        .as_sequence()
        .unwrap()
        .iter()
        .find(|r| r["name"].as_str() == Some("position"))
        .unwrap();
    assert_eq!(held["held"].as_bool(), Some(true));
    assert!(close(held["rate"].as_f64().unwrap(), 3.0 / 0.5, 1e-12));
}

/// A free mass under a force has no equilibrium: the error names the position (what
/// nothing fixes) and the momentum (whose rate nothing cancels), the status is 1, and
/// the folder of an earlier analysis keeps every byte; nothing else is left beside it.
#[test]
fn a_singular_equilibrium_names_the_states_and_leaves_the_folder_alone() {
    let dir = Scratch::new("steady-singular");
    let out = dir.join("set");
    run(&OWN, &["steady", "hanging", "--out", out.to_str().unwrap()]).unwrap();
    let before = contents(&out);
    let failure = run(&OWN, &["steady", "falling", "--out", out.to_str().unwrap()]).unwrap_err();
    assert_eq!(failure.exit_code(), 1, "{failure}");
    let message = failure.to_string();
    assert!(message.contains("singular"), "{message}");
    assert!(message.contains("`position`"), "{message}");
    assert!(message.contains("`mass.p`"), "{message}");
    assert_eq!(contents(&out), before, "the earlier set is untouched");
    assert_eq!(names(&dir), ["set"], "no staging or partial folder is left");
    // Without an earlier set, nothing at all is created.
    let fresh = dir.join("fresh");
    run(
        &OWN,
        &["steady", "falling", "--out", fresh.to_str().unwrap()],
    )
    .unwrap_err();
    assert!(!fresh.exists());
}

#[test]
fn an_unknown_state_is_a_usage_error_that_lists_the_states() {
    let dir = Scratch::new("steady-unknown");
    let out = dir.join("set");
    let failure = run(
        &OWN,
        &[
            "steady",
            "hanging",
            "--guess",
            "spring.x=1",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap_err();
    assert_eq!(failure.exit_code(), 2, "{failure}");
    let message = failure.to_string();
    assert!(message.contains("`spring.x`"), "{message}");
    assert!(
        message.contains("mass.p") && message.contains("spring.q"),
        "{message}"
    );
    assert!(!out.exists());
}

/// A scenario file gives the parameters and the starting state as `models run` reads
/// them (the DC motor at 6 V, its closed-form speed), the record keeps the scenario's
/// text; a sweep is refused (one model, one analysis) with nothing written.
#[test]
fn a_scenario_sets_parameters_and_a_sweep_is_refused() {
    let dir = Scratch::new("steady-scenario");
    let scenario = dir.join("motor.yaml");
    fs::write(
        &scenario,
        "model: dc_motor\nparameters:\n  voltage: 6.0\ninitial:\n  rotor.p: 0.001\n",
    )
    .unwrap();
    let out = dir.join("set");
    run(
        &MODELS,
        &[
            "steady",
            scenario.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let (speed, _) = dc_motor_closed_form(&DcMotorParams {
        voltage: 6.0,
        ..DcMotorParams::default()
    });
    let file = yaml(&out.join("steady.yaml"));
    let (found, _) = value(&file, "outputs", "motor_speed");
    assert!(close(found, speed, 1e-12), "{found} vs {speed}");
    let guess = file["states"]
        .as_sequence()
        .unwrap()
        .iter()
        .find(|r| r["name"].as_str() == Some("rotor.p"))
        .unwrap()["guess"]
        .as_f64();
    assert_eq!(
        guess,
        Some(0.001),
        "the scenario's initial state is the guess"
    );
    let record = yaml(&out.join("run.yaml"));
    assert!(record["scenario"]["text"]
        .as_str()
        .unwrap()
        .contains("voltage: 6.0"));

    let sweep = dir.join("sweep.yaml");
    fs::write(
        &sweep,
        "model: dc_motor\nsweep:\n  parameters:\n    - name: voltage\n      values: [6, 12]\n  peaks: [current]\n",
    )
    .unwrap();
    let other = dir.join("other");
    let failure = run(
        &MODELS,
        &[
            "steady",
            sweep.to_str().unwrap(),
            "--out",
            other.to_str().unwrap(),
        ],
    )
    .unwrap_err();
    assert_eq!(failure.exit_code(), 2, "{failure}");
    assert!(failure.to_string().contains("sweep"), "{failure}");
    assert!(!other.exists());
}

/// A folder the program did not write is refused before any work (status 2), its
/// content untouched; `--no-plots` leaves the data and the page.
#[test]
fn a_foreign_folder_is_refused_and_no_plots_draws_nothing() {
    let dir = Scratch::new("steady-foreign");
    let foreign = dir.join("mine");
    fs::create_dir_all(&foreign).unwrap();
    fs::write(foreign.join("notes.txt"), "keep me").unwrap();
    let failure = run(
        &OWN,
        &["steady", "hanging", "--out", foreign.to_str().unwrap()],
    )
    .unwrap_err();
    assert_eq!(failure.exit_code(), 2, "{failure}");
    assert_eq!(names(&foreign), ["notes.txt"]);
    assert_eq!(
        fs::read_to_string(foreign.join("notes.txt")).unwrap(),
        "keep me"
    );

    let out = dir.join("linear");
    run(
        &MODELS,
        &[
            "linearize",
            "rlc",
            "--no-plots",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let files = names(&out);
    assert!(files.contains(&"linear.json".to_owned()), "{files:?}");
    assert!(
        !files
            .iter()
            .any(|f| f.ends_with(".png") || f.ends_with(".svg")),
        "{files:?}"
    );
}

/// The quick return at rest has no equilibrium: its five bodies' poses (rotation
/// matrix `R` and position `r`) are integrals of their velocities that no force
/// depends on, and so is each slide joint's coordinate along its guide (`j3C`, `j5C`:
/// no stiffness there). The message groups the 62 undetermined states by element,
/// counts a vector state's components, and caps the 92 rates' list with a count. The
/// exact text is pinned: a change in the grouping, the order or the null space shows.
#[test]
fn the_quick_returns_singular_message_groups_the_free_states_by_body() {
    let dir = Scratch::new("steady-quick-return");
    let out = dir.join("set");
    let failure = run(
        &MODELS,
        &["steady", "quick_return", "--out", out.to_str().unwrap()],
    )
    .unwrap_err();
    assert_eq!(failure.exit_code(), 1, "{failure}");
    let message = failure.to_string();
    let body = |name: &str| format!("{name}: `R` (9 components), `r_x`, `r_y`, `r_z`");
    let bodies: Vec<String> = ["crank", "slider", "rocker", "rod", "output_slider"]
        .iter()
        .map(|b| body(b))
        .collect();
    let free = format!(
        "the equilibrium does not determine 62 states (j3C: `spring.q_x`; j5C: \
         `spring.q_x`; {}) (nothing pulls them back",
        bodies.join("; ")
    );
    assert!(message.contains(&free), "{message}");
    assert!(
        message.contains("no state cancels the rates of 92 states (slider: `rotation.p_y`, "),
        "{message}"
    );
    assert!(message.contains("; and 25 more states); hold"), "{message}");
    // Every motion is one state: no coupled motions are listed.
    assert!(
        !message.contains("free motions of several states"),
        "{message}"
    );
    assert!(!out.exists());
}
