//! The HTML report of a run: one self-contained `index.html` with the run's summary,
//! the sections its extras add (HTML fragments, e.g. an animation) and every figure
//! with its caption.
//!
//! The page has no external assets, and no scripts but those a section brings: each figure's SVG is inlined (its
//! `xmlns` attribute dropped, which HTML does not need), or, when only a PNG was drawn,
//! the PNG is embedded as a base64 `data:` URI. Links to the image files beside the
//! page are relative. All text is HTML-escaped.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use bgdsl_runtime::record::write_atomically;

use crate::plot::PlotError;

/// A figure drawn (or skipped, with no files and the reason in its caption).
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnFigure {
    /// Its id, such as `fig05` or an output's name.
    pub id: String,
    /// Its title.
    pub title: String,
    /// What it shows, how it was computed, and what it measured.
    pub caption: String,
    /// The image files written, one per format.
    pub files: Vec<PathBuf>,
}

/// The report's file name.
pub const INDEX_FILE: &str = "index.html";

/// Writes `out_dir/index.html` (the directory must exist), atomically: a page titled
/// `title` with `summary` in a `<pre>` block, then `sections` (HTML fragments, as they
/// are), then every figure, its title, image and caption; returns the path written. A figure without files (skipped) is listed with
/// its caption.
///
/// # Errors
///
/// [`PlotError::Io`] if an image cannot be read or the page cannot be written.
pub fn write_index(
    out_dir: &Path,
    title: &str,
    summary: &str,
    figures: &[DrawnFigure],
    sections: &[String],
) -> Result<PathBuf, PlotError> {
    let mut body = String::new();
    for figure in figures {
        body.push_str(&figure_html(figure)?);
    }
    let page = page(title, summary, sections, figures, &body);
    let path = out_dir.join(INDEX_FILE);
    write_atomically(&path, |out| out.write_all(page.as_bytes())).map_err(|e| PlotError::Io {
        path: e.path,
        action: "writing the report",
        source: e.source,
    })?;
    Ok(path)
}

const STYLE: &str = "body{font-family:sans-serif;max-width:1080px;margin:0 auto;padding:1em;\
color:#222}h1{font-size:1.6em}h2{font-size:1.25em;margin-top:1.5em}figure{margin:2.5em 0 0;\
padding-top:1em;border-top:1px solid #ccc}figure svg,figure img{width:100%;height:auto;\
display:block}figcaption{margin-top:.5em;line-height:1.45}pre{background:#f5f5f5;\
padding:1em;overflow-x:auto;font-size:.9em}.files{font-size:.9em;color:#555}\
nav ul{columns:2;font-size:.95em}";

/// The whole page around the figures' HTML.
fn page(
    title: &str,
    summary: &str,
    sections: &[String],
    figures: &[DrawnFigure],
    body: &str,
) -> String {
    let title = escape(title);
    let mut contents = String::new();
    for figure in figures {
        contents.push_str(&format!(
            "<li><a href=\"#{}\">{}</a></li>\n",
            escape(&figure.id),
            escape(&figure.title)
        ));
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{title}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n\
         <h1>{title}</h1>\n<h2>Summary of the run</h2>\n<pre>{}</pre>\n{}\
         <h2>Figures</h2>\n<nav><ul>\n{contents}</ul></nav>\n{body}</body>\n</html>\n",
        escape(summary),
        sections.concat()
    )
}

/// One `<figure>`: heading, image (inline SVG, else embedded PNG), caption, file links.
fn figure_html(figure: &DrawnFigure) -> Result<String, PlotError> {
    let svg = figure.files.iter().find(|f| has_extension(f, "svg"));
    let png = figure.files.iter().find(|f| has_extension(f, "png"));
    let image = match (svg, png) {
        (Some(svg), _) => inline_svg(&read_text(svg)?),
        (None, Some(png)) => format!(
            "<img alt=\"{}\" src=\"data:image/png;base64,{}\">",
            escape(&figure.title),
            base64(&read_bytes(png)?)
        ),
        (None, None) => String::new(),
    };
    let links: Vec<String> = figure
        .files
        .iter()
        .filter_map(|f| f.file_name())
        .map(|name| {
            let name = escape(&name.to_string_lossy());
            format!("<a href=\"{name}\">{name}</a>")
        })
        .collect();
    let links = if links.is_empty() {
        String::new()
    } else {
        format!(
            "<br><span class=\"files\">Files: {}</span>",
            links.join(", ")
        )
    };
    Ok(format!(
        "<figure id=\"{}\">\n<h2>{}</h2>\n{image}\n<figcaption>{}{links}</figcaption>\n</figure>\n",
        escape(&figure.id),
        escape(&figure.title),
        escape(&figure.caption)
    ))
}

fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, PlotError> {
    fs::read(path).map_err(|source| read_error(path, source))
}

fn read_text(path: &Path) -> Result<String, PlotError> {
    fs::read_to_string(path).map_err(|source| read_error(path, source))
}

fn read_error(path: &Path, source: io::Error) -> PlotError {
    PlotError::Io {
        path: path.to_path_buf(),
        action: "reading the image for the report",
        source,
    }
}

/// An SVG document as an element of an HTML page: from its `<svg` on (no XML
/// declaration), without the `xmlns` attribute (HTML puts `<svg>` in the SVG namespace
/// by itself).
fn inline_svg(svg: &str) -> String {
    let start = svg.find("<svg").unwrap_or(0);
    let svg = &svg[start..];
    let Some(end) = svg.find('>') else {
        return svg.to_owned();
    };
    let (tag, rest) = svg.split_at(end);
    let tag = tag
        .replace(" xmlns=\"http://www.w3.org/2000/svg\"", "")
        .replace(" xmlns='http://www.w3.org/2000/svg'", "");
    format!("{tag}{rest}")
}

/// `text` with `&`, `<`, `>`, `"` and `'` replaced by character references.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// `bytes` in standard base64 (RFC 4648, with `=` padding).
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for (i, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            if i <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> shift) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648() {
        // The test vectors of RFC 4648, section 10.
        for (plain, encoded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), encoded);
        }
        assert_eq!(base64(&[0xff, 0xfe, 0xfd]), "//79");
    }

    #[test]
    fn escapes_markup() {
        assert_eq!(
            escape("a < b & \"c\" > 'd'"),
            "a &lt; b &amp; &quot;c&quot; &gt; &#39;d&#39;"
        );
    }

    #[test]
    fn inlined_svg_drops_the_prolog_and_namespace() {
        let svg = "<?xml version=\"1.0\"?>\n<svg width=\"2\" viewBox=\"0 0 2 2\" \
                   xmlns=\"http://www.w3.org/2000/svg\">\n<path d=\"M0 0\"/></svg>";
        assert_eq!(
            inline_svg(svg),
            "<svg width=\"2\" viewBox=\"0 0 2 2\">\n<path d=\"M0 0\"/></svg>"
        );
    }

    #[test]
    fn writes_a_page_with_every_caption() {
        let dir = std::env::temp_dir().join(format!("bgdsl-report-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let svg = dir.join("a.svg");
        fs::write(
            &svg,
            "<svg xmlns=\"http://www.w3.org/2000/svg\"><path/></svg>",
        )
        .unwrap();
        let png = dir.join("b.png");
        fs::write(&png, b"\x89PNG").unwrap();
        let figures = [
            DrawnFigure {
                id: "fig05".into(),
                title: "Force <x>".into(),
                caption: "caption & one".into(),
                files: vec![png.clone(), svg.clone()],
            },
            DrawnFigure {
                id: "fig06".into(),
                title: "Six".into(),
                caption: "caption two".into(),
                files: vec![png],
            },
            DrawnFigure {
                id: "fig20".into(),
                title: "Skipped".into(),
                caption: "Not drawn: too short".into(),
                files: vec![],
            },
        ];
        let path = write_index(&dir, "Run <1>", "rows  5001\nok", &figures, &[]).unwrap();
        let html = fs::read_to_string(&path).unwrap();
        fs::remove_dir_all(&dir).unwrap();
        assert!(html.contains("<title>Run &lt;1&gt;</title>"));
        assert!(html.contains("<pre>rows  5001\nok</pre>"));
        assert!(html.contains("caption &amp; one"));
        assert!(html.contains("caption two") && html.contains("Not drawn: too short"));
        assert!(html.contains("<svg><path/></svg>"));
        assert!(html.contains("src=\"data:image/png;base64,iVBORw==\""));
        assert!(!html.contains("http:") && !html.contains("https:"));
    }
}
