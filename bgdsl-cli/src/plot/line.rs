//! Line charts: named series of `(x, y)` points, a legend beside the plot, a title
//! wrapped to the width.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{nice_ticks, padded_range, Tick, TickedAxis};
use super::clip::clip;
use super::decimate::{for_display, thousands, Thinned};
use super::file::{write_images, DrawResult, Drawing};
use super::font::FONT_FAMILY;
use super::{ImageFormat, PlotError, DEFAULT_SIZE};

/// One named curve. A point with a non-finite coordinate (NaN) is a gap: the curve is
/// drawn as the separate polylines between gaps ([`polylines`](super::polylines)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// The legend entry.
    pub label: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series named `label` through `points`.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points,
        }
    }
}

/// A 2-D line chart.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineChart {
    /// The title above the plot (wrapped to the image's width when too long).
    pub title: String,
    /// The x axis's description, with its unit, e.g. `time t (s)`.
    pub x_label: String,
    /// The y axis's description, with its unit.
    pub y_label: String,
    /// The curves, drawn in order; the legend lists them in this order.
    pub series: Vec<Series>,
}

/// How one series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SeriesStyle {
    /// Line colour, RGB.
    pub color: (u8, u8, u8),
    /// Line width, pixels.
    pub width: u32,
    /// Whether the line is dashed.
    pub dashed: bool,
}

impl SeriesStyle {
    /// A solid line of `color`, 2 px wide.
    pub const fn solid(color: (u8, u8, u8)) -> Self {
        SeriesStyle {
            color,
            width: 2,
            dashed: false,
        }
    }

    /// A dashed line of `color`, 2 px wide.
    pub const fn dashed(color: (u8, u8, u8)) -> Self {
        SeriesStyle {
            color,
            width: 2,
            dashed: true,
        }
    }
}

/// The colours given to series without a style, in order: red, green and blue first
/// (the x, y and z components), then others.
pub const PALETTE: [(u8, u8, u8); 6] = [
    (214, 39, 40),
    (44, 160, 44),
    (31, 119, 180),
    (255, 127, 14),
    (148, 103, 189),
    (0, 0, 0),
];

/// A shaded band between two curves over the same x values, drawn under the series
/// (e.g. the 5–95 % quantiles of a study's samples).
#[derive(Clone, Debug, PartialEq)]
pub struct Fill {
    /// `(x, lower, upper)`, in x order; a point with a non-finite value breaks the band.
    pub points: Vec<(f64, f64, f64)>,
    /// Fill colour, RGB.
    pub color: (u8, u8, u8),
    /// Opacity in `[0, 1]`.
    pub opacity: f64,
}

/// Choices beyond the chart's content. The default: [`DEFAULT_SIZE`], ranges fitted to
/// the data with 4 % padding, round-number ticks, the [`PALETTE`].
#[derive(Clone, Debug, PartialEq)]
pub struct ChartOptions {
    /// Image size, pixels (for a stacked chart, the size of each panel).
    pub size: (u32, u32),
    /// A fixed x range instead of the data's.
    pub x_range: Option<(f64, f64)>,
    /// A fixed y range instead of the data's; curves are clipped to it.
    pub y_range: Option<(f64, f64)>,
    /// Fixed x ticks (e.g. at multiples of π/2) instead of round numbers.
    pub x_ticks: Option<Vec<Tick>>,
    /// The style of series `i`; series beyond the list take [`PALETTE`]`[i]`.
    pub styles: Vec<SeriesStyle>,
    /// A remark written in the plot's top left corner, e.g. that a curve goes off
    /// scale (a chart whose curves were thinned for display says so below it).
    pub note: Option<String>,
    /// Bands shaded under the series, in order (later ones on top); they count in the
    /// fitted ranges.
    pub fills: Vec<Fill>,
}

impl Default for ChartOptions {
    fn default() -> Self {
        ChartOptions {
            size: DEFAULT_SIZE,
            x_range: None,
            y_range: None,
            x_ticks: None,
            styles: Vec::new(),
            note: None,
            fills: Vec::new(),
        }
    }
}

