//! The paper's figures, 3 to 19, and two it lacks, drawn from a run's [`Results`].
//!
//! Each figure is one image per format in the output directory, named after its figure
//! number with a descriptive suffix (`fig05_force_O1_vs_time.png`), titled as in the
//! paper, with its axes labelled with units and its components in the legend as x, y
//! and z:
//!
//! | id | content |
//! |---|---|
//! | `fig03` | orientation of the crank, the unit vectors of \[⁰₁R\] traced in 3-D |
//! | `fig04` | angular momentum of the crank against time |
//! | `fig05`, `fig06` | force at the crank's fixed end O1 against time, crank angle |
//! | `fig07`, `fig08` | drive torque Tc against time, crank angle |
//! | `fig09`, `fig10` | force at the pin A2 on the slider against time, crank angle |
//! | `fig11` | position of the rocker's centre of mass against time |
//! | `fig12` | translational momentum of the rocker against time |
//! | `fig13`, `fig14` | force at the rocker's fixed end O3 against time, crank angle |
//! | `fig15` | orientation of the connecting rod, \[⁰₄R\], in 3-D |
//! | `fig16` | position of the output slider's centre of mass against time |
//! | `fig17` | translational momentum of the output slider against time |
//! | `fig18`, `fig19` | force on the output slider at O5 against time, crank angle |
//! | `fig20` | not in the paper: the output slider's position, velocity and acceleration over the last full crank revolution against the rigid-body kinematics |
//! | `fig21` | not in the paper: the energy balance over time |
//!
//! Plots against the crank angle wrap it to one revolution, [0, 2π) rad (the paper's
//! axis is in radians), and break each curve at every wrap instead of drawing a line
//! across the plot ([`wrap_by_revolution`]). When a start-up transient spans more than
//! 2.5 times what the rest of the run does (the drive torque's 500 N·m at t = 0), the y
//! axis is fitted to the run after its first fifth and the chart and caption say what
//! went off scale. The figures are drawn in parallel (rayon).
//!
//! The catalogue of figures is in the private `catalogue` submodule; Fig. 20 and
//! Fig. 21 have their own (`revolution`, `energy`).

mod catalogue;
mod energy;
mod revolution;

use core::f64::consts::{FRAC_PI_2, PI, TAU};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::plot::{
    draw_line_chart_with, draw_trajectory_3d, settled_range, ChartOptions, ImageFormat, LineChart,
    PlotError, Series, Series3d, SettledRange, Tick, Trajectory3d,
};

pub use crate::plot::wrap_by_revolution;

use super::results::{Results, CRANK_ANGLE};
use crate::quick_return_rigid::{DrivenMechanism, Mechanism};
use catalogue::{number, Figure, Plot, Quantity, Stat, FIGURES, IDS};

/// Every figure id [`draw_figures`] knows, in order: `fig03` … `fig19` (the paper's),
/// `fig20` (the output slider against the rigid kinematics) and `fig21` (the energy
/// balance).
pub const FIGURE_IDS: &[&str] = &IDS;

/// Which figures to draw, in which formats.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FigureOptions {
    /// The image formats, each figure drawn once per format.
    pub formats: Vec<ImageFormat>,
    /// The ids of the figures to draw (see [`FIGURE_IDS`]); `None` draws them all.
    pub only: Option<Vec<String>>,
}

impl Default for FigureOptions {
    /// PNG and SVG, every figure.
    fn default() -> Self {
        FigureOptions {
            formats: ImageFormat::ALL.to_vec(),
            only: None,
        }
    }
}

pub use bgdsl_cli::report::DrawnFigure;

