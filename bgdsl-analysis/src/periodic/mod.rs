//! Periodic steady state of a periodically driven (or autonomous, periodically moving)
//! model by shooting, and its Floquet multipliers.
//!
//! The period map `P(x₀) = x(t₀ + T; t₀, x₀)` is integrated with its exact sensitivity,
//! the monodromy matrix `Φ = ∂x(t₀ + T)/∂x₀` (the variational equations `dΦ/dt = J Φ`,
//! `Φ(t₀) = I`, with `J` exact: [`crate::sensitivity`]'s staggered integrator), and
//! Newton's method solves `P(x₀) − x₀ − s = 0`, where `s` holds the known advance per
//! period of the states that are not periodic but periodic modulo a shift (an angle
//! that grows by 2π per turn: [`Shift`]).
//!
//! # Neutral directions
//!
//! `Φ − I` is singular along every direction in which the model does not settle:
//!
//! - **Autonomous models** (a mechanism driven at constant speed, as the quick return
//!   is): a point moved along the orbit is on the orbit, so `Φ f(x*) = f(x*)` exactly —
//!   a multiplier exactly 1, its eigenvector the velocity `f(x*)`.
//!   [`NeutralDirections::along_flow`] measures how much of `f(x*)` lies in the neutral
//!   subspace and [`NeutralDirections::flow_invariance`] how exactly `Φ f = f` holds.
//! - **First integrals**: a rotation matrix held in nine states keeps `RᵀR` constant
//!   along every motion (its derivative is `Rᵀ(Ω + Ωᵀ)R = 0` for a skew `Ω`), so the
//!   six directions per body that change `RᵀR` neither grow nor decay.
//! - **Free coordinates** (a rigid joint's position, a crank angle that is a state):
//!   a multiplier 1 whose direction shifts the coordinate; name them as [`Shift`]s when
//!   they advance by a known amount per period.
//!
//! Newton's step is taken in state variables scaled by their magnitudes and solved by
//! a singular value decomposition that leaves out the singular values of `Φ − I` below
//! [`PeriodicOptions::neutral_tolerance`]: it moves nothing along the neutral
//! directions (the minimum-norm correction), which the residual's components along
//! them cannot move either (they vanish to second order). The result reports the
//! neutral subspace's dimension and the states it is made of.

mod coordinates;
mod floquet;

pub use floquet::NeutralDirections;

use core::fmt;

use bgdsl_runtime::{Model, Radau5Options, Simulation, Solver};
use nalgebra::{Complex, DMatrix};

use crate::error::AnalysisError;
use crate::sensitivity::variational::{propagate, Homogeneous};

/// A state that is periodic modulo an advance per period: `x_i(t₀ + T) = x_i(t₀) +
/// per_period` on the orbit (a crank angle held as a state: `2π` per turn).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shift {
    /// The state's index.
    pub state: usize,
    /// Its advance over one period.
    pub per_period: f64,
}

/// A state nothing depends on, and its advance over one period of the orbit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeState {
    /// Its index.
    pub index: usize,
    /// Its name.
    pub name: &'static str,
    /// `x_i(t₀ + T) − x_i(t₀)` on the orbit.
    pub drift: f64,
}

/// The states whose column of `Φ` is the unit vector to round-off (nothing depends on
/// them), but for those given a shift.
fn free_states(phi: &DMatrix<f64>, shifts: &[Shift]) -> Vec<bool> {
    let n = phi.nrows();
    (0..n)
        .map(|j| {
            !shifts.iter().any(|s| s.state == j)
                && (0..n).all(|i| {
                    let identity = if i == j { 1.0 } else { 0.0 };
                    (phi[(i, j)] - identity).abs() <= 1e-12
                })
        })
        .collect()
}

/// How the periodic orbit is sought.
#[derive(Clone, Copy, Debug)]
pub struct PeriodicOptions {
    /// The period, s (of the drive: `2π/ω`).
    pub period: f64,
    /// The time the orbit starts at (the phase of a time-dependent drive).
    pub t0: f64,
    /// SDIRK steps per period for the monodromy matrix (default 400).
    pub steps: usize,
    /// The solver of the state (default: Radau5 at `rtol` 1e-9, `atol` 1e-11).
    pub solver: Solver,
    /// Converged when every `|x_i(t₀ + T) − x_i(t₀) − s_i|` is at most `tolerance`
    /// times the state's scale `|x_i| + 1e-3 max_j |x_j|` (default 1e-4: the period
    /// map's own integration error, set by the solver's tolerances, is the floor; on the
    /// quick return it is about 1e-5 so measured).
    pub tolerance: f64,
    /// Newton iterations at most (default 20).
    pub max_iterations: usize,
    /// Periods simulated from the guess before Newton starts (default 0).
    pub warmup_periods: usize,
    /// Singular values of the scaled `Φ − I` (in the unknowns) below this are neutral
    /// directions, left out of the Newton step and of the convergence test (default
    /// 1e-6: the exactly neutral ones, which come out at 1e-8 or less on the quick
    /// return; a larger value also drops slowly attracting directions, and the orbit
    /// found may then be off the attracting one along them).
    pub neutral_tolerance: f64,
}

