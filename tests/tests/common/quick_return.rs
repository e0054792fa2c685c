//! Checks of a quick return model's flagship run (`models::quick_return`), generic over
//! the model: any [`Model`] whose outputs carry the spec's column names
//! (`shared/quick-return-spec.md`, "The results file"). `tests/quick_return_results.rs`
//! runs them on the hand-written model; the model written in the bond-graph language
//! runs the same checks with one line each:
//!
//! ```ignore
//! let run = quick_return::flagship_run(&model, "generated"); // share it (OnceLock)
//! quick_return::check_results_file(&run);      // header, rows, times, crank angle
//! quick_return::check_signs(&run, weight);     // each force on the named link
//! quick_return::check_default_scenario(&run);  // period, time ratio, momentum peaks
//! quick_return::check_planar(&run);            // out-of-plane components zero
//! quick_return::check_transients_decay(&run);
//! quick_return::check_orthonormal(&run);       // RᵀR = I for R1 and R4
//! quick_return::check_summary(&run);           // stroke ≈ 0.7 m, ratio just under 2
//! quick_return::check_runs(&model_without_gravity, "generated_g0");
//! quick_return::check_energy_balance(&model); // E(5) − E(0) = ∫P_in − ∫P_diss
//! quick_return::check_failure_leaves_nothing(&model, "generated_failure");
//! quick_return::check_recording_allocates_nothing(&model); // with `counting` installed
//! ```
//!
//! Every tolerance says where it comes from.

use std::f64::consts::{FRAC_PI_2, TAU};
use std::fs;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::time::Duration;

use bgdsl_runtime::{Model, Radau5Options, Scalar, Simulation, Solver};
use models::quick_return::results::{sample_time, Results, COLUMNS, FILE_NAME, N_ROWS, T_END};
use models::quick_return::run::{run_flagship, Error};
use models::quick_return::summary::Summary;

/// The spec's header row, typed in from the spec's table (not built from
/// [`COLUMNS`], so that it checks that constant too).
pub const SPEC_HEADER: &str = "t,crank_angle,\
R1_11,R1_21,R1_31,R1_12,R1_22,R1_32,R1_13,R1_23,R1_33,\
h1_x,h1_y,h1_z,F_O1_x,F_O1_y,F_O1_z,Tc_x,Tc_y,Tc_z,F_A2_x,F_A2_y,F_A2_z,\
r_C3_x,r_C3_y,r_C3_z,p3_x,p3_y,p3_z,F_O3_x,F_O3_y,F_O3_z,\
R4_11,R4_21,R4_31,R4_12,R4_22,R4_32,R4_13,R4_23,R4_33,\
r_C5_x,r_C5_y,r_C5_z,p5_x,p5_y,p5_z,F_O5_x,F_O5_y,F_O5_z,F_5C_x,F_5C_y,F_5C_z,\
E_stored,P_in,P_diss";

/// The crank's period at the drive's 5 rad/s, s.
pub const PERIOD: f64 = TAU / 5.0;

/// Radau5 with the given tolerances.
pub fn radau5(rtol: f64, atol: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol,
        ..Default::default()
    })
}

/// The solver of the checks: Radau5 at rtol 1e-6 and atol 1e-10. The smallest states
/// whose accuracy shows in the results are the joints' deflections, `q = F / K`: about
/// 1e-4 m for 10 N at 1e5 N/m. Radau5 scales both tolerances by `0.1 rtol^(-1/3)` (×10
/// here), so atol 1e-10 holds them to ~1e-9 m, i.e. 1e-4 N in force, ~1e-6 of the
/// peak forces (~250 N) — the level rtol sets for everything else. Measured on the hand
/// model against a run at rtol 1e-10: the largest deviation of any column is 6.5e-6 of
/// its peak with atol 1e-10, against 1.7e-5 with 1e-9 and 4.8e-5 with 1e-8, and 5.1e-6
/// with 1e-11 (no longer limited by atol).
pub fn flagship_solver() -> Solver {
    radau5(1e-6, 1e-10)
}

/// An empty scratch directory `name` under the target's temporary directory.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("quick_return")
        .join(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("a scratch directory");
    dir
}

/// The file names in `dir`, sorted.
pub fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .expect("a readable directory")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A results file read back: its header line and its columns, in the file's order.
#[derive(Clone, Debug)]
pub struct Csv {
    /// The first line.
    pub header: String,
    /// The values, one vector per column of [`COLUMNS`].
    pub columns: Vec<Vec<f64>>,
    /// Whether the file ends with a line break.
    pub ends_with_newline: bool,
}

