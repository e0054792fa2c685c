//! The error weights every method measures its errors in: `w_i = atol_i + rtol |x_i|`
//! (or `atol_i + rtol max(|x_i|, |x_new_i|)` where a method compares the two ends of a
//! step), with one relative tolerance and an absolute tolerance for every state or one
//! per state. An error vector `e` is accepted when its weighted root-mean-square norm
//! `sqrt(mean((e_i / w_i)^2))` is at most 1 (Hairer, Nørsett & Wanner, *Solving ODEs I*,
//! Sect. II.4, eq. (4.11); SUNDIALS' `ewt`).
//!
//! A weight may be zero (`atol_i = 0` at `x_i = 0`): a zero error then counts as zero
//! and any other as infinite ([`scaled`]), so no division by zero produces a NaN.

/// The absolute tolerance: one for every state, or one per state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Atol<'a> {
    /// The same for every state.
    All(f64),
    /// One per state, in the order of the states.
    Each(&'a [f64]),
}

impl Atol<'_> {
    /// The absolute tolerance of state `i`.
    #[inline(always)]
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Atol::All(a) => *a,
            Atol::Each(a) => a[i],
        }
    }
}

/// The weights `atol_i + rtol |x_i|` of an error norm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ErrorWeights<'a> {
    /// The relative tolerance.
    pub rtol: f64,
    /// The absolute tolerance(s).
    pub atol: Atol<'a>,
}

impl ErrorWeights<'_> {
    /// The weight of state `i` at the value `x`: `atol_i + rtol |x|`.
    #[inline(always)]
    pub fn at(&self, i: usize, x: f64) -> f64 {
        self.atol.get(i) + self.rtol * x.abs()
    }

    /// The weight of state `i` over a step from `x` to `x_new`:
    /// `atol_i + rtol max(|x|, |x_new|)`.
    #[inline(always)]
    pub fn over(&self, i: usize, x: f64, x_new: f64) -> f64 {
        self.atol.get(i) + self.rtol * x.abs().max(x_new.abs())
    }

    /// Writes the weights at the state `x` into `w`.
    pub fn fill(&self, x: &[f64], w: &mut [f64]) {
        for (i, (wi, xi)) in w.iter_mut().zip(x).enumerate() {
            *wi = self.at(i, *xi);
        }
    }

    /// The state whose weight at `x` is the smallest, with that weight (`None` without
    /// states): the state held to the tightest absolute error, for messages.
    pub fn tightest(&self, x: &[f64]) -> Option<(usize, f64)> {
        (0..x.len())
            .map(|i| (i, self.at(i, x[i])))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// The weighted root-mean-square norm `sqrt(mean((v_i / w_i)^2))` of `n` values already
/// divided by their weights (0 for `n = 0`).
#[inline]
pub(crate) fn rms(v: impl Iterator<Item = f64>, n: usize) -> f64 {
    let sum: f64 = v.map(|r| r * r).sum();
    crate::math::sqrt(sum / n.max(1) as f64)
}

/// `v / w`, where a zero weight (a purely relative tolerance at a zero state) makes a
/// zero `v` zero and any other `v` infinite.
#[inline(always)]
pub(crate) fn scaled(v: f64, w: f64) -> f64 {
    if w > 0.0 {
        v / w
    } else if v == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// Tolerances a method keeps: `rtol` and one `atol` per state (the same number
/// repeated when the user gave one for every state). Owned, for the stiff methods,
/// which keep them (transformed, for Radau5) between runs.
#[cfg(feature = "std")]
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Tolerances {
    /// The relative tolerance.
    pub rtol: f64,
    /// One absolute tolerance per state.
    pub atol: Vec<f64>,
}

#[cfg(feature = "std")]
impl Tolerances {
    /// `rtol` and the same `atol` for each of `n` states.
    pub fn uniform(rtol: f64, atol: f64, n: usize) -> Self {
        Tolerances {
            rtol,
            atol: vec![atol; n],
        }
    }

    /// The error weights of these tolerances.
    pub fn weights(&self) -> ErrorWeights<'_> {
        ErrorWeights {
            rtol: self.rtol,
            atol: Atol::Each(&self.atol),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_per_state_and_zero_weights() {
        let atol = [1e-3, 0.0];
        let w = ErrorWeights {
            rtol: 0.5,
            atol: Atol::Each(&atol),
        };
        assert_eq!(w.at(0, -2.0), 1e-3 + 1.0);
        assert_eq!(w.over(1, 1.0, -4.0), 2.0);
        assert_eq!(w.tightest(&[0.0, 0.0]), Some((1, 0.0)));
        assert_eq!(scaled(0.0, 0.0), 0.0);
        assert_eq!(scaled(1e-300, 0.0), f64::INFINITY);
        assert_eq!(scaled(3.0, 1.5), 2.0);
        let all = ErrorWeights {
            rtol: 0.5,
            atol: Atol::All(1e-3),
        };
        assert_eq!(all.at(1, -2.0), w.at(0, -2.0));
        // sqrt((9 + 16) / 2)
        assert_eq!(rms([3.0, 4.0].into_iter(), 2), 12.5f64.sqrt());
    }
}
