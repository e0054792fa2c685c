//! `models bode` in-process: the third-order Butterworth ladder against
//! `H(s) = 1/(2(s+1)(s²+s+1))` read back from `bode.csv`, a user's own driven
//! oscillator against `1/(m s² + c s + k)`, the default band, the figures, and the
//! usage errors (nothing written).

mod analysis_common;
mod common;

use std::f64::consts::PI;

use analysis_common::{assert_png, csv, names, run, yaml, MODELS};
use bgdsl_cli::{catalogue, Catalogue};
use bgdsl_runtime::bond_graph;
use common::Scratch;
use std::sync::LazyLock;

bond_graph! {
    /// A mass on a damped spring driven by a force.
    pub model Driven {
        /// mass
        param m = 2.0 in "kg";
        /// stiffness
        param k = 800.0 in "N/m";
        /// damping
        param c = 8.0 in "N·s/m";
        /// the driving force
        param force = 0.0 in "N";
        Se drive = force;
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        R damper = c;
        1 v;
        drive -> v -> { mass, spring, damper };
        /// Position of the mass, m.
        output x = spring.q in "m";
    }
}

/// A user's own program.
static OWN: LazyLock<Catalogue> = LazyLock::new(|| catalogue![Driven]);

/// `(magnitude dB, phase °)` of `h` given as (re, im).
fn db_deg(re: f64, im: f64) -> (f64, f64) {
    (
        10.0 * (re * re + im * im).log10(),
        im.atan2(re).to_degrees(),
    )
}

/// `H(jω) = 1/(2(jω+1)(1 − ω² + jω))`: magnitude in dB and the continuous phase
/// `−atan ω − atan2(ω, 1 − ω²)` (from 0° to −270°).
fn butterworth(omega: f64) -> (f64, f64) {
    let magnitude = 1.0
        / (2.0
            * (1.0 + omega * omega).sqrt()
            * ((1.0 - omega * omega).powi(2) + omega * omega).sqrt());
    let phase = -(omega.atan() + omega.atan2(1.0 - omega * omega));
    (20.0 * magnitude.log10(), phase.to_degrees())
}

