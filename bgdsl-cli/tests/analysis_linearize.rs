//! `models linearize` in-process: `linear.json` with the issue's keys and shapes, the
//! series RLC's and the quarter car's A (and the RLC's B, C, D) against the matrices
//! written by hand, the quarter car's eigenvalues in `modes.csv` against its
//! characteristic polynomial, and the operating points `--at TIME` (the RLC's step
//! response in closed form) and `--at steady` (the DC motor's closed-form speed).

mod analysis_common;
mod common;

use std::fs;

use analysis_common::{assert_png, close, csv, names, rows, run, strings, yaml, MODELS};
use common::Scratch;
use models::dc_motor::DcMotorParams;
use models::quarter_car::QuarterCarParams;
use models::rlc::SeriesRlcParams;

/// `linear.json` of a run into `out`, with the keys issue 16 fixes checked for shape:
/// names, operating point and matrices (lists of rows) that fit one another.
fn linear_json(out: &std::path::Path) -> serde_yaml::Value {
    let json = yaml(&out.join("linear.json"));
    let (n, k, m) = (
        strings(&json["states"]).len(),
        strings(&json["inputs"]).len(),
        strings(&json["outputs"]).len(),
    );
    assert_eq!(json["x"].as_sequence().unwrap().len(), n);
    assert_eq!(json["u"].as_sequence().unwrap().len(), k);
    assert!(json["t"].as_f64().is_some());
    for (key, r, c) in [("A", n, n), ("B", n, k), ("C", m, n), ("D", m, k)] {
        let matrix = rows(&json[key]);
        assert_eq!(matrix.len(), r, "{key} rows");
        assert!(matrix.iter().all(|row| row.len() == c), "{key} columns");
    }
    json
}

/// The entry of `matrix` at the named row and column.
fn at(json: &serde_yaml::Value, key: &str, row: (&str, &str), column: (&str, &str)) -> f64 {
    let r = strings(&json[row.0])
        .iter()
        .position(|n| n == row.1)
        .unwrap();
    let c = strings(&json[column.0])
        .iter()
        .position(|n| n == column.1)
        .unwrap();
    rows(&json[key])[r][c]
}

