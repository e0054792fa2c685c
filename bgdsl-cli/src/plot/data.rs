//! Preparing sampled data for charts: wrapping an angle to one revolution without
//! drawing across the wrap, running integrals, and a y range that is not squashed by a
//! start-up transient.

use core::f64::consts::TAU;

/// The points `(angle mod 2π, value)` for plotting against an angle over one
/// revolution, [0, 2π): where the angle passes a multiple of 2π between two samples,
/// the curve is closed to the edge of the plot at the crossing (its value interpolated
/// linearly), broken with a NaN point, and resumed from the other edge; so no segment
/// crosses the plot. A non-finite angle or value is a gap too. `angle` is unwrapped
/// (continuous, turning either way); the slices are paired up to the shorter one.
pub fn wrap_by_revolution(angle: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    let gap = (f64::NAN, f64::NAN);
    let mut out = Vec::with_capacity(angle.len() + angle.len() / 100 + 4);
    let mut previous: Option<(f64, f64)> = None;
    for (&a, &v) in angle.iter().zip(values) {
        if !(a.is_finite() && v.is_finite()) {
            if previous.take().is_some() {
                out.push(gap);
            }
            continue;
        }
        if let Some((pa, pv)) = previous {
            let (turn, turn_before) = ((a / TAU).floor(), (pa / TAU).floor());
            if turn != turn_before {
                let rising = turn > turn_before;
                let edge = turn.max(turn_before) * TAU;
                let crossing = pv + (v - pv) * (edge - pa) / (a - pa);
                if (turn - turn_before).abs() == 1.0 {
                    let (from, to) = if rising { (TAU, 0.0) } else { (0.0, TAU) };
                    out.extend([(from, crossing), gap, (to, crossing)]);
                } else {
                    out.push(gap);
                }
            }
        }
        out.push((wrap_angle(a), v));
        previous = Some((a, v));
    }
    out
}

/// `a` reduced to [0, 2π).
pub fn wrap_angle(a: f64) -> f64 {
    let w = a - (a / TAU).floor() * TAU;
    if w >= TAU {
        0.0
    } else {
        w.max(0.0)
    }
}

/// `∫ y dt` from the first sample to each sample, by the trapezoid rule (the slices
/// paired up to the shorter one). A non-finite value makes the rest non-finite.
pub fn cumulative_trapezoid(t: &[f64], y: &[f64]) -> Vec<f64> {
    let n = t.len().min(y.len());
    let mut out = Vec::with_capacity(n);
    let mut sum = 0.0;
    for i in 0..n {
        if i > 0 {
            sum += 0.5 * (t[i] - t[i - 1]) * (y[i] + y[i - 1]);
        }
        out.push(sum);
    }
    out
}

/// A y range fitted to the samples after a start-up, see [`settled_range`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettledRange {
    /// The range to plot: the values from `from` on, padded by 6 %.
    pub range: (f64, f64),
    /// The first sample time counted as settled.
    pub from: f64,
    /// The smallest and largest value of the whole run.
    pub full: (f64, f64),
}

