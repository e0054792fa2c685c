//! `models periodic`: the periodic steady state of a periodically driven model, by
//! shooting, with its Floquet multipliers (`orbit.csv`, `floquet.json`, figures,
//! `index.html`, `run.yaml`).

use clap::Args;
use serde_yaml::Value;

use bgdsl_analysis::periodic::PeriodicOptions;

use super::{execute, plan, state_value, ModelArgs};
use crate::catalog::analysis::periodic::{orbit_columns, results_set, PeriodicRequest};
use crate::catalog::{Catalogue, Entry, RunPlan};
use crate::cli::Failure;

/// The arguments of `models periodic`.
#[derive(Clone, Debug, Args)]
pub struct PeriodicArgs {
    /// The model and its settings. The orbit starts at the start time (`--t-start`: the
    /// drive's phase), from the initial state (Newton's first guess); its samples are
    /// the columns a run records.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The period, s (of the drive).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub period: Option<f64>,
    /// The parameter that sets the drive's frequency: the period is 2π/value for a
    /// parameter in rad/s, 1/value for one in Hz or 1/s, the value itself for one in
    /// s, e.g. `--drive omega`.
    #[arg(long, value_name = "PARAM", conflicts_with = "period")]
    pub drive: Option<String>,
    /// Periods simulated from the initial state before Newton's method starts (to
    /// start near an attracting orbit; the library then settles up to 20 more while
    /// each halves the change over a period).
    #[arg(long, value_name = "N", default_value_t = PeriodicOptions::new(1.0).warmup_periods)]
    pub warmup: usize,
    /// Samples per period in orbit.csv (one more row closes the period).
    #[arg(long, value_name = "N", default_value_t = 200)]
    pub points: usize,
    /// Converged when the period map moves every state by at most this fraction of its
    /// scale (its largest magnitude over the period, plus 1e-3 of the largest state's).
    #[arg(long, value_name = "X", default_value_t = PeriodicOptions::new(1.0).tolerance)]
    pub tolerance: f64,
    /// Newton iterations allowed.
    #[arg(long, value_name = "N", default_value_t = PeriodicOptions::new(1.0).max_iterations)]
    pub max_iterations: usize,
    /// SDIRK steps per period of the monodromy matrix; the multipliers are checked
    /// against half as many, and one that moves by more than 1e-2 is reported as not
    /// resolved (the quick return's neutral out-of-plane ones at 400 steps: a pair of
    /// modulus 2.2, 1.012 at 1600 steps).
    #[arg(long, value_name = "N", default_value_t = PeriodicOptions::new(1.0).steps)]
    pub steps: usize,
    /// A state that is periodic up to a fixed advance per period, e.g. a crank angle
    /// held as a state: `--shift theta=6.283185307179586` (repeatable).
    #[arg(long, value_name = "STATE=ADVANCE", allow_hyphen_values = true)]
    pub shift: Vec<String>,
}

impl Default for PeriodicArgs {
    /// The command line's defaults.
    fn default() -> Self {
        let request = PeriodicRequest::new(1.0);
        PeriodicArgs {
            model: ModelArgs::default(),
            period: None,
            drive: None,
            warmup: request.warmup_periods,
            points: request.points,
            tolerance: request.tolerance,
            max_iterations: request.max_iterations,
            shift: Vec::new(),
            steps: request.steps,
        }
    }
}

/// The period in seconds from the value of a drive parameter with unit `unit`.
fn period_of(value: f64, unit: &str) -> Option<f64> {
    match unit.trim() {
        "rad/s" | "rad·s⁻¹" | "rad s⁻¹" => Some(core::f64::consts::TAU / value),
        "Hz" | "1/s" | "s⁻¹" => Some(1.0 / value),
        "s" => Some(value),
        _ => None,
    }
}