impl ChartOptions {
    fn style(&self, i: usize) -> SeriesStyle {
        self.styles
            .get(i)
            .copied()
            .unwrap_or(SeriesStyle::solid(PALETTE[i % PALETTE.len()]))
    }
}

/// Draws `chart` with the default [`ChartOptions`] to `path_without_extension` + `.png`
/// and/or `.svg`, atomically; returns the files written.
///
/// # Errors
///
/// [`PlotError::Font`] if no font is found, [`PlotError::Draw`] or [`PlotError::Io`]
/// naming the image that failed.
pub fn draw_line_chart(
    chart: &LineChart,
    path_without_extension: &Path,
    formats: &[ImageFormat],
) -> Result<Vec<PathBuf>, PlotError> {
    draw_line_chart_with(
        chart,
        &ChartOptions::default(),
        path_without_extension,
        formats,
    )
}

/// Draws `chart` as [`draw_line_chart`] does, with `options`.
///
/// # Errors
///
/// As [`draw_line_chart`].
pub fn draw_line_chart_with(
    chart: &LineChart,
    options: &ChartOptions,
    path_without_extension: &Path,
    formats: &[ImageFormat],
) -> Result<Vec<PathBuf>, PlotError> {
    let drawing = Stacked {
        title: "",
        panels: std::slice::from_ref(chart),
        options: std::slice::from_ref(options),
    };
    write_images(&drawing, path_without_extension, formats)
}

/// Draws several charts stacked vertically in one image under a common `title`, each
/// panel with its own title (drawn smaller), axes and legend; panel `i` uses
/// `options[i]` (or the default) and the image is as wide as the widest panel and as
/// high as all of them together.
///
/// # Errors
///
/// As [`draw_line_chart`].
pub fn draw_stacked_charts(
    title: &str,
    panels: &[LineChart],
    options: &[ChartOptions],
    path_without_extension: &Path,
    formats: &[ImageFormat],
) -> Result<Vec<PathBuf>, PlotError> {
    let defaults;
    let options = if options.len() >= panels.len() {
        options
    } else {
        defaults = (0..panels.len())
            .map(|i| options.get(i).cloned().unwrap_or_default())
            .collect::<Vec<_>>();
        &defaults
    };
    let drawing = Stacked {
        title,
        panels,
        options,
    };
    write_images(&drawing, path_without_extension, formats)
}

/// Font sizes, pixels.
pub(crate) const TITLE_SIZE: u32 = 22;
const PANEL_TITLE_SIZE: u32 = 18;
const AXIS_DESC_SIZE: u32 = 18;
const TICK_SIZE: u32 = 15;
const LEGEND_SIZE: u32 = 16;

/// At most this many round-number ticks on an axis.
const X_TICKS: usize = 10;
const Y_TICKS: usize = 10;

/// Charts stacked vertically under an optional common title.
struct Stacked<'a> {
    title: &'a str,
    panels: &'a [LineChart],
    options: &'a [ChartOptions],
}

impl Stacked<'_> {
    /// The widest panel's width ([`DEFAULT_SIZE`]'s without panels).
    fn width(&self) -> u32 {
        let widest = self.options.iter().map(|o| o.size.0).max();
        widest.unwrap_or(DEFAULT_SIZE.0).max(1)
    }

    fn common_title_height(&self) -> u32 {
        title_height(
            &title_lines(self.title, TITLE_SIZE, self.width()),
            TITLE_SIZE,
        )
    }

    /// The legend strip's width, the same for every panel so that their plots line up.
    fn legend_width(&self) -> u32 {
        let labels = self
            .panels
            .iter()
            .flat_map(|c| c.series.iter().map(|s| s.label.as_str()))
            .filter(|l| !l.is_empty());
        legend_width(labels, self.width())
    }
}

