//! Draws every figure of the flagship's default run, 0–5 s, into `out/quick_return/`
//! with `index.html`, and prints how long each step took:
//!
//! ```text
//! cargo run --release -p models --example figures [OUT_DIR]
//! ```

use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

use bgdsl_runtime::{Radau5Options, Solver};
use models::plot::ImageFormat;
use models::quick_return::figures::{draw_figures, FigureOptions};
use models::quick_return::results::sample_times;
use models::quick_return::run::record;
use models::quick_return::summary::Summary;
use models::quick_return::QuickReturn;
use models::report::write_index;

fn main() -> Result<(), Box<dyn Error>> {
    let out_dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("out/quick_return"));
    let model = QuickReturn::default();
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-10,
        ..Default::default()
    });
    let started = Instant::now();
    let recorded = record(&model, solver, &sample_times())?;
    let run_time = started.elapsed();

    let png_only = FigureOptions {
        formats: vec![ImageFormat::Png],
        only: None,
    };
    let started = Instant::now();
    draw_figures(&recorded.results, &model.params, &out_dir, &png_only)?;
    let png_time = started.elapsed();

    let started = Instant::now();
    let figures = draw_figures(
        &recorded.results,
        &model.params,
        &out_dir,
        &FigureOptions::default(),
    )?;
    let both_time = started.elapsed();

    let summary = Summary::of(&recorded).to_string();
    let started = Instant::now();
    let index = write_index(
        &out_dir,
        "Quick return mechanism: default run",
        &summary,
        &figures,
        &[],
    )?;
    let index_time = started.elapsed();

    println!("{summary}");
    println!("run (integration and recording): {run_time:?}");
    println!("{} figures, PNG only: {png_time:?}", figures.len());
    println!("{} figures, PNG and SVG: {both_time:?}", figures.len());
    println!("{} written in {index_time:?}", index.display());
    Ok(())
}