impl PeriodicOptions {
    /// The defaults for period `period` starting at `t0 = 0`.
    pub fn new(period: f64) -> Self {
        PeriodicOptions {
            period,
            t0: 0.0,
            steps: 400,
            solver: Solver::Radau5(Radau5Options {
                rtol: 1e-9,
                atol: 1e-11,
                ..Default::default()
            }),
            tolerance: 1e-4,
            max_iterations: 20,
            warmup_periods: 0,
            neutral_tolerance: 1e-6,
        }
    }
}

/// Why no periodic orbit was found.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum PeriodicError {
    /// A simulation or evaluation failed.
    Analysis(AnalysisError),
    /// Newton's method did not reach the tolerance.
    NotConverged {
        /// The iterations done.
        iterations: usize,
        /// The last scaled residual (1 is the tolerance).
        residual: f64,
        /// The state with the largest scaled residual.
        worst_state: &'static str,
    },
    /// The period is not a positive finite number.
    BadPeriod(f64),
}

impl fmt::Display for PeriodicError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PeriodicError::Analysis(e) => write!(f, "{e}"),
            PeriodicError::NotConverged {
                iterations,
                residual,
                worst_state,
            } => write!(
                f,
                "no periodic orbit found: after {iterations} Newton iterations the period \
                 map still moves the state by {residual:.2e} times the tolerance (most: \
                 `{worst_state}`); the motion may not be periodic with this period (a state \
                 that drifts or grows per turn should be given as a shift), or start \
                 closer (warm-up periods)"
            ),
            PeriodicError::BadPeriod(p) => {
                write!(
                    f,
                    "the period must be a positive number of seconds, not {p}"
                )
            }
        }
    }
}

impl std::error::Error for PeriodicError {}

impl From<AnalysisError> for PeriodicError {
    fn from(e: AnalysisError) -> Self {
        PeriodicError::Analysis(e)
    }
}

impl From<bgdsl_runtime::SolverError> for PeriodicError {
    fn from(e: bgdsl_runtime::SolverError) -> Self {
        PeriodicError::Analysis(e.into())
    }
}

/// A periodic orbit and its stability.
#[derive(Clone, Debug)]
pub struct PeriodicOrbit {
    /// The time the orbit starts at.
    pub t0: f64,
    /// The period, s.
    pub period: f64,
    /// The state on the orbit at `t0`.
    pub x0: Vec<f64>,
    /// The shifts the orbit was sought modulo.
    pub shifts: Vec<Shift>,
    /// The free states: those nothing depends on (their column of `Φ` is exactly the
    /// unit vector), pure integrators such as a spring-less joint's deflection. They
    /// are not required to return: their advance over the period is whatever the orbit
    /// makes it, reported here.
    pub free_states: Vec<FreeState>,
    /// `Φ = ∂x(t₀ + T)/∂x(t₀)` at the orbit (`n × n`).
    pub monodromy: DMatrix<f64>,
    /// The Floquet multipliers (eigenvalues of `Φ`), largest modulus first.
    pub multipliers: Vec<Complex<f64>>,
    /// The neutral directions (singular values of `Φ − I` near zero).
    pub neutral: NeutralDirections,
    /// Newton iterations done.
    pub iterations: usize,
    /// The final scaled residual outside the neutral directions, relative to the
    /// tolerance (at most 1).
    pub residual: f64,
    /// The largest scaled residual along the neutral directions, which Newton's method
    /// cannot remove (the motion neither returns nor departs there): the drift per
    /// period of what is not periodic.
    pub neutral_residual: f64,
    /// Periods integrated in all (with and without `Φ`).
    pub periods_integrated: usize,
}

/// One period from `x0` without sensitivities: the end state.
fn period_map<M: Model>(
    model: &M,
    options: &PeriodicOptions,
    x0: &[f64],
) -> Result<Vec<f64>, PeriodicError> {
    let mut sim = Simulation::new(model, options.solver)?;
    let mut end = x0.to_vec();
    sim.run(
        options.t0,
        x0,
        &[options.t0 + options.period],
        &mut |_t: f64, x: &[f64], _y: &[f64]| end.copy_from_slice(x),
    )?;
    Ok(end)
}