impl Csv {
    /// Reads the results file at `path`, panicking on anything that is not a header and
    /// rows of 56 numbers.
    pub fn read(path: &Path) -> Csv {
        let text = fs::read_to_string(path).expect("the results file");
        let mut lines = text.lines();
        let header = lines.next().expect("a header row").to_owned();
        let mut columns = vec![Vec::with_capacity(N_ROWS); COLUMNS.len()];
        for (row, line) in lines.enumerate() {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(
                fields.len(),
                COLUMNS.len(),
                "row {row} has {} fields",
                fields.len()
            );
            for (column, field) in columns.iter_mut().zip(fields) {
                column.push(
                    field
                        .parse()
                        .unwrap_or_else(|_| panic!("row {row}: `{field}` is not a number")),
                );
            }
        }
        Csv {
            header,
            columns,
            ends_with_newline: text.ends_with('\n'),
        }
    }

    /// The number of data rows.
    pub fn rows(&self) -> usize {
        self.columns[0].len()
    }

    /// Column `name`.
    pub fn col(&self, name: &str) -> &[f64] {
        let i = COLUMNS
            .iter()
            .position(|c| *c == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        &self.columns[i]
    }

    /// The sample times.
    pub fn t(&self) -> &[f64] {
        &self.columns[0]
    }

    /// The rows with `from <= t <= to`.
    pub fn rows_between(&self, from: f64, to: f64) -> core::ops::Range<usize> {
        let t = self.t();
        t.partition_point(|&v| v < from)..t.partition_point(|&v| v <= to)
    }

    /// Column `name` at time `t` (linear interpolation between the samples).
    pub fn at(&self, name: &str, t: f64) -> f64 {
        let times = self.t();
        let k = times.partition_point(|&v| v <= t).clamp(1, times.len() - 1);
        let (t0, t1) = (times[k - 1], times[k]);
        let c = self.col(name);
        c[k - 1] + (t - t0) / (t1 - t0) * (c[k] - c[k - 1])
    }
}

/// The flagship run of a model, as written and summarised.
#[derive(Debug)]
pub struct FlagshipRun {
    /// What `run_flagship` returned.
    pub summary: Summary,
    /// The results file read back.
    pub csv: Csv,
    /// The directory it was written to.
    pub dir: PathBuf,
}

/// Runs `model` as the flagship ([`run_flagship`] with [`flagship_solver`]) into the
/// scratch directory `name` and reads the results file back.
pub fn flagship_run<M: Model>(model: &M, name: &str) -> FlagshipRun {
    let dir = scratch_dir(name);
    let summary = run_flagship(model, flagship_solver(), &dir)
        .unwrap_or_else(|e| panic!("the flagship run of {}: {e}", M::NAME));
    eprintln!("{summary}");
    let csv = Csv::read(&dir.join(FILE_NAME));
    FlagshipRun { summary, csv, dir }
}

/// The largest absolute value.
fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The results file is the spec's: the exact header; 5001 rows, at `t = k / 1000`
/// exactly (the CSV writes numbers so that they read back bit for bit); every value
/// finite; the directory holds the file and nothing else (no temporary file left); the
/// crank angle starts at π/2 (to 1e-12: the model's atan2 of its initial orientation,
/// rounding only), is continuous (no step over 0.1 rad between rows; at 5 rad/s a row
/// advances 0.005 rad) and advances at 5 rad/s on average once settled (over the last
/// whole crank period, to 0.5 %, as the period).
pub fn check_results_file(run: &FlagshipRun) {
    let csv = &run.csv;
    assert_eq!(csv.header, SPEC_HEADER);
    assert_eq!(COLUMNS.join(","), SPEC_HEADER);
    assert!(csv.ends_with_newline);
    assert_eq!(csv.rows(), N_ROWS);
    assert_eq!(run.summary.rows, N_ROWS);
    for (k, &t) in csv.t().iter().enumerate() {
        assert_eq!(
            t.to_bits(),
            (k as f64 / 1000.0).to_bits(),
            "row {k}: t = {t}"
        );
        assert_eq!(t, sample_time(k));
    }
    assert_eq!(csv.t()[N_ROWS - 1], T_END);
    for (name, column) in COLUMNS.iter().zip(&csv.columns) {
        assert!(column.iter().all(|v| v.is_finite()), "{name} is not finite");
    }
    assert_eq!(files_in(&run.dir), [FILE_NAME]);

    let angle = csv.col("crank_angle");
    assert!(
        (angle[0] - FRAC_PI_2).abs() <= 1e-12,
        "crank_angle starts at {}",
        angle[0]
    );
    let largest_step = angle
        .windows(2)
        .fold(0.0f64, |m, w| m.max((w[1] - w[0]).abs()));
    eprintln!("largest crank-angle step between rows: {largest_step:.5} rad");
    assert!(largest_step <= 0.1, "crank_angle jumps by {largest_step}");
    let speed = (csv.at("crank_angle", T_END) - csv.at("crank_angle", T_END - PERIOD)) / PERIOD;
    eprintln!("mean crank speed over the last period: {speed:.6} rad/s");
    assert!(
        (speed / 5.0 - 1.0).abs() <= 5e-3,
        "mean crank speed {speed}"
    );
    // The angle is the spec's atan2(R1[1][0], R1[1][1]) plus whole turns (to rounding
    // of the angle's size, ~30 rad).
    let (r21, r22) = (csv.col("R1_21"), csv.col("R1_22"));
    for k in 0..csv.rows() {
        let turns = (angle[k] - r21[k].atan2(r22[k])) / TAU;
        assert!(
            (turns - turns.round()).abs() <= 1e-12,
            "row {k}: crank_angle {} is not atan2(R1_21, R1_22) plus whole turns",
            angle[k]
        );
    }
}

/// The crank's length O1–A1 (the spec's fixed geometry), m.
pub const CRANK_LENGTH: f64 = 0.2;

/// The signs of the forces and torques: each is the one the named coupling exerts on
/// the named link (the spec's convention), shown by balances that hold only with the
/// right signs:
/// - at t = 0 the drive torque is R_C · 5 rad/s > 0 on the crank (counter-clockwise,
///   along +Z0): `Tc_z(0) > 0`;
/// - the ground holds the mechanism up: over the last whole period the mean of
///   `F_O1_y + F_O3_y + F_5C_y` (the only forces from the ground) is the total weight
///   `weight` (the mean of d/dt of the total momentum over a period is its change over
///   the period divided by T, nearly zero once settled), to 0.1 % of the weight (the
///   trapezoid rule on the 1 ms samples and the remaining transient; 1.3e-4 is seen on
///   the hand model); the mean horizontal force is zero to the same;
/// - the output slider: `dp5_x/dt = F_O5_x + F_5C_x` (the rod coupling and the guide are
///   the only forces on it along X0), with dp5_x/dt by central differences of the
///   1 ms samples over 2.5–5 s, to 0.1 % of the force's peak (the differences' error,
///   h²/6 of the third derivative: 7e-6 is seen on the hand model, whose forces are
///   smooth once settled; a wrong sign would leave an error of the order of the peak);
/// - the crank: `dh1_z/dt = Tc_z + (a_O1 × F_O1)_z − (a_A1 × F_A2)_z`, the couplings acting
///   at O1 and A1, at arms `a = ∓(CRANK_LENGTH / 2) e1` from its centre (`e1`, the
///   crank's body x-axis, is the first column of R1), and the crank receiving −F_A2 at
///   A1; same differences and tolerance, of the peak |Tc_z| (6e-7 is seen).
pub fn check_signs(run: &FlagshipRun, weight: f64) {
    let csv = &run.csv;
    assert!(csv.col("Tc_z")[0] > 0.0, "Tc_z(0) = {}", csv.col("Tc_z")[0]);

    let last_period = csv.rows_between(T_END - PERIOD, T_END);
    let mean_over = |f: &dyn Fn(usize) -> f64| {
        // Trapezoid rule over the rows, then the partial first interval.
        let t = csv.t();
        let mut integral = 0.0;
        for k in last_period.start + 1..last_period.end {
            integral += 0.5 * (f(k) + f(k - 1)) * (t[k] - t[k - 1]);
        }
        integral / (t[last_period.end - 1] - t[last_period.start])
    };
    let lift = mean_over(&|k| csv.col("F_O1_y")[k] + csv.col("F_O3_y")[k] + csv.col("F_5C_y")[k]);
    let side = mean_over(&|k| csv.col("F_O1_x")[k] + csv.col("F_O3_x")[k] + csv.col("F_5C_x")[k]);
    eprintln!("ground forces over the last period: mean x {side:.4} N, mean y {lift:.4} N (weight {weight} N)");
    assert!(
        (lift - weight).abs() <= 1e-3 * weight.max(1.0),
        "the ground holds up {lift} N of {weight} N"
    );
    assert!(
        side.abs() <= 1e-3 * weight.max(1.0),
        "mean horizontal ground force {side} N"
    );

    let window = csv.rows_between(2.5, T_END);
    let t = csv.t();
    let rate = |name: &str, k: usize| {
        let c = csv.col(name);
        (c[k + 1] - c[k - 1]) / (t[k + 1] - t[k - 1])
    };
    let residual = |lhs: &str, rhs: &dyn Fn(usize) -> f64, scale: f64| {
        let worst = (window.start.max(1)..window.end.min(csv.rows() - 1))
            .map(|k| (rate(lhs, k) - rhs(k)).abs())
            .fold(0.0f64, f64::max);
        worst / scale
    };
    let col = |name: &str| csv.col(name);
    let slider_force = |k: usize| col("F_O5_x")[k] + col("F_5C_x")[k];
    let slider_scale = max_abs(&col("F_O5_x")[window.clone()]);
    let slider = residual("p5_x", &slider_force, slider_scale);
    let half = 0.5 * CRANK_LENGTH;
    let crank_torque = |k: usize| {
        let (ex, ey) = (col("R1_11")[k], col("R1_21")[k]);
        let cross = |fx: f64, fy: f64| ex * fy - ey * fx;
        col("Tc_z")[k]
            - half * cross(col("F_O1_x")[k], col("F_O1_y")[k])
            - half * cross(col("F_A2_x")[k], col("F_A2_y")[k])
    };
    let crank_scale = max_abs(&col("Tc_z")[window.clone()]);
    let crank = residual("h1_z", &crank_torque, crank_scale);
    eprintln!(
        "momentum balances over 2.5-5 s: output slider {slider:.2e} of the peak F_O5_x, \
         crank {crank:.2e} of the peak Tc_z"
    );
    assert!(
        slider <= 1e-3,
        "dp5_x/dt ≠ F_O5_x + F_5C_x: {slider:e} of the peak"
    );
    assert!(
        crank <= 1e-3,
        "dh1_z/dt ≠ the torques on the crank: {crank:e} of the peak"
    );
}

/// The qualitative findings of the paper in the default scenario, measured over the
/// settled 2.5–5 s by the summary:
/// - the period is 2π/5 s to 0.5 % (the crank follows the 5 rad/s source through a
///   compliant coupling that relaxes with R_C/K_C = 1 s, so a trace of the start is
///   left at 2.5 s; 0.04 % is seen on the hand model), and the slider's period agrees;
/// - the return stroke is the quicker: time ratio 2.0 ± 0.1 (exactly 2 for rigid links;
///   the joints' deflections shift the turning points: 1.945 is seen on the hand
///   model), with the larger momentum peak (|p5_x| during the return above that during
///   the forward stroke);
/// - the window holds complete strokes of both kinds (at least 3 turning points).
pub fn check_default_scenario(run: &FlagshipRun) {
    let m = &run.summary.measured;
    assert!(m.turning_points.len() >= 3, "{:?}", m.turning_points);
    let period = m.period.expect("a measured period");
    assert!(
        (period / PERIOD - 1.0).abs() <= 5e-3,
        "period {period} s, expected {PERIOD} s"
    );
    let slider = m.slider_period.expect("a slider period");
    assert!(
        (slider / PERIOD - 1.0).abs() <= 5e-3,
        "slider period {slider} s"
    );
    let ratio = m.time_ratio.expect("a time ratio");
    assert!((ratio - 2.0).abs() <= 0.1, "time ratio {ratio}");
    let forward = m.forward_time.unwrap();
    let back = m.return_time.unwrap();
    assert!(back < forward, "return {back} s, forward {forward} s");
    let (fwd_peak, ret_peak) = (
        m.forward_momentum_peak.unwrap(),
        m.return_momentum_peak.unwrap(),
    );
    assert!(
        ret_peak > fwd_peak,
        "peak momentum: return {ret_peak}, forward {fwd_peak}"
    );
}

/// The motion stays in the plane: the out-of-plane components of every force,
/// momentum and position (z), of the crank's angular momentum and drive torque (x, y),
/// and of the orientations (R_13, R_23, R_31, R_32; R_33 − 1) stay below 1e-9 of their
/// vector's peak magnitude over the run (of 1 for the orientations). No term of the
/// equations feeds them from an in-plane start, so they are zero but for rounding.
pub fn check_planar(run: &FlagshipRun) {
    let csv = &run.csv;
    let norm_peak = |prefix: &str| {
        let [x, y, z] = ["x", "y", "z"].map(|a| csv.col(&format!("{prefix}_{a}")));
        (0..csv.rows()).fold(0.0f64, |m, k| {
            m.max((x[k] * x[k] + y[k] * y[k] + z[k] * z[k]).sqrt())
        })
    };
    let vectors: [(&str, &[&str]); 11] = [
        ("F_O1", &["z"]),
        ("F_A2", &["z"]),
        ("F_O3", &["z"]),
        ("F_O5", &["z"]),
        ("F_5C", &["z"]),
        ("p3", &["z"]),
        ("p5", &["z"]),
        ("r_C3", &["z"]),
        ("r_C5", &["z"]),
        ("h1", &["x", "y"]),
        ("Tc", &["x", "y"]),
    ];
    for (prefix, components) in vectors {
        let scale = norm_peak(prefix);
        assert!(scale > 0.0, "{prefix} is zero throughout");
        for c in components {
            let name = format!("{prefix}_{c}");
            let worst = max_abs(csv.col(&name));
            assert!(
                worst <= 1e-9 * scale,
                "{name} leaves the plane: {worst:e} (scale {scale})"
            );
        }
    }
    for r in ["R1", "R4"] {
        for entry in ["13", "23", "31", "32"] {
            let name = format!("{r}_{entry}");
            let worst = max_abs(csv.col(&name));
            assert!(worst <= 1e-9, "{name} = {worst:e}");
        }
        let name = format!("{r}_33");
        let worst = csv
            .col(&name)
            .iter()
            .fold(0.0f64, |m, v| m.max((v - 1.0).abs()));
        assert!(worst <= 1e-9, "{name} − 1 = {worst:e}");
    }
}

/// The start-up transients die out:
/// - the peak |Tc_z| over 0–0.5 s (the sudden start: the drive damper alone gives
///   R_C · 5 rad/s = 500 N·m at t = 0) exceeds that over 4.5–5 s;
/// - the cycle-to-cycle difference of the drive torque and of the in-plane joint
///   forces, `max |F(t + T) − F(t)|` over one period `T` (samples `t + T` linearly
///   interpolated), is at most a quarter as large between the last two periods (from
///   5 − 2T) as between the first two after the start (from 0.5 s). The slowest
///   transient is the drive coupling's, e^(−t / 1 s) (R_C/K_C = 1 s), which predicts a
///   factor of about e^(−2) ≈ 0.14 between the two (0.085 is seen on the hand model for
///   every signal).
pub fn check_transients_decay(run: &FlagshipRun) {
    let csv = &run.csv;
    let peak_over =
        |name: &str, from: f64, to: f64| max_abs(&csv.col(name)[csv.rows_between(from, to)]);
    let (early, late) = (peak_over("Tc_z", 0.0, 0.5), peak_over("Tc_z", 4.5, 5.0));
    eprintln!("peak |Tc_z|: {early:.3} N·m over 0-0.5 s, {late:.3} N·m over 4.5-5 s");
    assert!(early > late, "peak |Tc_z| {early} early, {late} late");

    let difference = |name: &str, from: f64| {
        let t = csv.t();
        csv.rows_between(from, from + PERIOD)
            .map(|k| (csv.at(name, t[k] + PERIOD) - csv.col(name)[k]).abs())
            .fold(0.0f64, f64::max)
    };
    for name in [
        "Tc_z", "F_O1_x", "F_O1_y", "F_A2_x", "F_A2_y", "F_O3_x", "F_O3_y", "F_O5_x", "F_O5_y",
    ] {
        let first = difference(name, 0.5);
        let last = difference(name, T_END - 2.0 * PERIOD);
        let peak = max_abs(csv.col(name));
        eprintln!(
            "{name}: cycle-to-cycle difference {:.2e} then {:.2e} of the peak {peak:.2}",
            first / peak,
            last / peak
        );
        assert!(
            last <= 0.25 * first,
            "{name}: cycle-to-cycle difference {first} early, {last} late"
        );
    }
}

/// The orientation matrices stay orthonormal: at every row, `RᵀR − I` (R1 and R4,
/// rebuilt from their columns `R_ij`) is below 1e-6 in every entry, and `det R > 0`.
/// `dR/dt = skew(w) R` keeps `RᵀR` constant exactly, so only the solver's error
/// (rtol 1e-6) drifts it.
pub fn check_orthonormal(run: &FlagshipRun) {
    let csv = &run.csv;
    for r in ["R1", "R4"] {
        let entry: Vec<Vec<&[f64]>> = (1..=3)
            .map(|i| (1..=3).map(|j| csv.col(&format!("{r}_{i}{j}"))).collect())
            .collect();
        let matrix = |k: usize| -> [[f64; 3]; 3] {
            core::array::from_fn(|i| core::array::from_fn(|j| entry[i][j][k]))
        };
        let mut worst: f64 = 0.0;
        for k in 0..csv.rows() {
            let rows = matrix(k);
            let m = |i: usize, j: usize| rows[i][j];
            for a in 0..3 {
                for b in 0..3 {
                    let dot: f64 = (0..3).map(|i| m(i, a) * m(i, b)).sum();
                    let identity = if a == b { 1.0 } else { 0.0 };
                    worst = worst.max((dot - identity).abs());
                }
            }
            let det = m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1))
                - m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0))
                + m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
            assert!(det > 0.0, "{r} at row {k}: det {det}");
        }
        eprintln!("{r}: largest |RᵀR − I| entry {worst:e}");
        assert!(worst <= 1e-6, "{r}: |RᵀR − I| reaches {worst:e}");
    }
}

