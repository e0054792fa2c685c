//! The linear variational equations `dS/dt = J(t, x(t)) S + F(t, x(t))` along a
//! trajectory, integrated staggered: the state by the runtime's solver (its dense output
//! sampled at every stage time), the sensitivity matrix `S` (`n × m`) by Alexander's
//! three-stage, stiffly accurate, L-stable SDIRK method of order 3 (R. Alexander, SIAM
//! J. Numer. Anal. 14 (1977); Hairer & Wanner, *Solving ODEs II*, IV.6) on a given grid,
//! with the exact Jacobian of [`JacobianEvaluator`] at each stage.
//!
//! L-stability matters: a bond-graph model's stiff joints give modes that decay within
//! a step, and an A-stable but not L-stable method (the trapezoidal rule) would keep
//! them alive with multipliers near −1, which Floquet analysis would report as neutral.

use bgdsl_runtime::{JacobianEvaluator, Model, Simulation, Solver};
use nalgebra::DMatrix;

use crate::error::AnalysisError;

/// γ of Alexander's method: the root in (1/6, 1/2) of `γ³ − 3γ² + 3γ/2 − 1/6 = 0`.
const GAMMA: f64 = 0.435_866_521_508_459;

/// The stage times as fractions of the step.
const C: [f64; 3] = [GAMMA, 0.5 * (1.0 + GAMMA), 1.0];

/// The strictly lower part of the Butcher matrix (the diagonal is [`GAMMA`]); the last
/// row is also the weights (stiffly accurate).
fn a(i: usize, j: usize) -> f64 {
    let b1 = -(6.0 * GAMMA * GAMMA - 16.0 * GAMMA + 1.0) / 4.0;
    let b2 = (6.0 * GAMMA * GAMMA - 20.0 * GAMMA + 5.0) / 4.0;
    match (i, j) {
        (1, 0) => 0.5 * (1.0 - GAMMA),
        (2, 0) => b1,
        (2, 1) => b2,
        _ => 0.0,
    }
}

/// The forcing term `F(t, x)` (`n × m`) of the variational equations: `∂f/∂p` for
/// parameter sensitivities, nothing for the monodromy matrix.
pub(crate) trait Forcing {
    /// Writes `F(t, x)` into `out` (`n × m`).
    fn forcing(&mut self, t: f64, x: &[f64], out: &mut DMatrix<f64>);
}

/// No forcing: `dS/dt = J S` (the monodromy matrix, `∂x(t)/∂x(t₀)`).
pub(crate) struct Homogeneous;

impl Forcing for Homogeneous {
    fn forcing(&mut self, _t: f64, _x: &[f64], out: &mut DMatrix<f64>) {
        out.fill(0.0);
    }
}

/// The state along the grid, as the runtime's solver computed it.
pub(crate) struct Propagated {
    /// The runtime solver's statistics: accepted steps.
    pub accepted: usize,
}

/// Integrates `x` from `x0` over `grid` with `solver`, and `S` (given at `grid[0]`,
/// overwritten with its value at the last node) over the same grid, `substeps` SDIRK
/// steps per interval; calls `at_node(k, x, S)` at every node.
pub(crate) fn propagate<M: Model>(
    model: &M,
    (solver, substeps): (Solver, usize),
    x0: &[f64],
    grid: &[f64],
    s: &mut DMatrix<f64>,
    forcing: &mut impl Forcing,
    mut at_node: impl FnMut(usize, &[f64], &DMatrix<f64>),
) -> Result<Propagated, AnalysisError> {
    let n = M::N_STATES;
    let substeps = substeps.max(1);
    if grid.len() < 2 {
        return Err(AnalysisError::Dimension {
            what: "time grid (at least two times)",
            expected: 2,
            found: grid.len(),
        });
    }
    // Every stage time, in increasing order: the solver's samples.
    let mut times = Vec::with_capacity((grid.len() - 1) * substeps * 3);
    for w in grid.windows(2) {
        let h = (w[1] - w[0]) / substeps as f64;
        for k in 0..substeps {
            let start = w[0] + k as f64 * h;
            for (i, c) in C.iter().enumerate() {
                let last = k + 1 == substeps && i == 2;
                times.push(if last { w[1] } else { start + c * h });
            }
        }
    }
    let mut states = Vec::with_capacity(times.len() * n);
    let mut sim = Simulation::new(model, solver)?;
    let stats = sim.run(
        grid[0],
        x0,
        &times,
        &mut |_t: f64, x: &[f64], _y: &[f64]| states.extend_from_slice(x),
    )?;

    let m = s.ncols();
    let mut evaluator = JacobianEvaluator::new(model);
    let mut jac = DMatrix::<f64>::zeros(n, n);
    let mut row_major = vec![0.0; n * n];
    let mut f = DMatrix::<f64>::zeros(n, m);
    let mut stage_k: [DMatrix<f64>; 3] = core::array::from_fn(|_| DMatrix::zeros(n, m));
    at_node(0, x0, s);
    let mut sample = 0;
    for (node, w) in grid.windows(2).enumerate() {
        let h = (w[1] - w[0]) / substeps as f64;
        for k in 0..substeps {
            let start = w[0] + k as f64 * h;
            for i in 0..3 {
                let t = start + C[i] * h;
                let x = &states[sample * n..(sample + 1) * n];
                sample += 1;
                evaluator.evaluate(model, t, x, &mut row_major);
                for (r, row) in row_major.chunks_exact(n).enumerate() {
                    for (c, v) in row.iter().enumerate() {
                        jac[(r, c)] = *v;
                    }
                }
                forcing.forcing(t, x, &mut f);
                // (I − hγJ) Y = S + h Σ_{j<i} a_ij K_j + hγ F, then K_i = J Y + F.
                let mut rhs = s.clone();
                for (j, kj) in stage_k.iter().enumerate().take(i) {
                    rhs += kj * (h * a(i, j));
                }
                rhs += &f * (h * GAMMA);
                let mut iteration = &jac * (-h * GAMMA);
                for d in 0..n {
                    iteration[(d, d)] += 1.0;
                }
                let lu = iteration.lu();
                if !lu.solve_mut(&mut rhs) {
                    return Err(AnalysisError::NonFinite {
                        what: "variational equations (singular I − hγJ)",
                        name: format!("t = {t}"),
                    });
                }
                let ki = &mut stage_k[i];
                ki.gemm(1.0, &jac, &rhs, 0.0);
                *ki += &f;
                if i == 2 {
                    // Stiffly accurate: the last stage is the step's result.
                    s.copy_from(&rhs);
                }
            }
        }
        let x_end = &states[(sample - 1) * n..sample * n];
        at_node(node + 1, x_end, s);
    }
    Ok(Propagated {
        accepted: stats.accepted,
    })
}
