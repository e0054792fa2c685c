//! Phase portraits: one quantity against another (a position against its velocity),
//! asked for by name in a scenario (`plots: {phase: [[x, v], ...]}`) or on the command
//! line (`--phase x,v`). Each pair is recorded at every sample whatever `record` says,
//! and drawn as `phase_<x>_<y>.png` and `.svg`, the start and the end marked.

use std::path::Path;

use bgdsl_runtime::Recorder;

use super::super::columns::{column_unit, Column};
use super::super::{Entry, RunError};
use super::{file_stem, plot_error, stop_if_interrupted, with_unit, DrawnFigure};
use crate::plot::{draw_line_chart, ImageFormat, LineChart, Series};

/// A phase portrait asked for: two states or outputs, each by name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PhasePair {
    /// The quantity along the horizontal axis.
    pub x: (String, Column),
    /// The quantity along the vertical axis.
    pub y: (String, Column),
}

impl PhasePair {
    /// Its figure id and file stem, `phase_<x>_<y>` (with the names' characters other
    /// than letters, digits, `_` and `-` as `_`).
    pub fn id(&self) -> String {
        format!("phase_{}_{}", file_stem(&self.x.0), file_stem(&self.y.0))
    }
}

/// Records the pairs of a run's phase portraits at every sample.
pub struct PhaseRecorder {
    pairs: Vec<PhasePair>,
    points: Vec<Vec<(f64, f64)>>,
}

impl PhaseRecorder {
    /// A recorder of `pairs`, with room for `capacity` samples each.
    pub fn new(pairs: &[PhasePair], capacity: usize) -> Self {
        PhaseRecorder {
            pairs: pairs.to_vec(),
            points: pairs.iter().map(|_| Vec::with_capacity(capacity)).collect(),
        }
    }

    /// The points recorded for each pair, in the pairs' order.
    pub fn points(&self) -> &[Vec<(f64, f64)>] {
        &self.points
    }
}

impl Recorder for PhaseRecorder {
    fn record(&mut self, _t: f64, x: &[f64], y: &[f64]) {
        for (pair, points) in self.pairs.iter().zip(&mut self.points) {
            points.push((pair.x.1.value(x, y), pair.y.1.value(x, y)));
        }
    }
}

/// The portraits of everything `recorder` holds.
pub(in crate::catalog) fn draw(
    entry: &Entry,
    recorder: &PhaseRecorder,
    dir: &Path,
) -> Result<Vec<DrawnFigure>, RunError> {
    let mut drawn = Vec::new();
    for (pair, points) in recorder.pairs.iter().zip(&recorder.points) {
        if points.len() < 2 {
            continue;
        }
        stop_if_interrupted()?;
        let (x, y) = (&pair.x.0, &pair.y.0);
        // A series of one point is drawn as a dot.
        let ends = |p: (f64, f64)| vec![p];
        let chart = LineChart {
            title: format!(
                "{} ({}): phase portrait, {y} against {x}",
                entry.model.type_name(),
                entry.name
            ),
            x_label: with_unit(x, column_unit(&*entry.model, x).0),
            y_label: with_unit(y, column_unit(&*entry.model, y).0),
            series: vec![
                Series::new(format!("({x}, {y})"), points.clone()),
                Series::new("start", ends(points[0])),
                Series::new("end", ends(points[points.len() - 1])),
            ],
        };
        let id = pair.id();
        let files =
            draw_line_chart(&chart, &dir.join(&id), &ImageFormat::ALL).map_err(plot_error)?;
        drawn.push(DrawnFigure {
            id,
            title: chart.title,
            caption: format!(
                "`{y}` against `{x}` at every sample of {}'s run, from the start to the end \
                 (the legend's last two entries, as dots).",
                entry.name
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
    fn records_each_pair_from_states_and_outputs() {
        let pairs = [
            PhasePair {
                x: ("spring.q".into(), Column::State(1)),
                y: ("speed".into(), Column::Output(0)),
            },
            PhasePair {
                x: ("mass.p".into(), Column::State(0)),
                y: ("spring.q".into(), Column::State(1)),
            },
        ];
        assert_eq!(pairs[0].id(), "phase_spring_q_speed");
        let mut r = PhaseRecorder::new(&pairs, 2);
        r.record(0.0, &[1.0, 2.0], &[3.0]);
        r.record(0.1, &[4.0, 5.0], &[6.0]);
        assert_eq!(r.points()[0], [(2.0, 3.0), (5.0, 6.0)]);
        assert_eq!(r.points()[1], [(1.0, 2.0), (4.0, 5.0)]);
    }
}
