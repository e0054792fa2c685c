//! `models bode`: frequency responses from inputs to outputs at an operating point
//! (`bode.csv`, the magnitude and phase figures).

use clap::Args;

use super::linearize::PointArgs;
use super::{execute, names, plan, ModelArgs};
use crate::catalog::analysis::bode::{default_band, responses, results_set, Band, DEFAULT_POINTS};
use crate::catalog::analysis::AnalysisFailure;
use crate::catalog::{format_number, Catalogue};
use crate::cli::Failure;

/// The arguments of `models bode`.
#[derive(Clone, Debug, Default, Args)]
pub struct BodeArgs {
    /// The model and its settings.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The input: a declared input or a scalar parameter (e.g. a source's `voltage`);
    /// several comma-separated or repeated [default: every declared input].
    #[arg(long, value_name = "U")]
    pub input: Vec<String>,
    /// The output; several comma-separated or repeated [default: every output].
    #[arg(long, value_name = "Y")]
    pub output: Vec<String>,
    /// The lowest frequency, in hertz (Hz, not rad/s) [default: a decade below the
    /// slowest mode, rounded down to a decade].
    #[arg(long, value_name = "HZ")]
    pub from: Option<f64>,
    /// The highest frequency, in hertz [default: a decade above the fastest mode,
    /// rounded up to a decade].
    #[arg(long, value_name = "HZ")]
    pub to: Option<f64>,
    /// The number of frequencies, spaced evenly in logarithm.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_POINTS)]
    pub points: usize,
    /// The operating point.
    #[command(flatten)]
    pub point: PointArgs,
}

/// `models bode ...`.
pub(crate) fn bode(args: &BodeArgs, catalogue: &'static Catalogue) -> Result<(), Failure> {
    let inputs = names(&args.input);
    let outputs = names(&args.output);
    let mut options = args.point.options();
    if !inputs.is_empty() {
        options.push(("input".to_owned(), inputs.join("+")));
    }
    if !outputs.is_empty() {
        options.push(("output".to_owned(), outputs.join("+")));
    }
    for (key, value) in [("from", args.from), ("to", args.to)] {
        if let Some(v) = value {
            options.push((key.to_owned(), format_number(v)));
        }
    }
    if args.points != DEFAULT_POINTS {
        options.push(("points".to_owned(), args.points.to_string()));
    }
    let (entry, plan) = plan(&args.model, catalogue, "bode", &options)?;
    if inputs.is_empty() && entry.model.inputs().is_empty() {
        let scalars: Vec<&str> = entry
            .model
            .parameters()
            .iter()
            .filter(|p| p.len == 1)
            .map(|p| p.name)
            .collect();
        return Err(Failure::Usage(format!(
            "{} declares no input: name the one to drive with --input, a parameter such as \
             {}",
            entry.name,
            scalars.join(", ")
        )));
    }
    // The band is checked before anything runs, as far as it is given.
    let given = Band {
        from: args.from.unwrap_or(f64::MIN_POSITIVE),
        to: args.to.unwrap_or(f64::MAX),
        points: args.points,
    };
    given.check().map_err(Failure::Usage)?;
    let request = args.point.request(entry, inputs, outputs)?;
    execute(entry, &plan, || {
        let linear = entry.model.linearize(&plan, &request)?;
        let fitted = default_band(&linear, args.points);
        let band = Band {
            from: args.from.unwrap_or(fitted.from),
            to: args.to.unwrap_or(fitted.to),
            points: args.points,
        };
        band.check().map_err(AnalysisFailure::Usage)?;
        let responses = responses(&linear, &band);
        Ok(results_set(entry, request.at, &linear, &band, &responses))
    })
}
