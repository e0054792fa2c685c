//! The modes' participation factors against a matrix built from known eigenvectors:
//! `A = S B S⁻¹` with `B` block diagonal (two complex pairs, `a ± ib` from the blocks
//! `[[a, b], [−b, a]]`, and two real eigenvalues), so that the right eigenvectors of
//! `A` are `S v_B` and the left ones `S⁻ᵀ w_B`, with `v_B = (1, i)`, `w_B = (1, −i)` on
//! a pair's block and unit vectors on a real eigenvalue's. The participation factor
//! `|wᵢ vᵢ| / Σⱼ |wⱼ vⱼ|` (Pérez-Arriaga, Verghese and Schweppe, 1982) computed from
//! them is the reference.

use bgdsl_analysis::modes;
use nalgebra::{Complex, DMatrix, DVector};

#[test]
fn participation_factors_match_known_eigenvectors() {
    let n = 6;
    // B: pair −1 ± 3i (states 0, 1), −2 (2), −5 (3), pair −0.5 ± 10i (4, 5).
    let mut b = DMatrix::<f64>::zeros(n, n);
    for (k, (a, w)) in [(0, (-1.0, 3.0)), (4, (-0.5, 10.0))] {
        b[(k, k)] = a;
        b[(k + 1, k + 1)] = a;
        b[(k, k + 1)] = w;
        b[(k + 1, k)] = -w;
    }
    b[(2, 2)] = -2.0;
    b[(3, 3)] = -5.0;
    // A well-conditioned, full S with no special structure.
    let s = DMatrix::from_fn(n, n, |i, j| {
        f64::from(u8::from(i == j)) + 0.4 * ((1 + i * n + j) as f64 * 1.7).sin()
    });
    let s_inv = s.clone().try_inverse().expect("S is invertible");
    let a = &s * &b * &s_inv;
    let c = |re: f64, im: f64| Complex::new(re, im);
    // (eigenvalue, v_B, w_B) for each mode with Im λ ≥ 0.
    let unit = |k: usize| DVector::from_fn(n, |i, _| c(f64::from(u8::from(i == k)), 0.0));
    let pair = |k: usize, sign: f64| {
        DVector::from_fn(n, |i, _| match i {
            _ if i == k => c(1.0, 0.0),
            _ if i == k + 1 => c(0.0, sign),
            _ => c(0.0, 0.0),
        })
    };
    let expected = [
        (c(-1.0, 3.0), pair(0, 1.0), pair(0, -1.0)),
        (c(-2.0, 0.0), unit(2), unit(2)),
        (c(-5.0, 0.0), unit(3), unit(3)),
        (c(-0.5, 10.0), pair(4, 1.0), pair(4, -1.0)),
    ];
    let sc = s.map(|v| c(v, 0.0));
    let s_inv_t = s_inv.transpose().map(|v| c(v, 0.0));
    let found = modes(&a);
    assert_eq!(found.len(), expected.len(), "{found:?}");
    for (lambda, v_b, w_b) in expected {
        let mode = found
            .iter()
            .find(|m| (m.eigenvalue - lambda).norm() < 1e-9 * lambda.norm())
            .unwrap_or_else(|| panic!("no mode at {lambda}: {found:?}"));
        let (v, w) = (&sc * v_b, &s_inv_t * w_b);
        let products: Vec<f64> = v
            .iter()
            .zip(w.iter())
            .map(|(v, w)| (v * w).norm())
            .collect();
        let total: f64 = products.iter().sum();
        for (i, p) in products.iter().enumerate() {
            let got = mode.participation[i];
            assert!(
                (got - p / total).abs() < 1e-9,
                "λ = {lambda}, state {i}: {got} against {}",
                p / total
            );
        }
    }
}
