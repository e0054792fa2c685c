//! The comparison a hybrid quick return entry prints in its summary: the same run
//! again with some parameters changed (the friction off, the end stop moved out of the
//! stroke), and what each measured over the summary's window side by side: the
//! quick-return time ratio, the stroke times, the drive torque and the powers.

use core::fmt::Write as _;

use bgdsl_runtime::Simulation;
use serde::de::DeserializeOwned;
use serde_yaml::Value;

use super::{Catalogued, Entry, RunPlan};
use crate::plot::cumulative_trapezoid;
use crate::quick_return::results::Results;
use crate::quick_return::summary::Measured;
use bgdsl_cli::catalog::{initial_state, params_from};

/// A run to compare with: the entry's own with these parameters set.
#[derive(Clone, Copy, Debug)]
pub struct Compare {
    /// What the other run is, e.g. `without friction`.
    pub label: &'static str,
    /// The parameters it sets (name, value); the rest are the run's.
    pub set: &'static [(&'static str, f64)],
}

/// What both runs measured over the second half of the span recorded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compared {
    /// Forward over return stroke time.
    pub time_ratio: Option<f64>,
    /// Mean forward (slow) stroke time, s.
    pub forward_time: Option<f64>,
    /// Mean return (quick) stroke time, s.
    pub return_time: Option<f64>,
    /// `max |Tc|`, N·m.
    pub peak_torque: f64,
    /// The mean of `Tc_z` over the window, N·m.
    pub mean_torque: f64,
    /// The mean drive power over the window, W.
    pub mean_power_in: f64,
    /// The mean dissipated power over the window (`P_diss`), W.
    pub mean_power_diss: f64,
}

impl Compared {
    /// The quantities of `results` over `window`.
    pub fn of(results: &Results, window: [f64; 2]) -> Self {
        let m = Measured::of(results, window);
        let mean = |name| time_mean(results, name, window);
        Compared {
            time_ratio: m.time_ratio,
            forward_time: m.forward_time,
            return_time: m.return_time,
            peak_torque: m.drive_torque.value,
            mean_torque: mean("Tc_z"),
            mean_power_in: mean("P_in"),
            mean_power_diss: mean("P_diss"),
        }
    }
}

/// The time average of column `name` over `window` (trapezoid rule on the samples).
pub fn time_mean(results: &Results, name: &str, window: [f64; 2]) -> f64 {
    let t = results.times();
    let v = results.column(name).unwrap_or(&[]);
    let first = t.partition_point(|&t| t < window[0]);
    let end = t.partition_point(|&t| t <= window[1]).min(v.len());
    if end <= first + 1 {
        return f64::NAN;
    }
    let (t, v) = (&t[first..end], &v[first..end]);
    let integral = cumulative_trapezoid(t, v).last().copied().unwrap_or(0.0);
    let span = t[t.len() - 1] - t[0];
    if span > 0.0 {
        integral / span
    } else {
        f64::NAN
    }
}

/// The second half of the span the results cover (the summary's window).
pub fn window(results: &Results) -> [f64; 2] {
    let t = results.times();
    match (t.first(), t.last()) {
        (Some(&a), Some(&b)) => [0.5 * (a + b), b],
        _ => [0.0, 0.0],
    }
}

/// The summary's comparison lines: the plan run again with `compare`'s parameters,
/// and both runs' [`Compared`] quantities; a line saying why when the other run fails.
pub(super) fn summary<M: Catalogued>(
    entry: &Entry,
    compare: &Compare,
    plan: &RunPlan,
    this: Option<&Results>,
) -> String
where
    M::Params: DeserializeOwned,
{
    let mut s = String::new();
    let Some(this) = this else {
        return s;
    };
    let setting = compare
        .set
        .iter()
        .map(|(name, value)| format!("{name} = {value}"))
        .collect::<Vec<_>>()
        .join(", ");
    let other = match run_with::<M>(plan, compare) {
        Ok(other) => other,
        Err(why) => {
            let _ = writeln!(
                s,
                "compared with  {} ({setting}): not run, {why}",
                compare.label
            );
            return s;
        }
    };
    let window = window(this);
    let (a, b) = (Compared::of(this, window), Compared::of(&other, window));
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "  {:<26} {:<16} {} ({setting}, {})",
        format!("over {}-{} s", window[0], window[1]),
        "this run",
        compare.label,
        entry.name
    );
    let opt = |v: Option<f64>, prec: usize, unit: &str| match v {
        Some(v) => format!("{v:.prec$}{unit}"),
        None => "n/a".to_owned(),
    };
    let rows = [
        (
            "quick-return time ratio",
            opt(a.time_ratio, 5, ""),
            opt(b.time_ratio, 5, ""),
        ),
        (
            "forward stroke time",
            opt(a.forward_time, 5, " s"),
            opt(b.forward_time, 5, " s"),
        ),
        (
            "return stroke time",
            opt(a.return_time, 5, " s"),
            opt(b.return_time, 5, " s"),
        ),
        (
            "peak drive torque |Tc|",
            format!("{:.3} N·m", a.peak_torque),
            format!("{:.3} N·m", b.peak_torque),
        ),
        (
            "mean drive torque Tc_z",
            format!("{:.4} N·m", a.mean_torque),
            format!("{:.4} N·m", b.mean_torque),
        ),
        (
            "mean drive power P_in",
            format!("{:.4} W", a.mean_power_in),
            format!("{:.4} W", b.mean_power_in),
        ),
        (
            "mean dissipation P_diss",
            format!("{:.4} W", a.mean_power_diss),
            format!("{:.4} W", b.mean_power_diss),
        ),
    ];
    for (quantity, mine, theirs) in rows {
        let _ = writeln!(s, "  {quantity:<26} {mine:<16} {theirs}");
    }
    s
}

/// The plan's run with `compare`'s parameters, recorded into the results columns.
fn run_with<M: Catalogued>(plan: &RunPlan, compare: &Compare) -> Result<Results, String>
where
    M::Params: DeserializeOwned,
{
    let mut params = plan.params.clone();
    for (name, value) in compare.set {
        params.insert(Value::String((*name).to_owned()), Value::from(*value));
    }
    let model = M::from_params(params_from(&params).map_err(|e| e.to_string())?);
    let x0 = initial_state(&model, &plan.initial);
    let mut results = Results::for_model::<M>(plan.times.len()).map_err(|e| e.to_string())?;
    let mut sim = Simulation::new(&model, plan.solver).map_err(|e| e.to_string())?;
    let t0 = plan.times.first().copied().unwrap_or(0.0);
    sim.run(t0, &x0, &plan.times, &mut results)
        .map_err(|e| format!("the {} run failed: {e}", plan.solver.name()))?;
    Ok(results)
}