impl Drawing for Stacked<'_> {
    fn size(&self) -> (u32, u32) {
        let height: u32 = self.options.iter().map(|o| o.size.1).sum();
        (self.width(), height + self.common_title_height())
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        let mut rest = root.clone();
        if !self.title.is_empty() {
            let (head, below) = rest.split_vertically(self.common_title_height());
            draw_title(&head, self.title, TITLE_SIZE)?;
            rest = below;
        }
        let single = self.panels.len() == 1 && self.title.is_empty();
        let title_size = if single { TITLE_SIZE } else { PANEL_TITLE_SIZE };
        let legend = self.legend_width();
        for (chart, options) in self.panels.iter().zip(self.options) {
            let (area, below) = rest.split_vertically(options.size.1);
            draw_chart(&area, chart, options, title_size, legend)?;
            rest = below;
        }
        Ok(())
    }
}

/// The lines of `text` at font `size` wrapped to fit `width` less a margin.
fn title_lines(text: &str, size: u32, width: u32) -> Vec<String> {
    let font = (FONT_FAMILY, size).into_font();
    let max_width = width.saturating_sub(40);
    wrap(text, |s| {
        font.box_size(s).map(|(w, _)| w).unwrap_or(u32::MAX) <= max_width
    })
}

/// The height that `lines` of a title at font `size` take, margins included.
fn title_height(lines: &[String], size: u32) -> u32 {
    if lines.is_empty() {
        0
    } else {
        TITLE_TOP + lines.len() as u32 * (size + 6) + 6
    }
}

/// Space above a title, pixels.
const TITLE_TOP: u32 = 12;

/// Draws `text` centred at the top of `area`, wrapped to its width; returns the height
/// used.
pub(crate) fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: u32,
) -> Result<u32, Box<dyn std::error::Error + Send + Sync>>
where
    DB::ErrorType: 'static,
{
    let width = area.dim_in_pixel().0;
    let lines = title_lines(text, size, width);
    let style = TextStyle::from((FONT_FAMILY, size).into_font())
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (i, line) in lines.iter().enumerate() {
        let y = TITLE_TOP + i as u32 * (size + 6);
        area.draw_text(line, &style, ((width / 2) as i32, y as i32))?;
    }
    Ok(title_height(&lines, size))
}

/// Greedy word wrap: as many words per line as `fits`.
fn wrap(text: &str, fits: impl Fn(&str) -> bool) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let candidate = if line.is_empty() {
            word.to_owned()
        } else {
            format!("{line} {word}")
        };
        if line.is_empty() || fits(&candidate) {
            line = candidate;
        } else {
            lines.push(std::mem::replace(&mut line, word.to_owned()));
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// The width of a legend strip for `labels` in an image `image_width` wide (at most a
/// third of it), pixels; 0 without labels.
pub(crate) fn legend_width<'a>(labels: impl Iterator<Item = &'a str>, image_width: u32) -> u32 {
    let font = (FONT_FAMILY, LEGEND_SIZE).into_font();
    let widest = labels
        .map(|l| font.box_size(l).map(|(w, _)| w).unwrap_or(0))
        .max();
    match widest {
        Some(w) => (w + 80).min(image_width / 3),
        None => 0,
    }
}

/// Draws one chart (title, plot, legend strip `legend` pixels wide) filling `area`.
fn draw_chart<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &LineChart,
    options: &ChartOptions,
    title_size: u32,
    legend: u32,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let title_height = draw_title(area, &chart.title, title_size)?;
    let (_, body) = area.split_vertically(title_height);
    let (plot, legend_area) = body.split_horizontally(body.dim_in_pixel().0 - legend);
    draw_plot(&plot, chart, options)?;
    if legend > 0 {
        let entries: Vec<(&str, SeriesStyle)> = chart
            .series
            .iter()
            .enumerate()
            .map(|(i, s)| (s.label.as_str(), options.style(i)))
            .collect();
        draw_legend(&legend_area, &entries)?;
    }
    Ok(())
}

