//! How well each Floquet multiplier is resolved: the eigenvalues of `Φ` at `N` SDIRK
//! steps per period matched one to one with those at `N/2` steps, the distance to its
//! partner being a multiplier's error estimate.
//!
//! Why a second resolution rather than a condition number: where exactly neutral
//! multipliers form (near-)Jordan blocks, an error `ε` of `Φ` moves them by `ε^{1/m}`
//! (`m` the block's size), far beyond first-order perturbation theory, and a
//! spurious pair may leave the unit circle (the quick return at 400 steps: modulus 2.2,
//! at 200 steps 19.7 and 2.7). Such eigenvalues move a lot when `N` halves; a
//! resolved one converges at the method's order (the quick return's genuine 1.0817:
//! 1.084608, 1.082075, 1.081746 at 200, 400, 800 steps, the differences shrinking by
//! 7.7 ≈ 2³). The distance `|μ_N − μ_{N/2}|` is the error of the coarser value, so it
//! bounds `μ_N`'s error whenever the multiplier converges at least at order one
//! (`√ε`'s order 1.5 included); for a simple multiplier at order 3 it overstates the
//! error about sevenfold.
//!
//! The matching minimises the sum of distances (the assignment problem, solved by the
//! Hungarian method with potentials: Kuhn, Naval Res. Logist. Q. 2 (1955); Munkres,
//! J. SIAM 5 (1957)), so a multiplier cannot claim a partner another one is closer to.

use nalgebra::{Complex, DMatrix};

/// Each of `fine`'s multipliers' distance to its partner among `coarse`'s (the same
/// number) in the matching of least total distance; infinite when the two differ in
/// number (one eigenvalue computation failed).
pub(super) fn errors(fine: &[Complex<f64>], coarse: &[Complex<f64>]) -> Vec<f64> {
    if fine.len() != coarse.len() {
        return vec![f64::INFINITY; fine.len()];
    }
    let cost = DMatrix::from_fn(fine.len(), coarse.len(), |i, j| {
        (fine[i] - coarse[j]).norm()
    });
    if cost.iter().any(|c| !c.is_finite()) {
        return vec![f64::INFINITY; fine.len()];
    }
    assignment(&cost)
        .into_iter()
        .enumerate()
        .map(|(i, j)| cost[(i, j)])
        .collect()
}

