//! Rendering a drawing to PNG and SVG files, atomically.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use plotters::coord::Shift;
use plotters::prelude::{BitMapBackend, DrawingArea, DrawingBackend, IntoDrawingArea, SVGBackend};

use super::{font, ImageFormat, PlotError};

/// What a drawing function returns: plotters' errors, boxed.
pub(crate) type DrawResult = Result<(), Box<dyn std::error::Error + Send + Sync>>;

/// Something that can draw itself on any plotters backend.
pub(crate) trait Drawing {
    /// The image size, pixels.
    fn size(&self) -> (u32, u32);

    /// Draws on `root`, which covers the whole image.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult
    where
        DB::ErrorType: 'static;
}

/// Draws `drawing` once per format (repeated formats once), to
/// `path_without_extension` + `.png` / `.svg`; returns the files written, in the order
/// of `formats`.
pub(crate) fn write_images<D: Drawing>(
    drawing: &D,
    path_without_extension: &Path,
    formats: &[ImageFormat],
) -> Result<Vec<PathBuf>, PlotError> {
    font::ensure_font()?;
    let mut written = Vec::with_capacity(formats.len());
    for (i, &format) in formats.iter().enumerate() {
        if formats[..i].contains(&format) {
            continue;
        }
        let path = with_extension(path_without_extension, format);
        match format {
            ImageFormat::Png => write_png(drawing, &path)?,
            ImageFormat::Svg => write_svg(drawing, &path)?,
        }
        written.push(path);
    }
    Ok(written)
}

/// `path` with `.` and the format's extension appended to its file name (any dot
/// already in the name is kept).
pub(crate) fn with_extension(path: &Path, format: ImageFormat) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".");
    name.push(format.extension());
    PathBuf::from(name)
}

fn write_png<D: Drawing>(drawing: &D, path: &Path) -> Result<(), PlotError> {
    let temporary = Temporary::create(path, ImageFormat::Png)?;
    {
        let root = BitMapBackend::new(temporary.path(), drawing.size()).into_drawing_area();
        drawing
            .draw(&root)
            .and_then(|()| root.present().map_err(Into::into))
            .map_err(|e| draw_error(path, &*e))?;
    }
    temporary.commit(path)
}

fn write_svg<D: Drawing>(drawing: &D, path: &Path) -> Result<(), PlotError> {
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, drawing.size()).into_drawing_area();
        drawing
            .draw(&root)
            .and_then(|()| root.present().map_err(Into::into))
            .map_err(|e| draw_error(path, &*e))?;
    }
    let temporary = Temporary::create(path, ImageFormat::Svg)?;
    let io_error = |source| PlotError::Io {
        path: path.to_path_buf(),
        action: "writing the temporary file",
        source,
    };
    let mut file = OpenOptions::new()
        .write(true)
        .truncate(true)
        .open(temporary.path())
        .map_err(io_error)?;
    file.write_all(text.as_bytes()).map_err(io_error)?;
    drop(file);
    temporary.commit(path)
}

fn draw_error(path: &Path, error: &(dyn std::error::Error + Send + Sync)) -> PlotError {
    PlotError::Draw {
        path: path.to_path_buf(),
        message: error.to_string(),
    }
}

/// A temporary file beside a destination, named `.NAME.tmp-PID-N.EXT`, removed when
/// dropped unless committed.
struct Temporary {
    path: Option<PathBuf>,
}

impl Temporary {
    /// Creates a new, empty temporary file beside `destination` (which must name a
    /// file), so that no other writer can take the name.
    fn create(destination: &Path, format: ImageFormat) -> Result<Self, PlotError> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let io_error = |source| PlotError::Io {
            path: destination.to_path_buf(),
            action: "creating a temporary file in its directory",
            source,
        };
        let stem = destination
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_suffix(format.extension()))
            .and_then(|n| n.strip_suffix('.'))
            .ok_or_else(|| {
                io_error(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    "the path does not name a file",
                ))
            })?;
        let dir = destination.parent().unwrap_or(Path::new(""));
        let mut attempts = 0;
        loop {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let name = format!(
                ".{stem}.tmp-{}-{n}.{}",
                std::process::id(),
                format.extension()
            );
            let path = dir.join(name);
            match OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(_) => return Ok(Temporary { path: Some(path) }),
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempts < 100 => {
                    attempts += 1;
                }
                Err(e) => return Err(io_error(e)),
            }
        }
    }

    fn path(&self) -> &Path {
        self.path.as_deref().unwrap_or(Path::new(""))
    }

    /// Syncs the temporary file and renames it onto `destination`.
    fn commit(mut self, destination: &Path) -> Result<(), PlotError> {
        let io_error = |action, source| PlotError::Io {
            path: destination.to_path_buf(),
            action,
            source,
        };
        let path = self.path();
        File::open(path)
            .and_then(|f| f.sync_all())
            .map_err(|e| io_error("syncing the temporary file", e))?;
        fs::rename(path, destination)
            .map_err(|e| io_error("renaming the temporary file onto it", e))?;
        self.path = None;
        Ok(())
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if let Some(path) = self.path.take() {
            let _ = fs::remove_file(path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn appends_the_extension() {
        assert_eq!(
            with_extension(Path::new("out/fig05_a.b"), ImageFormat::Svg),
            PathBuf::from("out/fig05_a.b.svg")
        );
        assert_eq!(
            with_extension(Path::new("fig"), ImageFormat::Png),
            PathBuf::from("fig.png")
        );
    }
}