/// The period asked for, and where it came from (for the summary and the record).
fn period(args: &PeriodicArgs, entry: &Entry, plan: &RunPlan) -> Result<(f64, String), Failure> {
    let (period, source) = match (&args.period, &args.drive) {
        (Some(t), _) => (*t, "--period".to_owned()),
        (None, Some(name)) => {
            let info = entry
                .model
                .parameters()
                .iter()
                .find(|p| p.name == name.as_str())
                .ok_or_else(|| {
                    let names: Vec<&str> =
                        entry.model.parameters().iter().map(|p| p.name).collect();
                    Failure::Usage(format!(
                        "--drive {name}: the model {} has no parameter `{name}`; its \
                         parameters: {}",
                        entry.name,
                        names.join(", ")
                    ))
                })?;
            let value = match plan.params.get(name.as_str()) {
                Some(Value::Number(n)) => n.as_f64(),
                _ => None,
            }
            .ok_or_else(|| {
                Failure::Usage(format!("--drive {name}: `{name}` is not a single number"))
            })?;
            let period = period_of(value, info.unit).ok_or_else(|| {
                Failure::Usage(format!(
                    "--drive {name}: `{name}` is in {}, not a frequency (rad/s, Hz) or a \
                     period (s); give the period with --period T",
                    if info.unit.is_empty() {
                        "no unit"
                    } else {
                        info.unit
                    }
                ))
            })?;
            (period, format!("from {name} = {value} {}", info.unit))
        }
        (None, None) => {
            return Err(Failure::Usage(format!(
                "periodic needs the period: give --period T (s), or --drive PARAM for the \
                 parameter that sets the drive's frequency (rad/s or Hz), e.g. --drive {}",
                entry
                    .model
                    .parameters()
                    .iter()
                    .find(|p| period_of(1.0, p.unit).is_some() && p.unit != "s")
                    .map_or("omega", |p| p.name)
            )))
        }
    };
    if !(period.is_finite() && period > 0.0) {
        return Err(Failure::Usage(format!(
            "the period must be a positive number of seconds, not {period} ({source})"
        )));
    }
    Ok((period, source))
}

/// `models periodic ...`.
pub(crate) fn periodic(args: &PeriodicArgs, catalogue: &'static Catalogue) -> Result<(), Failure> {
    let mut options = Vec::new();
    if let Some(t) = args.period {
        options.push(("period".to_owned(), t.to_string()));
    }
    if let Some(drive) = &args.drive {
        options.push(("drive".to_owned(), drive.clone()));
    }
    for shift in &args.shift {
        let (name, value) = shift.split_once('=').unwrap_or((shift, ""));
        options.push((format!("shift.{}", name.trim()), value.trim().to_owned()));
    }
    let (entry, plan) = plan(&args.model, catalogue, "periodic", &options)?;
    let (period, source) = period(args, entry, &plan)?;
    if !(args.tolerance.is_finite() && args.tolerance > 0.0) {
        return Err(Failure::Usage(format!(
            "--tolerance {}: give a positive number (e.g. 1e-4)",
            args.tolerance
        )));
    }
    if args.steps == 0 {
        return Err(Failure::Usage(
            "--steps 0: give at least one step per period".to_owned(),
        ));
    }
    if args.points < 2 {
        return Err(Failure::Usage(format!(
            "--points {}: give at least 2 samples per period",
            args.points
        )));
    }
    let chosen_solver =
        args.model.solver.is_some() || args.model.rtol.is_some() || args.model.atol.is_some();
    let mut shifts = Vec::new();
    for flag in &args.shift {
        let (state, advance) = state_value(entry, "--shift", flag)?;
        if shifts.iter().any(|&(s, _)| s == state) {
            return Err(Failure::Usage(format!(
                "--shift {flag}: that state is shifted twice"
            )));
        }
        shifts.push((state, advance));
    }
    let request = PeriodicRequest {
        period,
        warmup_periods: args.warmup,
        points: args.points,
        tolerance: args.tolerance,
        max_iterations: args.max_iterations,
        solver: chosen_solver.then_some(plan.solver),
        shifts,
        steps: args.steps,
    };
    let columns = orbit_columns(entry, &plan);
    let only: Vec<crate::catalog::Column> = columns.iter().map(|(_, c)| *c).collect();
    execute(entry, &plan, || {
        let found = entry.model.periodic(&plan, &only, &request)?;
        Ok(results_set(entry, &request, &source, &columns, &found))
    })
}

#[cfg(test)]
mod tests {
    use super::period_of;

    #[test]
    fn periods_from_frequencies_by_unit() {
        assert_eq!(period_of(2.0, "Hz"), Some(0.5));
        assert_eq!(period_of(4.0, "rad/s"), Some(core::f64::consts::TAU / 4.0));
        assert_eq!(period_of(3.0, "s"), Some(3.0));
        assert_eq!(period_of(3.0, "kg"), None);
    }
}