/// When the values of `columns` over the whole run span more than `ratio` times what
/// they span from time `from` on (a start-up transient that would squash the rest of
/// the plot), the range of the later values, padded; `None` otherwise, or if no later
/// value is finite.
pub fn settled_range(t: &[f64], columns: &[&[f64]], from: f64, ratio: f64) -> Option<SettledRange> {
    let start = t.iter().position(|&ti| ti >= from)?;
    let extent = |rows: std::ops::RangeFrom<usize>| {
        columns
            .iter()
            .flat_map(|c| c.get(rows.clone()).unwrap_or(&[]).iter().copied())
            .filter(|v| v.is_finite())
            .fold(None, |acc: Option<(f64, f64)>, v| match acc {
                None => Some((v, v)),
                Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
            })
    };
    let (full, later) = (extent(0..)?, extent(start..)?);
    let scale = full.0.abs().max(full.1.abs());
    let later_span = (later.1 - later.0).max(scale * 1e-9);
    if full.1 - full.0 <= ratio * later_span {
        return None;
    }
    let pad = 0.06 * later_span;
    Some(SettledRange {
        range: (later.0 - pad, later.1 + pad),
        from: t[start],
        full,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::{FRAC_PI_2, PI};

    fn largest_step(points: &[(f64, f64)]) -> f64 {
        points
            .windows(2)
            .filter(|w| w.iter().all(|p| p.0.is_finite()))
            .map(|w| (w[1].0 - w[0].0).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn wrapping_breaks_each_revolution_at_the_edges() {
        // 3 revolutions from π/2 in 100 steps; the value is the unwrapped angle.
        let angle: Vec<f64> = (0..=100)
            .map(|i| FRAC_PI_2 + 6.0 * PI * f64::from(i) / 100.0)
            .collect();
        let points = wrap_by_revolution(&angle, &angle);
        let gaps: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].0.is_nan())
            .collect();
        assert_eq!(gaps.len(), 3, "crossings of 2π, 4π and 6π");
        assert!(largest_step(&points) < 0.2, "no segment across the plot");
        for &g in &gaps {
            let (before, after) = (points[g - 1], points[g + 1]);
            assert_eq!((before.0, after.0), (TAU, 0.0));
            assert_eq!(before.1, after.1);
            // The value interpolated at the edge is the crossing angle itself.
            let turns = before.1 / TAU;
            assert!((turns - turns.round()).abs() < 1e-12);
        }
        let finite = points.iter().filter(|p| p.0.is_finite());
        assert!(finite.clone().all(|p| (0.0..=TAU).contains(&p.0)));
        assert_eq!(finite.count(), 101 + 2 * 3);
    }

    #[test]
    fn wrapping_handles_backward_turns_and_gaps() {
        let angle = [0.3, 0.1, -0.1, -0.3, f64::NAN, -0.5, -0.6];
        let values = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        let points = wrap_by_revolution(&angle, &values);
        assert_eq!(points.len(), 10, "{points:?}");
        assert_eq!(&points[..3], &[(0.3, 1.0), (0.1, 2.0), (0.0, 2.5)]);
        assert!(points[3].0.is_nan());
        assert_eq!(points[4], (TAU, 2.5));
        assert!((points[5].0 - (TAU - 0.1)).abs() < 1e-15);
        assert!(points[7].0.is_nan(), "the NaN angle is a gap");
        assert!(largest_step(&points) < 0.3);
        assert_eq!(wrap_angle(-1e-18), 0.0);
        assert_eq!(wrap_angle(TAU), 0.0);
    }

    #[test]
    fn trapezoid_integrates_a_ramp_exactly() {
        let t = [0.0, 0.5, 1.0, 2.0];
        assert_eq!(cumulative_trapezoid(&t, &t), [0.0, 0.125, 0.5, 2.0]);
        assert!(cumulative_trapezoid(&[], &[1.0]).is_empty());
    }

    #[test]
    fn a_start_up_spike_is_left_off_scale() {
        let t: Vec<f64> = (0..100).map(f64::from).collect();
        let spike: Vec<f64> = t
            .iter()
            .map(|&t| if t < 5.0 { 100.0 } else { t.sin() })
            .collect();
        let zero = vec![0.0; 100];
        let fit = settled_range(&t, &[&spike, &zero], 20.0, 2.0).unwrap();
        assert_eq!(fit.from, 20.0);
        assert_eq!(fit.full.1, 100.0);
        assert!(fit.range.0 < -0.99 && fit.range.1 > 0.99 && fit.range.1 < 1.2);
        // Without the spike the whole range is kept.
        let calm: Vec<f64> = t.iter().map(|t| t.sin()).collect();
        assert_eq!(settled_range(&t, &[&calm], 20.0, 2.0), None);
        assert_eq!(settled_range(&t, &[&calm], 200.0, 2.0), None);
    }
}
