//! What a quick return run measured, over its settled part, and what it cost.
//!
//! The measurements ([`Measured`]) are taken from the results-file columns alone, over
//! the window [`WINDOW`] = 2.5–5 s (after the start-up transient), so they apply to any
//! model recorded into [`Results`]:
//!
//! - **Stroke**: `max − min` of `r_C5_x` over the window's samples.
//! - **Turning points** of the output slider: the instants where `r_C5_x` stops and
//!   reverses, i.e. where `p5_x` (= m5 · d r_C5_x/dt) changes sign, located by linear
//!   interpolation of `p5_x` between the two samples around the sign change (the
//!   momentum crosses zero with a finite slope, so this is accurate to O(h²) of the 1 ms
//!   sample spacing; locating the extreme from `r_C5_x` itself, which is flat there,
//!   would not be). A *right* turning point (a maximum of `r_C5_x`) ends a return stroke
//!   and starts a forward stroke; a *left* one (a minimum) the opposite. A reversal
//!   whose travel from the previous turning point is under 10 % of the stroke (a
//!   vibration, not a stroke) is dropped together with that previous turning point.
//! - **Forward stroke**: the slow stroke, from a right turning point to the next left
//!   one (the slider moving towards −X0; the crank turns 240° for rigid links of the
//!   spec's geometry).
//!   **Return stroke**: from a left turning point to the next right one (120°).
//! - **Quick-return time ratio**: the mean duration of the complete forward strokes
//!   inside the window divided by the mean duration of the complete return strokes
//!   (exactly 240°/120° = 2 for rigid links of the spec's geometry at constant crank
//!   speed; the compliant joints shift the turning points, making it a little under 2).
//! - **Period**: from the crank angle, the time between its first and last crossing
//!   (inside the window) of a multiple of 2π divided by the whole turns between them,
//!   each crossing located by linear interpolation. The crank angle, unlike the
//!   slider's turning points, increases steadily at about `w_drive`, so each crossing
//!   time is well conditioned and does not depend on the deflections of the joints
//!   downstream; it is also the period the spec states (that of the crank, 2π/w_drive).
//!   The period from successive same-side turning points of the slider is reported
//!   beside it as a check; in periodic motion the two agree.
//! - **Peak output momentum** `max |p5_x|` during the complete forward and return
//!   strokes (the paper: the return is quicker, with the larger momentum peak).
//! - **Peak drive torque**: `max |Tc|` (Euclidean norm) and `max |Tc_z|`.
//! - **Peak joint forces**: `max |F|` (Euclidean norm) of the forces at O1, A2, O3 and O5
//!   (columns `F_O1_*`, `F_A2_*`, `F_O3_*`, `F_O5_*`), with the time of each peak.
//!
//! The [`Summary`] adds the solver, its counters and the wall time, and beside the
//! measurements the values of the rigid mechanism with the run's own parameters
//! ([`RigidReference`]: the stroke and time ratio of
//! [`try_quick_return_cycle`], the
//! period `2π/|w_drive|`); its `Display` prints a table.

use core::f64::consts::TAU;
use core::fmt;
use std::path::PathBuf;
use std::time::Duration;

use bgdsl_runtime::{Solver, Stats};

use super::results::{Results, CRANK_ANGLE, N_COLUMNS};
use super::run::Recorded;
use crate::quick_return_rigid::{try_quick_return_cycle, Mechanism};
pub use bgdsl_cli::catalog::SolverSettings;

/// The settled part of the run the measurements are taken over, s (both ends included).
pub const WINDOW: [f64; 2] = [2.5, 5.0];

/// A reversal travelling less than this fraction of the stroke is a vibration.
const MIN_TRAVEL: f64 = 0.1;

/// Which end of its stroke the output slider turns at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// A maximum of `r_C5_x` (the slider furthest towards +X0): a forward stroke starts.
    Right,
    /// A minimum of `r_C5_x`: a return stroke starts.
    Left,
}

