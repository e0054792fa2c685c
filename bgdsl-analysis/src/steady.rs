//! Equilibria: a state `x*` with `f(t, x*, p, u) = 0` for fixed time, parameters and
//! inputs, by Newton's method on the exact Jacobian ∂f/∂x with a backtracking line
//! search, from a guess. Chosen states can be held at their guessed values (their own
//! rates are then not required to vanish: a position that grows at constant speed).
//!
//! A singular Jacobian means the equilibrium is not determined: a free rigid-body
//! motion (nothing pulls a position back), an integrator in a loop. The error names the
//! states the equilibrium cannot fix (the null space of the Jacobian) and the rates no
//! state can cancel (its left null space), computed on the Jacobian scaled row by row
//! and column by column so that units do not decide.

use bgdsl_runtime::Model;
use nalgebra::{DMatrix, DVector};

use crate::partials::{check_finite, check_state, state_partials};
use crate::AnalysisError;

/// How [`equilibrium`] iterates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyOptions {
    /// The time at which `f` is evaluated (models with time-dependent sources).
    pub t: f64,
    /// Converged when every Newton step is below `tolerance · (|xᵢ| + scaleᵢ)`, where
    /// `scaleᵢ` is the largest `|xᵢ|` met (at least `1e-9`), or when every rate is at
    /// round-off: below `1e-12` of the sum `Σⱼ |∂fᵢ/∂xⱼ · xⱼ|` of its terms.
    pub tolerance: f64,
    /// Newton iterations allowed.
    pub max_iterations: usize,
    /// A Jacobian is singular when its smallest singular value (after scaling rows and
    /// columns to unit largest entry) is below this times its largest.
    pub singular_below: f64,
}

impl Default for SteadyOptions {
    fn default() -> Self {
        SteadyOptions {
            t: 0.0,
            tolerance: 1e-12,
            max_iterations: 100,
            singular_below: 1e-12,
        }
    }
}