/// Draws the figures `options` selects from `results` into `out_dir` (created if
/// needed), returning each figure drawn, in [`FIGURE_IDS`] order. A figure that
/// cannot be drawn from these results (the steady-revolution figure of a run shorter
/// than a crank revolution) is returned with no files and the reason in its caption.
///
/// # Errors
///
/// [`PlotError::UnknownFigure`] (before anything is drawn) if `options.only` names a
/// figure that does not exist; [`PlotError::Io`] if `out_dir` cannot be created;
/// [`PlotError::Interrupted`] after a signal ([`crate::interrupt`]); otherwise the
/// first error drawing a figure.
pub fn draw_figures(
    results: &Results,
    params: &dyn Mechanism,
    out_dir: &Path,
    options: &FigureOptions,
) -> Result<Vec<DrawnFigure>, PlotError> {
    if let Some(only) = &options.only {
        if let Some(unknown) = only.iter().find(|id| !FIGURE_IDS.contains(&id.as_str())) {
            return Err(PlotError::UnknownFigure {
                id: unknown.clone(),
                valid: FIGURE_IDS,
            });
        }
    }
    std::fs::create_dir_all(out_dir).map_err(|source| PlotError::Io {
        path: out_dir.to_path_buf(),
        action: "creating the directory",
        source,
    })?;
    let selected = |id: &str| {
        options
            .only
            .as_ref()
            .is_none_or(|only| only.iter().any(|o| o == id))
    };
    let data = Data {
        results,
        mechanism: DrivenMechanism::of(params),
    };
    // The figures are independent: drawn in parallel, collected in order.
    let chosen: Vec<&Figure> = FIGURES.iter().filter(|f| selected(f.id)).collect();
    chosen
        .par_iter()
        .map(|figure| {
            // A signal stops the drawing between figures.
            if crate::interrupt::requested() {
                return Err(PlotError::Interrupted);
            }
            data.draw(figure, out_dir, &options.formats)
        })
        .collect()
}

/// The run's results and mechanism, and how to draw each kind of figure from them.
struct Data<'a> {
    results: &'a Results,
    mechanism: DrivenMechanism,
}