/// The summary's measurements of the default model: the stroke within 1 cm of the
/// rigid 0.7 m (the compliant joints shift the turning points; 0.7020 m is seen on the
/// hand model), the time ratio a little under 2 (in [1.9, 2): 1.945 is seen), the
/// period 2π/5 s to 0.5 %; they agree with the file (stroke = max − min of r_C5_x over
/// 2.5–5 s); the peaks are positive and finite; and the solver did work.
pub fn check_summary(run: &FlagshipRun) {
    let s = &run.summary;
    let m = &s.measured;
    assert!((m.stroke - 0.7).abs() <= 0.01, "stroke {} m", m.stroke);
    let x5 = &run.csv.col("r_C5_x")[run.csv.rows_between(2.5, 5.0)];
    let (lo, hi) = x5
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    assert_eq!(m.stroke, hi - lo);
    let ratio = m.time_ratio.unwrap();
    assert!((1.9..2.0).contains(&ratio), "time ratio {ratio}");
    let period = m.period.unwrap();
    assert!((period / PERIOD - 1.0).abs() <= 5e-3, "period {period}");
    assert!(m.drive_torque.value > 0.0 && m.drive_torque.value.is_finite());
    assert!(m.drive_torque_z.value <= m.drive_torque.value);
    for p in &m.joint_forces {
        assert!(p.value > 0.0 && p.value.is_finite(), "{p:?}");
        assert!((2.5..=5.0).contains(&p.t), "{p:?}");
    }
    assert!(s.stats.accepted > 0 && s.stats.n_jac > 0 && s.stats.n_lu > 0);
    assert!(s.file.is_some());
    let table = s.to_string();
    for label in [
        "solver",
        "steps",
        "derivatives",
        "Jacobians",
        "wall time",
        "stroke",
        "time ratio",
        "period",
        "drive torque",
        "|F_O1|",
        "|F_A2|",
        "|F_O3|",
        "|F_O5|",
    ] {
        assert!(
            table.contains(label),
            "the summary lacks `{label}`:\n{table}"
        );
    }
}

