//! Curves in 3-D, such as the paths traced by the tips of the unit vectors of an
//! orientation matrix, drawn in plotters' `Cartesian3d` with the data's z axis up.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use plotters::coord::ranged3d::Cartesian3d;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{nice_ticks, padded_range, without_collisions, PlacedLabel};
use super::file::{write_images, DrawResult, Drawing};
use super::font::FONT_FAMILY;
use super::line::{draw_legend, draw_title, legend_width, SeriesStyle, PALETTE, TITLE_SIZE};
use super::{ImageFormat, PlotError, DEFAULT_SIZE};

/// One named curve in 3-D; a non-finite point is a gap.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series3d {
    /// The legend entry.
    pub label: String,
    /// The points `(x, y, z)`, in drawing order.
    pub points: Vec<(f64, f64, f64)>,
}

/// A 3-D chart of curves. The data's z axis is drawn vertical, x and y span the floor.
/// Each curve is marked where it starts (a ring) and ends (a dot); the legend says so.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trajectory3d {
    /// The title above the plot.
    pub title: String,
    /// The x, y and z axes' names (drawn at the positive end of each axis).
    pub axis_labels: [String; 3],
    /// Fixed ranges of x, y and z; `None` fits them to the data (each with 5 % padding).
    pub range: Option<[(f64, f64); 3]>,
    /// The curves, coloured as the [`PALETTE`](super::line::PALETTE) in order.
    pub series: Vec<Series3d>,
    /// The legend entries for the start and end marks, e.g. `start (t = 0 s)`; empty
    /// strings leave them out of the legend (the marks are still drawn).
    pub marks: [String; 2],
    /// Whether to draw a thin line from the origin to each curve's first point (the
    /// unit vectors at the start).
    pub from_origin: bool,
}

/// The view: elevation and azimuth of plotters' projection, rad.
const PITCH: f64 = 0.75;
/// The tick labels' size, px.
const TICK_FONT_SIZE: i32 = 14;
const YAW: f64 = 0.55;

/// Draws `chart` to `path_without_extension` + `.png` and/or `.svg`, atomically, at
/// [`DEFAULT_SIZE`]; returns the files written.
///
/// # Errors
///
/// As [`draw_line_chart`](super::draw_line_chart).
pub fn draw_trajectory_3d(
    chart: &Trajectory3d,
    path_without_extension: &Path,
    formats: &[ImageFormat],
) -> Result<Vec<PathBuf>, PlotError> {
    write_images(chart, path_without_extension, formats)
}

/// A point in plotters' 3-D coordinates: plotters draws its y axis vertical, so the
/// data's z goes there; the data's y goes in depth, negated so that the picture keeps
/// the data's right-handedness (x, y, z counter-clockwise seen from +z).
type View = (f64, f64, f64);

fn view((x, y, z): (f64, f64, f64)) -> View {
    (x, z, -y)
}