impl Data<'_> {
    fn column(&self, name: &str) -> &[f64] {
        self.results.column(name).unwrap_or(&[])
    }

    fn draw(
        &self,
        figure: &Figure,
        out_dir: &Path,
        formats: &[ImageFormat],
    ) -> Result<DrawnFigure, PlotError> {
        let path = out_dir.join(figure.name);
        let title = format!("Fig. {}: {}", number(figure.id), figure.title);
        let (caption, files) = match figure.plot {
            Plot::Orientation { matrix } => self.orientation(&title, matrix, &path, formats)?,
            Plot::Time(q) => self.against_time(&title, q, &path, formats)?,
            Plot::Angle(q) => self.against_angle(&title, q, &path, formats)?,
            Plot::OutputSlider => self.output_slider(&title, &path, formats)?,
            Plot::EnergyBalance => self.energy_balance(&title, &path, formats)?,
        };
        let caption = if figure.about.is_empty() {
            caption
        } else {
            format!("{} {caption}", figure.about)
        };
        Ok(DrawnFigure {
            id: figure.id.to_owned(),
            title,
            caption: caption.trim().to_owned(),
            files,
        })
    }

    /// The time span of the run, for captions.
    fn span(&self) -> String {
        let t = self.results.times();
        match (t.first(), t.last()) {
            (Some(a), Some(b)) => format!("t = {a} to {b} s"),
            _ => "no samples".to_owned(),
        }
    }

    fn orientation(
        &self,
        title: &str,
        matrix: &str,
        path: &Path,
        formats: &[ImageFormat],
    ) -> Result<(String, Vec<PathBuf>), PlotError> {
        let column = |row: usize, col: usize| self.column(&format!("{matrix}_{row}{col}"));
        let series = ["x", "y", "z"]
            .iter()
            .enumerate()
            .map(|(j, axis)| {
                let (a, b, c) = (column(1, j + 1), column(2, j + 1), column(3, j + 1));
                Series3d {
                    label: format!("{axis} unit vector"),
                    points: a
                        .iter()
                        .zip(b)
                        .zip(c)
                        .map(|((&a, &b), &c)| (a, b, c))
                        .collect(),
                }
            })
            .collect();
        let times = self.results.times();
        let at = |t: Option<&f64>| t.map(|t| format!(" (t = {t} s)")).unwrap_or_default();
        let chart = Trajectory3d {
            title: title.to_owned(),
            axis_labels: ["X0".into(), "Y0".into(), "Z0".into()],
            range: Some([(-1.0, 1.0); 3]),
            series,
            marks: [
                format!("start{}", at(times.first())),
                format!("end{}", at(times.last())),
            ],
            from_origin: true,
        };
        let files = draw_trajectory_3d(&chart, path, formats)?;
        let caption = format!(
            "A ring marks where each tip starts, a dot where it ends ({}); thin lines from \
             the origin show the unit vectors at the start. Where two tips run along the \
             same path (the x and y unit vectors of a link turning in the X0-Y0 plane), \
             the x curve is drawn wider, under the y curve.",
            self.span()
        );
        Ok((caption, files))
    }

    /// The x, y and z components of `q` against `x`, each as `arrange(x, values)` puts
    /// them.
    fn components(&self, q: Quantity, arrange: impl Fn(&[f64]) -> Vec<(f64, f64)>) -> Vec<Series> {
        ["x", "y", "z"]
            .iter()
            .map(|axis| {
                let values = self.column(&format!("{}_{axis}", q.prefix));
                Series::new(*axis, arrange(values))
            })
            .collect()
    }

    fn against_time(
        &self,
        title: &str,
        q: Quantity,
        path: &Path,
        formats: &[ImageFormat],
    ) -> Result<(String, Vec<PathBuf>), PlotError> {
        let t = self.results.times();
        let chart = LineChart {
            title: title.to_owned(),
            x_label: "time t (s)".to_owned(),
            y_label: q.y_label.to_owned(),
            series: self.components(q, |v| pairs(t, v)),
        };
        let (options, zoom) = self.fitted(q, ChartOptions::default());
        let files = draw_line_chart_with(&chart, &options, path, formats)?;
        Ok((format!("{zoom}{}", self.statistic(q)), files))
    }

    fn against_angle(
        &self,
        title: &str,
        q: Quantity,
        path: &Path,
        formats: &[ImageFormat],
    ) -> Result<(String, Vec<PathBuf>), PlotError> {
        let angle = self.column(CRANK_ANGLE);
        let chart = LineChart {
            title: title.to_owned(),
            x_label: "crank angle θ (rad), wrapped to one revolution".to_owned(),
            y_label: q.y_label.to_owned(),
            series: self.components(q, |v| wrap_by_revolution(angle, v)),
        };
        let (options, zoom) = self.fitted(q, revolution_axis());
        let files = draw_line_chart_with(&chart, &options, path, formats)?;
        let caption = format!(
            "The crank angle is wrapped to [0, 2π): each revolution is drawn as a separate \
             curve, broken where the angle passes 2π (no line across the plot). \
             {zoom}{}",
            self.statistic(q)
        );
        Ok((caption, files))
    }

    /// The components of `q`.
    fn vector(&self, q: Quantity) -> [&[f64]; 3] {
        ["x", "y", "z"].map(|a| self.column(&format!("{}_{a}", q.prefix)))
    }

    /// `options` with the y range fitted to the run after its start-up when the
    /// start-up transient would squash the rest (see [`settled_range`]), and the
    /// caption's sentence saying so (empty when the range is the whole run's).
    fn fitted(&self, q: Quantity, options: ChartOptions) -> (ChartOptions, String) {
        let Some(fit) = self.settled(&self.vector(q)) else {
            return (options, String::new());
        };
        let (lo, hi) = (significant(fit.full.0), significant(fit.full.1));
        let options = ChartOptions {
            y_range: Some(fit.range),
            note: Some(format!(
                "off scale before t = {} s: {lo} to {hi} {}",
                fit.from, q.unit
            )),
            ..options
        };
        let sentence = format!(
            "The y axis is fitted to the run from t = {} s on; the start-up transient \
             before it goes off scale (values from {lo} to {hi} {}). ",
            fit.from, q.unit
        );
        (options, sentence)
    }

    /// The range of `columns` after the start-up (the first [`SETTLE_FRACTION`] of
    /// the run), when the whole run spans more than [`ZOOM_RATIO`] times it.
    fn settled(&self, columns: &[&[f64]]) -> Option<SettledRange> {
        let t = self.results.times();
        let (first, last) = (*t.first()?, *t.last()?);
        let from = first + SETTLE_FRACTION * (last - first);
        settled_range(t, columns, from, ZOOM_RATIO)
    }

    /// The caption's measurement of `q`: its largest magnitude and when, or the range of
    /// each component; and which components are zero throughout.
    fn statistic(&self, q: Quantity) -> String {
        let t = self.results.times();
        let c = self.vector(q);
        let magnitude = |i: usize| (c[0][i].powi(2) + c[1][i].powi(2) + c[2][i].powi(2)).sqrt();
        let n = t.len().min(c.iter().map(|c| c.len()).min().unwrap_or(0));
        let peak = (0..n)
            .map(|i| (i, magnitude(i)))
            .filter(|(_, m)| m.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((at, largest)) = peak else {
            return "No samples.".to_owned();
        };
        let measured = match q.stat {
            Stat::Peak => format!(
                "Largest magnitude over {}: {} {} at t = {} s.",
                self.span(),
                significant(largest),
                q.unit,
                t[at]
            ),
            Stat::Span => {
                let ranges: Vec<String> = ["x", "y", "z"]
                    .iter()
                    .zip(&c)
                    .filter(|(_, v)| v.iter().any(|v| v.abs() > 1e-12 * largest))
                    .filter_map(|(a, v)| {
                        let finite = || v.iter().copied().filter(|v| v.is_finite());
                        let (lo, hi) = (finite().reduce(f64::min)?, finite().reduce(f64::max)?);
                        Some(format!(
                            "{a} from {} to {} m",
                            significant(lo),
                            significant(hi)
                        ))
                    })
                    .collect();
                format!("Over {}: {}.", self.span(), ranges.join("; "))
            }
        };
        let zero: Vec<&str> = ["x", "y", "z"]
            .into_iter()
            .zip(&c)
            .filter(|(_, v)| v.iter().all(|v| v.abs() <= 1e-12 * largest))
            .map(|(a, _)| a)
            .collect();
        match zero.as_slice() {
            [] => measured,
            [one] => format!("{measured} The {one} component is zero throughout."),
            [rest @ .., last] => format!(
                "{measured} The {} and {last} components are zero throughout (their lines \
                 coincide).",
                rest.join(", ")
            ),
        }
    }
}

