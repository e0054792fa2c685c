//! Charts drawn with plotters, to PNG and SVG, written atomically.
//!
//! - [`LineChart`]: named series of `(x, y)` points against one x axis (a NaN point
//!   breaks a series into separate polylines), drawn with [`draw_line_chart`] or, with
//!   [`ChartOptions`] (fixed ranges, custom ticks, line styles), [`draw_line_chart_with`];
//!   several charts stacked over one another share a file with [`draw_stacked_charts`].
//! - [`Trajectory3d`]: curves in 3-D (the tips of the unit vectors of an orientation
//!   matrix), drawn with [`draw_trajectory_3d`].
//! - Data preparation: [`wrap_by_revolution`] (an angle wrapped to one revolution,
//!   broken at each wrap), [`cumulative_trapezoid`], [`settled_range`] (a y range not
//!   squashed by a start-up transient).
//!
//! Line charts are thinned for display ([`decimate`]): a curve of more points than the
//! plot has pixel columns to show keeps the first, lowest, highest and last point of
//! each column, so peaks survive and an image stays small whatever the run's length,
//! and the chart says so in its corner (`drawn from 3,600 of 955,001 points (min/max
//! per pixel column)`).
//!
//! Each chart is written once per requested [`ImageFormat`], to
//! `path_without_extension` plus `.png` or `.svg`. Nothing half-written is ever left
//! under a final name: each image is drawn into a temporary file in the same directory
//! (`.NAME.tmp-PID-N.png`, still ending in the format's extension) which is synced and
//! renamed onto the final name, and removed on any error.
//!
//! Text needs a TrueType font found on disk at run time ([`font`]); when none is found
//! the error says what to install.

pub mod font;

mod axis;
mod clip;
mod data;
pub mod decimate;
mod file;
mod line;
mod trajectory;

use core::fmt;
use std::io;
use std::path::PathBuf;

pub use axis::{format_tick, nice_ticks, Tick};
pub use clip::polylines;
pub use data::{cumulative_trapezoid, settled_range, wrap_angle, wrap_by_revolution, SettledRange};
pub use line::{
    draw_line_chart, draw_line_chart_with, draw_stacked_charts, ChartOptions, Fill, LineChart,
    Series, SeriesStyle, PALETTE,
};
pub use trajectory::{draw_trajectory_3d, Series3d, Trajectory3d};

/// Width of a chart image, pixels.
pub const WIDTH: u32 = 1024;

/// Height of a (single) chart image, pixels.
pub const HEIGHT: u32 = 640;

/// The default image size, `(WIDTH, HEIGHT)`.
pub const DEFAULT_SIZE: (u32, u32) = (WIDTH, HEIGHT);

/// An image file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ImageFormat {
    /// A bitmap, `.png`.
    Png,
    /// A vector drawing, `.svg`.
    Svg,
}

impl ImageFormat {
    /// Both formats, PNG first.
    pub const ALL: [ImageFormat; 2] = [ImageFormat::Png, ImageFormat::Svg];

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            ImageFormat::Png => "png",
            ImageFormat::Svg => "svg",
        }
    }
}

impl fmt::Display for ImageFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.extension())
    }
}

/// What went wrong drawing or writing a chart.
#[derive(Debug)]
#[non_exhaustive]
pub enum PlotError {
    /// No usable font (see [`font::ensure_font`]).
    Font {
        /// The font file that failed, if one was named or found.
        path: Option<PathBuf>,
        /// Why, and what to install.
        reason: String,
    },
    /// plotters failed while drawing an image.
    Draw {
        /// The image being drawn (its final name).
        path: PathBuf,
        /// plotters' message.
        message: String,
    },
    /// A file or directory could not be written.
    Io {
        /// The file (its final name) or directory.
        path: PathBuf,
        /// What was being done.
        action: &'static str,
        /// The underlying error.
        source: io::Error,
    },
    /// Drawing was interrupted (a signal, see [`crate::interrupt`]).
    Interrupted,
    /// A figure was asked for by an id that does not exist.
    UnknownFigure {
        /// The id asked for.
        id: String,
        /// The ids that exist.
        valid: &'static [&'static str],
    },
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlotError::Font {
                path: Some(path),
                reason,
            } => write!(f, "cannot use font `{}`: {reason}", path.display()),
            PlotError::Font { path: None, reason } => write!(f, "cannot draw plots: {reason}"),
            PlotError::Draw { path, message } => {
                write!(f, "could not draw `{}`: {message}", path.display())
            }
            PlotError::Io {
                path,
                action,
                source,
            } => write!(
                f,
                "could not write `{}`: {action} failed: {source}",
                path.display()
            ),
            PlotError::Interrupted => f.write_str("drawing was interrupted"),
            PlotError::UnknownFigure { id, valid } => {
                write!(f, "no figure `{id}`; the figures are {}", valid.join(", "))
            }
        }
    }
}

impl std::error::Error for PlotError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            PlotError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}
