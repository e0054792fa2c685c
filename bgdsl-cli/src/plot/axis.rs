//! Axis ranges, tick positions and tick labels, and the axis type charts are built on.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};

/// A tick mark: where it is and what it says.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    /// Its position on the axis, in data units.
    pub value: f64,
    /// Its label.
    pub label: String,
}

impl Tick {
    /// A tick at `value` labelled `label`.
    pub fn new(value: f64, label: impl Into<String>) -> Self {
        Tick {
            value,
            label: label.into(),
        }
    }
}

/// "Nice" tick positions covering `[lo, hi]`: multiples of 1, 2 or 5 × 10^k, at most
/// about `max_count` of them, all inside the range. Empty if the range is empty or not
/// finite.
pub fn nice_ticks(lo: f64, hi: f64, max_count: usize) -> Vec<Tick> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo || max_count == 0 {
        return Vec::new();
    }
    let step = nice_step((hi - lo) / max_count.max(1) as f64);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    let mut ticks: Vec<Tick> = Vec::new();
    for k in first..=last {
        let value = k as f64 * step;
        let tick = Tick::new(value, format_tick(value, step));
        // Two ticks that read the same would say nothing twice.
        if ticks.last().is_none_or(|t| t.label != tick.label) {
            ticks.push(tick);
        }
    }
    ticks
}

/// The smallest of 1, 2, 5 × 10^k not below `raw`.
fn nice_step(raw: f64) -> f64 {
    let magnitude = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|s| *s >= raw * (1.0 - 1e-12))
        .unwrap_or(10.0 * magnitude)
}

/// `value` written with as many decimals as the tick spacing `step` needs; in
/// scientific notation when that is more than 6 decimals or the value is a million or
/// more. Zero is `0`
/// (never `-0` or `1e-17`).
pub fn format_tick(value: f64, step: f64) -> String {
    let value = if value.abs() < step.abs() * 1e-9 {
        0.0
    } else {
        value
    };
    let step = step.abs();
    if value == 0.0 {
        return "0".to_owned();
    }
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    // A step such as 0.25 needs one more decimal than its magnitude says.
    let decimals = if (step * 10f64.powi(decimals as i32)).fract().abs() > 1e-9 {
        decimals + 1
    } else {
        decimals
    };
    if decimals > 6 || value.abs() >= 1e6 {
        // Enough digits to tell neighbouring ticks apart (an f64 holds 15-16).
        let digits = (step.log10().floor() - value.abs().log10().floor())
            .abs()
            .min(15.0) as usize;
        return format!("{value:.digits$e}");
    }
    format!("{value:.decimals$}")
}

/// A tick label placed on the picture: its text centred at a pixel position.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedLabel {
    /// The text.
    pub text: String,
    /// The centre of the text, in pixels.
    pub at: (i32, i32),
}

/// The labels that can be drawn without two of them overlapping: in order, each kept
/// unless its box (about `font_size × 0.6` pixels per character wide, `font_size` high,
/// plus a 2-pixel margin) meets the box of one kept before it. Where axes meet at a
/// corner of a 3-D box, their end labels land on one another; the first axis's wins,
/// so no label is ever drawn over another (or twice).
pub fn without_collisions(labels: Vec<PlacedLabel>, font_size: f64) -> Vec<PlacedLabel> {
    let half_size = |l: &PlacedLabel| {
        let chars = l.text.chars().count() as f64;
        (0.5 * 0.6 * font_size * chars + 2.0, 0.5 * font_size + 2.0)
    };
    let mut kept: Vec<PlacedLabel> = Vec::new();
    for label in labels {
        let (w, h) = half_size(&label);
        let collides = kept.iter().any(|k| {
            let (kw, kh) = half_size(k);
            f64::from((label.at.0 - k.at.0).abs()) < w + kw
                && f64::from((label.at.1 - k.at.1).abs()) < h + kh
        });
        if !collides {
            kept.push(label);
        }
    }
    kept
}

/// The range `[lo, hi]` of the finite values, widened as [`widen`] does. `None` if no
/// value is finite.
pub(crate) fn padded_range(values: impl Iterator<Item = f64>, pad: f64) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return None;
    }
    Some(widen(lo, hi, pad))
}

/// `[lo, hi]` widened by `pad` of its span on both sides; a flat range is widened to
/// ±10 % of its value, or ±1 around zero.
pub(crate) fn widen(lo: f64, hi: f64, pad: f64) -> (f64, f64) {
    let span = hi - lo;
    let scale = lo.abs().max(hi.abs());
    if span <= scale * 1e-9 || span == 0.0 {
        let half = if scale > 0.0 { 0.1 * scale } else { 1.0 };
        return (lo - half, hi + half);
    }
    (lo - pad * span, hi + pad * span)
}

/// A linear axis over a range whose grid lines are given ticks (labelled with their
/// labels, drawn bold) and the midpoints between them (light).
pub(crate) struct TickedAxis {
    pub(crate) range: (f64, f64),
    pub(crate) ticks: Vec<Tick>,
}