/// An instant where the output slider reverses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurningPoint {
    /// When, s (interpolated between samples).
    pub t: f64,
    /// `r_C5_x` there, m (interpolated likewise).
    pub x: f64,
    /// Which end.
    pub side: Side,
}

/// The peak magnitude of a vector signal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// The joint or quantity, e.g. `"O1"`.
    pub name: &'static str,
    /// The largest Euclidean norm, in the signal's unit.
    pub value: f64,
    /// The sample time at which it occurs, s.
    pub t: f64,
}

/// The quantities measured over [`WINDOW`] (see the [module documentation](self) for
/// each definition). Quantities that need turning points or crank-angle crossings are
/// `None` when the window has too few of them (a mechanism that does not move).
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// The window, s.
    pub window: [f64; 2],
    /// Samples inside the window.
    pub samples: usize,
    /// `max − min` of `r_C5_x`, m.
    pub stroke: f64,
    /// `[min, max]` of `r_C5_x`, m.
    pub x5_range: [f64; 2],
    /// The output slider's turning points, in time order.
    pub turning_points: Vec<TurningPoint>,
    /// Mean duration of the complete forward (slow) strokes, s.
    pub forward_time: Option<f64>,
    /// Mean duration of the complete return (quick) strokes, s.
    pub return_time: Option<f64>,
    /// `forward_time / return_time`.
    pub time_ratio: Option<f64>,
    /// The crank's period, from its crossings of multiples of 2π, s.
    pub period: Option<f64>,
    /// Whole crank turns the period was measured over.
    pub period_turns: usize,
    /// The period from successive same-side turning points of the slider, s.
    pub slider_period: Option<f64>,
    /// `max |p5_x|` during the complete forward strokes, kg·m/s.
    pub forward_momentum_peak: Option<f64>,
    /// `max |p5_x|` during the complete return strokes, kg·m/s.
    pub return_momentum_peak: Option<f64>,
    /// `max |Tc|`, N·m.
    pub drive_torque: Peak,
    /// `max |Tc_z|`, N·m.
    pub drive_torque_z: Peak,
    /// `max |F|` at O1, A2, O3 and O5, N.
    pub joint_forces: [Peak; 4],
}

impl Measured {
    /// The measurements over `window` of a recorded run.
    pub fn of(results: &Results, window: [f64; 2]) -> Self {
        let t = results.times();
        let first = t.partition_point(|&t| t < window[0]);
        let end = t.partition_point(|&t| t <= window[1]);
        let range = first..end.max(first);
        let col = |name: &str| &results.column(name).expect("a results column")[range.clone()];
        let t = &t[range.clone()];

        let x5 = col("r_C5_x");
        let (lo, hi) = x5
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let stroke = if x5.is_empty() { 0.0 } else { hi - lo };

        let p5 = col("p5_x");
        let turning_points = turning_points(t, x5, p5, MIN_TRAVEL * stroke);
        let strokes = |from: Side| {
            turning_points
                .windows(2)
                .filter(move |pair| pair[0].side == from)
                .map(|pair| (pair[0].t, pair[1].t))
        };
        let mean_duration = |from: Side| mean(strokes(from).map(|(a, b)| b - a));
        let momentum_peak = |from: Side| {
            strokes(from)
                .map(|(a, b)| {
                    t.iter()
                        .zip(p5)
                        .filter(|(&ts, _)| ts >= a && ts <= b)
                        .fold(0.0f64, |m, (_, p)| m.max(p.abs()))
                })
                .reduce(f64::max)
        };
        let forward_time = mean_duration(Side::Right);
        let return_time = mean_duration(Side::Left);
        let time_ratio = match (forward_time, return_time) {
            (Some(f), Some(r)) => Some(f / r),
            _ => None,
        };
        let slider_period = mean([Side::Right, Side::Left].into_iter().flat_map(|side| {
            let at: Vec<f64> = turning_points
                .iter()
                .filter(|p| p.side == side)
                .map(|p| p.t)
                .collect();
            at.windows(2).map(|w| w[1] - w[0]).collect::<Vec<_>>()
        }));
        let (period, period_turns) = crank_period(t, col(CRANK_ANGLE));

        let vector_peak = |name: &'static str, prefix: &str| {
            let [x, y, z] = ["x", "y", "z"].map(|a| col(&format!("{prefix}_{a}")));
            peak(name, t, (0..t.len()).map(|k| norm([x[k], y[k], z[k]])))
        };
        let tc_z = col("Tc_z");
        Measured {
            window,
            samples: t.len(),
            stroke,
            x5_range: [lo, hi],
            forward_time,
            return_time,
            time_ratio,
            period,
            period_turns,
            slider_period,
            forward_momentum_peak: momentum_peak(Side::Right),
            return_momentum_peak: momentum_peak(Side::Left),
            drive_torque: vector_peak("Tc", "Tc"),
            drive_torque_z: peak("Tc_z", t, tc_z.iter().map(|v| v.abs())),
            joint_forces: [
                vector_peak("O1", "F_O1"),
                vector_peak("A2", "F_A2"),
                vector_peak("O3", "F_O3"),
                vector_peak("O5", "F_O5"),
            ],
            turning_points,
        }
    }
}

