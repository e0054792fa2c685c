//! The scene as HTML: a section for `index.html`, or a page of its own.

use std::fmt::Write as _;
use std::io::{self, Write as _};
use std::path::Path;

use bgdsl_runtime::record::write_atomically;

use super::{Scene, Shape, View};

/// The `id` of the section's element (the player finds its parts inside it; a page
/// holds one animation).
pub const SECTION_ID: &str = "bgdsl-animation";

/// The player, run once the section is in the page.
const PLAYER: &str = include_str!("player.js");

const STYLE: &str = "#bgdsl-animation canvas{display:block;border:1px solid #ccc;\
max-width:100%}#bgdsl-animation .controls{display:flex;flex-wrap:wrap;gap:.8em;\
align-items:center;margin:.5em 0}#bgdsl-animation .scrub{flex:1 1 240px}\
#bgdsl-animation output{font-variant-numeric:tabular-nums;min-width:9em}\
#bgdsl-animation .legend{list-style:none;padding:0;display:flex;flex-wrap:wrap;gap:1em}\
#bgdsl-animation .swatch{display:inline-block;width:.9em;height:.9em;margin-right:.3em;\
vertical-align:middle}#bgdsl-animation .errors{color:#b00}";

/// A self-contained HTML fragment that plays `scene`: a `<section id="bgdsl-animation">`
/// with its heading, a canvas, the controls (play/pause, a scrub slider, speed 0.1×–4×,
/// the time and the scene's angle), a legend of the bodies, the scene as JSON and the
/// player's script. It needs nothing from the network or beside the page. The
/// section's `data-ready` attribute is set once a frame is drawn and its `.errors`
/// block receives any error the player meets (for a headless browser's DOM dump).
pub fn section(scene: &Scene) -> String {
    let how = match scene.view {
        View::Plane { .. } => "Seen face on to the plane of the motion.",
        View::Orbit => "Drag the picture to turn it.",
    };
    let mut speeds = String::new();
    for s in ["0.1", "0.25", "0.5", "1", "2", "4"] {
        let selected = if s == "1" { " selected" } else { "" };
        let _ = write!(speeds, "<option value=\"{s}\"{selected}>{s}×</option>");
    }
    format!(
        "<section id=\"{SECTION_ID}\">\n<style>{STYLE}</style>\n<h2>Animation</h2>\n\
         <canvas width=\"800\" height=\"480\"></canvas>\n<div class=\"controls\">\
         <button type=\"button\" class=\"play\">Play</button>\
         <input type=\"range\" class=\"scrub\" min=\"0\" max=\"0\" value=\"0\" step=\"1\" \
         aria-label=\"frame\"><label>speed <select class=\"speed\">{speeds}</select></label>\
         <output class=\"time\"></output><output class=\"angle\"></output></div>\n\
         <ul class=\"legend\"></ul>\n<p class=\"files\">{how} {frames} frames from t = {t0} s \
         to {t1} s.</p>\n<pre class=\"errors\" hidden></pre>\n\
         <script type=\"application/json\" class=\"data\">{json}</script>\n\
         <script>\n{PLAYER}</script>\n</section>\n",
        frames = scene.times.len(),
        t0 = scene.times.first().copied().unwrap_or(0.0),
        t1 = scene.times.last().copied().unwrap_or(0.0),
        json = scene_json(scene),
    )
}

/// Writes `scene` as a page of its own at `path` (atomically), titled `title`.
///
/// # Errors
///
/// The I/O error of writing the page.
pub fn write_page(path: &Path, title: &str, scene: &Scene) -> io::Result<()> {
    let page = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{title}</title>\n<style>body{{font-family:sans-serif;margin:8px;\
         color:#222}}h1{{font-size:1.2em;margin:0 0 .3em}}h2{{display:none}}</style>\n\
         </head>\n<body>\n<h1>{title}</h1>\n{}</body>\n</html>\n",
        section(scene),
        title = escape_html(title)
    );
    write_atomically(path, |out| out.write_all(page.as_bytes())).map_err(|e| e.source)
}

/// The scene as the player reads it: times, bodies (`p`: positions, `r`: orientations
/// column by column, both flat), angle, ground points and view. Positions carry five
/// significant digits of the scene's extent, orientations four decimals: far below a
/// pixel, and a few hundred kilobytes for 2000 frames of five bodies.
fn scene_json(scene: &Scene) -> String {
    let extent = scene
        .bodies
        .iter()
        .flat_map(|b| b.position.iter().flatten())
        .chain(scene.ground.iter().flatten())
        .fold(
            0.0_f64,
            |m, v| if v.is_finite() { m.max(v.abs()) } else { m },
        );
    let position_decimals = decimals(extent, 5);
    let mut out = String::from("{\"times\":");
    numbers(&mut out, scene.times.iter().copied(), None);
    out.push_str(",\"bodies\":[");
    for (i, body) in scene.bodies.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        out.push_str("{\"name\":");
        string(&mut out, &body.name);
        out.push_str(",\"shape\":");
        match &body.shape {
            Shape::Box { size } => {
                out.push_str("{\"box\":");
                numbers(&mut out, size.iter().copied(), None);
                out.push('}');
            }
            Shape::Segment { from, to } => {
                out.push_str("{\"segment\":[");
                numbers(&mut out, from.iter().copied(), None);
                out.push(',');
                numbers(&mut out, to.iter().copied(), None);
                out.push_str("]}");
            }
            Shape::Marker => out.push_str("{\"marker\":true}"),
        }
        out.push_str(",\"p\":");
        numbers(
            &mut out,
            body.position.iter().flatten().copied(),
            Some(position_decimals),
        );
        out.push_str(",\"r\":");
        numbers(
            &mut out,
            body.orientation.iter().flatten().copied(),
            Some(4),
        );
        out.push('}');
    }
    out.push_str("],\"angle\":");
    match &scene.angle {
        Some((label, degrees)) => {
            out.push_str("{\"label\":");
            string(&mut out, label);
            out.push_str(",\"deg\":");
            numbers(&mut out, degrees.iter().copied(), Some(2));
            out.push('}');
        }
        None => out.push_str("null"),
    }
    out.push_str(",\"ground\":[");
    for (i, g) in scene.ground.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        numbers(&mut out, g.iter().copied(), None);
    }
    out.push_str("],\"view\":");
    match &scene.view {
        View::Plane { u, v } => {
            out.push_str("{\"plane\":{\"u\":");
            numbers(&mut out, u.iter().copied(), None);
            out.push_str(",\"v\":");
            numbers(&mut out, v.iter().copied(), None);
            out.push_str("}}");
        }
        View::Orbit => out.push_str("\"orbit\""),
    }
    out.push('}');
    out
}