/// `model` (meant: the default with g = 0) runs through the flagship, writes a
/// complete file, and still moves periodically (period to 0.5 %).
pub fn check_runs<M: Model>(model: &M, name: &str) {
    let run = flagship_run(model, name);
    assert_eq!(run.csv.rows(), N_ROWS);
    assert_eq!(files_in(&run.dir), [FILE_NAME]);
    let period = run.summary.measured.period.expect("a period");
    assert!((period / PERIOD - 1.0).abs() <= 5e-3, "period {period}");
}

/// A run that fails (a wall-time limit of 1 ns, reached before the first step) returns
/// [`Error::Solver`] saying so, and leaves the output directory as it was: empty when
/// it was empty (no results file, no temporary file), and with an earlier results file
/// unchanged byte for byte.
pub fn check_failure_leaves_nothing<M: Model>(model: &M, name: &str) {
    let solver = Solver::Radau5(Radau5Options {
        max_wall_time: Some(Duration::from_nanos(1)),
        ..Default::default()
    });
    let dir = scratch_dir(name);
    let err = run_flagship(model, solver, &dir).expect_err("a 1 ns wall-time limit");
    let message = err.to_string();
    eprintln!("{message}");
    assert!(matches!(err, Error::Solver { .. }), "{err:?}");
    assert!(message.contains("wall-time limit"), "{message}");
    assert!(message.contains(M::NAME), "{message}");
    assert!(
        files_in(&dir).is_empty(),
        "left behind: {:?}",
        files_in(&dir)
    );

    let earlier = "an earlier results file\n";
    fs::write(dir.join(FILE_NAME), earlier).unwrap();
    run_flagship(model, solver, &dir).expect_err("a 1 ns wall-time limit");
    assert_eq!(files_in(&dir), [FILE_NAME]);
    assert_eq!(fs::read_to_string(dir.join(FILE_NAME)).unwrap(), earlier);

    // A directory that cannot be created (its parent is a file): an I/O error naming it.
    let blocked = dir.join(FILE_NAME).join("sub");
    let err = run_flagship(model, flagship_solver_short(), &blocked)
        .expect_err("a directory under a file");
    assert!(matches!(err, Error::Io { .. }), "{err:?}");
    assert!(
        err.to_string().contains(&*blocked.to_string_lossy()),
        "{err}"
    );
}