/// The mean, or `None` of nothing.
fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The largest of `values` (one per sample time in `t`) and when it occurs.
fn peak(name: &'static str, t: &[f64], values: impl Iterator<Item = f64>) -> Peak {
    let mut best = Peak {
        name,
        value: 0.0,
        t: f64::NAN,
    };
    for (&ts, v) in t.iter().zip(values) {
        if v > best.value || best.t.is_nan() {
            best = Peak {
                name,
                value: v,
                t: ts,
            };
        }
    }
    best
}

/// Linear interpolation of `(a, b)` at fraction `s`.
fn lerp(a: f64, b: f64, s: f64) -> f64 {
    a + s * (b - a)
}

/// The sign changes of `p` (zeros skipped), located by linear interpolation, with
/// reversals travelling less than `min_travel` dropped in pairs.
fn turning_points(t: &[f64], x: &[f64], p: &[f64], min_travel: f64) -> Vec<TurningPoint> {
    let mut kept: Vec<TurningPoint> = Vec::new();
    let mut last: Option<usize> = None; // the last sample with p != 0
    for k in 0..p.len() {
        if p[k] == 0.0 || !p[k].is_finite() {
            continue;
        }
        if let Some(j) = last {
            if p[j].signum() != p[k].signum() {
                let s = p[j] / (p[j] - p[k]);
                let point = TurningPoint {
                    t: lerp(t[j], t[k], s),
                    x: lerp(x[j], x[k], s),
                    side: if p[j] > 0.0 { Side::Right } else { Side::Left },
                };
                match kept.last() {
                    Some(prev) if (point.x - prev.x).abs() < min_travel => {
                        kept.pop();
                    }
                    _ => kept.push(point),
                }
            }
        }
        last = Some(k);
    }
    kept
}

/// The crank's period from its crossings of multiples of 2π: the time between the
/// first and the last crossing divided by the whole turns between them, and that
/// number of turns.
fn crank_period(t: &[f64], angle: &[f64]) -> (Option<f64>, usize) {
    let mut first: Option<(f64, f64)> = None; // (time, level in turns)
    let mut last: Option<(f64, f64)> = None;
    for k in 1..angle.len() {
        let (a, b) = (angle[k - 1] / TAU, angle[k] / TAU);
        if !a.is_finite() || !b.is_finite() || a.floor() == b.floor() {
            continue;
        }
        // The level crossed (the one nearest to b when several are, as cannot happen
        // at 1 ms sampling of a crank turning at ~5 rad/s).
        let level = if b > a { b.floor() } else { a.floor() };
        let s = (level - a) / (b - a);
        let crossing = (lerp(t[k - 1], t[k], s), level);
        first.get_or_insert(crossing);
        last = Some(crossing);
    }
    match (first, last) {
        (Some(f), Some(l)) if l.1 != f.1 => {
            let turns = (l.1 - f.1).abs();
            (Some((l.0 - f.0) / turns), turns as usize)
        }
        _ => (None, 0),
    }
}