/// The series RLC from its source voltage: with `p` the inductor's flux linkage and
/// `q` the capacitor's charge, `ṗ = V − R p/L − q/C` and `q̇ = p/L`, so
/// `A = [[−R/L, −1/C], [1/L, 0]]`, `B = [1, 0]ᵀ`, the current `p/L` and the capacitor
/// voltage `q/C`.
#[test]
fn the_rlc_matrices_are_those_written_by_hand_and_linear_json_has_the_issues_keys() {
    let dir = Scratch::new("linearize-rlc");
    let out = dir.join("rlc");
    run(
        &MODELS,
        &[
            "linearize",
            "rlc",
            "--inputs",
            "voltage",
            "--outputs",
            "current,capacitor_voltage",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let p = SeriesRlcParams::default();
    let json = linear_json(&out);
    assert_eq!(strings(&json["inputs"]), ["voltage"]);
    assert_eq!(strings(&json["outputs"]), ["current", "capacitor_voltage"]);
    assert_eq!(json["u"][0].as_f64(), Some(p.voltage));
    assert_eq!(json["t"].as_f64(), Some(0.0));
    let s = ("states", "inductor.p");
    let q = ("states", "capacitor.q");
    let expect = [
        ("A", s, s, -p.resistance / p.inductance),
        ("A", s, q, -1.0 / p.capacitance),
        ("A", q, s, 1.0 / p.inductance),
        ("A", q, q, 0.0),
        ("B", s, ("inputs", "voltage"), 1.0),
        ("B", q, ("inputs", "voltage"), 0.0),
        ("C", ("outputs", "current"), s, 1.0 / p.inductance),
        ("C", ("outputs", "current"), q, 0.0),
        (
            "C",
            ("outputs", "capacitor_voltage"),
            q,
            1.0 / p.capacitance,
        ),
        ("D", ("outputs", "current"), ("inputs", "voltage"), 0.0),
    ];
    for (key, row, column, value) in expect {
        let found = at(&json, key, row, column);
        assert!(
            (found - value).abs() <= 1e-14 * value.abs(),
            "{key}[{}, {}] = {found}, by hand {value}",
            row.1,
            column.1
        );
    }
    let mut expected = vec![
        ".models-results",
        "A.csv",
        "B.csv",
        "C.csv",
        "D.csv",
        "eigenvalues.png",
        "eigenvalues.svg",
        "index.html",
        "linear.json",
        "linear.m",
        "modes.csv",
        "run.yaml",
    ];
    expected.sort();
    assert_eq!(names(&out), expected);
    assert_png(&out.join("eigenvalues.png"));
    // The CSV of A has the states as its header and row labels.
    let a = fs::read_to_string(out.join("A.csv")).unwrap();
    assert!(
        a.starts_with(",inductor.p,capacitor.q\n") || a.starts_with(",capacitor.q,inductor.p\n"),
        "{a}"
    );
    let record = yaml(&out.join("run.yaml"));
    assert_eq!(record["analysis"]["command"].as_str(), Some("linearize"));
    assert_eq!(record["analysis"]["at"].as_str(), Some("initial"));
}

/// The quarter car's A by hand (states `q_t`, `p_u`, `q_s`, `p_b`:
/// `q̇_t = v_r − p_u/m_u`, `ṗ_u = k_t q_t − F_s − m_u g`, `q̇_s = p_u/m_u − p_b/m_s`,
/// `ṗ_b = F_s − m_s g` with `F_s = k_s q_s + c (p_u/m_u − p_b/m_s)`), and each
/// eigenvalue of `modes.csv` a root of its characteristic polynomial
/// `m_s m_u s⁴ + c (m_s + m_u) s³ + (k_s m_s + k_s m_u + k_t m_s) s² + c k_t s + k_s k_t`.
#[test]
fn the_quarter_cars_matrix_and_modes_match_its_characteristic_polynomial() {
    let dir = Scratch::new("linearize-quarter-car");
    let out = dir.join("car");
    run(
        &MODELS,
        &[
            "linearize",
            "quarter_car",
            "--at",
            "steady",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let p = QuarterCarParams::default();
    let (ms, mu, ks, c, kt) = (
        p.sprung_mass,
        p.unsprung_mass,
        p.suspension_stiffness,
        p.suspension_damping,
        p.tyre_stiffness,
    );
    let names = ["tyre.q", "unsprung.p", "spring.q", "sprung.p"];
    let hand = [
        [0.0, -1.0 / mu, 0.0, 0.0],
        [kt, -c / mu, -ks, c / ms],
        [0.0, 1.0 / mu, 0.0, -1.0 / ms],
        [0.0, c / mu, ks, -c / ms],
    ];
    let json = linear_json(&out);
    for (i, row) in names.iter().enumerate() {
        for (j, column) in names.iter().enumerate() {
            let found = at(&json, "A", ("states", row), ("states", column));
            assert!(
                (found - hand[i][j]).abs() <= 1e-14 * hand[i][j].abs(),
                "A[{row}, {column}] = {found}, by hand {}",
                hand[i][j]
            );
        }
    }
    let coefficients = [
        ks * kt,
        c * kt,
        ks * ms + ks * mu + kt * ms,
        c * (ms + mu),
        ms * mu,
    ];
    let (header, modes) = csv(&out.join("modes.csv"));
    assert_eq!(
        &header[..5],
        [
            "real_per_s",
            "imag_rad_per_s",
            "natural_frequency_rad_per_s",
            "natural_frequency_hz",
            "damping_ratio"
        ]
    );
    assert_eq!(modes.len(), 2, "two oscillating modes");
    for mode in &modes {
        let (re, im) = (mode[0], mode[1]);
        assert!(im > 0.0 && re < 0.0, "{mode:?}");
        // P(λ) by Horner in complex arithmetic, against the size of its terms: the
        // eigenvalues carry round-off amplified by the spread of the stiffnesses
        // (k_t/k_s = 10), so |P(λ)| is about 1e-9 of the largest term; 1e-8 allowed.
        let (mut pr, mut pi) = (0.0, 0.0);
        for &a in coefficients.iter().rev() {
            (pr, pi) = (pr * re - pi * im + a, pr * im + pi * re);
        }
        let modulus = (re * re + im * im).sqrt();
        let scale = coefficients
            .iter()
            .enumerate()
            .map(|(k, a)| a * modulus.powi(k as i32))
            .fold(0.0, f64::max);
        assert!(
            (pr * pr + pi * pi).sqrt() <= 1e-8 * scale,
            "P({re} + {im}i) ≠ 0"
        );
        assert!(close(mode[2], modulus, 1e-12));
        assert!(close(
            mode[3],
            modulus / (2.0 * std::f64::consts::PI),
            1e-12
        ));
        assert!(close(mode[4], -re / modulus, 1e-12));
    }
    // At the equilibrium the springs carry the weights: the static deflections.
    let x = &json["x"];
    let index = |name: &str| {
        strings(&json["states"])
            .iter()
            .position(|n| n == name)
            .unwrap()
    };
    let tyre = x[index("tyre.q")].as_f64().unwrap();
    assert!(close(tyre, (ms + mu) * p.g / kt, 1e-12), "{tyre}");
    let spring = x[index("spring.q")].as_f64().unwrap();
    assert!(close(spring, ms * p.g / ks, 1e-12), "{spring}");
}

/// `--at 0.002`: the operating point is the state of a run at 2 ms, here the series
/// RLC's step response in closed form (α = R/2L, ω_d = √(1/LC − α²)):
/// `i = V/(L ω_d) e^{−αt} sin ω_d t`, `q = C V (1 − e^{−αt}(cos ω_d t + α/ω_d sin ω_d t))`,
/// within 1e-6 of their scales V/(L ω_d) and C V at rtol 1e-10.
#[test]
fn an_operating_point_at_a_time_is_the_state_a_run_reaches() {
    let dir = Scratch::new("linearize-at-time");
    let out = dir.join("rlc");
    run(
        &MODELS,
        &[
            "linearize",
            "rlc",
            "--at",
            "0.002",
            "--rtol",
            "1e-10",
            "--atol",
            "1e-16",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let p = SeriesRlcParams::default();
    let (v, r, l, cap) = (p.voltage, p.resistance, p.inductance, p.capacitance);
    let t = 0.002;
    let alpha = r / (2.0 * l);
    let wd = (1.0 / (l * cap) - alpha * alpha).sqrt();
    let current = v / (l * wd) * (-alpha * t).exp() * (wd * t).sin();
    let charge =
        cap * v * (1.0 - (-alpha * t).exp() * ((wd * t).cos() + alpha / wd * (wd * t).sin()));
    let json = linear_json(&out);
    assert_eq!(json["t"].as_f64(), Some(t));
    let states = strings(&json["states"]);
    let x = |name: &str| {
        json["x"][states.iter().position(|n| n == name).unwrap()]
            .as_f64()
            .unwrap()
    };
    assert!(
        (x("inductor.p") / l - current).abs() <= 1e-6 * v / (l * wd),
        "{} vs {current}",
        x("inductor.p") / l
    );
    assert!(
        (x("capacitor.q") - charge).abs() <= 1e-6 * cap * v,
        "{} vs {charge}",
        x("capacitor.q")
    );
}

/// `--at steady` puts the DC motor's operating point at its closed-form steady speed
/// (the rotor's momentum `J ω_m`, see `analysis_steady.rs`), and a model without
/// declared inputs has a B with no columns unless a parameter is named.
#[test]
fn the_steady_operating_point_is_the_equilibrium() {
    let dir = Scratch::new("linearize-steady");
    let out = dir.join("motor");
    run(
        &MODELS,
        &[
            "linearize",
            "dc_motor",
            "--at",
            "steady",
            "--inputs",
            "voltage,load_torque",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let p = DcMotorParams::default();
    let n = p.gear_ratio;
    let b = p.rotor_friction + p.load_friction / (n * n);
    let speed = (p.voltage - p.resistance * p.load_torque / (n * p.torque_constant))
        / (p.resistance * b / p.torque_constant + p.torque_constant);
    let json = linear_json(&out);
    let states = strings(&json["states"]);
    let rotor = json["x"][states.iter().position(|s| s == "rotor.p").unwrap()]
        .as_f64()
        .unwrap();
    assert!(close(rotor, p.rotor_inertia * speed, 1e-12), "{rotor}");
    assert_eq!(strings(&json["inputs"]), ["voltage", "load_torque"]);
    // The supply's voltage drives the coil's flux linkage one to one: ∂ṗ_coil/∂V = 1.
    assert_eq!(
        at(&json, "B", ("states", "coil.p"), ("inputs", "voltage")),
        1.0
    );
    let record = yaml(&out.join("run.yaml"));
    assert_eq!(record["analysis"]["at"].as_str(), Some("steady"));
}

#[test]
fn an_unknown_input_is_a_usage_error_naming_the_candidates() {
    let dir = Scratch::new("linearize-unknown");
    let out = dir.join("rlc");
    let failure = run(
        &MODELS,
        &[
            "linearize",
            "rlc",
            "--inputs",
            "volts",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap_err();
    assert_eq!(failure.exit_code(), 2, "{failure}");
    let message = failure.to_string();
    assert!(
        message.contains("`volts`") && message.contains("`voltage`"),
        "{message}"
    );
    assert!(!out.exists());
    let failure = run(
        &MODELS,
        &[
            "linearize",
            "rlc",
            "--at",
            "-1",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap_err();
    assert_eq!(failure.exit_code(), 2, "{failure}");
    assert!(
        failure.to_string().contains("before the run's start"),
        "{failure}"
    );
    assert!(!out.exists());
}
