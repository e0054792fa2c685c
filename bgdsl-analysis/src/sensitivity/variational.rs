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

use std::sync::Arc;

use bgdsl_runtime::{Jacobian, JacobianEvaluator, Model, ShiftedLu, Simulation, Solver};
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
    let mut stages = Stages::new(model, m);
    at_node(0, x0, s);
    let mut sample = 0;
    for (node, w) in grid.windows(2).enumerate() {
        let h = (w[1] - w[0]) / substeps as f64;
        for k in 0..substeps {
            let start = w[0] + k as f64 * h;
            for (i, c) in C.iter().enumerate() {
                let t = start + c * h;
                let x = &states[sample * n..(sample + 1) * n];
                sample += 1;
                stages.stage(model, (t, x), h, i, s, forcing)?;
            }
        }
        let x_end = &states[(sample - 1) * n..sample * n];
        at_node(node + 1, x_end, s);
    }
    Ok(Propagated {
        accepted: stats.accepted,
    })
}

/// The SDIRK stages' storage, allocated once per [`propagate`]: the stage's Jacobian
/// (over the model's sparsity pattern) and its non-zeros, the factors of `σ I − J`
/// (`σ = 1 / hγ`: the runtime's sparse LU, analysed once), the forcing, the stage
/// derivatives and the stage value. A stage allocates nothing.
struct Stages {
    evaluator: JacobianEvaluator,
    jac: Jacobian,
    lu: ShiftedLu,
    /// The non-zero entries of `jac` (row, column, value): the product `J Y` skips
    /// the structural zeros (most of the flagship's pattern).
    nonzeros: Vec<(u32, u32, f64)>,
    f: DMatrix<f64>,
    stage_k: [DMatrix<f64>; 3],
    y: DMatrix<f64>,
}

impl Stages {
    /// The storage for `model`'s variational equations with `m` columns.
    fn new<M: Model>(model: &M, m: usize) -> Self {
        let n = M::N_STATES;
        let evaluator = JacobianEvaluator::new(model);
        let pattern = evaluator.pattern().clone();
        let lu = ShiftedLu::new(&pattern);
        let jac = Jacobian::new(Arc::new(pattern));
        Stages {
            nonzeros: Vec::with_capacity(jac.nnz()),
            evaluator,
            jac,
            lu,
            f: DMatrix::zeros(n, m),
            stage_k: core::array::from_fn(|_| DMatrix::zeros(n, m)),
            y: DMatrix::zeros(n, m),
        }
    }

    /// Stage `i` of the step of length `h` from `s`, at `(t, x)`: solves
    /// `(I − hγJ) Y = S + h Σ_{j<i} a_ij K_j + hγ F` as
    /// `(σ I − J) Y = σ S + Σ_{j<i} (a_ij / γ) K_j + F`, then `K_i = J Y + F`; the
    /// last stage's `Y` is the step's result (stiffly accurate), written to `s`.
    fn stage<M: Model>(
        &mut self,
        model: &M,
        (t, x): (f64, &[f64]),
        h: f64,
        i: usize,
        s: &mut DMatrix<f64>,
        forcing: &mut impl Forcing,
    ) -> Result<(), AnalysisError> {
        self.evaluator.evaluate_sparse(model, t, x, &mut self.jac);
        forcing.forcing(t, x, &mut self.f);
        let sigma = 1.0 / (h * GAMMA);
        let singular = |_| AnalysisError::NonFinite {
            what: "variational equations (singular I − hγJ)",
            name: format!("t = {t}"),
        };
        self.lu.factor(sigma, &self.jac).map_err(singular)?;
        self.y.copy_from(&self.f);
        add_scaled(&mut self.y, sigma, s);
        for (j, kj) in self.stage_k.iter().enumerate().take(i) {
            add_scaled(&mut self.y, a(i, j) / GAMMA, kj);
        }
        for mut column in self.y.column_iter_mut() {
            self.lu.solve(column.as_mut_slice());
        }
        self.nonzeros.clear();
        for r in 0..M::N_STATES {
            let (cols, values) = self.jac.row(r);
            for (&c, &v) in cols.iter().zip(values) {
                if v != 0.0 {
                    self.nonzeros.push((r as u32, c as u32, v));
                }
            }
        }
        let ki = &mut self.stage_k[i];
        ki.copy_from(&self.f);
        for (mut k_col, y_col) in ki.column_iter_mut().zip(self.y.column_iter()) {
            let (k_col, y_col) = (k_col.as_mut_slice(), y_col.as_slice());
            for &(r, c, v) in &self.nonzeros {
                k_col[r as usize] += v * y_col[c as usize];
            }
        }
        if i == 2 {
            s.copy_from(&self.y);
        }
        Ok(())
    }
}

/// `y += alpha x`, entry by entry.
fn add_scaled(y: &mut DMatrix<f64>, alpha: f64, x: &DMatrix<f64>) {
    for (y, x) in y.as_mut_slice().iter_mut().zip(x.as_slice()) {
        *y += alpha * x;
    }
}
