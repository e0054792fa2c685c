//! The quick return figures drawn from real (short) runs of the flagship: every figure
//! id produces its files, each PNG decodes with the expected size and is not blank,
//! each SVG holds drawn paths, plots against the crank angle never draw across the
//! wrap, a run too short for a revolution skips only the revolution figure, and the
//! report holds every caption and no external reference.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

use bgdsl_runtime::{Radau5Options, Solver};
use models::plot::{draw_line_chart, ImageFormat, LineChart, PlotError, Series, HEIGHT, WIDTH};
use models::quick_return::figures::{
    draw_figures, wrap_by_revolution, DrawnFigure, FigureOptions, FIGURE_IDS,
};
use models::quick_return::results::{sample_time, Results, CRANK_ANGLE};
use models::quick_return::run::record;
use models::quick_return::QuickReturn;
use models::report::{escape, write_index};

/// A fresh directory under the system's temporary directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        static N: AtomicU32 = AtomicU32::new(0);
        let dir = std::env::temp_dir().join(format!(
            "bgdsl-figures-{name}-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = fs::remove_dir_all(&dir);
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

/// The flagship with its default parameters from 0 to `t_end`, sampled every 1 ms.
fn run_until(t_end: f64) -> Results {
    let n = (t_end * 1000.0).round() as usize;
    let times: Vec<f64> = (0..=n).map(sample_time).collect();
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-10,
        ..Default::default()
    });
    record(&QuickReturn::default(), solver, &times)
        .expect("the flagship runs")
        .results
}

/// The image's width, height and RGBA pixels.
fn decode_png(path: &Path) -> (u32, u32, Vec<[u8; 4]>) {
    let mut decoder = png::Decoder::new(fs::File::open(path).unwrap());
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let pixels = buf[..info.buffer_size()]
        .chunks(channels)
        .map(|p| match *p {
            [r, g, b, a] => [r, g, b, a],
            [r, g, b] => [r, g, b, 255],
            [v, a] => [v, v, v, a],
            [v] => [v, v, v, 255],
            _ => unreachable!(),
        })
        .collect();
    (info.width, info.height, pixels)
}

/// A chart image: many distinct colours (lines, anti-aliased text) and a sensible share
/// of non-white pixels (not blank, not a filled rectangle).
fn assert_not_blank(path: &Path, pixels: &[[u8; 4]]) {
    let distinct: std::collections::BTreeSet<[u8; 4]> = pixels.iter().copied().collect();
    let inked = pixels.iter().filter(|p| p[..3] != [255, 255, 255]).count();
    let share = inked as f64 / pixels.len() as f64;
    assert!(
        distinct.len() >= 20,
        "{}: only {} colours",
        path.display(),
        distinct.len()
    );
    assert!(
        (0.02..0.7).contains(&share),
        "{}: {:.1} % of the pixels are not white",
        path.display(),
        100.0 * share
    );
}

