//! The distributions the fit's intervals and checks read (through `statrs`).

use statrs::distribution::{ChiSquared, ContinuousCDF, StudentsT};

/// The standard normal quantile `z(0.975)`.
const Z_975: f64 = 1.959_963_984_540_054;

/// The Student-t quantile `t(0.975, ν)` for `ν > 0` degrees of freedom, not
/// necessarily whole (an effective number); the normal quantile 1.959964 for `ν = ∞`
/// (a variance known, not estimated). NaN for `ν ≤ 0`.
pub fn t_quantile_975(dof: f64) -> f64 {
    if dof == f64::INFINITY {
        return Z_975;
    }
    StudentsT::new(0.0, 1.0, dof).map_or(f64::NAN, |t| t.inverse_cdf(0.975))
}

/// The probability that a χ² variable of `dof` degrees of freedom is at least `x`
/// (the upper tail). NaN when `dof ≤ 0`.
pub fn chi_square_upper_tail(x: f64, dof: f64) -> f64 {
    ChiSquared::new(dof).map_or(f64::NAN, |d| d.sf(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `t(0.975, ν)` against the table of the NIST/SEMATECH e-Handbook of Statistical
    /// Methods, §1.3.6.7.2 (three decimals).
    #[test]
    fn student_quantiles_match_the_table() {
        let table = [
            (1.0, 12.706),
            (2.0, 4.303),
            (3.0, 3.182),
            (5.0, 2.571),
            (10.0, 2.228),
            (30.0, 2.042),
            (100.0, 1.984),
        ];
        for (dof, t) in table {
            let q = t_quantile_975(dof);
            assert!((q - t).abs() < 5e-4, "t(0.975, {dof}) = {q}, table {t}");
        }
        assert_eq!(t_quantile_975(f64::INFINITY), Z_975);
        // Between whole numbers of degrees of freedom, between their quantiles.
        let q = t_quantile_975(4.5);
        assert!(t_quantile_975(5.0) < q && q < t_quantile_975(4.0));
        assert!(t_quantile_975(0.0).is_nan());
    }

    /// The χ² upper tail against the same handbook's table (§1.3.6.7.4): the 0.05 and
    /// 0.95 upper-tail points of 10 and 100 degrees of freedom.
    #[test]
    fn chi_square_tails_match_the_table() {
        for (x, dof, tail) in [
            (18.307, 10.0, 0.05),
            (3.940, 10.0, 0.95),
            (124.342, 100.0, 0.05),
            (77.929, 100.0, 0.95),
        ] {
            let p = chi_square_upper_tail(x, dof);
            assert!(
                (p - tail).abs() < 1e-4,
                "χ²({dof}) ≥ {x}: {p}, table {tail}"
            );
        }
    }
}