/// Every one of 50 frequencies from 0.01 Hz to 10 Hz (through the cut-off 1 rad/s,
/// 0.159 Hz), within 1e-9 dB and 1e-7° of the transfer function.
#[test]
fn the_butterworth_ladder_follows_its_transfer_function() {
    let dir = Scratch::new("bode-butterworth");
    let out = dir.join("filter");
    run(
        &MODELS,
        &[
            "bode",
            "butterworth",
            "--input",
            "voltage",
            "--output",
            "load_voltage",
            "--from",
            "0.01",
            "--to",
            "10",
            "--points",
            "50",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let (header, rows) = csv(&out.join("bode.csv"));
    assert_eq!(
        header,
        [
            "frequency_hz",
            "omega_rad_per_s",
            "load_voltage/voltage_db",
            "load_voltage/voltage_deg"
        ]
    );
    assert_eq!(rows.len(), 50);
    assert_eq!(rows[0][0], 0.01);
    assert_eq!(rows[49][0], 10.0);
    for row in &rows {
        assert!((row[1] - 2.0 * PI * row[0]).abs() <= 1e-15 * row[1]);
        let (db, deg) = butterworth(row[1]);
        assert!(
            (row[2] - db).abs() <= 1e-9,
            "{} Hz: {} dB, H gives {db}",
            row[0],
            row[2]
        );
        assert!(
            (row[3] - deg).abs() <= 1e-7,
            "{} Hz: {}°, H gives {deg}",
            row[0],
            row[3]
        );
    }
    // The low-frequency gain is −6.02 dB (the two terminations halve it); at ω = 1 the
    // magnitude is 3 dB below it.
    assert!((rows[0][2] + 20.0 * 2f64.log10()).abs() < 1e-3);
    let mut expected = vec![
        ".models-results",
        "bode.csv",
        "bode_magnitude.png",
        "bode_magnitude.svg",
        "bode_phase.png",
        "bode_phase.svg",
        "index.html",
        "run.yaml",
    ];
    expected.sort();
    assert_eq!(names(&out), expected);
    assert_png(&out.join("bode_magnitude.png"));
    assert_png(&out.join("bode_phase.png"));
    let svg = std::fs::read_to_string(out.join("bode_magnitude.svg")).unwrap();
    assert!(
        svg.contains("frequency f (Hz)") && svg.contains("dB re 1 V/V"),
        "axes with units"
    );
    let record = yaml(&out.join("run.yaml"));
    assert_eq!(record["analysis"]["command"].as_str(), Some("bode"));
    assert_eq!(record["analysis"]["points"].as_u64(), Some(50));
}

/// Without `--from` and `--to` the band runs from a decade below the slowest mode to a
/// decade above the fastest, in whole decades: the ladder's poles all have |s| = 1
/// rad/s (0.159 Hz), so 0.01 Hz to 10 Hz, 200 points; and every output by default.
#[test]
fn the_default_band_spans_the_modes_in_whole_decades() {
    let dir = Scratch::new("bode-default");
    let out = dir.join("filter");
    run(
        &MODELS,
        &["bode", "butterworth", "--out", out.to_str().unwrap()],
    )
    .unwrap();
    let (header, rows) = csv(&out.join("bode.csv"));
    assert_eq!(rows.len(), 200);
    assert_eq!((rows[0][0], rows[199][0]), (0.01, 10.0));
    assert_eq!(
        header.len(),
        2 + 2 * 3,
        "every output of the one input: {header:?}"
    );
}

/// A user's own model through the program library, driven by a parameter: the
/// position per force of a damped oscillator, `1/(m s² + c s + k)`.
#[test]
fn a_users_own_oscillator_follows_its_transfer_function() {
    let dir = Scratch::new("bode-own");
    let out = dir.join("driven");
    run(
        &OWN,
        &[
            "bode",
            "driven",
            "--input",
            "force",
            "--output",
            "x",
            "--from",
            "0.1",
            "--to",
            "100",
            "--points",
            "31",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .unwrap();
    let (header, rows) = csv(&out.join("bode.csv"));
    assert_eq!(header[2], "x/force_db");
    for row in &rows {
        let w = row[1];
        // 1/(k − m ω² + j c ω) = (k − m ω² − j c ω)/|…|²
        let (re, im) = (800.0 - 2.0 * w * w, 8.0 * w);
        let norm = re * re + im * im;
        let (db, deg) = db_deg(re / norm, -im / norm);
        assert!(
            (row[2] - db).abs() <= 1e-9,
            "{} Hz: {} vs {db}",
            row[0],
            row[2]
        );
        assert!(
            (row[3] - deg).abs() <= 1e-7,
            "{} Hz: {} vs {deg}",
            row[0],
            row[3]
        );
    }
}

#[test]
fn bad_bands_and_names_are_usage_errors_that_write_nothing() {
    let dir = Scratch::new("bode-errors");
    let out = dir.join("set");
    let o = out.to_str().unwrap();
    for (args, words) in [
        (
            vec![
                "bode",
                "butterworth",
                "--from",
                "10",
                "--to",
                "1",
                "--out",
                o,
            ],
            "must be above",
        ),
        (
            vec!["bode", "butterworth", "--from", "0", "--out", o],
            "> 0 Hz",
        ),
        (
            vec!["bode", "butterworth", "--points", "1", "--out", o],
            "at least 2",
        ),
        (
            vec!["bode", "butterworth", "--output", "vout", "--out", o],
            "`vout`",
        ),
        (vec!["bode", "rlc", "--out", o], "declares no input"),
    ] {
        let failure = run(&MODELS, &args).unwrap_err();
        assert_eq!(failure.exit_code(), 2, "{args:?}: {failure}");
        assert!(failure.to_string().contains(words), "{args:?}: {failure}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    assert!(names(&dir).is_empty());
}
