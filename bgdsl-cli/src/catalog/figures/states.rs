//! Charts of a model's states against time: one per scalar state, one per vector (the
//! consecutive states `r_x, r_y, r_z` or `R_11 … R_33` of one element, as
//! [`resolve_columns`](crate::catalog::resolve_columns) groups them) with a line per
//! component. A model with at most [`STATE_CHART_LIMIT`] states gets them by default;
//! beyond, a chart is drawn only when `plots` names it (by the state's or the vector's
//! name), so that the flagship's 121 states do not bury its page.

use std::path::Path;

use super::super::columns::{column_unit, Table};
use super::super::{Entry, Plots, RunError};
use super::{file_stem, plot_error, stop_if_interrupted, with_unit, DrawnFigure};
use crate::plot::{draw_line_chart, ImageFormat, LineChart, Series};

/// The most states a model may have for all of them to be drawn without being asked.
pub const STATE_CHART_LIMIT: usize = 12;

/// The prefix of files of state charts: `state_<name>.png`.
pub const FILE_PREFIX: &str = "state_";

/// One chart of states: a scalar state or the components of a vector.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StateGroup {
    /// Its id in `plots`: the state's name, or the vector's (`crank.r` for
    /// `crank.r_x`, `crank.r_y`, `crank.r_z`).
    pub id: String,
    /// The states drawn, by index in the state vector.
    pub members: Vec<usize>,
}

/// The vector name `name` is a component of (`crank.r` for `crank.r_x`; `crank.R` for
/// `crank.R_21`), if it is one.
fn vector_of(name: &str) -> Option<&str> {
    let (prefix, c) = name.rsplit_once('_')?;
    let component =
        matches!(c, "x" | "y" | "z") || (c.len() == 2 && c.chars().all(|ch| ch.is_ascii_digit()));
    (component && !prefix.is_empty()).then_some(prefix)
}

/// The charts of `states` (a model's state names, in order): consecutive components of
/// one vector together, every other state alone.
pub fn state_groups(states: &[&str]) -> Vec<StateGroup> {
    let mut groups: Vec<StateGroup> = Vec::new();
    let mut open: Option<&str> = None;
    for (i, name) in states.iter().enumerate() {
        let vector = vector_of(name);
        match (vector, open, groups.last_mut()) {
            (Some(v), Some(o), Some(last)) if v == o => last.members.push(i),
            _ => groups.push(StateGroup {
                id: vector.unwrap_or(name).to_owned(),
                members: vec![i],
            }),
        }
        open = vector;
    }
    // A "vector" of one component is that state alone, by its own name.
    for g in &mut groups {
        if g.members.len() == 1 {
            g.id = states[g.members[0]].to_owned();
        }
    }
    groups
}

/// Whether `plots` asks for the chart of `group` (of a model with `n_states` states).
pub fn wanted(group: &StateGroup, states: &[&str], n_states: usize, plots: &Plots) -> bool {
    match plots {
        Plots::None => false,
        Plots::All => n_states <= STATE_CHART_LIMIT,
        Plots::Only(ids) => ids
            .iter()
            .any(|id| *id == group.id || group.members.iter().any(|&m| states[m] == id)),
    }
}

/// The state charts `plots` asks for, of the states `table` recorded.
pub(in crate::catalog) fn draw(
    entry: &Entry,
    table: &Table,
    dir: &Path,
    plots: &Plots,
) -> Result<Vec<DrawnFigure>, RunError> {
    let states = entry.model.state_names();
    let mut drawn = Vec::new();
    if table.len() < 2 {
        return Ok(drawn);
    }
    for group in state_groups(states) {
        if !wanted(&group, states, states.len(), plots) {
            continue;
        }
        let series: Vec<Series> = group
            .members
            .iter()
            .filter_map(|&m| {
                let name = states[m];
                let (_, values) = table.columns().find(|(n, _)| *n == name)?;
                let points = table.times().iter().copied().zip(values.iter().copied());
                Some(Series::new(name, points.collect()))
            })
            .collect();
        if series.is_empty() {
            continue;
        }
        stop_if_interrupted()?;
        let units: Vec<&str> = series
            .iter()
            .map(|s| column_unit(&*entry.model, &s.label).0)
            .collect();
        let unit = if units.iter().all(|u| *u == units[0]) {
            units[0]
        } else {
            ""
        };
        let what = if group.members.len() > 1 {
            "components of state"
        } else {
            "state"
        };
        let chart = LineChart {
            title: format!(
                "{} ({}): {what} {} against time",
                entry.model.type_name(),
                entry.name,
                group.id
            ),
            x_label: "time t (s)".to_owned(),
            y_label: with_unit(&group.id, unit),
            series,
        };
        let stem = format!("{FILE_PREFIX}{}", file_stem(&group.id));
        let files =
            draw_line_chart(&chart, &dir.join(stem), &ImageFormat::ALL).map_err(plot_error)?;
        drawn.push(DrawnFigure {
            id: group.id.clone(),
            title: chart.title,
            caption: format!(
                "The {what} `{}` of {} at every sample, as the solver integrates it.",
                group.id, entry.name
            ),
            files,
        });
    }
    Ok(drawn)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_are_grouped_and_scalars_stand_alone() {
        let states = [
            "mass.p",
            "crank.r_x",
            "crank.r_y",
            "crank.r_z",
            "crank.R_11",
            "crank.R_21",
            "spring.q",
            "link.r_x",
            "lone.v_x",
            "shaft.q",
        ];
        let groups = state_groups(&states);
        let ids: Vec<&str> = groups.iter().map(|g| g.id.as_str()).collect();
        assert_eq!(
            ids,
            ["mass.p", "crank.r", "crank.R", "spring.q", "link.r_x", "lone.v_x", "shaft.q"]
        );
        assert_eq!(groups[1].members, [1, 2, 3]);
        assert_eq!(groups[2].members, [4, 5]);
        // Every state is drawn exactly once.
        let mut all: Vec<usize> = groups.iter().flat_map(|g| g.members.clone()).collect();
        all.sort_unstable();
        assert_eq!(all, (0..states.len()).collect::<Vec<_>>());
    }

    #[test]
    fn many_states_are_drawn_only_on_request() {
        let few = ["a", "b"];
        let groups = state_groups(&few);
        assert!(wanted(&groups[0], &few, few.len(), &Plots::All));
        assert!(!wanted(&groups[0], &few, few.len(), &Plots::None));
        let many: Vec<String> = (0..=STATE_CHART_LIMIT).map(|i| format!("s{i}")).collect();
        let many: Vec<&str> = many.iter().map(String::as_str).collect();
        let groups = state_groups(&many);
        assert!(!wanted(&groups[0], &many, many.len(), &Plots::All));
        let only = Plots::Only(vec!["s0".into()]);
        assert!(wanted(&groups[0], &many, many.len(), &only));
        assert!(!wanted(&groups[1], &many, many.len(), &only));
        // A vector by its name or by one component's.
        let v = ["r_x", "r_y"];
        let g = &state_groups(&v)[0];
        assert!(wanted(g, &v, 2, &Plots::Only(vec!["r".into()])));
        assert!(wanted(g, &v, 2, &Plots::Only(vec!["r_y".into()])));
    }
}