/// One period from `x0` with the monodromy matrix.
fn period_map_with_monodromy<M: Model>(
    model: &M,
    options: &PeriodicOptions,
    x0: &[f64],
) -> Result<(Vec<f64>, DMatrix<f64>), PeriodicError> {
    let n = x0.len();
    let mut phi = DMatrix::<f64>::identity(n, n);
    let grid = [options.t0, options.t0 + options.period];
    let mut end = x0.to_vec();
    propagate(
        model,
        (options.solver, options.steps),
        x0,
        &grid,
        &mut phi,
        &mut Homogeneous,
        |k, x, _| {
            if k == 1 {
                end.copy_from_slice(x)
            }
        },
    )?;
    Ok((end, phi))
}

/// The states' scales: `|x_i| + 1e-3 max_j |x_j|` (never zero unless `x` is).
fn scales(x: &[f64]) -> Vec<f64> {
    let big = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let floor = if big > 0.0 { 1e-3 * big } else { 1.0 };
    x.iter().map(|v| v.abs() + floor).collect()
}

/// The residual `P(x₀) − x₀ − s`, and its largest scaled entry with its index.
/// Free states (`free[i]`) are left out: their residual is zero.
fn residual(
    end: &[f64],
    x0: &[f64],
    shifts: &[Shift],
    free: &[bool],
    d: &[f64],
) -> (Vec<f64>, f64, usize) {
    let mut r: Vec<f64> = end.iter().zip(x0).map(|(e, x)| e - x).collect();
    for s in shifts {
        r[s.state] -= s.per_period;
    }
    for (ri, &f) in r.iter_mut().zip(free) {
        if f {
            *ri = 0.0;
        }
    }
    let (mut worst, mut at) = (0.0, 0);
    for (i, (ri, di)) in r.iter().zip(d).enumerate() {
        let v = (ri / di).abs();
        if v > worst || v.is_nan() {
            worst = v;
            at = i;
        }
    }
    (r, worst, at)
}

/// The periodic orbit of `model` through a state near `guess`, with period and
/// tolerances from `options`, periodic modulo `shifts`.
///
/// # Errors
/// [`PeriodicError::BadPeriod`]; [`PeriodicError::Analysis`] when a simulation fails or
/// `guess` or a shift does not fit the model; [`PeriodicError::NotConverged`] when
/// Newton's method does not reach the tolerance.
pub fn periodic_orbit<M: Model>(
    model: &M,
    guess: &[f64],
    shifts: &[Shift],
    options: &PeriodicOptions,
) -> Result<PeriodicOrbit, PeriodicError> {
    let n = M::N_STATES;
    if !(options.period.is_finite() && options.period > 0.0) {
        return Err(PeriodicError::BadPeriod(options.period));
    }
    if guess.len() != n {
        return Err(AnalysisError::Dimension {
            what: "state vector",
            expected: n,
            found: guess.len(),
        }
        .into());
    }
    if let Some(s) = shifts.iter().find(|s| s.state >= n) {
        return Err(AnalysisError::Dimension {
            what: "shifted state index",
            expected: n,
            found: s.state,
        }
        .into());
    }
    let mut x = guess.to_vec();
    let mut periods = 0;
    for _ in 0..options.warmup_periods {
        let mut end = period_map(model, options, &x)?;
        for s in shifts {
            end[s.state] -= s.per_period;
        }
        x = end;
        periods += 1;
    }
    let mut last = (0.0, 0);
    let mut mu = 0.0;
    let mut free: Vec<bool> = Vec::new();
    let coordinates = coordinates::Coordinates::new::<M>();
    for iteration in 0..=options.max_iterations {
        let (end, phi) = period_map_with_monodromy(model, options, &x)?;
        periods += 1;
        let d = scales(&x);
        if free.is_empty() {
            free = free_states(&phi, shifts);
        }
        // D⁻¹ (Φ − I) E S: the residual's change per scaled unknown.
        let dz = coordinates.scales(&d);
        let embedding = coordinates.embedding(&x);
        let mut defect = &phi * &embedding - &embedding;
        for (i, di) in d.iter().enumerate() {
            for (j, sj) in dz.iter().enumerate() {
                defect[(i, j)] *= sj / di;
            }
        }
        for (i, _) in free.iter().enumerate().filter(|(_, &f)| f) {
            defect.row_mut(i).fill(0.0);
        }
        let svd = defect.svd(true, true);
        let neutral_left = neutral_left_vectors(&svd, options.neutral_tolerance);
        let (r, _, _) = residual(&end, &x, shifts, &free, &d);
        let (err, worst, err_neutral) = split_residual(&r, &d, &neutral_left);
        last = (err, worst);
        if err <= options.tolerance {
            let neutral = floquet::neutral_directions(model, options, &x, &phi, &d);
            let free_states = free
                .iter()
                .enumerate()
                .filter(|(_, &f)| f)
                .map(|(i, _)| FreeState {
                    index: i,
                    name: M::STATE_NAMES.get(i).copied().unwrap_or("?"),
                    drift: end[i] - x[i],
                })
                .collect();
            let multipliers = floquet::multipliers(&coordinates.reduce(&phi, &x));
            return Ok(PeriodicOrbit {
                t0: options.t0,
                period: options.period,
                x0: x,
                shifts: shifts.to_vec(),
                free_states,
                multipliers,
                monodromy: phi,
                neutral,
                iterations: iteration,
                residual: err / options.tolerance,
                neutral_residual: err_neutral,
                periods_integrated: periods,
            });
        }
        if iteration == options.max_iterations {
            break;
        }
        // Levenberg–Marquardt damping of the Newton step: directions with singular
        // values below `mu` are shortened (gradient-like); `mu` grows while a step
        // fails to lower the residual and shrinks after one that does.
        let mut next: Vec<f64>;
        loop {
            let step = damped_step(&svd, &r, &d, &dz, options.neutral_tolerance, mu);
            next = coordinates.apply(&x, &step);
            periods += 1;
            // A step that leaves the model's domain (a rotation no longer one) is too
            // long: shorten it.
            let err_next = match period_map(model, options, &next) {
                Ok(end) => {
                    let dn = scales(&next);
                    let (rn, _, _) = residual(&end, &next, shifts, &free, &dn);
                    split_residual(&rn, &dn, &neutral_left).0
                }
                Err(_) => f64::INFINITY,
            };
            if err_next < err {
                mu *= 0.1;
                break;
            }
            mu = (mu * 10.0).max(1e-6);
            if mu > 1e6 {
                break;
            }
        }
        x = next;
    }
    Err(PeriodicError::NotConverged {
        iterations: options.max_iterations,
        residual: last.0 / options.tolerance,
        worst_state: M::STATE_NAMES.get(last.1).copied().unwrap_or("?"),
    })
}