/// Recording is free of heap allocation once set up: a 0–5 s run of `model` with
/// [`flagship_solver`] into [`Results`] made with room for the 5001 samples, the
/// simulation's workspace allocated beforehand, makes no allocation, as counted by
/// [`super::counting`] (the test binary must install its counting allocator).
pub fn check_recording_allocates_nothing<M: Model>(model: &M) {
    use super::counting::allocations_in;
    let (seen, ()) = allocations_in(|| drop(Results::for_model::<M>(N_ROWS)));
    assert!(
        seen > 0,
        "the counter does not see the set-up's allocations"
    );
    let times: Vec<f64> = (0..N_ROWS).map(sample_time).collect();
    let mut results = Results::for_model::<M>(N_ROWS).unwrap();
    let mut sim = Simulation::new(model, flagship_solver()).unwrap();
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let (n, ()) = allocations_in(|| {
        sim.run(0.0, &x0, &times, &mut results).unwrap();
    });
    assert_eq!(results.len(), N_ROWS);
    assert_eq!(n, 0, "recording the run allocated {n} times");
}

/// A cheap solver for runs whose results do not matter (loose tolerances).
fn flagship_solver_short() -> Solver {
    radau5(1e-3, 1e-6)
}

/// The energy balance over the whole run: `E_stored(t) − E_stored(0) = ∫P_in − ∫P_diss`
/// at every 1 ms sample and at 5 s, to 1e-6 of the drive's work `∫P_in` over 0–5 s, at
/// Radau5 rtol 1e-8 (atol 1e-12, scaled as in [`flagship_solver`]).
///
/// The integrals are integrated by the solver with the model ([`WithWork`]), not by the
/// trapezoid rule on the samples: the start is a jump (the drive damper takes the crank
/// from rest to 5 rad/s within J/R_C ≈ 2e-5 s, at P_in = 2500 W) and the joints ring at
/// ~160 Hz, so the rule would err by far more than 1e-6 of the work at 1 ms spacing.
/// Both sides then carry only the solver's error, about rtol; 1e-6 leaves a factor of
/// 100.
pub fn check_energy_balance<M: Model>(model: &M) {
    let adapted = WithWork::new(model);
    let n = M::N_STATES;
    let mut x0 = vec![0.0; n + 2];
    adapted.initial_state(&mut x0);
    let e_at = M::OUTPUT_NAMES
        .iter()
        .position(|o| *o == "E_stored")
        .expect("an output E_stored");
    let mut sim = Simulation::new(&adapted, radau5(1e-8, 1e-12)).unwrap();
    let mut samples: Vec<[f64; 4]> = Vec::with_capacity(N_ROWS);
    let mut keep = |t: f64, x: &[f64], y: &[f64]| samples.push([t, y[e_at], x[n], x[n + 1]]);
    let times: Vec<f64> = (0..N_ROWS).map(sample_time).collect();
    let stats = sim.run(0.0, &x0, &times, &mut keep).unwrap();
    let [_, e0, _, _] = samples[0];
    let [_, e_end, w_in, w_diss] = samples[N_ROWS - 1];
    eprintln!(
        "energy, 0-5 s: {stats:?}; E(5) − E(0) = {:.9} J, ∫P_in = {w_in:.9} J, ∫P_diss = \
         {w_diss:.9} J",
        e_end - e0
    );
    let residual = |e: f64, w_in: f64, w_diss: f64| (e - e0 - (w_in - w_diss)).abs();
    let at_end = residual(e_end, w_in, w_diss);
    let worst = samples
        .iter()
        .map(|s| residual(s[1], s[2], s[3]))
        .fold(0.0f64, f64::max);
    eprintln!(
        "energy residual: {:.2e} of ∫P_in at 5 s, {:.2e} at worst over the samples",
        at_end / w_in,
        worst / w_in
    );
    assert!(w_in > 0.0);
    assert!(
        at_end <= 1e-6 * w_in,
        "at 5 s: residual {at_end} J of {w_in} J"
    );
    assert!(
        worst <= 1e-6 * w_in,
        "along the run: residual {worst} J of {w_in} J"
    );
}

