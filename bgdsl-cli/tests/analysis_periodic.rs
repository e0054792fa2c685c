//! `models periodic` in-process, on a catalogue of this test's own: a damped
//! mass-spring driven by `F cos(ω t)`, whose periodic steady state and Floquet
//! multipliers are known in closed form.
//!
//! - `orbit.csv` is one period of `x = X cos(ω t − φ)`, `X = F / √((k − m ω²)² +
//!   (c ω)²)`, `φ = atan2(c ω, k − m ω²)`, and `p = m ẋ` (any linear-vibration text, e.g.
//!   Meirovitch, *Elements of Vibration Analysis*, §3.2), to 1e-6 of `X` (the orbit and
//!   its samples come from Radau5 at rtol 1e-9; shooting on a linear model converges
//!   in one Newton step).
//! - `floquet.json`'s multipliers are `e^{λ T}` for the eigenvalues `λ = −c/2m ± i
//!   √(k/m − (c/2m)²)` of the state matrix and `T = 2π/ω`, to 1e-6 (the monodromy
//!   matrix's integration error is about 1e-8).
//! - On the catalogue's (non-linear) Duffing oscillator, `ṗ = −k q − k3 q³ − c p/m +
//!   F cos ω t`, `q̇ = p/m`: the trace of the Jacobian is `−c/m` everywhere, so by
//!   Liouville's formula the product of the multipliers is `det Φ = e^{−c T/m}` on any
//!   orbit (to 2e-5 relative: the monodromy matrix comes from the library's SDIRK
//!   integration of the variational equations, 400 steps per period, which misses
//!   Liouville's value by 6e-6 relative here); `orbit.csv`'s last row equals its
//!   first to 1e-4 of each state's scale (the shooting converges to 1e-6 of its own
//!   scale; the samples come from a second run of the same solver); and the figures
//!   and page are written.
//! - The period comes from `--drive omega` (a parameter in rad/s: `T = 2π/ω`) or
//!   `--period`; without either, or with a drive parameter of another unit, the
//!   command refuses with a message saying what to give.

use std::fs;
use std::path::Path;
use std::sync::LazyLock;

use bgdsl_cli::cli::analysis::periodic::PeriodicArgs;
use bgdsl_cli::cli::analysis::ModelArgs;
use bgdsl_cli::cli::{execute, Cli, Command};
use bgdsl_cli::Catalogue;
use bgdsl_runtime::bond_graph;

mod analysis_common;
mod common;
use analysis_common::{csv, MODELS};
use common::Scratch;

/// `orbit.csv` in `out`: header names and rows, every entry a finite number.
fn orbit_csv(out: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let (header, rows) = csv(&out.join("orbit.csv"));
    assert!(
        rows.iter().flatten().all(|v| v.is_finite()),
        "orbit.csv holds a non-number"
    );
    (header, rows)
}

bond_graph! {
    /// A mass on a spring with a damper, driven by `F cos(ω t)`.
    pub model Forced {
        /// mass
        param m = 1.0 in "kg";
        /// stiffness
        param k = 4.0 in "N/m";
        /// damping coefficient
        param c = 0.4 in "N·s/m";
        /// drive amplitude
        param force = 1.0 in "N";
        /// drive angular frequency
        param omega = 3.0 in "rad/s";
        Se drive = force * (omega * t).cos();
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        R damper = c;
        1 v;
        drive -> v -> { mass, spring, damper };
        /// Displacement, m.
        output x = spring.q in "m";
    }
}

static CATALOGUE: LazyLock<Catalogue> = LazyLock::new(|| bgdsl_cli::catalogue![Forced]);

fn args(out: &Path, set: &[&str]) -> PeriodicArgs {
    PeriodicArgs {
        model: ModelArgs {
            target: "forced".to_owned(),
            out: Some(out.to_path_buf()),
            set: set.iter().map(|s| (*s).to_owned()).collect(),
            no_plots: true,
            ..ModelArgs::default()
        },
        ..PeriodicArgs::default()
    }
}

fn periodic(args: PeriodicArgs) -> Result<(), bgdsl_cli::cli::Failure> {
    periodic_in(args, &CATALOGUE)
}

fn periodic_in(
    args: PeriodicArgs,
    catalogue: &'static Catalogue,
) -> Result<(), bgdsl_cli::cli::Failure> {
    execute(
        Cli {
            command: Some(Command::Periodic(Box::new(args))),
        },
        catalogue,
    )
}