/// The x and y ranges of the chart: fixed ones, or the data's with 4 % padding (the x
/// range unpadded: the data usually start and end on the axis's natural limits).
fn ranges(chart: &LineChart, options: &ChartOptions) -> ((f64, f64), (f64, f64)) {
    let fills = || {
        options
            .fills
            .iter()
            .flat_map(|f| f.points.iter().flat_map(|&(x, lo, hi)| [(x, lo), (x, hi)]))
    };
    let points = || {
        chart
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .chain(fills())
    };
    let finite = || points().filter(|(x, y)| x.is_finite() && y.is_finite());
    let x = options
        .x_range
        .or_else(|| padded_range(finite().map(|p| p.0), 0.0))
        .unwrap_or((0.0, 1.0));
    let y = options
        .y_range
        .or_else(|| padded_range(finite().map(|p| p.1), 0.04))
        .unwrap_or((-1.0, 1.0));
    (x, y)
}

fn draw_plot<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &LineChart,
    options: &ChartOptions,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (x_range, y_range) = ranges(chart, options);
    let x_ticks = options
        .x_ticks
        .clone()
        .unwrap_or_else(|| nice_ticks(x_range.0, x_range.1, X_TICKS));
    let y_ticks = nice_ticks(y_range.0, y_range.1, Y_TICKS);
    let mut ctx = ChartBuilder::on(area)
        .margin_top(10)
        .margin_right(20)
        .margin_left(10)
        .x_label_area_size(56)
        .y_label_area_size(96)
        .build_cartesian_2d(
            TickedAxis {
                range: x_range,
                ticks: x_ticks,
            },
            TickedAxis {
                range: y_range,
                ticks: y_ticks,
            },
        )?;
    ctx.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .label_style((FONT_FAMILY, TICK_SIZE))
        .axis_desc_style((FONT_FAMILY, AXIS_DESC_SIZE))
        .bold_line_style(BLACK.mix(0.15))
        .light_line_style(BLACK.mix(0.05))
        .draw()?;
    for fill in &options.fills {
        draw_fill(&mut ctx, fill, y_range)?;
    }
    // Thinned for display (see `decimate`); the first series last, so that it is on top.
    let columns = ctx.plotting_area().dim_in_pixel().0 as usize;
    let thinned: Vec<Thinned> = chart
        .series
        .iter()
        .enumerate()
        .map(|(i, series)| {
            let lines = clip(&series.points, x_range, y_range);
            for_display(lines, x_range, columns, options.style(i).dashed)
        })
        .collect();
    for (i, thinned) in thinned.iter().enumerate().rev() {
        let style = options.style(i);
        let color = RGBColor(style.color.0, style.color.1, style.color.2);
        let shape = color.stroke_width(style.width);
        for line in &thinned.lines {
            let points = line.iter().copied();
            if line.len() == 1 {
                ctx.draw_series(points.map(|p| Circle::new(p, 2, shape.filled())))?;
            } else if style.dashed {
                ctx.draw_series(DashedLineSeries::new(points, 8, 5, shape))?;
            } else {
                ctx.draw_series(LineSeries::new(points, shape))?;
            }
        }
    }
    let note = [options.note.clone(), decimation_note(&thinned)]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join("\n");
    if !note.is_empty() {
        draw_note(&ctx.plotting_area().strip_coord_spec(), &note)?;
    }
    Ok(())
}

/// Shades `fill` as one polygon per run of finite points (upper edge forward, lower edge
/// back), its values clamped to the y range.
fn draw_fill<DB: DrawingBackend>(
    ctx: &mut ChartContext<'_, DB, Cartesian2d<TickedAxis, TickedAxis>>,
    fill: &Fill,
    (y_lo, y_hi): (f64, f64),
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let color = RGBColor(fill.color.0, fill.color.1, fill.color.2).mix(fill.opacity);
    let finite = |p: &&(f64, f64, f64)| p.0.is_finite() && p.1.is_finite() && p.2.is_finite();
    let points: Vec<&(f64, f64, f64)> = fill.points.iter().collect();
    for run in points.split(|p| !finite(p)) {
        if run.len() < 2 {
            continue;
        }
        let clamp = |v: f64| v.clamp(y_lo, y_hi);
        let outline: Vec<(f64, f64)> = run
            .iter()
            .map(|p| (p.0, clamp(p.2)))
            .chain(run.iter().rev().map(|p| (p.0, clamp(p.1))))
            .collect();
        ctx.draw_series(std::iter::once(Polygon::new(outline, color.filled())))?;
    }
    Ok(())
}

