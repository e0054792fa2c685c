//! The solver of a scenario: the model's, or the one named, with tolerances, step and
//! limits set and checked.

use std::time::Duration;

use bgdsl_runtime::{Solver, SolverError};

use super::resolve::{Overrides, Places, RTOL_RANGE};
use super::{AtolSpec, Diagnostics, Origin, Scenario};
use crate::catalog::{describe_value, format_number, Entry};

/// The solver: the model's, or the one named, with the tolerances and limits set.
pub(super) fn solver(
    entry: &Entry,
    scenario: &Scenario,
    overrides: &Overrides,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<Solver> {
    let spec = scenario.solver.clone().unwrap_or_default();
    let key = |k: &str| places.keys(&["solver", k]);
    let (named, name_origin) = match (&overrides.solver, &spec.method) {
        (Some(n), _) => (Some(n.clone()), Origin::Flag(format!("--solver {n}"))),
        (None, Some(n)) => (Some(n.clone()), key("method")),
        (None, None) => (None, Origin::Nowhere),
    };
    let mut solver = match named {
        Some(name) => match Solver::from_name(&name) {
            Ok(s) if s.name() == entry.solver.name() => entry.solver,
            Ok(s) => s,
            Err(e) => {
                d.push(name_origin, e.to_string());
                return None;
            }
        },
        None => entry.solver,
    };
    let before = d.0.len();
    let setting =
        |flag: Option<f64>, file: Option<f64>, name: &str| pick(flag, file, name, || key(name));
    let method = solver.name();
    let fixed = matches!(solver, Solver::Rk4(_) | Solver::DormandPrinceFixed(_));
    if let Some((rtol, origin)) = setting(overrides.rtol, spec.rtol, "rtol") {
        if fixed {
            d.push(
                origin,
                format!("rtol does not apply to the fixed-step solver {method}; set `step`"),
            );
        } else if !(RTOL_RANGE[0]..=RTOL_RANGE[1]).contains(&rtol) {
            d.push(
                origin,
                format!(
                    "rtol must be in [1e-14, 0.1], found {}",
                    format_number(rtol)
                ),
            );
        } else {
            set_tolerance(&mut solver, Some(rtol), None);
        }
    }
    let (file_atol, atol_key): (Option<f64>, &[&str]) = match &spec.atol {
        Some(AtolSpec::All(a)) => (Some(*a), &["solver", "atol"]),
        Some(AtolSpec::PerState(map)) => match map.get("default") {
            Some(v) => match v.as_f64() {
                Some(a) => (Some(a), &["solver", "atol", "default"]),
                None => {
                    d.push(
                        places.keys(&["solver", "atol", "default"]),
                        format!(
                            "the default atol must be a finite number > 0, found {}",
                            describe_value(v)
                        ),
                    );
                    (None, &[])
                }
            },
            None => (None, &[]),
        },
        None => (None, &[]),
    };
    let atol_setting = pick(overrides.atol, file_atol, "atol", || places.keys(atol_key));
    if let Some((atol, origin)) = atol_setting {
        if fixed {
            d.push(
                origin,
                format!("atol does not apply to the fixed-step solver {method}; set `step`"),
            );
        } else if !(atol.is_finite() && atol > 0.0) {
            d.push(
                origin,
                format!(
                    "atol must be a finite number > 0, found {}",
                    format_number(atol)
                ),
            );
        } else {
            set_tolerance(&mut solver, None, Some(atol));
        }
    }
    if let Some((step, origin)) = setting(overrides.step, spec.step, "step") {
        match &mut solver {
            Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => {
                if step.is_finite() && step > 0.0 {
                    o.step = step;
                } else {
                    d.push(origin, format!(
                        "the step must be a number of seconds > 0, found {}",
                        format_number(step)
                    ));
                }
            }
            _ => d.push(
                origin,
                format!("`step` applies only to the fixed-step solvers rk4 and dopri5-fixed, not {method}"),
            ),
        }
    }
    if let Some(max_step) = spec.max_step {
        if max_step.is_nan() || max_step <= 0.0 {
            d.push(
                key("max_step"),
                format!(
                    "max_step must be a number of seconds > 0, found {}",
                    format_number(max_step)
                ),
            );
        } else {
            match &mut solver {
                Solver::DormandPrince(o) => o.max_step = max_step,
                Solver::Radau5(o) => o.max_step = max_step,
                Solver::Rodas4(o) | Solver::Rodas5P(o) => o.max_step = max_step,
                _ => d.push(
                    key("max_step"),
                    format!(
                        "`max_step` applies only to the adaptive solvers, not {method}; set `step`"
                    ),
                ),
            }
        }
    }
    let max_steps = pick(overrides.max_steps, spec.max_steps, "max-steps", || {
        key("max_steps")
    });
    if let Some((max_steps, origin)) = max_steps {
        if max_steps == 0 {
            d.push(origin, "max_steps must be an integer > 0, found 0");
        } else {
            match &mut solver {
                Solver::Rk4(o) | Solver::DormandPrinceFixed(o) => o.max_steps = max_steps,
                Solver::DormandPrince(o) => o.max_steps = max_steps,
                Solver::Radau5(o) => o.max_steps = max_steps,
                Solver::Rodas4(o) | Solver::Rodas5P(o) => o.max_steps = max_steps,
                _ => {}
            }
        }
    }
    if let Some(limit) = spec.max_wall_time {
        if !(limit.is_finite() && limit > 0.0) {
            d.push(
                key("max_wall_time"),
                format!(
                    "max_wall_time must be a number of seconds > 0, found {}",
                    format_number(limit)
                ),
            );
        } else {
            let limit = Some(Duration::from_secs_f64(limit));
            match &mut solver {
                Solver::Radau5(o) => o.max_wall_time = limit,
                Solver::Rodas4(o) | Solver::Rodas5P(o) => o.max_wall_time = limit,
                _ => d.push(
                    key("max_wall_time"),
                    format!("max_wall_time applies only to the stiff solvers radau5, rodas4 and rodas5p, not {method}"),
                ),
            }
        }
    }
    if d.0.len() > before {
        return None;
    }
    if let Err(e) = solver.validate() {
        let origin = match &e {
            SolverError::InvalidOptions { option, .. } => key(option),
            _ => Origin::Nowhere,
        };
        d.push(origin, e.to_string());
        return None;
    }
    Some(solver)
}

/// The per-state settings of a scenario's solver (`solver.atol` as a mapping,
/// `solver.non_negative`), checked by state name against `solver` (already resolved:
/// the atol of the states not named is its own).
pub(super) struct PerState {
    /// One absolute tolerance per state, when `solver.atol` names states.
    pub(super) atol: Option<Vec<f64>>,
    /// The states held at or above zero, by index.
    pub(super) non_negative: Vec<usize>,
}

/// Reads `solver.atol` (when a mapping) and `solver.non_negative` for `entry`'s states.
pub(super) fn per_state(
    entry: &Entry,
    scenario: &Scenario,
    solver: Option<&Solver>,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> PerState {
    let mut result = PerState {
        atol: None,
        non_negative: Vec::new(),
    };
    let Some(spec) = &scenario.solver else {
        return result;
    };
    let states = entry.model.state_names();
    let unknown = |name: &str| {
        format!(
            "unknown state `{name}`; {}",
            super::resolve::name_list("states", &entry.name, states, "--states")
        )
    };
    // The method's atol after the scenario's and the flags' settings (None: fixed step).
    let base = solver.and_then(|s| match s {
        Solver::DormandPrince(o) => Some(o.atol),
        Solver::Radau5(o) => Some(o.atol),
        Solver::Rodas4(o) | Solver::Rodas5P(o) => Some(o.atol),
        _ => None,
    });
    let method = solver.map_or("the solver", |s| s.name());
    if let Some(AtolSpec::PerState(map)) = &spec.atol {
        let mut atol = vec![base.unwrap_or(f64::NAN); states.len()];
        for (key, value) in map {
            let Some(name) = key.as_str() else {
                d.push(
                    places.keys(&["solver", "atol"]),
                    format!(
                        "a state name must be a string, found {}",
                        crate::catalog::format_value(key)
                    ),
                );
                continue;
            };
            if name == "default" {
                continue;
            }
            let origin = places.keys(&["solver", "atol", name]);
            let Some(index) = states.iter().position(|s| *s == name) else {
                d.push(origin, unknown(name));
                continue;
            };
            match value.as_f64() {
                Some(a) if a.is_finite() && a > 0.0 => atol[index] = a,
                _ => d.push(
                    origin,
                    format!(
                        "the atol of `{name}` must be a finite number > 0, found {}",
                        describe_value(value)
                    ),
                ),
            }
        }
        match base {
            Some(_) => result.atol = Some(atol),
            None if solver.is_some() => d.push(
                places.keys(&["solver", "atol"]),
                format!("atol does not apply to the fixed-step solver {method}; set `step`"),
            ),
            None => {}
        }
    }
    if let Some(names) = &spec.non_negative {
        let origin = || places.keys(&["solver", "non_negative"]);
        for name in names {
            match states.iter().position(|s| s == name) {
                Some(index) if !result.non_negative.contains(&index) => {
                    result.non_negative.push(index)
                }
                Some(_) => d.push(origin(), format!("`{name}` is listed twice")),
                None => d.push(origin(), unknown(name)),
            }
        }
        if base.is_none() && solver.is_some() && !names.is_empty() {
            d.push(
                origin(),
                format!(
                    "non_negative applies only to the adaptive solvers, not the fixed-step {method}"
                ),
            );
        }
    }
    result
}

/// A number as a message shows it: an `f64` in the shortest form that reads back to it
/// (`1e-300`, not 300 zeros), a count as it is.
pub(super) trait Shown: Copy {
    /// The number as text.
    fn shown(self) -> String;
}

impl Shown for f64 {
    fn shown(self) -> String {
        format_number(self)
    }
}

impl Shown for usize {
    fn shown(self) -> String {
        self.to_string()
    }
}

/// A setting from its command-line flag `--flag_name` (which wins) or from the file,
/// with where it came from; `None` when neither gives it.
pub(super) fn pick<T: Shown>(
    flag: Option<T>,
    file: Option<T>,
    flag_name: &str,
    file_origin: impl FnOnce() -> Origin,
) -> Option<(T, Origin)> {
    match (flag, file) {
        (Some(v), _) => Some((v, Origin::Flag(format!("--{flag_name} {}", v.shown())))),
        (None, Some(v)) => Some((v, file_origin())),
        (None, None) => None,
    }
}

/// Sets the tolerances of an adaptive solver.
fn set_tolerance(solver: &mut Solver, rtol: Option<f64>, atol: Option<f64>) {
    let (r, a) = match solver {
        Solver::DormandPrince(o) => (&mut o.rtol, &mut o.atol),
        Solver::Radau5(o) => (&mut o.rtol, &mut o.atol),
        Solver::Rodas4(o) | Solver::Rodas5P(o) => (&mut o.rtol, &mut o.atol),
        _ => return,
    };
    if let Some(rtol) = rtol {
        *r = rtol;
    }
    if let Some(atol) = atol {
        *a = atol;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scenario's tolerances reach every adaptive method, Rodas5P included (a method
    /// missing from `set_tolerance` would silently keep its defaults).
    #[test]
    fn tolerances_reach_every_adaptive_method() {
        for name in ["dopri5", "radau5", "rodas4", "rodas5p"] {
            let mut solver = Solver::from_name(name).unwrap();
            set_tolerance(&mut solver, Some(1e-8), Some(1e-12));
            let (rtol, atol) = match solver {
                Solver::DormandPrince(o) => (o.rtol, o.atol),
                Solver::Radau5(o) => (o.rtol, o.atol),
                Solver::Rodas4(o) | Solver::Rodas5P(o) => (o.rtol, o.atol),
                other => panic!("{} is not adaptive", other.name()),
            };
            assert_eq!((rtol, atol), (1e-8, 1e-12), "{name}");
        }
    }
}