#[test]
fn the_orbit_and_multipliers_of_a_driven_oscillator_match_the_closed_form() {
    let scratch = Scratch::new("closed-form");
    let out = scratch.join("orbit");
    let mut a = args(&out, &["c=0.4"]);
    a.drive = Some("omega".to_owned());
    a.points = 50;
    periodic(a).unwrap();

    let (m, k, c, f, w) = (1.0f64, 4.0f64, 0.4f64, 1.0f64, 3.0f64);
    let period = core::f64::consts::TAU / w;
    let amplitude = f / ((k - m * w * w).powi(2) + (c * w).powi(2)).sqrt();
    let phase = (c * w).atan2(k - m * w * w);

    let (header, rows) = orbit_csv(&out);
    assert_eq!(header, ["t", "mass.p", "spring.q", "x"]);
    assert_eq!(rows.len(), 51, "50 intervals over one period, both ends");
    assert!((rows[50][0] - rows[0][0] - period).abs() < 1e-12);
    for row in &rows {
        let t = row[0];
        let x = amplitude * (w * t - phase).cos();
        let p = -m * amplitude * w * (w * t - phase).sin();
        assert!(
            (row[2] - x).abs() < 1e-6 * amplitude,
            "t = {t}: q {} vs {x}",
            row[2]
        );
        assert!(
            (row[3] - x).abs() < 1e-6 * amplitude,
            "t = {t}: x {} vs {x}",
            row[3]
        );
        assert!(
            (row[1] - p).abs() < 1e-6 * amplitude * w,
            "t = {t}: p {} vs {p}",
            row[1]
        );
    }

    let floquet: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("floquet.json")).unwrap()).unwrap();
    assert!((floquet["period"].as_f64().unwrap() - period).abs() < 1e-12);
    let decay = -c / (2.0 * m);
    let omega_d = (k / m - decay * decay).sqrt();
    let mut found: Vec<[f64; 2]> = floquet["multipliers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|pair| [pair[0].as_f64().unwrap(), pair[1].as_f64().unwrap()])
        .collect();
    found.sort_by(|a, b| a[1].total_cmp(&b[1]));
    let modulus = (decay * period).exp();
    let angle = omega_d * period;
    let expected = [
        [modulus * angle.cos(), -modulus * angle.sin().abs()],
        [modulus * angle.cos(), modulus * angle.sin().abs()],
    ];
    for (got, want) in found.iter().zip(&expected) {
        assert!(
            (got[0] - want[0]).abs() < 1e-6 && (got[1] - want[1]).abs() < 1e-6,
            "multiplier {got:?} vs e^(λT) = {want:?}"
        );
    }
    assert_eq!(floquet["stability"], "attracting");
    // The results set: the data files, the record, the page.
    for name in ["run.yaml", "index.html", "orbit.units.csv"] {
        assert!(out.join(name).is_file(), "{name} missing");
    }
}

#[test]
fn the_period_is_required_and_a_drive_parameter_must_be_a_frequency() {
    let scratch = Scratch::new("no-period");
    let out = scratch.join("orbit");
    let message = periodic(args(&out, &[])).unwrap_err().to_string();
    assert!(
        message.contains("--period") && message.contains("--drive"),
        "{message}"
    );
    let mut a = args(&out, &[]);
    a.drive = Some("m".to_owned());
    let message = periodic(a).unwrap_err().to_string();
    assert!(
        message.contains("`m`") && message.contains("kg"),
        "{message}"
    );
    let mut a = args(&out, &[]);
    a.drive = Some("nope".to_owned());
    let message = periodic(a).unwrap_err().to_string();
    assert!(message.contains("no parameter `nope`"), "{message}");
    let mut a = args(&out, &[]);
    a.period = Some(-1.0);
    let message = periodic(a).unwrap_err().to_string();
    assert!(message.contains("positive"), "{message}");
    let mut a = args(&out, &[]);
    a.period = Some(1.0);
    a.shift = vec!["theta=6.28".to_owned()];
    let message = periodic(a).unwrap_err().to_string();
    assert!(message.contains("no state `theta`"), "{message}");
    let mut a = args(&out, &[]);
    a.period = Some(1.0);
    a.shift = vec!["spring.q=two".to_owned()];
    let message = periodic(a).unwrap_err().to_string();
    assert!(message.contains("not a finite number"), "{message}");
    assert!(!out.exists(), "nothing is written");
}

#[test]
fn the_catalogue_duffing_orbit_closes_and_its_multipliers_obey_liouville() {
    let scratch = Scratch::new("duffing");
    let out = scratch.join("orbit");
    let mut a = args(&out, &[]);
    a.model.target = "duffing".to_owned();
    a.model.no_plots = false;
    a.drive = Some("omega".to_owned());
    a.warmup = 5;
    a.points = 100;
    periodic_in(a, &MODELS).unwrap();

    // The catalogue's defaults: m = 1 kg, c = 0.1 N·s/m, ω = 1.2 rad/s.
    let (m, c, w) = (1.0f64, 0.1f64, 1.2f64);
    let period = core::f64::consts::TAU / w;
    let floquet: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("floquet.json")).unwrap()).unwrap();
    let pairs: Vec<(f64, f64)> = floquet["multipliers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    assert_eq!(pairs.len(), 2);
    // The product of a conjugate pair or of two real multipliers.
    let product = (
        pairs[0].0 * pairs[1].0 - pairs[0].1 * pairs[1].1,
        pairs[0].0 * pairs[1].1 + pairs[0].1 * pairs[1].0,
    );
    let liouville = (-c * period / m).exp();
    assert!(
        (product.0 / liouville - 1.0).abs() < 2e-5 && product.1.abs() < 1e-12,
        "det Φ = {product:?}, e^(−cT/m) = {liouville}"
    );
    assert_eq!(floquet["stability"], "attracting");

    let (header, rows) = orbit_csv(&out);
    assert_eq!(&header[..3], ["t", "mass.p", "spring.q"]);
    let (first, last) = (&rows[0], &rows[rows.len() - 1]);
    assert!((last[0] - first[0] - period).abs() < 1e-12);
    let scale = first[1].abs().max(first[2].abs());
    for i in 1..=2 {
        let tolerance = 1e-4 * (first[i].abs() + 1e-3 * scale);
        assert!(
            (last[i] - first[i]).abs() <= tolerance,
            "{}: {} → {}",
            header[i],
            first[i],
            last[i]
        );
    }
    for name in [
        "floquet_multipliers.svg",
        "orbit_x.png",
        "orbit_spring_q.svg",
        "index.html",
    ] {
        assert!(out.join(name).is_file(), "{name} missing");
    }
    let page = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains("Floquet multipliers") && page.contains("inside the unit circle"));
}
