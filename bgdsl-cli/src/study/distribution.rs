//! The distributions a Monte Carlo study draws parameters from, and the draws of one
//! sample: reproducible from the study's seed and the sample's index alone.
//!
//! # The random numbers
//!
//! Sample `i` of a study with seed `s` draws from its own ChaCha8 keystream (crate
//! `chacha20`, `ChaCha8Rng`): the key is `s` (8 bytes, little-endian, then 24 zero
//! bytes), the stream number is `i`, the position starts at 0. The parameters draw from
//! that stream one after the other in the scenario's order, with `rand_distr`'s samplers
//! (`Uniform` on `[lo, hi)`, `Normal`, `LogNormal`). So the draws of sample `i` depend on
//! the seed, `i` and the study's list of distributions, and on nothing else: not on the
//! other samples, on which shard runs it, on the number of threads or on the order the
//! samples run in. `chacha20` (0.10) and `rand_distr` (0.6) keep their values stable
//! within a minor version; a test pins the first draws so that a change shows.

use chacha20::ChaCha8Rng;
use rand_core::SeedableRng;
use rand_distr::{Distribution as _, LogNormal, Normal, Uniform};

/// Where a parameter's values come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    /// Uniform on `[lo, hi)`; `lo < hi`, both finite.
    Uniform {
        /// The lower end (included).
        lo: f64,
        /// The upper end (excluded).
        hi: f64,
    },
    /// Normal (Gaussian) with this mean and standard deviation (`sd >= 0`).
    Normal {
        /// The mean.
        mean: f64,
        /// The standard deviation.
        sd: f64,
    },
    /// Log-normal: `ln x` is normal with mean `mu` and standard deviation `sigma`
    /// (so the median of `x` is `exp(mu)`).
    LogNormal {
        /// The mean of `ln x`.
        mu: f64,
        /// The standard deviation of `ln x` (`>= 0`).
        sigma: f64,
    },
    /// Given values: sample `i` takes `values[i]` (a column of a CSV file, rows in
    /// order); draws nothing from the random stream.
    Values(Vec<f64>),
}

/// Why a distribution's settings are unusable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BadDistribution(pub String);

impl Distribution {
    /// Checks the settings: finite numbers, `lo < hi`, deviations `>= 0`, given values
    /// finite and at least `samples` of them.
    ///
    /// # Errors
    ///
    /// What is wrong, worded for the scenario's user.
    pub fn check(&self, samples: usize) -> Result<(), BadDistribution> {
        let finite = |name: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(BadDistribution(format!(
                    "`{name}` must be a finite number, found {v}"
                )))
            }
        };
        let deviation = |name: &str, v: f64| {
            finite(name, v)?;
            if v < 0.0 {
                return Err(BadDistribution(format!("`{name}` must be >= 0, found {v}")));
            }
            Ok(())
        };
        match *self {
            Distribution::Uniform { lo, hi } => {
                finite("lo", lo)?;
                finite("hi", hi)?;
                if lo >= hi {
                    return Err(BadDistribution(format!(
                        "a uniform range [lo, hi] needs lo < hi, found [{lo}, {hi}]"
                    )));
                }
            }
            Distribution::Normal { mean, sd } => {
                finite("mean", mean)?;
                deviation("sd", sd)?;
            }
            Distribution::LogNormal { mu, sigma } => {
                finite("mu", mu)?;
                deviation("sigma", sigma)?;
            }
            Distribution::Values(ref values) => {
                if let Some((row, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                    return Err(BadDistribution(format!(
                        "value {} (row {}) is not a finite number: {v}",
                        row + 1,
                        row + 1
                    )));
                }
                if values.len() < samples {
                    return Err(BadDistribution(format!(
                        "the column has {} values, fewer than the {samples} samples",
                        values.len()
                    )));
                }
            }
        }
        Ok(())
    }

    /// One draw for sample `index` from `rng` (that sample's stream).
    ///
    /// # Panics
    ///
    /// Never for settings that passed [`check`](Self::check) (and `index` below the
    /// number of samples checked).
    fn draw(&self, index: usize, rng: &mut ChaCha8Rng) -> f64 {
        match *self {
            Distribution::Uniform { lo, hi } => Uniform::new(lo, hi)
                .expect("checked: lo < hi, finite")
                .sample(rng),
            Distribution::Normal { mean, sd } => Normal::new(mean, sd)
                .expect("checked: finite, sd >= 0")
                .sample(rng),
            Distribution::LogNormal { mu, sigma } => LogNormal::new(mu, sigma)
                .expect("checked: finite, sigma >= 0")
                .sample(rng),
            Distribution::Values(ref values) => values[index],
        }
    }
}

/// The random stream of sample `index` of the study seeded `seed`.
fn stream(seed: u64, index: usize) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    let mut rng = ChaCha8Rng::from_seed(key);
    rng.set_stream(index as u64);
    rng
}