/// What the rigid-link mechanism with a run's parameters does: the reference the
/// measurements are printed beside.
#[derive(Clone, Debug, PartialEq)]
pub enum RigidReference {
    /// Not computed: the summary was made without the run's parameters.
    Unknown,
    /// The rigid mechanism has no such cycle with these parameters; why.
    Undefined(String),
    /// The rigid values.
    Cycle {
        /// The output slider's travel between its extremes, m.
        stroke: f64,
        /// The slow (forward) stroke's duration over the quick (return) one's at the
        /// constant crank speed `w_drive`.
        time_ratio: f64,
        /// The crank's period `2π/|w_drive|`, s.
        period: f64,
    },
}

impl RigidReference {
    /// The rigid mechanism's cycle with the links and pivot distance of `p`, driven at
    /// its drive speed `w_drive`. A crank turning clockwise (`w_drive < 0`) makes the other stroke
    /// the slow one, so the ratio is inverted.
    pub fn of(p: &dyn Mechanism) -> Self {
        let w_drive = p.drive_speed();
        if !(w_drive.is_finite() && w_drive != 0.0) {
            return RigidReference::Undefined(format!(
                "the crank is not driven (w_drive = {} rad/s)",
                w_drive
            ));
        }
        match try_quick_return_cycle(&p.rigid_params()) {
            Ok(cycle) => RigidReference::Cycle {
                stroke: cycle.stroke,
                time_ratio: if w_drive > 0.0 {
                    cycle.time_ratio
                } else {
                    1.0 / cycle.time_ratio
                },
                period: TAU / w_drive.abs(),
            },
            Err(why) => RigidReference::Undefined(why.to_string()),
        }
    }
}

/// A finished flagship run: the model, the solver and its counters, the wall time, the
/// results file and the [`Measured`] quantities. `Display` prints it as a table.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The model's name.
    pub model: &'static str,
    /// The solver and its settings.
    pub solver: Solver,
    /// The solver's counters.
    pub stats: Stats,
    /// Wall time of the integration (with the recording), excluding the writing.
    pub wall: Duration,
    /// Samples recorded.
    pub rows: usize,
    /// The first and the last sample time, s.
    pub span: [f64; 2],
    /// The results file and the time it took to write, if it was written.
    pub file: Option<(PathBuf, Duration)>,
    /// What was measured over [`WINDOW`] (or the window given to [`Summary::over`]).
    pub measured: Measured,
    /// Why the run stopped before its last sample time, when it did: the samples (and
    /// the file) are then partial, and `Display` says so first.
    pub failure: Option<String>,
    /// The lines on what differs from the model's defaults (as
    /// [`provenance::summary_lines`](crate::provenance::summary_lines) writes them),
    /// printed after the model's line.
    pub overrides: Option<String>,
    /// The rigid-link values printed beside the measurements ([`RigidReference::Unknown`]
    /// until [`Summary::with_params`] gives the run's parameters).
    pub rigid: RigidReference,
}

impl Summary {
    /// The summary of a recorded run, measured over [`WINDOW`] (no file yet).
    pub fn of(recorded: &Recorded) -> Self {
        Self::over(recorded, WINDOW)
    }

    /// The summary of a recorded run, measured over `window` (s, both ends included; no
    /// file yet).
    pub fn over(recorded: &Recorded, window: [f64; 2]) -> Self {
        let t = recorded.results.times();
        Summary {
            model: recorded.results.model_name(),
            solver: recorded.solver,
            stats: recorded.stats,
            wall: recorded.wall,
            rows: recorded.results.len(),
            span: [
                t.first().copied().unwrap_or(f64::NAN),
                t.last().copied().unwrap_or(f64::NAN),
            ],
            file: None,
            measured: Measured::of(&recorded.results, window),
            failure: None,
            overrides: None,
            rigid: RigidReference::Unknown,
        }
    }

