//! Fig. 21 (not in the paper): the energy balance over time.

use std::path::{Path, PathBuf};

use crate::plot::{
    cumulative_trapezoid, draw_stacked_charts, ChartOptions, ImageFormat, LineChart, PlotError,
    Series, SeriesStyle, SettledRange, WIDTH,
};

use super::{pairs, significant, Data, PANEL_HEIGHT};

impl Data<'_> {
    pub(super) fn energy_balance(
        &self,
        title: &str,
        path: &Path,
        formats: &[ImageFormat],
    ) -> Result<(String, Vec<PathBuf>), PlotError> {
        let balance = EnergyBalance::new(self);
        let t = self.results.times();
        let fit = self.settled(&[&balance.residual]);
        let charts = balance.charts(t, fit.as_ref());
        let panel = |styles| ChartOptions {
            size: (WIDTH, PANEL_HEIGHT),
            styles,
            ..ChartOptions::default()
        };
        let blue = SeriesStyle::solid((31, 119, 180));
        let red = SeriesStyle::solid((214, 39, 40));
        let options = [
            panel(vec![blue, red]),
            panel(vec![blue, SeriesStyle::dashed((0, 0, 0))]),
            panel(vec![SeriesStyle::solid((0, 0, 0))]),
        ];
        let files = draw_stacked_charts(title, &charts, &options, path, formats)?;
        Ok((balance.caption(self, fit.as_ref()), files))
    }
}

/// The energy balance of a run: running integrals of the drive's and the dampers'
/// power, the change of the stored energy, and the residual.
struct EnergyBalance {
    /// Whether the run had events (their energy is then part of `net`).
    events: bool,
    w_in: Vec<f64>,
    w_diss: Vec<f64>,
    stored: Vec<f64>,
    net: Vec<f64>,
    residual: Vec<f64>,
}

impl EnergyBalance {
    fn new(data: &Data<'_>) -> Self {
        let t = data.results.times();
        let e = data.column("E_stored");
        let w_in = cumulative_trapezoid(t, data.column("P_in"));
        let w_diss = cumulative_trapezoid(t, data.column("P_diss"));
        let e0 = e.first().copied().unwrap_or(0.0);
        let stored: Vec<f64> = e.iter().map(|e| e - e0).collect();
        // Events (an impact, a stuck slide's release) change the stored energy at an
        // instant: their sum up to each sample joins the supplied energy. A sample at
        // an event's time holds the state after it.
        let events = data.results.event_energies();
        let (mut next, mut jumps) = (0, 0.0);
        let net: Vec<f64> = t
            .iter()
            .zip(w_in.iter().zip(&w_diss))
            .map(|(&ts, (a, b))| {
                while let Some(&(_, change)) = events.get(next).filter(|(te, _)| *te <= ts) {
                    jumps += change;
                    next += 1;
                }
                a - b + jumps
            })
            .collect();
        let residual = stored.iter().zip(&net).map(|(s, n)| s - n).collect();
        EnergyBalance {
            events: !events.is_empty(),
            w_in,
            w_diss,
            stored,
            net,
            residual,
        }
    }

    /// The three panels; the residual's from `fit.from` on when a start-up jump
    /// would squash it.
    fn charts(&self, t: &[f64], fit: Option<&SettledRange>) -> [LineChart; 3] {
        let start = fit.map_or(0, |f| t.iter().position(|&ti| ti >= f.from).unwrap_or(0));
        let residual_title = match fit {
            Some(f) => format!(
                "Difference (balance residual) after the start-up, t ≥ {} s",
                f.from
            ),
            None => "Difference (balance residual)".to_owned(),
        };
        let chart = |title: &str, series| LineChart {
            title: title.to_owned(),
            x_label: "time t (s)".to_owned(),
            y_label: "energy (J)".to_owned(),
            series,
        };
        [
            chart(
                "Energy supplied by the drive and dissipated in the dampers",
                vec![
                    Series::new("∫ P_in dt", pairs(t, &self.w_in)),
                    Series::new("∫ P_diss dt", pairs(t, &self.w_diss)),
                ],
            ),
            chart(
                "Change of stored energy and net energy supplied",
                vec![
                    Series::new("E_stored(t) − E_stored(0)", pairs(t, &self.stored)),
                    Series::new(
                        if self.events {
                            "∫ (P_in − P_diss) dt + Σ ΔE_events"
                        } else {
                            "∫ (P_in − P_diss) dt"
                        },
                        pairs(t, &self.net),
                    ),
                ],
            ),
            chart(
                &residual_title,
                vec![Series::new(
                    "difference",
                    pairs(
                        &t[start.min(t.len())..],
                        self.residual.get(start..).unwrap_or(&[]),
                    ),
                )],
            ),
        ]
    }

    fn caption(&self, data: &Data<'_>, fit: Option<&SettledRange>) -> String {
        let t = data.results.times();
        let last = |v: &[f64]| v.last().copied().unwrap_or(0.0);
        let intro = format!(
            "Not in the paper. The power balance of the bond graph integrated over time \
             ({}): the energy the drive supplies (∫ P_in dt) and the energy all dampers \
             dissipate (∫ P_diss dt), both by the trapezoid rule on the samples; the change \
             of the stored energy (column E_stored: kinetic, gravitational and, where \
             the model has springs, elastic) against their difference; and the residual ΔE_stored − ∫ (P_in − \
             P_diss) dt, zero for an exact solution integrated exactly. At the end: ∫ P_in \
             dt = {} J, ∫ P_diss dt = {} J, ΔE_stored = {} J, residual {} J.",
            data.span(),
            significant(last(&self.w_in)),
            significant(last(&self.w_diss)),
            significant(last(&self.stored)),
            significant(last(&self.residual)),
        );
        let intro = if self.events {
            let total: f64 = data.results.event_energies().iter().map(|(_, e)| e).sum();
            format!(
                "{intro} The run's {} events changed the stored energy at their instants by \
                 {} J in all (an impact's loss, a stuck slide's released spring: \
                 bgdsl_runtime::event_energy); the net energy supplied includes them.",
                data.results.event_energies().len(),
                significant(total)
            )
        } else {
            intro
        };
        let Some(fit) = fit else {
            return intro;
        };
        let start = t.iter().position(|&ti| ti >= fit.from).unwrap_or(0);
        let at_start = self.residual[start];
        let drift = self.residual[start..]
            .iter()
            .map(|r| (r - at_start).abs())
            .fold(0.0, f64::max);
        let jump_end = self.residual[..=start]
            .iter()
            .position(|r| r.abs() >= 0.9 * at_start.abs())
            .unwrap_or(start);
        let p_in_peak = data
            .column("P_in")
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        format!(
            "{intro} The residual reaches {} J by t = {} s (90 % of it by t = {} s, while \
             P_in peaks at {} W after the sudden start: the trapezoid rule does not resolve \
             that spike on the samples); from t = {} s to the end it changes by at most {} \
             J, {} % of the energy supplied; its panel shows that part.",
            significant(at_start),
            fit.from,
            t[jump_end],
            significant(p_in_peak),
            fit.from,
            significant(drift),
            significant(100.0 * drift / last(&self.w_in).abs().max(f64::MIN_POSITIVE)),
        )
    }
}