/// The most states and outputs a model may have for [`WithWork`].
const MAX_STATES: usize = 1024;
const MAX_OUTPUTS: usize = 256;

/// The state names of `M` followed by `W_in` and `W_diss`, built at compile time.
struct WorkNames<M>(PhantomData<M>);

impl<M: Model> WorkNames<M> {
    const ALL: [&'static str; MAX_STATES] = {
        assert!(
            M::N_STATES + 2 <= MAX_STATES,
            "too many states for WithWork"
        );
        assert!(M::N_OUTPUTS <= MAX_OUTPUTS, "too many outputs for WithWork");
        let mut names = [""; MAX_STATES];
        let mut i = 0;
        while i < M::N_STATES {
            names[i] = M::STATE_NAMES[i];
            i += 1;
        }
        names[M::N_STATES] = "W_in";
        names[M::N_STATES + 1] = "W_diss";
        names
    };
    const ALL_REF: &'static [&'static str; MAX_STATES] = &Self::ALL;
    const NAMES: &'static [&'static str] = Self::ALL_REF.split_at(M::N_STATES + 2).0;
}

/// Model `M` with two more states, the drive's work `W_in = ∫P_in dt` and the
/// dissipated energy `W_diss = ∫P_diss dt` (from its outputs `P_in` and `P_diss`), so
/// that the solver integrates them with the same accuracy as the motion. The Jacobian
/// is dense (no sparsity pattern is declared), which costs time, not accuracy.
pub struct WithWork<'m, M> {
    model: &'m M,
    p_in: usize,
    p_diss: usize,
}