/// The assignment of least total cost for a square matrix of finite costs: row `i`
/// gets column `result[i]`. Shortest augmenting paths with row and column potentials,
/// `O(n³)`.
fn assignment(cost: &DMatrix<f64>) -> Vec<usize> {
    let n = cost.nrows();
    // Potentials u (rows) and v (columns); column `j`'s row `row_of[j]`; index 0 of
    // the column arrays is a virtual column the augmenting path starts from.
    let mut u = vec![0.0; n + 1];
    let mut v = vec![0.0; n + 1];
    let mut row_of = vec![usize::MAX; n + 1];
    let mut previous = vec![0usize; n + 1];
    for row in 0..n {
        row_of[0] = row;
        let mut column = 0;
        let mut slack = vec![f64::INFINITY; n + 1];
        let mut used = vec![false; n + 1];
        loop {
            used[column] = true;
            let i = row_of[column];
            let (mut delta, mut next) = (f64::INFINITY, 0);
            for j in 1..=n {
                if used[j] {
                    continue;
                }
                let reduced = cost[(i, j - 1)] - u[i + 1] - v[j];
                if reduced < slack[j] {
                    slack[j] = reduced;
                    previous[j] = column;
                }
                if slack[j] < delta {
                    delta = slack[j];
                    next = j;
                }
            }
            for j in 0..=n {
                if used[j] {
                    u[row_of[j] + 1] += delta;
                    v[j] -= delta;
                } else {
                    slack[j] -= delta;
                }
            }
            column = next;
            if row_of[column] == usize::MAX {
                break;
            }
        }
        // Flip the path back to the virtual column.
        while column != 0 {
            let before = previous[column];
            row_of[column] = row_of[before];
            column = before;
        }
    }
    let mut result = vec![0; n];
    for j in 1..=n {
        result[row_of[j]] = j - 1;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::periodic::eigenvalues;

    /// Every permutation of 0..n (n small), for the brute-force check.
    fn permutations(n: usize) -> Vec<Vec<usize>> {
        if n == 0 {
            return vec![Vec::new()];
        }
        let mut all = Vec::new();
        for p in permutations(n - 1) {
            for k in 0..=p.len() {
                let mut q = p.clone();
                q.insert(k, n - 1);
                all.push(q);
            }
        }
        all
    }

    /// The assignment's total equals the least over all 720 permutations of a 6 × 6
    /// cost matrix of pseudo-random entries (ties impossible to 1e-12 here).
    #[test]
    fn assignment_is_optimal() {
        let mut seed = 12345u64;
        let mut random = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20 {
            let cost = DMatrix::from_fn(6, 6, |_, _| random());
            let total = |p: &[usize]| {
                p.iter()
                    .enumerate()
                    .map(|(i, &j)| cost[(i, j)])
                    .sum::<f64>()
            };
            let best = permutations(6)
                .iter()
                .map(|p| total(p))
                .fold(f64::INFINITY, f64::min);
            let found = assignment(&cost);
            let mut seen = found.clone();
            seen.sort_unstable();
            assert_eq!(seen, (0..6).collect::<Vec<_>>());
            assert!(
                (total(&found) - best).abs() < 1e-12,
                "{} vs {best}",
                total(&found)
            );
        }
    }

    /// A 5 × 5 matrix with a 2 × 2 Jordan block at 1 and the simple eigenvalues 0.5,
    /// −0.3 and 1.2, conjugated by a fixed well-conditioned matrix.
    fn conjugated(perturbation: f64, direction: &DMatrix<f64>) -> DMatrix<f64> {
        let mut j = DMatrix::<f64>::zeros(5, 5);
        j[(0, 0)] = 1.0;
        j[(0, 1)] = 1.0;
        j[(1, 1)] = 1.0;
        j[(2, 2)] = 0.5;
        j[(3, 3)] = -0.3;
        j[(4, 4)] = 1.2;
        let t = DMatrix::from_fn(5, 5, |i, k| {
            if i == k {
                2.0
            } else {
                0.3 / (1.0 + (i + 2 * k) as f64)
            }
        });
        let ti = t.clone().try_inverse().unwrap();
        &t * (j + direction * perturbation) * ti
    }

    /// The perturbation's shape: full, so the Jordan block splits by `√ε`.
    fn direction() -> DMatrix<f64> {
        DMatrix::from_fn(5, 5, |i, k| ((i * 5 + k) as f64 * 0.7).sin())
    }

    /// `Φ_N = Φ + εE`, `Φ_{N/2} = Φ + 8εE` (an order-3 method's error; ε = 1e-10): every
    /// multiplier's error estimate bounds its actual distance from the exact spectrum
    /// {1, 1, 0.5, −0.3, 1.2}, the simple ones' estimates are below 1e-8 and the Jordan
    /// pair's (split by √ε ≈ 1e-5) below 1e-4: all resolved at a tolerance of 1e-3.
    #[test]
    fn errors_bound_the_distance_to_the_exact_spectrum() {
        let e = direction();
        let fine = eigenvalues(&conjugated(1e-10, &e)).unwrap();
        let coarse = eigenvalues(&conjugated(8e-10, &e)).unwrap();
        let errors = errors(&fine, &coarse);
        let exact = [1.0, 1.0, 0.5, -0.3, 1.2];
        for (mu, error) in fine.iter().zip(&errors) {
            let distance = exact
                .iter()
                .map(|x| (mu - x).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(
                distance <= *error,
                "{mu}: off by {distance:e}, estimate {error:e}"
            );
            let jordan = (mu - 1.0).norm() < 1e-3;
            assert!(*error < if jordan { 1e-4 } else { 1e-8 }, "{mu}: {error:e}");
        }
        assert_eq!(
            errors.iter().filter(|&&e| e > 1e-8).count(),
            2,
            "{errors:?}"
        );
    }

    /// The same at ε = 1e-4: the Jordan pair splits by about 1e-2 (and by 2.8e-2 at
    /// 8ε), so its error estimates exceed the 1e-3 tolerance (not resolved), while the
    /// simple multipliers 0.5, −0.3 and 1.2 stay resolved, each within its estimate.
    #[test]
    fn a_split_jordan_block_is_not_resolved() {
        let e = direction();
        let fine = eigenvalues(&conjugated(1e-4, &e)).unwrap();
        let coarse = eigenvalues(&conjugated(8e-4, &e)).unwrap();
        let errors = errors(&fine, &coarse);
        for (mu, error) in fine.iter().zip(&errors) {
            if (mu - 1.0).norm() < 0.1 {
                assert!(
                    *error > 1e-3,
                    "{mu}: {error:e} (the pair is split by {:e})",
                    (mu - 1.0).norm()
                );
            } else {
                let exact = [0.5, -0.3, 1.2]
                    .iter()
                    .map(|x| (mu - x).norm())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    exact <= *error && *error < 1e-3,
                    "{mu}: {exact:e} vs {error:e}"
                );
            }
        }
    }

    /// Different counts (a failed eigenvalue computation): nothing is resolved.
    #[test]
    fn unequal_counts_resolve_nothing() {
        let one = [Complex::new(1.0, 0.0)];
        assert_eq!(errors(&one, &[]), vec![f64::INFINITY]);
    }
}
