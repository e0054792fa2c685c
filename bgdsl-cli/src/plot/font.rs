//! The one font every chart is drawn with, found on disk at run time.
//!
//! plotters is built without `font-kit` (no fontconfig), so a TrueType font must be
//! registered with it before any text is measured or drawn. [`ensure_font`] does that
//! once per process: it takes the file named by the [`FONT_ENV`] environment variable
//! if set, otherwise the first of [`CANDIDATES`] that exists, otherwise any `.ttf`
//! under `/usr/share/fonts`; it reads the file, leaks its bytes (plotters keeps a
//! `&'static [u8]`; this happens once) and registers it as [`FONT_FAMILY`].

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use plotters::style::{register_font, FontStyle};

use super::PlotError;

/// The family name charts ask plotters for; SVG files name it too, so a viewer without
/// the registered font still uses a sans-serif one.
pub const FONT_FAMILY: &str = "sans-serif";

/// The environment variable that names a `.ttf` file to use instead of the search.
pub const FONT_ENV: &str = "BGDSL_FONT";

/// Where a regular sans-serif TrueType font usually is, in the order tried: DejaVu Sans
/// (Debian/Ubuntu, Arch, Fedora), then Liberation Sans, then the macOS and Windows Arial.
pub const CANDIDATES: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation-sans/LiberationSans-Regular.ttf",
    "/usr/share/fonts/TTF/LiberationSans-Regular.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "/Library/Fonts/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// The directory searched for any `.ttf` when no candidate exists.
pub const FONT_DIR: &str = "/usr/share/fonts";

/// What to install when no font is found.
pub const FONT_HINT: &str = "install a TrueType font (Debian/Ubuntu: `apt-get install \
    fonts-dejavu-core`; Fedora: `dnf install dejavu-sans-fonts`) or set BGDSL_FONT to a .ttf file";

/// The registered font's file, once registered.
static REGISTERED: Mutex<Option<&'static Path>> = Mutex::new(None);

/// Registers the charts' font with plotters, once per process, and returns its file.
///
/// # Errors
///
/// [`PlotError::Font`] if [`FONT_ENV`] names a file that cannot be read or is not a
/// TrueType/OpenType font, or if no font is found at all (the message says what to
/// install).
pub fn ensure_font() -> Result<&'static Path, PlotError> {
    let mut registered = REGISTERED.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(path) = *registered {
        return Ok(path);
    }
    let path = match std::env::var_os(FONT_ENV) {
        Some(chosen) if !chosen.is_empty() => {
            let path = PathBuf::from(chosen);
            register(&path).map_err(|reason| PlotError::Font {
                path: Some(path.clone()),
                reason: format!("{reason} (named by {FONT_ENV})"),
            })?;
            path
        }
        _ => search()?,
    };
    let path: &'static Path = Box::leak(path.into_boxed_path());
    *registered = Some(path);
    Ok(path)
}

/// Tries every candidate, then every `.ttf` under [`FONT_DIR`], and registers the
/// first that loads.
fn search() -> Result<PathBuf, PlotError> {
    let mut found = CANDIDATES.iter().map(PathBuf::from).collect::<Vec<_>>();
    found.extend(fonts_under(Path::new(FONT_DIR)));
    for path in found {
        if path.is_file() && register(&path).is_ok() {
            return Ok(path);
        }
    }
    Err(PlotError::Font {
        path: None,
        reason: format!(
            "no usable TrueType font found (tried {} and every .ttf under {FONT_DIR}): \
             {FONT_HINT}",
            CANDIDATES.join(", ")
        ),
    })
}

/// Every `.ttf` under `dir` (recursively, at most 4 levels), regular sans-serif faces
/// first, each group in path order (so the choice does not depend on directory order).
fn fonts_under(dir: &Path) -> Vec<PathBuf> {
    let mut fonts = Vec::new();
    collect_ttf(dir, 4, &mut fonts);
    fonts.sort_by_key(|p| (style_rank(p), p.clone()));
    fonts
}

/// 0 for a regular sans face, 1 for other regular faces, 2 for bold, italic,
/// monospaced or symbol faces.
fn style_rank(path: &Path) -> u8 {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let special = [
        "bold", "italic", "oblique", "mono", "light", "math", "symbol",
    ];
    if special.iter().any(|s| name.contains(s)) {
        2
    } else if name.contains("sans") {
        0
    } else {
        1
    }
}

fn collect_ttf(dir: &Path, depth: u32, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            if depth > 0 {
                collect_ttf(&path, depth - 1, out);
            }
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ttf"))
        {
            out.push(path);
        }
    }
}

/// Reads `path`, checks that it starts like a TrueType/OpenType file, leaks the bytes
/// and registers them as the normal style of [`FONT_FAMILY`].
fn register(path: &Path) -> Result<(), String> {
    let bytes = fs::read(path).map_err(|e: io::Error| format!("cannot read it: {e}"))?;
    if !looks_like_a_font(&bytes) {
        return Err("it is not a TrueType or OpenType font".to_owned());
    }
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    register_font(FONT_FAMILY, FontStyle::Normal, bytes)
        .map_err(|_| "plotters could not parse it as a font".to_owned())
}

/// Whether `bytes` start with an sfnt version tag (TrueType, OpenType CFF, Apple).
fn looks_like_a_font(bytes: &[u8]) -> bool {
    matches!(
        bytes.get(..4),
        Some([0, 1, 0, 0]) | Some(b"OTTO") | Some(b"true") | Some(b"ttcf")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefers_regular_sans_faces() {
        assert_eq!(style_rank(Path::new("/f/DejaVuSans.ttf")), 0);
        assert_eq!(style_rank(Path::new("/f/DejaVuSerif.ttf")), 1);
        assert_eq!(style_rank(Path::new("/f/DejaVuSans-Bold.ttf")), 2);
        assert_eq!(style_rank(Path::new("/f/DejaVuSansMono.ttf")), 2);
    }

    #[test]
    fn recognises_font_headers() {
        assert!(looks_like_a_font(&[0, 1, 0, 0, 9]));
        assert!(looks_like_a_font(b"OTTO...."));
        assert!(!looks_like_a_font(b"<html>"));
        assert!(!looks_like_a_font(b"ab"));
    }
}