impl<'m, M: Model> WithWork<'m, M> {
    /// `model` with the two integrals.
    pub fn new(model: &'m M) -> Self {
        let at = |name: &str| {
            M::OUTPUT_NAMES
                .iter()
                .position(|o| *o == name)
                .unwrap_or_else(|| panic!("{} has no output {name}", M::NAME))
        };
        WithWork {
            model,
            p_in: at("P_in"),
            p_diss: at("P_diss"),
        }
    }
}

impl<M: Model> Model for WithWork<'_, M> {
    type Params = M::Params;
    const NAME: &'static str = M::NAME;
    const STATE_NAMES: &'static [&'static str] = WorkNames::<M>::NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = M::OUTPUT_NAMES;

    fn params(&self) -> &M::Params {
        self.model.params()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        let n = M::N_STATES;
        self.model.initial_state(&mut x0[..n]);
        x0[n] = 0.0;
        x0[n + 1] = 0.0;
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let n = M::N_STATES;
        self.model.derivatives(t, &x[..n], &mut dx[..n]);
        let mut y = [T::from_f64(0.0); MAX_OUTPUTS];
        self.model.outputs(t, &x[..n], &mut y[..M::N_OUTPUTS]);
        dx[n] = y[self.p_in];
        dx[n + 1] = y[self.p_diss];
    }

    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        self.model.outputs(t, &x[..M::N_STATES], y);
    }

    fn default_solver(&self) -> Solver {
        self.model.default_solver()
    }
}