fn finite3(p: &&(f64, f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite() && p.2.is_finite()
}

/// The runs of finite points of `points`, each thinned to points at least `min_step`
/// apart (the first and last kept), so that wide lines are drawn from segments longer
/// than their width; and a segment that joins the same two cells of a grid `min_step`
/// wide as an earlier one is dropped, so that a path retraced many times (hundreds of
/// revolutions) is drawn once and the image stays small.
fn thinned_runs(points: &[(f64, f64, f64)], min_step: f64) -> Vec<Vec<View>> {
    let cell = |p: (f64, f64, f64)| {
        let q = |v: f64| (v / min_step).round() as i64;
        (q(p.0), q(p.1), q(p.2))
    };
    let mut drawn = HashSet::new();
    let mut out = Vec::new();
    for run in points.split(|p| !finite3(&p)).filter(|run| !run.is_empty()) {
        let mut kept: Vec<(f64, f64, f64)> = vec![run[0]];
        for (i, &p) in run.iter().enumerate().skip(1) {
            let last = kept[kept.len() - 1];
            let d =
                ((p.0 - last.0).powi(2) + (p.1 - last.1).powi(2) + (p.2 - last.2).powi(2)).sqrt();
            if d >= min_step || i == run.len() - 1 {
                kept.push(p);
            }
        }
        if kept.len() == 1 {
            out.push(vec![view(kept[0])]);
            continue;
        }
        let mut current: Vec<View> = Vec::new();
        for pair in kept.windows(2) {
            let (a, b) = (cell(pair[0]), cell(pair[1]));
            if drawn.insert((a.min(b), a.max(b))) {
                if current.is_empty() {
                    current.push(view(pair[0]));
                }
                current.push(view(pair[1]));
            } else if !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
        }
        if !current.is_empty() {
            out.push(current);
        }
    }
    out
}

impl Trajectory3d {
    fn ranges(&self) -> [(f64, f64); 3] {
        if let Some(range) = self.range {
            return range;
        }
        let finite = || {
            self.series
                .iter()
                .flat_map(|s| s.points.iter())
                .filter(finite3)
        };
        [
            padded_range(finite().map(|p| p.0), 0.05).unwrap_or((-1.0, 1.0)),
            padded_range(finite().map(|p| p.1), 0.05).unwrap_or((-1.0, 1.0)),
            padded_range(finite().map(|p| p.2), 0.05).unwrap_or((-1.0, 1.0)),
        ]
    }

    /// The first series wider, so that a later one drawn over the same path (the tips
    /// of two unit vectors turning in one plane trace the same circle) leaves it
    /// visible on both sides.
    fn style(i: usize) -> SeriesStyle {
        SeriesStyle {
            width: if i == 0 { 4 } else { 2 },
            ..SeriesStyle::solid(PALETTE[i % PALETTE.len()])
        }
    }

    /// The tick labels of the three axes, each along the edge of the box that lies
    /// furthest out on the picture, set off outwards; a label that would overlap one
    /// already placed (where two axes' edges meet at a corner) is left out
    /// ([`without_collisions`]). The vertical axis is labelled first.
    fn draw_tick_labels<DB: DrawingBackend, X, Y, Z>(
        &self,
        chart: &mut ChartContext<'_, DB, Cartesian3d<X, Y, Z>>,
        ranges: [(f64, f64); 3],
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
        Z: Ranged<ValueType = f64>,
    {
        let pixel = |p: (f64, f64, f64)| chart.as_coord_spec().translate(&view(p));
        let corner = |bits: [usize; 3]| {
            let pick = |axis: usize| {
                let (lo, hi) = ranges[axis];
                if bits[axis] == 0 {
                    lo
                } else {
                    hi
                }
            };
            (pick(0), pick(1), pick(2))
        };
        let centre = pixel((
            0.5 * (ranges[0].0 + ranges[0].1),
            0.5 * (ranges[1].0 + ranges[1].1),
            0.5 * (ranges[2].0 + ranges[2].1),
        ));
        let mut placed = Vec::new();
        for axis in [2, 0, 1] {
            let (lo, hi) = ranges[axis];
            let others: Vec<usize> = (0..3).filter(|&a| a != axis).collect();
            // The four edges along `axis`, by the other two axes' ends; the one whose
            // middle is furthest from the picture's centre is on the outline.
            let edge = (0..4)
                .map(|k| {
                    let mut bits = [0; 3];
                    bits[others[0]] = k & 1;
                    bits[others[1]] = k >> 1;
                    bits
                })
                .max_by_key(|bits| {
                    let (a, b) = (pixel(corner(*bits)), {
                        let mut far = *bits;
                        far[axis] = 1;
                        pixel(corner(far))
                    });
                    let mid = ((a.0 + b.0) / 2 - centre.0, (a.1 + b.1) / 2 - centre.1);
                    mid.0 * mid.0 + mid.1 * mid.1
                })
                .unwrap_or([0; 3]);
            for tick in nice_ticks(lo, hi, 4) {
                let mut at = corner(edge);
                match axis {
                    0 => at.0 = tick.value,
                    1 => at.1 = tick.value,
                    _ => at.2 = tick.value,
                }
                let p = pixel(at);
                let out = (f64::from(p.0 - centre.0), f64::from(p.1 - centre.1));
                let length = out.0.hypot(out.1).max(1.0);
                let (ux, uy) = (out.0 / length, out.1 / length);
                // Far enough out that the text's box clears the edge.
                let size = f64::from(TICK_FONT_SIZE);
                let half_width = 0.3 * size * tick.label.chars().count() as f64;
                let offset = 8.0 + ux.abs() * half_width + uy.abs() * 0.5 * size;
                placed.push(PlacedLabel {
                    text: tick.label,
                    at: (
                        p.0 + (offset * ux).round() as i32,
                        p.1 + (offset * uy).round() as i32,
                    ),
                });
            }
        }
        let style = TextStyle::from((FONT_FAMILY, TICK_FONT_SIZE).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center));
        let area = chart.plotting_area().strip_coord_spec();
        let (x0, y0) = (area.get_base_pixel().0, area.get_base_pixel().1);
        for label in without_collisions(placed, f64::from(TICK_FONT_SIZE)) {
            area.draw(&Text::new(
                label.text,
                (label.at.0 - x0, label.at.1 - y0),
                style.clone(),
            ))?;
        }
        Ok(())
    }

    /// Thin grey axes through the origin (or the nearest point of the box), each named
    /// at its positive end.
    fn draw_axes<DB: DrawingBackend, X, Y, Z>(
        &self,
        chart: &mut ChartContext<'_, DB, Cartesian3d<X, Y, Z>>,
        [x, y, z]: [(f64, f64); 3],
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
        Z: Ranged<ValueType = f64>,
    {
        let text = TextStyle::from((FONT_FAMILY, 20).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center));
        let axis = BLACK.mix(0.45).stroke_width(1);
        let o = |(lo, hi): (f64, f64)| 0f64.clamp(lo, hi);
        let (ox, oy, oz) = (o(x), o(y), o(z));
        let beyond = |(lo, hi): (f64, f64)| hi + 0.1 * (hi - lo);
        let ends = [
            ((x.0, oy, oz), (x.1, oy, oz), (beyond(x), oy, oz)),
            ((ox, y.0, oz), (ox, y.1, oz), (ox, beyond(y), oz)),
            ((ox, oy, z.0), (ox, oy, z.1), (ox, oy, beyond(z))),
        ];
        for ((from, to, label_at), label) in ends.into_iter().zip(&self.axis_labels) {
            chart.draw_series(std::iter::once(PathElement::new(
                vec![view(from), view(to)],
                axis,
            )))?;
            chart.draw_series(std::iter::once(Text::new(
                label.clone(),
                view(label_at),
                text.clone(),
            )))?;
        }
        Ok(())
    }
}

impl Drawing for Trajectory3d {
    fn size(&self) -> (u32, u32) {
        DEFAULT_SIZE
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        let title_height = draw_title(root, &self.title, TITLE_SIZE)?;
        let (_, body) = root.split_vertically(title_height);
        let entries: Vec<(&str, SeriesStyle)> = self
            .series
            .iter()
            .enumerate()
            .map(|(i, s)| {
                (
                    s.label.as_str(),
                    SeriesStyle {
                        width: 2,
                        ..Self::style(i)
                    },
                )
            })
            .collect();
        let marks: Vec<&str> = self
            .marks
            .iter()
            .map(String::as_str)
            .filter(|m| !m.is_empty())
            .collect();
        let labels = entries.iter().map(|e| e.0).chain(marks.iter().copied());
        let width = legend_width(labels, body.dim_in_pixel().0);
        let (plot, legend) = body.split_horizontally(body.dim_in_pixel().0 - width);
        self.draw_plot(&plot)?;
        draw_legend(&legend, &entries)?;
        self.draw_mark_legend(&legend, &marks)?;
        Ok(())
    }
}

impl Trajectory3d {
    fn draw_plot<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let [x, y, z] = self.ranges();
        let mut chart =
            ChartBuilder::on(area)
                .margin(20)
                .build_cartesian_3d(x.0..x.1, z.0..z.1, -y.1..-y.0)?;
        chart.with_projection(|mut p| {
            p.pitch = PITCH;
            p.yaw = YAW;
            p.scale = 0.85;
            p.into_matrix()
        });
        // plotters draws the grid; the tick labels are placed below, so that those
        // meeting at a corner of the box are not drawn over one another.
        let blank = |_: &f64| String::new();
        chart
            .configure_axes()
            .label_style((FONT_FAMILY, TICK_FONT_SIZE))
            .x_formatter(&blank)
            .y_formatter(&blank)
            .z_formatter(&blank)
            .x_labels(5)
            .y_labels(5)
            .z_labels(5)
            .light_grid_style(BLACK.mix(0.06))
            .bold_grid_style(BLACK.mix(0.15))
            .max_light_lines(1)
            .draw()?;
        self.draw_tick_labels(&mut chart, [x, y, z])?;
        self.draw_axes(&mut chart, [x, y, z])?;
        let diagonal = ((x.1 - x.0).powi(2) + (y.1 - y.0).powi(2) + (z.1 - z.0).powi(2)).sqrt();
        for (i, series) in self.series.iter().enumerate() {
            let style = Self::style(i);
            let color = RGBColor(style.color.0, style.color.1, style.color.2);
            for run in thinned_runs(&series.points, 1e-2 * diagonal) {
                chart.draw_series(LineSeries::new(run, color.stroke_width(style.width)))?;
            }
            let mut finite = series.points.iter().filter(finite3);
            let Some(&first) = finite.next() else {
                continue;
            };
            let last = finite.next_back().copied().unwrap_or(first);
            if self.from_origin {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![view((0.0, 0.0, 0.0)), view(first)],
                    color.mix(0.7).stroke_width(1),
                )))?;
            }
            chart.draw_series([
                Circle::new(view(first), 6, color.stroke_width(2)),
                Circle::new(view(last), 4, color.filled()),
            ])?;
        }
        Ok(())
    }

    /// The legend rows for the start and end marks, below the series' rows (drawn over
    /// the plain line samples [`draw_legend`] would give them).
    fn draw_mark_legend<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        marks: &[&str],
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let text = TextStyle::from((FONT_FAMILY, 16).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let row = 26;
        let mut y = 24 + self.series.len() as i32 * row;
        let kinds = self.marks.iter().enumerate().filter(|(_, m)| !m.is_empty());
        for ((kind, _), label) in kinds.zip(marks) {
            if kind == 0 {
                area.draw(&Circle::new((22, y), 7, BLACK.stroke_width(2)))?;
            } else {
                area.draw(&Circle::new((22, y), 5, BLACK.filled()))?;
            }
            area.draw_text(label, &text, (48, y))?;
            y += row;
        }
        Ok(())
    }
}
