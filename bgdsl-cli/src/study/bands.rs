//! Quantile bands of a study's trajectories: at every sample time, the 5, 25, 50, 75 and
//! 95 % quantiles of each recorded column over the samples.
//!
//! Quantiles are Hyndman and Fan's type 7 (the default of R's `quantile`, NumPy's
//! `quantile` and Excel's `PERCENTILE.INC`): for sorted values `x[0] <= ... <= x[n-1]`
//! and probability `p`, `h = (n - 1) p`, and the quantile is
//! `x[floor h] + (h - floor h) (x[floor h + 1] - x[floor h])`. Samples whose run failed
//! (NaN) are left out. The values are sorted before use, so the bands do not depend on
//! the order the samples ran or were merged in.

/// The probabilities of the bands, in the order of `bands.csv`'s columns.
pub const PROBABILITIES: [f64; 5] = [0.05, 0.25, 0.50, 0.75, 0.95];

/// The suffixes of `bands.csv`'s columns, one per probability: `<column>_q05`, ...
pub const SUFFIXES: [&str; 5] = ["q05", "q25", "q50", "q75", "q95"];

/// The type-7 quantile of `sorted` (ascending, no NaN) at probability `p` in `[0, 1]`;
/// NaN for no values.
pub fn quantile_sorted(sorted: &[f64], p: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        1 => sorted[0],
        n => {
            let h = (n - 1) as f64 * p;
            let lo = (h.floor() as usize).min(n - 1);
            let hi = (lo + 1).min(n - 1);
            let frac = h - lo as f64;
            if frac == 0.0 {
                sorted[lo]
            } else {
                sorted[lo] + frac * (sorted[hi] - sorted[lo])
            }
        }
    }
}

/// The five band quantiles ([`PROBABILITIES`]) of `values`, NaNs left out.
pub fn band(values: impl Iterator<Item = f64>) -> [f64; 5] {
    let mut sorted: Vec<f64> = values.filter(|v| !v.is_nan()).collect();
    sorted.sort_by(f64::total_cmp);
    PROBABILITIES.map(|p| quantile_sorted(&sorted, p))
}

/// The bands of a study: `bands[t][c]` are the five quantiles of column `c` at time
/// index `t`, over `trajectories[s][t * columns + c]` for every sample `s` (each
/// trajectory row-major: times, then columns).
pub fn bands(trajectories: &[&[f64]], times: usize, columns: usize) -> Vec<Vec<[f64; 5]>> {
    (0..times)
        .map(|t| {
            (0..columns)
                .map(|c| band(trajectories.iter().map(|s| s[t * columns + c])))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values from R 4.x: `quantile(c(1, 2, 4, 8, 16), c(.05, .25, .5, .75, .95))`
    /// (type 7) gives 1.2, 2, 4, 8, 14.4.
    #[test]
    fn type_7_matches_r() {
        let q = band([16.0, 1.0, 8.0, 2.0, 4.0].into_iter());
        let expected = [1.2, 2.0, 4.0, 8.0, 14.4];
        for (a, b) in q.iter().zip(expected) {
            assert!((a - b).abs() < 1e-12, "{q:?}");
        }
    }

    #[test]
    fn failed_samples_are_left_out_and_order_does_not_matter() {
        let a = band([3.0, f64::NAN, 1.0, 2.0].into_iter());
        let b = band([1.0, 2.0, 3.0].into_iter());
        assert_eq!(a, b);
        assert_eq!(a[2], 2.0);
        assert!(band([f64::NAN].into_iter())[0].is_nan());
        assert_eq!(band([5.0].into_iter()), [5.0; 5]);
    }

    /// The quantiles of 0, 1, ..., 100 are 100 p exactly (h is whole).
    #[test]
    fn quantiles_of_a_uniform_grid_are_its_probabilities() {
        let q = band((0..=100).rev().map(f64::from));
        assert_eq!(q, [5.0, 25.0, 50.0, 75.0, 95.0]);
    }

    #[test]
    fn bands_take_each_time_and_column_over_the_samples() {
        // Two times, two columns, three samples.
        let s: [&[f64]; 3] = [
            &[0.0, 10.0, 1.0, 11.0],
            &[2.0, 30.0, 3.0, 31.0],
            &[1.0, 20.0, 2.0, 21.0],
        ];
        let b = bands(&s, 2, 2);
        assert_eq!(b[0][0][2], 1.0);
        assert_eq!(b[0][1][2], 20.0);
        assert_eq!(b[1][0][2], 2.0);
        assert_eq!(b[1][1][4], 30.0, "type 7: h = 1.9, 21 + 0.9 (31 - 21)");
    }
}