impl Ranged for TickedAxis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let (lo, hi) = self.range;
        let fraction = if hi > lo {
            (value - lo) / (hi - lo)
        } else {
            0.5
        };
        let pixel = f64::from(limit.0) + fraction * f64::from(limit.1 - limit.0);
        // Far outside values saturate; curves are clipped to the range before drawing.
        pixel.round().clamp(-1e6, 1e6) as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let bold = self.ticks.iter().map(|t| t.value);
        if hint.weight().allow_light_points() {
            let values: Vec<f64> = bold.collect();
            values.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
        } else {
            bold.collect()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.range.0..self.range.1
    }
}

impl ValueFormatter<f64> for TickedAxis {
    /// The label of the tick nearest `value`.
    fn format_ext(&self, value: &f64) -> String {
        self.ticks
            .iter()
            .min_by(|a, b| (a.value - value).abs().total_cmp(&(b.value - value).abs()))
            .map(|t| t.label.clone())
            .unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(ticks: &[Tick]) -> Vec<&str> {
        ticks.iter().map(|t| t.label.as_str()).collect()
    }

    #[test]
    fn ticks_are_round_numbers_inside_the_range() {
        assert_eq!(
            labels(&nice_ticks(0.0, 5.0, 10)),
            ["0", "0.5", "1.0", "1.5", "2.0", "2.5", "3.0", "3.5", "4.0", "4.5", "5.0"]
        );
        assert_eq!(
            labels(&nice_ticks(-166.3, 254.9, 10)),
            ["-150", "-100", "-50", "0", "50", "100", "150", "200", "250"]
        );
        assert_eq!(
            labels(&nice_ticks(-0.0007, 0.0009, 8)),
            ["-0.0006", "-0.0004", "-0.0002", "0", "0.0002", "0.0004", "0.0006", "0.0008"]
        );
        assert_eq!(
            labels(&nice_ticks(0.0, 0.0085, 5)),
            ["0", "0.002", "0.004", "0.006", "0.008"]
        );
        assert!(nice_ticks(1.0, 1.0, 5).is_empty());
        assert!(nice_ticks(f64::NAN, 1.0, 5).is_empty());
    }

    /// Far from zero the labels used to stop at 6 digits: 1e12 + 2 and 1e12 + 4 both
    /// read `1.000000e12`.
    #[test]
    fn tick_labels_never_repeat() {
        for (lo, hi) in [
            (1e12, 1e12 + 10.0),
            (-1.0, 1.0),
            (1e6, 1e6 + 3e-6),
            (0.0, 1e-300),
        ] {
            let ticks = nice_ticks(lo, hi, 5);
            assert!(ticks.len() >= 2, "{lo}..{hi}: {ticks:?}");
            let mut labels = labels(&ticks);
            labels.dedup();
            assert_eq!(labels.len(), ticks.len(), "{lo}..{hi}: {ticks:?}");
        }
        assert_eq!(
            labels(&nice_ticks(1e12, 1e12 + 10.0, 5)),
            [
                "1.000000000000e12",
                "1.000000000002e12",
                "1.000000000004e12",
                "1.000000000006e12",
                "1.000000000008e12",
                "1.000000000010e12"
            ]
        );
    }

    #[test]
    fn tick_labels_have_the_steps_precision() {
        assert_eq!(format_tick(0.25, 0.25), "0.25");
        assert_eq!(format_tick(1e-17, 0.1), "0");
        assert_eq!(format_tick(-0.0, 1.0), "0");
        assert_eq!(format_tick(2e6, 1e6), "2e6");
        assert_eq!(format_tick(1.5e-5, 5e-6), "0.000015");
        assert_eq!(format_tick(1.5e-7, 5e-8), "1.5e-7");
        assert_eq!(format_tick(0.0242, 5e-5), "0.02420");
    }

    #[test]
    fn ranges_are_padded_and_never_flat() {
        assert_eq!(
            padded_range([0.0, 10.0].into_iter(), 0.05),
            Some((-0.5, 10.5))
        );
        assert_eq!(
            padded_range([0.0, 0.0].into_iter(), 0.05),
            Some((-1.0, 1.0))
        );
        assert_eq!(padded_range([2.0].into_iter(), 0.05), Some((1.8, 2.2)));
        assert_eq!(padded_range([f64::NAN].into_iter(), 0.05), None);
    }

    fn placed(text: &str, at: (i32, i32)) -> PlacedLabel {
        PlacedLabel {
            text: text.to_owned(),
            at,
        }
    }

    /// Fig. 3 drew the vertical axis's "1.0" and the depth axis's "-1.0" at the same
    /// corner pixel (153, 247), and the x axis's "-1.0" 10 px from the depth axis's
    /// "1.0".
    #[test]
    fn labels_that_collide_are_drawn_once() {
        let labels = vec![
            placed("1.0", (153, 247)),
            placed("0.5", (153, 316)),
            placed("-1.0", (360, 56)),
            placed("-1.0", (153, 247)),
            placed("1.0", (350, 66)),
            placed("0.5", (301, 83)),
            placed("0.5", (153, 316)),
        ];
        let kept = without_collisions(labels, 14.0);
        assert_eq!(
            kept,
            [
                placed("1.0", (153, 247)),
                placed("0.5", (153, 316)),
                placed("-1.0", (360, 56)),
                placed("0.5", (301, 83)),
            ]
        );
        // Labels well apart are all kept, whatever they say.
        let apart: Vec<PlacedLabel> = (0..5).map(|i| placed("-1.0", (0, 40 * i))).collect();
        assert_eq!(without_collisions(apart.clone(), 14.0), apart);
    }
}
