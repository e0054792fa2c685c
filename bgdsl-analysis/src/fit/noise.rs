//! Each column's noise variance from the residuals, its share of the degrees of
//! freedom, and the effective degrees of freedom of each estimate's variance.

use nalgebra::DMatrix;

use super::lm::Layout;

/// Per column: the samples, the raw residual sum of squares, and the residual degrees
/// of freedom `nₖ − hₖ`, `hₖ` the sum of the leverages (the hat matrix's diagonal,
/// `H = J_w (J_wᵀJ_w)⁻¹ J_wᵀ` of the whitened Jacobian `jw`) over the column's rows.
///
/// With weights proportional to the true `1/σₖ²` and a model linear in the parameters,
/// the residuals are `(I − H)` times the noise, so `E[RSSₖ] = σₖ² (nₖ − hₖ)`: the
/// unbiased estimate of a column's variance divides by `nₖ − hₖ`, and the `hₖ` add up
/// to the number of parameters (Seber & Wild, *Nonlinear Regression*, 1989, §2.1.3).
pub(super) struct ColumnSums {
    pub samples: Vec<usize>,
    pub rss: Vec<f64>,
    pub dof: Vec<f64>,
}

impl ColumnSums {
    pub fn new(layout: &Layout, raw: &[f64], jw: &DMatrix<f64>, inverse: &DMatrix<f64>) -> Self {
        let n = layout.scales.len();
        let mut samples = vec![0; n];
        let mut rss = vec![0.0; n];
        let mut leverage = vec![0.0; n];
        let projected = jw * inverse;
        for (i, (&c, r)) in layout.row_columns.iter().zip(raw).enumerate() {
            samples[c] += 1;
            rss[c] += r * r;
            leverage[c] += projected.row(i).dot(&jw.row(i));
        }
        let dof = samples
            .iter()
            .zip(&leverage)
            .map(|(&n, h)| n as f64 - h)
            .collect();
        ColumnSums { samples, rss, dof }
    }
}

/// The Welch–Satterthwaite effective degrees of freedom of each parameter's variance
/// `C_jj = Σₖ aₖⱼ`, where `aₖⱼ = Σ_{i∈k} (C J_wᵢᵀ)ⱼ²` is column `k`'s share and each
/// estimated column's variance has `νₖ` degrees of freedom:
/// `ν_j = C_jj² / Σₖ (aₖⱼ² / νₖ)` (ISO GUM, JCGM 100:2008, G.4.1). Columns whose σ is
/// given (`nu` infinite) contribute no uncertainty to the variance; with none
/// estimated, `ν_j` is infinite.
pub(super) fn effective_dof(
    layout: &Layout,
    jw: &DMatrix<f64>,
    covariance: &DMatrix<f64>,
    nu: &[f64],
) -> Vec<f64> {
    let np = covariance.ncols();
    let mut share = DMatrix::<f64>::zeros(nu.len(), np);
    let gain = jw * covariance;
    for (i, &c) in layout.row_columns.iter().enumerate() {
        for j in 0..np {
            share[(c, j)] += gain[(i, j)].powi(2);
        }
    }
    (0..np)
        .map(|j| {
            let spread: f64 = (0..nu.len())
                .filter(|&c| nu[c].is_finite())
                .map(|c| share[(c, j)].powi(2) / nu[c])
                .sum();
            if spread > 0.0 {
                covariance[(j, j)].powi(2) / spread
            } else {
                f64::INFINITY
            }
        })
        .collect()
}
