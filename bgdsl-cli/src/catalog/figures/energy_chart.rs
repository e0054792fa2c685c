//! The energy balance's figure, `energy_balance.png` and `.svg`, from a run's
//! [`EnergyBalance`].

use core::fmt::Write as _;
use std::path::Path;

use super::super::{Entry, RunError};
use super::energy::{sig, EnergyBalance};
use super::{plot_error, stop_if_interrupted, DrawnFigure};
use crate::plot::{
    draw_stacked_charts, ChartOptions, ImageFormat, LineChart, Series, SeriesStyle, WIDTH,
};

/// The energy balance's figure id and file stem.
pub const FIGURE_ID: &str = "energy_balance";

/// Draws the balance of `entry`'s run as `energy_balance.png` and `.svg`: the stored
/// energy against what the powers say it is, and their difference.
pub(in crate::catalog) fn draw(
    entry: &Entry,
    balance: &EnergyBalance,
    dir: &Path,
) -> Result<Option<DrawnFigure>, RunError> {
    if balance.len() < 2 {
        return Ok(None);
    }
    stop_if_interrupted()?;
    let t = &balance.times;
    let pairs = |v: &[f64]| t.iter().copied().zip(v.iter().copied()).collect::<Vec<_>>();
    let predicted: Vec<f64> = (0..balance.len()).map(|i| balance.predicted(i)).collect();
    let events = balance.event_count > 0;
    let account = if events {
        "E(t0) + ∫ P_in dt − ∫ P_diss dt + Σ ΔE_events"
    } else {
        "E(t0) + ∫ P_in dt − ∫ P_diss dt"
    };
    let chart = |title: &str, series| LineChart {
        title: title.to_owned(),
        x_label: "time t (s)".to_owned(),
        y_label: "energy (J)".to_owned(),
        series,
    };
    let panels = [
        chart(
            "Stored energy and the energy account of the powers",
            vec![
                Series::new("E(t) stored", pairs(&balance.stored)),
                Series::new(account, pairs(&predicted)),
            ],
        ),
        chart(
            "Energy supplied and dissipated since the start",
            vec![
                Series::new("∫ P_in dt", pairs(&balance.supplied)),
                Series::new("∫ P_diss dt", pairs(&balance.dissipated)),
            ],
        ),
        chart(
            "Difference (balance residual)",
            vec![Series::new("difference", pairs(&balance.residual()))],
        ),
    ];
    let panel = |styles| ChartOptions {
        size: (WIDTH, 400),
        styles,
        ..ChartOptions::default()
    };
    let blue = SeriesStyle::solid((31, 119, 180));
    let options = [
        panel(vec![blue, SeriesStyle::dashed((214, 39, 40))]),
        panel(vec![
            SeriesStyle::solid((44, 160, 44)),
            SeriesStyle::solid((255, 127, 14)),
        ]),
        // 1 px: plotters' bitmap backend draws steep 2 px segments of a noisy curve
        // far past their ends (the SVG is right).
        panel(vec![SeriesStyle {
            width: 1,
            ..SeriesStyle::solid((0, 0, 0))
        }]),
    ];
    let title = format!(
        "{} ({}): energy balance",
        entry.model.type_name(),
        entry.name
    );
    let files = draw_stacked_charts(
        &title,
        &panels,
        &options,
        &dir.join(FIGURE_ID),
        &ImageFormat::ALL,
    )
    .map_err(plot_error)?;
    let last = |v: &[f64]| v.last().copied().unwrap_or(0.0);
    let (worst, at) = balance.largest_residual().unwrap_or((0.0, 0.0));
    let mut caption = format!(
        "The energy account of the bond graph (Model::power_balance): the energy its \
         storage elements hold, E(t), against E(t0) plus the energy its sources supplied \
         minus the energy its resistors dissipated since the start, {account}; and their \
         difference, zero for an exact solution integrated exactly. The powers are \
         integrated between samples by the corrected trapezoid rule (their rates of \
         change along the motion at both ends). At the end: ∫ P_in dt = {} J, \
         ∫ P_diss dt = {} J, E = {} J. The largest difference, {} J at t = {} s, is {:.1e} \
         of the energy scale {} J: the solver's error and the quadrature's between \
         samples, which grows where the samples do not resolve the powers' changes (a \
         sudden start); a finer sampling interval tells them apart.",
        sig(last(&balance.supplied)),
        sig(last(&balance.dissipated)),
        sig(last(&balance.stored)),
        sig(worst),
        sig(at),
        worst.abs() / balance.scale().max(f64::MIN_POSITIVE),
        sig(balance.scale()),
    );
    if events {
        let _ = write!(
            caption,
            " The run's {} events changed the stored energy at their instants by {} J in \
             all (bgdsl_runtime::event_energy); the account includes them.",
            balance.event_count,
            sig(last(&balance.events))
        );
    }
    Ok(Some(DrawnFigure {
        id: FIGURE_ID.to_owned(),
        title,
        caption,
        files,
    }))
}