    /// This summary with the rigid-link reference of the run's parameters `p`.
    #[must_use]
    pub fn with_params(mut self, p: &dyn Mechanism) -> Self {
        self.rigid = RigidReference::of(p);
        self
    }
}

/// An optional number with a unit and a precision, or "n/a".
struct Opt(Option<f64>, usize, &'static str);

impl fmt::Display for Opt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = match self.0 {
            Some(v) => format!("{v:.prec$}{}", self.2, prec = self.1),
            None => "n/a".to_owned(),
        };
        // Pad as asked (the table's columns).
        f.pad(&text)
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// One row of the measurements table: quantity, measured value, rigid-link value,
/// details.
fn row(
    f: &mut fmt::Formatter<'_>,
    quantity: &str,
    measured: impl fmt::Display,
    rigid: &str,
    detail: impl fmt::Display,
) -> fmt::Result {
    writeln!(f, "  {quantity:<26} {measured:<16} {rigid:<12} {detail}")
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.stats;
        let m = &self.measured;
        if let Some(failure) = &self.failure {
            writeln!(f, "PARTIAL RUN   {failure}")?;
        }
        writeln!(
            f,
            "model          {} (quick return mechanism), {} to {} s",
            self.model, self.span[0], self.span[1]
        )?;
        if let Some(overrides) = &self.overrides {
            f.write_str(overrides)?;
        }
        writeln!(f, "solver         {}", SolverSettings(&self.solver))?;
        writeln!(
            f,
            "steps          {} ({} accepted, {} rejected)",
            s.steps(),
            s.accepted,
            s.rejected
        )?;
        writeln!(f, "derivatives    {} evaluations", s.n_rhs)?;
        writeln!(
            f,
            "Jacobians      {} ({} directional derivatives by automatic differentiation), {} LU \
             factorizations",
            s.n_jac, s.n_jac_rhs, s.n_lu
        )?;
        write!(f, "wall time      {:.1} ms integrating", ms(self.wall))?;
        match &self.file {
            Some((path, write)) => {
                writeln!(f, ", {:.1} ms writing the file", ms(*write))?;
                writeln!(
                    f,
                    "results        {} ({} rows, {N_COLUMNS} columns{})",
                    path.display(),
                    self.rows,
                    if self.failure.is_some() {
                        ", partial"
                    } else {
                        ""
                    }
                )?;
            }
            None => writeln!(f, " ({} samples, not written)", self.rows)?,
        }
        writeln!(f)?;
        writeln!(
            f,
            "  {:<26} {:<16} {:<12} ({} samples)",
            format!("over {}-{} s", m.window[0], m.window[1]),
            "measured",
            "rigid links",
            m.samples
        )?;
        let (stroke, ratio, period) = match &self.rigid {
            RigidReference::Cycle {
                stroke,
                time_ratio,
                period,
            } => (
                format!("{stroke:.5} m"),
                format!("{time_ratio:.5}"),
                format!("{period:.5} s"),
            ),
            _ => ("n/a".to_owned(), "n/a".to_owned(), "n/a".to_owned()),
        };
        row(
            f,
            "output-slider stroke",
            format!("{:.5} m", m.stroke),
            &stroke,
            format!("r_C5_x from {:.5} to {:.5} m", m.x5_range[0], m.x5_range[1]),
        )?;
        row(
            f,
            "quick-return time ratio",
            Opt(m.time_ratio, 5, ""),
            &ratio,
            format!(
                "forward stroke {}, return stroke {}",
                Opt(m.forward_time, 5, " s"),
                Opt(m.return_time, 5, " s")
            ),
        )?;
        row(
            f,
            "period",
            Opt(m.period, 5, " s"),
            &period,
            format!(
                "crank, over {} turn(s); slider turning points {}",
                m.period_turns,
                Opt(m.slider_period, 5, " s")
            ),
        )?;
        row(
            f,
            "peak |p5_x| in the return",
            Opt(m.return_momentum_peak, 4, " kg·m/s"),
            "",
            format!(
                "forward stroke {}",
                Opt(m.forward_momentum_peak, 4, " kg·m/s")
            ),
        )?;
        row(
            f,
            "peak drive torque |Tc|",
            format!("{:.3} N·m", m.drive_torque.value),
            "",
            format!(
                "at t = {:.3} s; |Tc_z| {:.3} N·m",
                m.drive_torque.t, m.drive_torque_z.value
            ),
        )?;
        for p in &m.joint_forces {
            row(
                f,
                &format!("peak joint force |F_{}|", p.name),
                format!("{:.3} N", p.value),
                "",
                format!("at t = {:.3} s", p.t),
            )?;
        }
        match &self.rigid {
            RigidReference::Cycle { .. } => {}
            RigidReference::Unknown => writeln!(
                f,
                "  (rigid links n/a: the summary was made without the run's parameters)"
            )?,
            RigidReference::Undefined(why) => writeln!(f, "  (rigid links n/a: {why})")?,
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quick_return::QuickReturnParams;

    #[test]
    fn finds_turning_points_and_drops_wiggles() {
        // x = sin(2π t) sampled every 1 ms over 2 s, with a small wiggle at t ≈ 0.6.
        let t: Vec<f64> = (0..=2000).map(|k| k as f64 / 1000.0).collect();
        let x: Vec<f64> = t.iter().map(|t| (TAU * t).sin()).collect();
        let mut p: Vec<f64> = t.iter().map(|t| TAU * (TAU * t).cos()).collect();
        p[600] = 1e-3; // sign flip inside the (negative) stretch: two spurious reversals
        let points = turning_points(&t, &x, &p, 0.2);
        let times: Vec<f64> = points.iter().map(|p| p.t).collect();
        let expected = [0.25, 0.75, 1.25, 1.75];
        assert_eq!(times.len(), expected.len(), "{points:?}");
        for (a, b) in times.iter().zip(expected) {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
        assert_eq!(points[0].side, Side::Right);
        assert_eq!(points[1].side, Side::Left);
    }

    #[test]
    fn measures_the_crank_period() {
        let t: Vec<f64> = (0..=5000).map(|k| k as f64 / 1000.0).collect();
        let angle: Vec<f64> = t
            .iter()
            .map(|t| core::f64::consts::FRAC_PI_2 + 5.0 * t)
            .collect();
        let (period, turns) = crank_period(&t, &angle);
        assert_eq!(turns, 3);
        assert!((period.unwrap() - TAU / 5.0).abs() < 1e-12);
        let (none, zero) = crank_period(&t[..100], &angle[..100]);
        assert_eq!((none, zero), (None, 0));
    }

    #[test]
    fn the_rigid_reference_is_the_runs_own() {
        let defaults = QuickReturnParams::default();
        let RigidReference::Cycle {
            stroke,
            time_ratio,
            period,
        } = RigidReference::of(&defaults)
        else {
            panic!("the spec's mechanism has a cycle");
        };
        assert!((stroke - 0.7).abs() < 1e-12 && (time_ratio - 2.0).abs() < 1e-12);
        assert!((period - TAU / 5.0).abs() < 1e-15);
        // Turning the other way makes the other stroke the slow one.
        let reversed = QuickReturnParams {
            w_drive: -2.0,
            ..QuickReturnParams::default()
        };
        let RigidReference::Cycle {
            time_ratio, period, ..
        } = RigidReference::of(&reversed)
        else {
            panic!("a cycle");
        };
        assert!((time_ratio - 0.5).abs() < 1e-12 && (period - TAU / 2.0).abs() < 1e-15);
        let whitworth = QuickReturnParams {
            d: 0.1,
            ..QuickReturnParams::default()
        };
        assert!(matches!(
            RigidReference::of(&whitworth),
            RigidReference::Undefined(why) if why.contains("not shorter than the pivot distance")
        ));
    }
}
