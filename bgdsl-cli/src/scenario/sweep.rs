//! The sweep of a scenario: its axes, metrics and window, with every point's
//! parameters checked.

use std::collections::BTreeMap;

use super::locate::KeyPath;
use super::resolve::{column, Places};
use super::{AxisSpec, Diagnostics, Origin, SweepSpec};
use crate::catalog::{format_number, metric_unit, Axis, Entry, Metric, RunPlan, SweepPlan};

/// The most values one axis may have.
const MAX_STEPS: usize = 10_000;

/// The sweep: axes, metrics and window, with every point's parameters checked.
pub(super) fn sweep(
    entry: &Entry,
    spec: &SweepSpec,
    base: RunPlan,
    origins: &BTreeMap<String, Origin>,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<SweepPlan> {
    let root = KeyPath::keys(&["sweep"]);
    let before = d.0.len();
    if spec.parameters.is_empty() || spec.parameters.len() > 2 {
        d.push(
            places.file(&root.key("parameters")),
            format!(
                "a sweep is over one or two parameters, found {}",
                spec.parameters.len()
            ),
        );
    }
    let mut axes = Vec::new();
    for (i, axis) in spec.parameters.iter().enumerate() {
        let at = root.key("parameters").index(i);
        let info = entry
            .model
            .parameters()
            .iter()
            .find(|p| p.name == axis.name);
        match info {
            None => {
                let names: Vec<&str> = entry.model.parameters().iter().map(|p| p.name).collect();
                d.push(
                    places.file(&at.key("name")),
                    format!(
                        "unknown parameter `{}`; the parameters of {} are: {}",
                        axis.name,
                        entry.name,
                        names.join(", ")
                    ),
                );
                continue;
            }
            Some(p) if p.len != 1 => {
                d.push(
                    places.file(&at.key("name")),
                    format!(
                        "only scalar parameters can be swept; `{}` has {} numbers",
                        axis.name, p.len
                    ),
                );
                continue;
            }
            Some(_) => {}
        }
        if axes.iter().any(|a: &Axis| a.name == axis.name) {
            d.push(
                places.file(&at.key("name")),
                format!("`{}` is swept twice", axis.name),
            );
            continue;
        }
        let Some(values) = axis_values(axis, &at, places, d) else {
            continue;
        };
        match origins.get(&axis.name) {
            Some(origin @ Origin::Flag(_)) => d.push(
                origin.clone(),
                format!(
                    "`{}` is swept by the scenario (sweep.parameters[{i}]), so a value set \
                     here would be ignored; drop the --set, or the sweep's axis",
                    axis.name
                ),
            ),
            Some(origin @ Origin::File { .. }) => d.push(
                origin.clone(),
                format!(
                    "`{}` is swept (sweep.parameters[{i}]), so this value would be ignored; \
                     drop it, or the sweep's axis",
                    axis.name
                ),
            ),
            _ => {}
        }
        let unit = info.map(|p| p.unit.to_owned()).unwrap_or_default();
        axes.push(Axis {
            name: axis.name.clone(),
            unit,
            values,
        });
    }
    let mut metrics = Vec::new();
    if spec.peaks.is_empty() {
        d.push(places.file(&root.key("peaks")), "`peaks` lists no output");
    }
    for (i, name) in spec.peaks.iter().enumerate() {
        let origin = places.file(&root.key("peaks").index(i));
        if let Some(columns) = column(entry, name, origin, d) {
            let names: Vec<&str> = columns.iter().map(|(n, _)| n.as_str()).collect();
            metrics.push(Metric {
                name: name.clone(),
                unit: metric_unit(&*entry.model, &names),
                columns: columns.into_iter().map(|(_, c)| c).collect(),
            });
        }
    }
    let [t0, t_end] = base.span();
    let window = spec.window.clone().unwrap_or_default();
    let window = [
        window.from.unwrap_or(0.5 * (t0 + t_end)),
        window.to.unwrap_or(t_end),
    ];
    if !(window[0] >= t0 && window[0] < window[1] && window[1] <= t_end) {
        d.push(
            places.file(&root.key("window")),
            format!(
                "the window [{}, {}] s must be a non-empty part of the time span [{t0}, {t_end}] s",
                window[0], window[1]
            ),
        );
    }
    if d.0.len() > before {
        return None;
    }
    let plan = SweepPlan {
        base,
        axes,
        metrics,
        window,
    };
    // Every point must make physical sense; report the first that does not. Problems
    // that no swept parameter takes part in are those of the base parameters, reported
    // with them.
    for point in plan.points() {
        let mut problems = entry.model.check(&plan.plan_at(&point).params);
        problems.retain(|p| plan.axes.iter().any(|a| p.keys.contains(&a.name)));
        if problems.is_empty() {
            continue;
        }
        for problem in problems {
            let axis = plan
                .axes
                .iter()
                .position(|a| problem.keys.contains(&a.name));
            let origin = match axis {
                Some(i) => places.file(&root.key("parameters").index(i)),
                None => problem
                    .keys
                    .iter()
                    .find_map(|k| origins.get(k).cloned())
                    .unwrap_or(Origin::Nowhere),
            };
            let at: Vec<String> = plan
                .axes
                .iter()
                .zip(&point)
                .map(|(a, v)| format!("{} = {v}", a.name))
                .collect();
            d.push(
                origin,
                format!("at the sweep point {}: {}", at.join(", "), problem.message),
            );
        }
        return None;
    }
    Some(plan)
}

/// The values of one axis: its `values`, or `steps` evenly spaced from `from` to `to`
/// (ends included); every problem with them reported.
fn axis_values(
    axis: &AxisSpec,
    at: &KeyPath,
    places: &Places<'_>,
    d: &mut Diagnostics,
) -> Option<Vec<f64>> {
    let before = d.0.len();
    let values = match (&axis.values, axis.from, axis.to, axis.steps) {
        (Some(values), None, None, None) => {
            if values.is_empty() {
                d.push(places.file(&at.key("values")), "`values` lists no value");
                return None;
            }
            let origin = places.file(&at.key("values"));
            if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
                d.push(
                    origin.clone(),
                    format!("every value must be finite, found {}", format_number(*bad)),
                );
            }
            let mut seen: Vec<f64> = Vec::new();
            for &v in values {
                if seen.contains(&v) {
                    d.push(
                        origin.clone(),
                        format!(
                            "{} is listed twice; each value is one run, list it once",
                            format_number(v)
                        ),
                    );
                    break;
                }
                seen.push(v);
            }
            values.clone()
        }
        (None, Some(from), Some(to), Some(steps)) => {
            for (key, v) in [("from", from), ("to", to)] {
                if !v.is_finite() {
                    d.push(
                        places.file(&at.key(key)),
                        format!(
                            "`{key}` must be a finite number, found {}",
                            format_number(v)
                        ),
                    );
                }
            }
            if steps < 1 {
                d.push(
                    places.file(&at.key("steps")),
                    "`steps` (the number of values, ends included) must be >= 1, found 0",
                );
            } else if steps > MAX_STEPS {
                d.push(
                    places.file(&at.key("steps")),
                    format!("`steps` must be at most {MAX_STEPS}, found {steps}"),
                );
            }
            if from > to {
                d.push(
                    places.file(&at.key("to")),
                    format!(
                        "`to` ({}) is below `from` ({}); a sweep goes up: swap them",
                        format_number(to),
                        format_number(from)
                    ),
                );
            } else if from == to && steps > 1 {
                d.push(
                    places.file(&at.key("steps")),
                    format!(
                        "`from` and `to` are both {}, so the {steps} steps would all be the \
                         same run; use `steps: 1` or widen the range",
                        format_number(from)
                    ),
                );
            } else if from < to && steps == 1 {
                d.push(
                    places.file(&at.key("steps")),
                    "one step gives only `from`; set `steps` >= 2 to reach `to`, or `to` equal \
                     to `from`",
                );
            }
            if d.0.len() > before {
                return None;
            }
            if steps == 1 {
                vec![from]
            } else {
                (0..steps)
                    .map(|k| from + (to - from) * k as f64 / (steps - 1) as f64)
                    .collect()
            }
        }
        _ => {
            d.push(
                places.file(at),
                "give either `values: [...]` or all of `from`, `to` and `steps`",
            );
            return None;
        }
    };
    (d.0.len() == before).then_some(values)
}