fn assert_svg_has_drawing(path: &Path, title_start: &str) {
    let svg = fs::read_to_string(path).unwrap();
    assert!(svg.contains("<svg"), "{}", path.display());
    let lines = svg.matches("<polyline").count() + svg.matches("<path").count();
    assert!(lines >= 3, "{}: {lines} polylines or paths", path.display());
    assert!(
        svg.contains(title_start),
        "{}: no `{title_start}`",
        path.display()
    );
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn extension(path: &Path) -> &str {
    path.extension().and_then(|e| e.to_str()).unwrap_or("")
}

/// Every figure's files: PNG then SVG, named after the id, in the output directory.
fn assert_files_of(figure: &DrawnFigure, dir: &Path) {
    let extensions: Vec<&str> = figure.files.iter().map(|f| extension(f)).collect();
    assert_eq!(extensions, ["png", "svg"], "{}", figure.id);
    for file in &figure.files {
        assert_eq!(file.parent(), Some(dir));
        let name = file.file_name().unwrap().to_string_lossy();
        assert!(name.starts_with(&format!("{}_", figure.id)), "{name}");
    }
}

#[test]
fn every_figure_of_a_short_run_is_drawn_readable_and_reported() {
    let results = run_until(1.5);
    let dir = Scratch::new("all");
    let params = QuickReturn::default().params;
    let figures = draw_figures(&results, &params, &dir.0, &FigureOptions::default()).unwrap();

    let ids: Vec<&str> = figures.iter().map(|f| f.id.as_str()).collect();
    assert_eq!(ids, FIGURE_IDS);
    for figure in &figures {
        assert_files_of(figure, &dir.0);
        let number = figure.id.trim_start_matches("fig").trim_start_matches('0');
        assert!(
            figure.title.starts_with(&format!("Fig. {number}: ")),
            "{}",
            figure.title
        );
        assert!(
            figure.caption.len() > 80,
            "{}: {}",
            figure.id,
            figure.caption
        );
        let (width, height, pixels) = decode_png(&figure.files[0]);
        assert_eq!(width, WIDTH, "{}", figure.id);
        if figure.id == "fig20" || figure.id == "fig21" {
            assert!(
                height > 3 * 400,
                "{}: three stacked panels, {height} px",
                figure.id
            );
        } else {
            assert_eq!(height, HEIGHT, "{}", figure.id);
        }
        assert_not_blank(&figure.files[0], &pixels);
        assert_svg_has_drawing(&figure.files[1], &format!("Fig. {number}:"));
    }
    // Only the figures: no temporary file left behind.
    assert_eq!(names_in(&dir.0).len(), 2 * FIGURE_IDS.len());
    assert!(names_in(&dir.0).iter().all(|n| !n.starts_with('.')));

    let index = write_index(&dir.0, "Short run <0-1.5 s>", "rows  1501\n", &figures, &[]).unwrap();
    let html = fs::read_to_string(&index).unwrap();
    assert!(html.contains("<title>Short run &lt;0-1.5 s&gt;</title>"));
    assert!(html.contains("<pre>rows  1501\n</pre>"));
    for figure in &figures {
        assert!(html.contains(&escape(&figure.caption)), "{}", figure.id);
        assert!(html.contains(&format!("id=\"{}\"", figure.id)));
    }
    assert_eq!(
        html.matches("<svg").count(),
        figures.len(),
        "every SVG inlined"
    );
    assert!(!html.contains("http:") && !html.contains("https:"));
    assert!(!html.contains("<script"));
}

#[test]
fn curves_against_the_crank_angle_never_cross_the_plot() {
    let results = run_until(1.5);
    let angle = results.column(CRANK_ANGLE).unwrap();
    assert!(
        angle[angle.len() - 1] > std::f64::consts::TAU,
        "the run passes 2π"
    );
    for name in ["F_O1_x", "Tc_z", "F_A2_y", "F_O3_x", "F_O5_y"] {
        let points = wrap_by_revolution(angle, results.column(name).unwrap());
        let drawn = points.iter().filter(|p| p.0.is_finite()).count();
        assert!(drawn >= results.len(), "{name}: every sample is drawn");
        assert!(
            points.iter().any(|p| p.0.is_nan()),
            "{name}: broken at the wrap"
        );
        for pair in points.windows(2) {
            let [(a, _), (b, _)] = [pair[0], pair[1]];
            if a.is_finite() && b.is_finite() {
                assert!((b - a).abs() <= std::f64::consts::PI, "{name}: {a} → {b}");
            }
        }
        assert!(points
            .iter()
            .filter(|p| p.0.is_finite())
            .all(|p| (0.0..=std::f64::consts::TAU).contains(&p.0)));
    }
}

#[test]
fn a_run_shorter_than_a_revolution_skips_only_the_revolution_figure() {
    // 0.3 s: the crank turns 1.5 rad.
    let results = run_until(0.3);
    let dir = Scratch::new("short");
    let options = FigureOptions {
        formats: vec![ImageFormat::Png],
        only: None,
    };
    let params = QuickReturn::default().params;
    let figures = draw_figures(&results, &params, &dir.0, &options).unwrap();
    assert_eq!(figures.len(), FIGURE_IDS.len());
    for figure in &figures {
        if figure.id == "fig20" {
            assert!(figure.files.is_empty());
            assert!(
                figure.caption.starts_with("Not drawn"),
                "{}",
                figure.caption
            );
        } else {
            assert_eq!(figure.files.len(), 1, "{}", figure.id);
            let (width, _, pixels) = decode_png(&figure.files[0]);
            assert_eq!(width, WIDTH);
            assert_not_blank(&figure.files[0], &pixels);
        }
    }
    let index = write_index(&dir.0, "short", "partial", &figures, &[]).unwrap();
    let html = fs::read_to_string(index).unwrap();
    assert!(html.contains("Not drawn"));
    assert_eq!(
        html.matches("data:image/png;base64,").count(),
        figures.len() - 1
    );
}

#[test]
fn a_run_with_no_samples_still_draws_empty_charts() {
    let results = Results::for_model::<QuickReturn>(0).unwrap();
    let dir = Scratch::new("empty");
    let options = FigureOptions {
        formats: vec![ImageFormat::Svg],
        only: Some(vec![
            "fig05".into(),
            "fig06".into(),
            "fig03".into(),
            "fig20".into(),
            "fig21".into(),
        ]),
    };
    let figures = draw_figures(&results, &QuickReturn::default().params, &dir.0, &options).unwrap();
    let ids: Vec<&str> = figures.iter().map(|f| f.id.as_str()).collect();
    assert_eq!(
        ids,
        ["fig03", "fig05", "fig06", "fig20", "fig21"],
        "in id order"
    );
    for figure in &figures {
        let expected = usize::from(figure.id != "fig20");
        assert_eq!(figure.files.len(), expected, "{}", figure.id);
    }
}

#[test]
fn unknown_figure_ids_are_refused_before_anything_is_written() {
    let dir = Scratch::new("unknown");
    let options = FigureOptions {
        formats: vec![ImageFormat::Png],
        only: Some(vec!["fig05".into(), "fig2".into()]),
    };
    let results = Results::for_model::<QuickReturn>(0).unwrap();
    let err = draw_figures(&results, &QuickReturn::default().params, &dir.0, &options).unwrap_err();
    assert!(matches!(&err, PlotError::UnknownFigure { id, .. } if id == "fig2"));
    let message = err.to_string();
    assert!(
        message.contains("`fig2`") && message.contains("fig03, fig04"),
        "{message}"
    );
    assert!(!dir.0.exists());
}

#[test]
fn line_charts_are_written_whole_or_not_at_all() {
    let dir = Scratch::new("chart");
    fs::create_dir_all(&dir.0).unwrap();
    let chart = LineChart {
        title: "A sine with a gap".into(),
        x_label: "time t (s)".into(),
        y_label: "value (1)".into(),
        series: vec![
            Series::new(
                "sin",
                (0..200)
                    .map(|i| f64::from(i) / 20.0)
                    .map(|t| {
                        if (4.0..5.0).contains(&t) {
                            (f64::NAN, f64::NAN)
                        } else {
                            (t, t.sin())
                        }
                    })
                    .collect(),
            ),
            Series::new(
                "cos",
                (0..200)
                    .map(|i| f64::from(i) / 20.0)
                    .map(|t| (t, t.cos()))
                    .collect(),
            ),
        ],
    };
    let files = draw_line_chart(&chart, &dir.0.join("sine"), &ImageFormat::ALL).unwrap();
    assert_eq!(files, [dir.0.join("sine.png"), dir.0.join("sine.svg")]);
    let (width, height, pixels) = decode_png(&files[0]);
    assert_eq!((width, height), (WIDTH, HEIGHT));
    assert_not_blank(&files[0], &pixels);
    let svg = fs::read_to_string(&files[1]).unwrap();
    assert!(
        svg.matches("<polyline").count() >= 3,
        "the sine in two pieces and the cosine"
    );
    assert_eq!(names_in(&dir.0), ["sine.png", "sine.svg"]);

    // A directory that does not exist: an error naming the file, nothing written.
    let missing = dir.0.join("missing").join("sine");
    let err = draw_line_chart(&chart, &missing, &[ImageFormat::Png]).unwrap_err();
    assert!(matches!(err, PlotError::Io { .. }), "{err}");
    assert!(err.to_string().contains("sine.png"), "{err}");
    assert_eq!(names_in(&dir.0), ["sine.png", "sine.svg"]);
}