/// An equilibrium found by [`equilibrium`].
#[derive(Clone, Debug, PartialEq)]
pub struct Equilibrium {
    /// The state.
    pub x: Vec<f64>,
    /// `f` there (zero but for round-off; the held states' rates may be anything).
    pub rates: Vec<f64>,
    /// The largest `|fᵢ|` over the states not held.
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// The equilibrium of `model` nearest (by Newton's method) to `guess`, holding the
/// states `held` at their guessed values.
///
/// # Errors
/// [`AnalysisError::Singular`] naming the states the equilibrium leaves undetermined;
/// [`AnalysisError::NotConverged`]; a guess of the wrong length; non-finite rates.
pub fn equilibrium<M: Model>(
    model: &M,
    guess: &[f64],
    held: &[usize],
    options: SteadyOptions,
) -> Result<Equilibrium, AnalysisError> {
    check_state::<M>(guess)?;
    let n = M::N_STATES;
    let free: Vec<usize> = (0..n).filter(|i| !held.contains(i)).collect();
    let mut x = guess.to_vec();
    let mut scale: Vec<f64> = x.iter().map(|v| v.abs().max(1e-9)).collect();
    let mut f = vec![0.0; n];
    let rates = |x: &[f64], f: &mut [f64]| -> Result<f64, AnalysisError> {
        model.derivatives(options.t, x, f);
        check_finite(f.iter().copied(), M::STATE_NAMES, "derivatives")?;
        Ok(free.iter().map(|&i| f[i] * f[i]).sum::<f64>())
    };
    let mut merit = rates(&x, &mut f)?;
    for iteration in 0..options.max_iterations {
        let jac = state_partials(model, options.t, &x)?.df;
        // Rates at round-off: below 1e-12 of the terms `Σⱼ |Jᵢⱼ xⱼ|` they sum.
        let settled = |f: &[f64]| {
            free.iter().all(|&i| {
                let terms: f64 = (0..n).map(|j| (jac[(i, j)] * x[j]).abs()).sum();
                f[i].abs() <= 1e-12 * terms
            })
        };
        if iteration > 0 && settled(&f) {
            let residual = free.iter().fold(0.0f64, |r, &i| r.max(f[i].abs()));
            return Ok(Equilibrium {
                x,
                rates: f,
                residual,
                iterations: iteration,
            });
        }
        let j = jac.select_rows(&free).select_columns(&free);
        let rhs = DVector::from_iterator(free.len(), free.iter().map(|&i| -f[i]));
        check_singular::<M>(&j, &free, options.singular_below)?;
        let Some(step) = j.clone().lu().solve(&rhs) else {
            return Err(singular_error::<M>(&j, &free));
        };
        let small = |lambda: f64, x: &[f64]| {
            free.iter().enumerate().all(|(k, &i)| {
                (lambda * step[k]).abs() <= options.tolerance * (x[i].abs() + scale[i])
            })
        };
        let converged = small(1.0, &x);
        // Backtracking on the sum of squared rates (a converged step is taken whole:
        // round-off may keep it from decreasing them).
        let mut lambda = 1.0;
        let mut trial = x.clone();
        loop {
            for (k, &i) in free.iter().enumerate() {
                trial[i] = x[i] + lambda * step[k];
            }
            match rates(&trial, &mut f) {
                Ok(m) if converged || m <= (1.0 - 1e-4 * lambda) * merit || settled(&f) => {
                    merit = m;
                    break;
                }
                _ if lambda < 1e-10 => {
                    return Err(AnalysisError::NotConverged {
                        iterations: iteration + 1,
                        residual: merit.sqrt(),
                    })
                }
                _ => lambda *= 0.5,
            }
        }
        x = trial;
        for (s, v) in scale.iter_mut().zip(&x) {
            *s = s.max(v.abs());
        }
        if converged || merit == 0.0 {
            model.derivatives(options.t, &x, &mut f);
            let residual = free.iter().fold(0.0f64, |r, &i| r.max(f[i].abs()));
            return Ok(Equilibrium {
                x,
                rates: f,
                residual,
                iterations: iteration + 1,
            });
        }
    }
    Err(AnalysisError::NotConverged {
        iterations: options.max_iterations,
        residual: merit.sqrt(),
    })
}

/// `j` with rows and columns scaled to unit largest entry (zero rows and columns kept).
fn equilibrated(j: &DMatrix<f64>) -> DMatrix<f64> {
    let mut s = j.clone();
    for mut row in s.row_iter_mut() {
        let m = row.amax();
        if m > 0.0 {
            row /= m;
        }
    }
    for mut col in s.column_iter_mut() {
        let m = col.amax();
        if m > 0.0 {
            col /= m;
        }
    }
    s
}

/// The error for a singular `j` (over the states `free`), if it is singular.
fn check_singular<M: Model>(
    j: &DMatrix<f64>,
    free: &[usize],
    below: f64,
) -> Result<(), AnalysisError> {
    if free.is_empty() {
        return Ok(());
    }
    let s = equilibrated(j).singular_values();
    let (max, min) = (s.max(), s.min());
    if max == 0.0 || min <= below * max {
        return Err(singular_error::<M>(j, free));
    }
    Ok(())
}

/// Names the states along the null space of `j` and the rates along its left null
/// space, each space as its free motions: the dominant states (above a tenth of the
/// largest) of each vector of its reduced basis ([`reduced`]), over the singular
/// vectors whose singular value is negligible.
fn singular_error<M: Model>(j: &DMatrix<f64>, free: &[usize]) -> AnalysisError {
    let s = equilibrated(j);
    let svd = s.svd(true, true);
    let (u, v_t) = (svd.u.expect("asked for U"), svd.v_t.expect("asked for Vᵀ"));
    let max = svd.singular_values.max();
    let null: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&k| max == 0.0 || svd.singular_values[k] <= 1e-9 * max)
        .collect();
    let right = DMatrix::from_fn(null.len(), free.len(), |r, c| v_t[(null[r], c)]);
    let left = DMatrix::from_fn(null.len(), free.len(), |r, c| u[(c, null[r])]);
    let named = |basis: DMatrix<f64>| -> Vec<Vec<String>> {
        reduced(basis)
            .into_iter()
            .map(|motion| {
                motion
                    .into_iter()
                    .map(|i| M::STATE_NAMES[free[i]].to_string())
                    .collect()
            })
            .collect()
    };
    let motions = named(right);
    let unbalanced = named(left);
    let union = |groups: &[Vec<String>]| {
        let mut all: Vec<String> = Vec::new();
        for name in groups.iter().flatten() {
            if !all.contains(name) {
                all.push(name.clone());
            }
        }
        // In the model's order, so that an element's states stay together.
        all.sort_by_key(|name| M::STATE_NAMES.iter().position(|n| *n == name.as_str()));
        all
    };
    AnalysisError::Singular {
        states: union(&motions),
        rates: union(&unbalanced),
        motions,
    }
}

/// The rows of `basis` (a basis of a subspace, one vector a row) brought to reduced
/// row echelon form by elimination with full pivoting, so that each vector moves as
/// few coordinates as the subspace allows (a free body's coordinate alone, when
/// nothing couples it); each as its dominant coordinates (above a tenth of its
/// largest), in increasing order, ordered by their first coordinate.
fn reduced(mut basis: DMatrix<f64>) -> Vec<Vec<usize>> {
    let (k, n) = basis.shape();
    let mut pivots = Vec::with_capacity(k);
    for r in 0..k {
        let mut best = (r, 0, 0.0f64);
        for row in r..k {
            for col in 0..n {
                let v = basis[(row, col)].abs();
                if v > best.2 {
                    best = (row, col, v);
                }
            }
        }
        let (row, col, size) = best;
        if size == 0.0 {
            break;
        }
        basis.swap_rows(r, row);
        let pivot = basis[(r, col)];
        for c in 0..n {
            basis[(r, c)] /= pivot;
        }
        for other in 0..k {
            let factor = basis[(other, col)];
            if other != r && factor != 0.0 {
                for c in 0..n {
                    basis[(other, c)] -= factor * basis[(r, c)];
                }
            }
        }
        pivots.push(col);
    }
    let mut motions: Vec<Vec<usize>> = (0..pivots.len())
        .map(|r| {
            let big = basis.row(r).amax();
            (0..n)
                .filter(|&c| basis[(r, c)].abs() >= 0.1 * big)
                .collect()
        })
        .collect();
    motions.sort();
    motions
}