/// The left singular vectors of the neutral directions (singular values at most
/// `neutral`).
fn neutral_left_vectors(
    svd: &nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>,
    neutral: f64,
) -> Vec<Vec<f64>> {
    let Some(u) = &svd.u else {
        return Vec::new();
    };
    svd.singular_values
        .iter()
        .enumerate()
        .filter(|(_, &sigma)| sigma <= neutral)
        .map(|(k, _)| u.column(k).iter().copied().collect())
        .collect()
}

/// The scaled residual split into its part outside the neutral directions (largest
/// entry, and where) and inside them (largest entry): Newton can remove only the first.
fn split_residual(r: &[f64], d: &[f64], neutral_left: &[Vec<f64>]) -> (f64, usize, f64) {
    let mut outside: Vec<f64> = r.iter().zip(d).map(|(ri, di)| ri / di).collect();
    let scaled = outside.clone();
    for u in neutral_left {
        let c: f64 = u.iter().zip(&scaled).map(|(a, b)| a * b).sum();
        for (o, ui) in outside.iter_mut().zip(u) {
            *o -= c * ui;
        }
    }
    let (mut worst, mut at) = (0.0, 0);
    for (i, v) in outside.iter().enumerate() {
        if v.abs() > worst || v.is_nan() {
            worst = v.abs();
            at = i;
        }
    }
    let inside = scaled
        .iter()
        .zip(&outside)
        .fold(0.0f64, |m, (s, o)| m.max((s - o).abs()));
    (worst, at, inside)
}

/// The damped Newton correction for `(Φ − I) δ = −r` from the SVD of the scaled
/// `Φ − I`: `−Σ σ/(σ² + μ²) (uᵀr) v` over the singular values above `neutral` (the
/// neutral directions are left alone; `μ = 0` is the minimum-norm Newton step).
fn damped_step(
    svd: &nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>,
    r: &[f64],
    d: &[f64],
    dz: &[f64],
    neutral: f64,
    mu: f64,
) -> Vec<f64> {
    let mut step = vec![0.0; dz.len()];
    let (Some(u), Some(v_t)) = (&svd.u, &svd.v_t) else {
        return step;
    };
    for (k, &sigma) in svd.singular_values.iter().enumerate() {
        if sigma <= neutral {
            continue;
        }
        let projection: f64 = (0..r.len()).map(|i| u[(i, k)] * r[i] / d[i]).sum();
        let coefficient = projection * sigma / (sigma * sigma + mu * mu);
        for (j, s) in step.iter_mut().enumerate() {
            *s -= coefficient * v_t[(k, j)] * dz[j];
        }
    }
    step
}