/// `drawn from 3,600 of 955,001 points (min/max per pixel column)` when some series
/// was thinned.
fn decimation_note(thinned: &[Thinned]) -> Option<String> {
    thinned.iter().any(Thinned::decimated).then(|| {
        let kept = thinned.iter().map(|t| t.kept as u64).sum();
        let total = thinned.iter().map(|t| t.total as u64).sum();
        format!(
            "drawn from {} of {} points (min/max per pixel column)",
            thousands(kept),
            thousands(total)
        )
    })
}

/// `note` (one or more lines) in the top left corner of the plotting area, on a white
/// box.
fn draw_note<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, note: &str) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let font = (FONT_FAMILY, LEGEND_SIZE).into_font();
    let lines: Vec<&str> = note.lines().collect();
    let row = LEGEND_SIZE as i32 + 6;
    let mut w = 0;
    for line in &lines {
        w = w.max(font.box_size(line)?.0 as i32);
    }
    let h = row * lines.len() as i32 - 6;
    area.draw(&Rectangle::new(
        [(6, 6), (18 + w, 14 + h)],
        WHITE.mix(0.85).filled(),
    ))?;
    area.draw(&Rectangle::new([(6, 6), (18 + w, 14 + h)], BLACK.mix(0.3)))?;
    let grey = BLACK.mix(0.8);
    let style = TextStyle::from(font)
        .color(&grey)
        .pos(Pos::new(HPos::Left, VPos::Top));
    for (i, line) in lines.iter().enumerate() {
        area.draw_text(line, &style, (12, 10 + i as i32 * row))?;
    }
    Ok(())
}

/// The legend: one line sample and label per entry, top to bottom.
pub(crate) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(&str, SeriesStyle)],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let text = TextStyle::from((FONT_FAMILY, LEGEND_SIZE).into_font())
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let row = LEGEND_SIZE as i32 + 10;
    let top = 24;
    for (i, (label, style)) in entries.iter().enumerate() {
        let color = RGBColor(style.color.0, style.color.1, style.color.2);
        let shape = color.stroke_width(style.width + 1);
        let y = top + i as i32 * row;
        let dashes: &[(i32, i32)] = if style.dashed {
            &[(4, 14), (20, 30), (36, 40)]
        } else {
            &[(4, 40)]
        };
        for &(from, to) in dashes {
            area.draw(&PathElement::new(vec![(from, y), (to, y)], shape))?;
        }
        area.draw_text(label, &text, (48, y))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fills_count_in_the_fitted_ranges() {
        let chart = LineChart {
            series: vec![Series::new("median", vec![(0.0, 1.0), (2.0, 1.0)])],
            ..LineChart::default()
        };
        let options = ChartOptions {
            fills: vec![Fill {
                points: vec![(0.0, -3.0, 5.0), (2.0, 0.0, 2.0)],
                color: (0, 0, 255),
                opacity: 0.2,
            }],
            ..ChartOptions::default()
        };
        let (x, (lo, hi)) = ranges(&chart, &options);
        assert_eq!(x, (0.0, 2.0));
        // The band's -3 and 5, padded by 4 % of their span.
        assert!(lo <= -3.0 && hi >= 5.0, "{lo} {hi}");
        let (_, (lo, hi)) = ranges(&chart, &ChartOptions::default());
        assert!(lo > -3.0 && hi < 5.0, "without the fill: {lo} {hi}");
    }

    #[test]
    fn titles_wrap_at_words() {
        let fits = |s: &str| s.len() <= 12;
        assert_eq!(
            wrap("force at the fixed end of the crank", fits),
            ["force at the", "fixed end of", "the crank"]
        );
        assert_eq!(
            wrap("averyveryverylongword x", fits),
            ["averyveryverylongword", "x"]
        );
    }
}
