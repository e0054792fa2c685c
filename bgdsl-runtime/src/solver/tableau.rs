//! Explicit Runge–Kutta methods as data: Butcher tableaux, embedded error weights and
//! dense-output weights. The kernel in [`super::explicit`] knows no method by name.

/// An explicit Runge–Kutta method with `s` stages.
#[derive(Debug)]
pub(crate) struct Tableau {
    /// The order of the solution formula `b`.
    pub order: u32,
    /// Nodes `c_1..c_s` (`c_1 = 0`).
    pub c: &'static [f64],
    /// The strictly lower triangle of the Butcher matrix: row `i` has `i` entries
    /// (`a[0]` is empty).
    pub a: &'static [&'static [f64]],
    /// Weights of the propagated solution.
    pub b: &'static [f64],
    /// Error weights `b - b_hat` of the embedded formula, if the method has one.
    pub error: Option<ErrorEstimate>,
    /// First same as last: the last stage is evaluated at the new solution
    /// (`a[s-1] == b`, `c_s = 1`), so it is the first stage of the next step.
    pub fsal: bool,
    /// Weights `d_1..d_s` of a continuous extension in the form of Hairer's DOPRI5
    /// (see [`super::explicit`]); needs `fsal`.
    pub dense: Option<&'static [f64]>,
}

/// An embedded error estimate `h * sum_j e_j k_j`.
#[derive(Debug)]
pub(crate) struct ErrorEstimate {
    /// `e = b - b_hat`.
    pub weights: &'static [f64],
    /// The order of the embedded formula `b_hat`; the error estimate is
    /// `O(h^(order + 1))`, which sets the exponent of the step-size controller.
    pub order: u32,
}

/// The classical Runge–Kutta method of order 4 (Kutta, 1901).
pub(crate) const RK4: Tableau = Tableau {
    order: 4,
    c: &[0.0, 0.5, 0.5, 1.0],
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    error: None,
    fsal: false,
    dense: None,
};

/// Dormand–Prince 5(4), "DOPRI5": J. R. Dormand & P. J. Prince, "A family of embedded
/// Runge-Kutta formulae", J. Comput. Appl. Math. 6 (1980) 19–26; coefficients as in
/// Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., Table II.5.2. The dense-output
/// weights `d` are Shampine's ("Some practical Runge-Kutta formulas", Math. Comp. 46
/// (1986) 135–150) as used in Hairer's code DOPRI5 (`CONTD5`).
pub(crate) const DORMAND_PRINCE_5: Tableau = Tableau {
    order: 5,
    c: &[0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    a: &[
        &[],
        &[1.0 / 5.0],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        &[
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ],
    b: &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ],
    error: Some(ErrorEstimate {
        // b - b_hat with b_hat = (5179/57600, 0, 7571/16695, 393/640, -92097/339200,
        // 187/2100, 1/40).
        weights: &[
            71.0 / 57600.0,
            0.0,
            -71.0 / 16695.0,
            71.0 / 1920.0,
            -17253.0 / 339200.0,
            22.0 / 525.0,
            -1.0 / 40.0,
        ],
        order: 4,
    }),
    fsal: true,
    dense: Some(&[
        -12715105075.0 / 11282082432.0,
        0.0,
        87487479700.0 / 32700410799.0,
        -10690763975.0 / 1880347072.0,
        701980252875.0 / 199316789632.0,
        -1453857185.0 / 822651844.0,
        69997945.0 / 29380423.0,
    ]),
};

impl Tableau {
    /// The number of stages.
    pub const fn stages(&self) -> usize {
        self.b.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-14 * (1.0 + b.abs())
    }

    /// `a_ij` of the full, zero-padded Butcher matrix.
    fn a(t: &Tableau, i: usize, j: usize) -> f64 {
        t.a[i].get(j).copied().unwrap_or(0.0)
    }

    /// The order conditions up to order 4 (HNW I, Table II.2.2) for weights `b`.
    fn order_conditions_up_to_4(t: &Tableau, b: &[f64]) -> [f64; 8] {
        let s = t.stages();
        let c = t.c;
        let ac = |i: usize| (0..s).map(|j| a(t, i, j) * c[j]).sum::<f64>();
        let ac2 = |i: usize| (0..s).map(|j| a(t, i, j) * c[j] * c[j]).sum::<f64>();
        let aac = |i: usize| (0..s).map(|j| a(t, i, j) * ac(j)).sum::<f64>();
        let sum = |f: &dyn Fn(usize) -> f64| (0..s).map(|i| b[i] * f(i)).sum::<f64>();
        [
            sum(&|_| 1.0) - 1.0,
            sum(&|i| c[i]) - 1.0 / 2.0,
            sum(&|i| c[i] * c[i]) - 1.0 / 3.0,
            sum(&ac) - 1.0 / 6.0,
            sum(&|i| c[i].powi(3)) - 1.0 / 4.0,
            sum(&|i| c[i] * ac(i)) - 1.0 / 8.0,
            sum(&ac2) - 1.0 / 12.0,
            sum(&aac) - 1.0 / 24.0,
        ]
    }

    fn check_shape(t: &Tableau) {
        let s = t.stages();
        assert_eq!(t.c.len(), s);
        assert_eq!(t.a.len(), s);
        for (i, row) in t.a.iter().enumerate() {
            assert_eq!(row.len(), i);
            // Row sums equal the nodes.
            assert!(close(row.iter().sum(), t.c[i]), "row {i}");
        }
    }

    #[test]
    fn rk4_satisfies_the_order_4_conditions() {
        check_shape(&RK4);
        for (k, r) in order_conditions_up_to_4(&RK4, RK4.b).iter().enumerate() {
            assert!(r.abs() < 1e-15, "condition {k}: residual {r}");
        }
    }

    #[test]
    fn dopri5_both_formulas_satisfy_the_order_4_conditions() {
        let t = &DORMAND_PRINCE_5;
        check_shape(t);
        let e = t.error.as_ref().unwrap();
        let b_hat: Vec<f64> = t.b.iter().zip(e.weights).map(|(b, e)| b - e).collect();
        for weights in [t.b, &b_hat[..]] {
            for (k, r) in order_conditions_up_to_4(t, weights).iter().enumerate() {
                assert!(r.abs() < 1e-14, "condition {k}: residual {r}");
            }
        }
        // FSAL: the last row of A is b, and the last node is 1.
        assert!(t.fsal);
        assert_eq!(t.c[t.stages() - 1], 1.0);
        for (a, b) in t.a[t.stages() - 1].iter().zip(t.b) {
            assert_eq!(a, b);
        }
        // The dense weights sum to zero: the fifth coefficient of the continuous
        // extension vanishes for y' = const.
        let d: f64 = t.dense.unwrap().iter().sum();
        assert!(d.abs() < 1e-14, "{d}");
    }

    #[test]
    fn dopri5_fifth_order_conditions_hold_for_b() {
        // Two of the nine fifth-order conditions: sum b c^4 = 1/5 and sum b c a c^2 ...
        // the quadrature ones are the ones a typo in b or c breaks first.
        let t = &DORMAND_PRINCE_5;
        let q4: f64 = t.b.iter().zip(t.c).map(|(b, c)| b * c.powi(4)).sum();
        assert!(close(q4, 1.0 / 5.0), "{q4}");
        let s = t.stages();
        let ac3: f64 = (0..s)
            .map(|i| t.b[i] * (0..s).map(|j| a(t, i, j) * t.c[j].powi(3)).sum::<f64>())
            .sum();
        assert!(close(ac3, 1.0 / 20.0), "{ac3}");
    }
}