/// The values of sample `index`: one per distribution, in order (see the [module
/// documentation](self) for how they are drawn).
pub fn draw(seed: u64, index: usize, distributions: &[Distribution]) -> Vec<f64> {
    let mut rng = stream(seed, index);
    distributions
        .iter()
        .map(|d| d.draw(index, &mut rng))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study() -> Vec<Distribution> {
        vec![
            Distribution::Uniform { lo: 2.0, hi: 5.0 },
            Distribution::Normal { mean: 1.0, sd: 0.5 },
            Distribution::LogNormal {
                mu: 0.5,
                sigma: 0.25,
            },
            Distribution::Values((0..1000).map(f64::from).collect()),
        ]
    }

    #[test]
    fn a_sample_depends_only_on_the_seed_and_its_index() {
        let all: Vec<Vec<f64>> = (0..1000).map(|i| draw(42, i, &study())).collect();
        // Any subset, in any order, gives the same values.
        for i in [999, 17, 0, 500, 17] {
            assert_eq!(draw(42, i, &study()), all[i]);
        }
        assert_ne!(all[0], all[1], "each index has its own stream");
        assert_ne!(draw(43, 0, &study()), all[0], "the seed matters");
        assert_eq!(all[7][3], 7.0, "sample i takes row i");
    }

    /// The first draws of seed 1, sample 0, as chacha20 0.10 and rand_distr 0.6 give
    /// them: a change in either crate's stream shows here, not in a user's results.
    #[test]
    fn the_stream_is_pinned() {
        let values = draw(1, 0, &study()[..3]);
        assert_eq!(
            values,
            [3.144468239714783, 0.5807190812055746, 2.4500877717090357]
        );
    }

    /// Sample mean and variance of 10^5 draws against the distribution's; the bounds
    /// are 5 standard errors (mean: sd/sqrt(n); variance: sqrt((mu4 - sd^4)/n)), so a
    /// correct sampler fails with probability below 1e-6, and the seed is fixed.
    #[test]
    fn moments_of_1e5_draws_match_the_distributions() {
        const N: usize = 100_000;
        let cases: [(Distribution, f64, f64, f64); 3] = [
            // (distribution, mean, variance, fourth central moment)
            (
                Distribution::Uniform { lo: 2.0, hi: 5.0 },
                3.5,
                9.0 / 12.0,
                81.0 / 80.0,
            ),
            (
                Distribution::Normal { mean: 1.0, sd: 0.5 },
                1.0,
                0.25,
                3.0 * 0.0625,
            ),
            {
                // Log-normal: E x^k = exp(k mu + k^2 sigma^2 / 2).
                let (mu, s2): (f64, f64) = (0.5, 0.0625);
                let m = |k: f64| (k * mu + k * k * s2 / 2.0).exp();
                let mean = m(1.0);
                let var = m(2.0) - mean * mean;
                let mu4 =
                    m(4.0) - 4.0 * mean * m(3.0) + 6.0 * mean * mean * m(2.0) - 3.0 * mean.powi(4);
                (Distribution::LogNormal { mu, sigma: 0.25 }, mean, var, mu4)
            },
        ];
        for (distribution, mean, var, mu4) in cases {
            let xs: Vec<f64> = (0..N)
                .map(|i| draw(7, i, std::slice::from_ref(&distribution))[0])
                .collect();
            let n = N as f64;
            let m = xs.iter().sum::<f64>() / n;
            let v = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
            let mean_bound = 5.0 * (var / n).sqrt();
            let var_bound = 5.0 * ((mu4 - var * var) / n).sqrt();
            assert!(
                (m - mean).abs() < mean_bound,
                "{distribution:?}: mean {m} vs {mean}"
            );
            assert!(
                (v - var).abs() < var_bound,
                "{distribution:?}: variance {v} vs {var}"
            );
        }
    }

    #[test]
    fn bad_settings_are_refused() {
        let bad = |d: Distribution| d.check(10).unwrap_err().0;
        assert_eq!(
            bad(Distribution::Uniform { lo: 1.0, hi: 1.0 }),
            "a uniform range [lo, hi] needs lo < hi, found [1, 1]"
        );
        assert_eq!(
            bad(Distribution::Normal {
                mean: 0.0,
                sd: -1.0
            }),
            "`sd` must be >= 0, found -1"
        );
        assert_eq!(
            bad(Distribution::LogNormal {
                mu: f64::NAN,
                sigma: 1.0
            }),
            "`mu` must be a finite number, found NaN"
        );
        assert_eq!(
            bad(Distribution::Values(vec![1.0; 4])),
            "the column has 4 values, fewer than the 10 samples"
        );
        assert!(Distribution::Values(vec![1.0; 10]).check(10).is_ok());
    }
}