/// Decimals that keep `significant` digits of numbers up to `extent`.
fn decimals(extent: f64, significant: i32) -> usize {
    if extent > 0.0 {
        (significant - 1 - extent.log10().floor() as i32).clamp(0, 15) as usize
    } else {
        significant as usize
    }
}

/// `[a,b,…]`: each number with `decimals` (trailing zeros dropped) or, without, in
/// the shortest form that reads back exactly; `null` for a number that is not finite
/// (JSON has none).
fn numbers(out: &mut String, values: impl Iterator<Item = f64>, decimals: Option<usize>) {
    out.push('[');
    for (i, v) in values.enumerate() {
        if i > 0 {
            out.push(',');
        }
        if !v.is_finite() {
            out.push_str("null");
            continue;
        }
        let start = out.len();
        match decimals {
            Some(d) => {
                let _ = write!(out, "{v:.d$}");
                if out[start..].contains('.') {
                    let trimmed = out.trim_end_matches('0').trim_end_matches('.').len();
                    out.truncate(trimmed);
                }
                if &out[start..] == "-0" {
                    out.truncate(start);
                    out.push('0');
                }
            }
            None => {
                let _ = write!(out, "{v}");
            }
        }
    }
    out.push(']');
}

/// A JSON string; `<`, `>` and `&` escaped too, so no text closes the `<script>`.
fn string(out: &mut String, text: &str) {
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '<' | '>' | '&' => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// `text` with HTML's special characters escaped.
fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod should {
    use super::*;
    use crate::animation::BodyTrack;

    fn scene() -> Scene {
        let body = BodyTrack {
            name: "arm</script>".into(),
            shape: Shape::Box {
                size: [0.2, 0.01, 0.01],
            },
            position: vec![[0.123_456_7, 0.0, 0.0], [0.0, 0.1, f64::NAN]],
            orientation: vec![[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]; 2],
        };
        Scene::new(vec![0.0, 0.5], vec![body]).with_angle("crank angle", vec![90.0, 118.6479])
    }

    #[test]
    fn write_numbers_to_their_precision_and_null_for_nan() {
        let json = scene_json(&scene());
        // Extent 0.12: five significant digits are 5 decimals; trailing zeros go.
        assert!(json.contains("\"p\":[0.12346,0,0,0,0.1,null]"), "{json}");
        assert!(json.contains("\"deg\":[90,118.65]"), "{json}");
        assert!(json.contains("\"times\":[0,0.5]"), "{json}");
        assert!(
            json.contains("\"shape\":{\"box\":[0.2,0.01,0.01]}"),
            "{json}"
        );
        assert!(json.contains("\"view\":{\"plane\""), "{json}");
    }

    #[test]
    fn keep_every_text_inside_its_script() {
        let html = section(&scene());
        assert_eq!(html.matches("</script>").count(), 2, "{html}");
        assert!(html.contains("\"name\":\"arm\\u003c/script\\u003e\""));
        assert!(!html.contains("http://") && !html.contains("https://"));
        assert!(!PLAYER.contains("</script"));
    }

    #[test]
    fn round_to_the_digits_asked() {
        let mut out = String::new();
        numbers(
            &mut out,
            [0.123_456_789, -0.000_001, 12.5].into_iter(),
            Some(5),
        );
        assert_eq!(out, "[0.12346,0,12.5]");
        assert_eq!(decimals(0.7, 6), 6);
        assert_eq!(decimals(12.0, 6), 4);
    }
}