/// The start-up part of a run, as a fraction of its span, left out when fitting a y
/// range that a start-up transient would squash.
const SETTLE_FRACTION: f64 = 0.2;

/// A y range is fitted to the settled part when the whole run spans more than this
/// many times as much.
const ZOOM_RATIO: f64 = 2.5;

/// Height of each panel of a stacked figure, pixels.
const PANEL_HEIGHT: u32 = 400;

/// `(t[i], v[i])` for every sample.
fn pairs(t: &[f64], v: &[f64]) -> Vec<(f64, f64)> {
    t.iter().copied().zip(v.iter().copied()).collect()
}

/// Chart options for an x axis that is the crank angle over one revolution, ticked at
/// multiples of π/2.
fn revolution_axis() -> ChartOptions {
    ChartOptions {
        x_range: Some((0.0, TAU)),
        x_ticks: Some(vec![
            Tick::new(0.0, "0"),
            Tick::new(FRAC_PI_2, "π/2"),
            Tick::new(PI, "π"),
            Tick::new(3.0 * FRAC_PI_2, "3π/2"),
            Tick::new(TAU, "2π"),
        ]),
        ..ChartOptions::default()
    }
}

/// `value` to 4 significant digits, in plain notation when reasonable.
fn significant(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let magnitude = value.abs().log10().floor();
    if !(-4.0..6.0).contains(&magnitude) {
        return format!("{value:.3e}");
    }
    let decimals = (3.0 - magnitude).max(0.0) as usize;
    format!("{value:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use catalogue::FIGURES;

    #[test]
    fn ids_are_the_papers_figures_and_two_more() {
        let expected: Vec<String> = (3..=21).map(|n| format!("fig{n:02}")).collect();
        assert_eq!(FIGURE_IDS, expected);
        for f in &FIGURES {
            assert!(f.name.starts_with(f.id), "{}", f.name);
        }
        assert_eq!(number("fig05"), "5");
        assert_eq!(number("fig19"), "19");
    }

    #[test]
    fn numbers_for_captions() {
        assert_eq!(significant(254.93), "254.9");
        assert_eq!(significant(0.0084812), "0.008481");
        assert_eq!(significant(1.5e-7), "1.500e-7");
        assert_eq!(significant(0.0), "0");
    }
}
