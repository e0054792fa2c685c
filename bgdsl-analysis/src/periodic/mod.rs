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
//! Newton's step is taken in the unknowns (`coordinates.rs`: rotations as three
//! angles, free states left out), scaled, and restricted to the range of `Φ_z − I`
//! (`newton.rs`): it changes neither the model's first integrals nor the orbit's
//! asymptotic phase to first order, so the orbit found is the one a run from the
//! starting state settles on, at the same times. Singular values of `Φ_z − I` below
//! [`PeriodicOptions::neutral_tolerance`] are neutral: left out of the step and of the
//! convergence test (the residual along them is reported as `neutral_residual`).
//! Newton's first step still moves the first integrals to second order, by about the
//! square of the residual it starts from: so plain periods are run first while they
//! settle fast ([`PeriodicOptions::max_settle_periods`]).
//!
//! The multipliers are the eigenvalues of `Φ_z` (balancing and a Francis QR iteration
//! of our own, `eigen.rs`: nalgebra's Schur cycles on the quick return's cluster at 1).
//! Their accuracy is that of `Φ`'s integration ([`PeriodicOptions::steps`]): where
//! the exactly neutral multipliers form non-trivial Jordan blocks (a free spin: its
//! angle grows with its momentum), an error `ε` of `Φ` moves them by about `√ε`, and a
//! split pair may leave the unit circle (the quick return at 400 steps: modulus 2.2).
//! So each multiplier gets an error estimate (`resolution.rs`): `Φ` is integrated once
//! more at `steps / 2`, the two sets of multipliers are matched one to one (least total
//! distance), and a multiplier's estimate is the distance to its partner
//! ([`PeriodicOrbit::multiplier_errors`]); it is resolved when that is at most
//! [`PeriodicOptions::multiplier_tolerance`] ([`PeriodicOrbit::resolved`]). A split
//! multiplier moves by more than its distance from 1 when the steps halve, so it is
//! never outside the unit circle by more than its estimate.

mod coordinates;
mod eigen;
mod floquet;
mod newton;
mod resolution;

pub use floquet::NeutralDirections;

/// The eigenvalues of a small dense real matrix (a monodromy matrix or a block of
/// one), in no particular order: balancing, Hessenberg reduction and the Francis
/// double-shift QR iteration with exceptional shifts. `None` when the iteration has not
/// converged after 30 sweeps per eigenvalue.
pub fn eigenvalues(matrix: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    if !matrix.is_square() {
        return None;
    }
    eigen::eigenvalues(matrix)
}

use core::fmt;

use bgdsl_runtime::{Model, Radau5Options, Simulation, Solver};
use nalgebra::{Complex, DMatrix, DVector};

use crate::error::AnalysisError;
use crate::sensitivity::variational::{propagate, Homogeneous};
use coordinates::Coordinates;
use newton::Defect;

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
    /// Converged when the residual over a period outside the neutral directions, in
    /// the unknowns (a rotation's in radians, its vector `log(Rᵀ R_end)`; a state's
    /// `x_i(t₀ + T) − x_i(t₀) − s_i`), is at most `tolerance` times the unknown's
    /// scale: 1 rad for a rotation, `peak_i + 1e-3 max_j peak_j` for a state, `peak`
    /// its largest magnitude over the period (default 1e-6; the period map's own
    /// integration error is the floor: on the quick return, at the default solver,
    /// Newton stalls at 1e-8 to 4e-8).
    pub tolerance: f64,
    /// Newton iterations at most (default 20).
    pub max_iterations: usize,
    /// Periods simulated from the guess before Newton starts (default 0).
    pub warmup_periods: usize,
    /// After the warm-up, further periods simulated while each at least halves the
    /// state's change over a period and that change (relative to the states'
    /// magnitudes) is above `√tolerance`, at most this many (default 20; 0: none). Newton's
    /// first step moves the model's first integrals (and the orbit's phase) by about
    /// the square of the residual it starts from (see `newton.rs`): on the quick
    /// return, from the residual after 2 periods (5e-2) the orbit's rocker ended 3e-5
    /// rad off the long run's; after 5 (1e-3), 5e-7 of the states' magnitudes.
    pub max_settle_periods: usize,
    /// Singular values of the scaled `Φ_z − I` (in the unknowns) below this are
    /// neutral directions, left out of the Newton step and of the convergence test
    /// (default 1e-4: above the monodromy matrix's integration error at the default
    /// 400 steps, which puts the exactly neutral directions of the quick return at up
    /// to 1.6e-5, and below its slowest physical one, 2.9e-3; off the orbit the
    /// threshold is raised to a tenth of the residual, by which the neutral singular
    /// values move there).
    pub neutral_tolerance: f64,
    /// Whether the multipliers are checked against those of `Φ` at `steps / 2` SDIRK
    /// steps (one more period with `Φ`, at half the cost), which gives each its error
    /// estimate ([`PeriodicOrbit::multiplier_errors`]; default true).
    pub check_multipliers: bool,
    /// A multiplier is resolved when its error estimate is at most this (default 1e-2:
    /// the quick return's genuine 1.0817 has 2.5e-3 at 400 steps, its spurious pair of
    /// modulus 2.2 more than 1).
    pub multiplier_tolerance: f64,
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
            tolerance: 1e-6,
            max_iterations: 20,
            warmup_periods: 0,
            max_settle_periods: 20,
            neutral_tolerance: 1e-4,
            check_multipliers: true,
            multiplier_tolerance: 1e-2,
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
    /// The Floquet multipliers, largest modulus first: the eigenvalues of `Φ` in the
    /// unknowns (rotations as three angles, free states left out), so the directions
    /// off the rotations and the free states' trivial 1s are not among them; empty if
    /// the QR iteration did not converge. The neutral ones are 1 to about the square
    /// root of `Φ`'s integration error (see the module's documentation).
    pub multipliers: Vec<Complex<f64>>,
    /// Each multiplier's error estimate: its distance to its partner among the
    /// multipliers of `Φ` at [`PeriodicOrbit::check_steps`] steps (matched one to one,
    /// least total distance; see [`PeriodicOptions::check_multipliers`]). It bounds the
    /// error when the multiplier converges at least at order one in the step; a
    /// multiplier of a Jordan block split by `Φ`'s integration error moves by more than
    /// its distance from 1, so it is never outside the unit circle by more than its
    /// error. Infinite when not checked.
    pub multiplier_errors: Vec<f64>,
    /// Whether each multiplier's error estimate is at most
    /// [`PeriodicOptions::multiplier_tolerance`].
    pub resolved: Vec<bool>,
    /// The SDIRK steps per period of the check (`steps / 2`; 0: not checked).
    pub check_steps: usize,
    /// The neutral directions (singular values of the scaled `Φ_z − I` below
    /// [`PeriodicOptions::neutral_tolerance`]).
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

/// The neutral threshold's share of the largest scaled residual (see the Newton loop).
const NEUTRAL_PER_RESIDUAL: f64 = 0.1;

/// Nodes of the period at which the monodromy run samples the state for its scales.
const SCALE_NODES: usize = 20;

/// The end state of a period, `Φ`, and each state's largest magnitude over it.
type Monodromy = (Vec<f64>, DMatrix<f64>, Vec<f64>);

/// The free states, the unknowns without them, and the shifts as (unknown, advance).
type Setup = (Vec<bool>, Coordinates, Vec<(usize, f64)>);

/// One period from `x0` with the monodromy matrix: the end state, `Φ`, and each
/// state's largest magnitude over the period (at [`SCALE_NODES`] times).
fn period_map_with_monodromy<M: Model>(
    model: &M,
    options: &PeriodicOptions,
    x0: &[f64],
) -> Result<Monodromy, PeriodicError> {
    let n = x0.len();
    let mut phi = DMatrix::<f64>::identity(n, n);
    let nodes = SCALE_NODES.min(options.steps.max(1));
    let grid: Vec<f64> = (0..=nodes)
        .map(|k| options.t0 + options.period * k as f64 / nodes as f64)
        .collect();
    let substeps = options.steps.max(1).div_ceil(nodes);
    let mut end = x0.to_vec();
    let mut peak: Vec<f64> = x0.iter().map(|v| v.abs()).collect();
    propagate(
        model,
        (options.solver, substeps),
        x0,
        &grid,
        &mut phi,
        &mut Homogeneous,
        |k, x, _| {
            for (p, v) in peak.iter_mut().zip(x) {
                *p = p.max(v.abs());
            }
            if k == nodes {
                end.copy_from_slice(x)
            }
        },
    )?;
    Ok((end, phi, peak))
}

/// The states' scales from their largest magnitudes over a period: `peak_i + 1e-3
/// max_j peak_j` (never zero unless every state is).
fn scales(peak: &[f64]) -> Vec<f64> {
    let big = peak.iter().fold(0.0f64, |m, v| m.max(*v));
    let floor = if big > 0.0 { 1e-3 * big } else { 1.0 };
    peak.iter().map(|v| v + floor).collect()
}

/// `S⁻¹ (Φ_z − I) S` from `Φ_z` and the unknowns' scales `s`.
fn scaled(mut a: DMatrix<f64>, s: &[f64]) -> DMatrix<f64> {
    for (i, si) in s.iter().enumerate() {
        a[(i, i)] -= 1.0;
        for (j, sj) in s.iter().enumerate() {
            a[(i, j)] *= sj / si;
        }
    }
    a
}

/// The largest change from `x` to `y` relative to `|x_i| + 1e-3 max_j |x_j|`.
fn relative_change(x: &[f64], y: &[f64]) -> f64 {
    let big = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let floor = if big > 0.0 { 1e-3 * big } else { 1.0 };
    x.iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((b - a).abs() / (a.abs() + floor)))
}

/// The scaled residual in the unknowns: `S⁻¹ (z(P(x)) − z(x) − s)`.
fn scaled_residual(
    coordinates: &Coordinates,
    x: &[f64],
    end: &[f64],
    shifts: &[(usize, f64)],
    s: &[f64],
) -> Vec<f64> {
    let mut r = coordinates.difference(x, end);
    for &(k, per_period) in shifts {
        r[k] -= per_period;
    }
    r.iter().zip(s).map(|(ri, si)| ri / si).collect()
}

/// The periodic orbit of `model` through a state near `guess`, with period and
/// tolerances from `options`, periodic modulo `shifts`.
///
/// The orbit found is the one a long run from `guess` (after the warm-up) settles on,
/// at the time it would be there (`t₀` plus whole periods): Newton's steps keep the
/// model's first integrals and the asymptotic phase (see `newton.rs`). A shift of a
/// state inside a rotation matrix or of a free state is ignored.
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
    let mut change = f64::INFINITY;
    for k in 0..options.warmup_periods + options.max_settle_periods {
        let mut end = period_map(model, options, &x)?;
        for s in shifts {
            end[s.state] -= s.per_period;
        }
        // Settling: on while a period at least halves the change over a period, down
        // to the square root of the tolerance (what Newton's first step then moves of
        // the first integrals is of the order of the tolerance).
        let now = relative_change(&x, &end);
        let settling = now <= 0.5 * change && now > options.tolerance.sqrt();
        if k >= options.warmup_periods && !settling {
            break;
        }
        change = now;
        x = end;
        periods += 1;
    }
    let mut last = (0.0, 0);
    let mut mu = 0.0;
    let mut setup: Option<Setup> = None;
    for iteration in 0..=options.max_iterations {
        let (end, phi, peak) = period_map_with_monodromy(model, options, &x)?;
        periods += 1;
        let (free, coordinates, shifted) = setup.get_or_insert_with(|| {
            let free = free_states(&phi, shifts);
            let coordinates = Coordinates::new::<M>(&free);
            let shifted = shifts
                .iter()
                .filter_map(|s| Some((coordinates.unknown_of_state(s.state)?, s.per_period)))
                .collect();
            (free, coordinates, shifted)
        });
        let d = scales(&peak);
        let s = coordinates.scales(|i| d[i]);
        // A = S⁻¹ (Φ_z − I) S: the scaled residual's change per scaled unknown.
        let a = scaled(coordinates.reduce(&phi, &x, &end), &s);
        let r = scaled_residual(coordinates, &x, &end, shifted, &s);
        // Off the orbit the neutral directions' singular values are off zero by about
        // the distance to it (a first integral's gradient at the start and at the end
        // of the period differ by that much): a threshold that follows the residual.
        let size = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let defect = Defect::new(
            a,
            options.neutral_tolerance.max(NEUTRAL_PER_RESIDUAL * size),
        );
        let (err, worst, err_neutral) = defect.split(&r);
        last = (err, coordinates.state_of(worst));
        if err <= options.tolerance {
            let neutral = floquet::neutral_directions(model, options, &x, coordinates, &defect, &s);
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
            let multipliers = floquet::multipliers(&defect.a);
            let check_steps = if options.check_multipliers {
                options.steps / 2
            } else {
                0
            };
            let coarse = PeriodicOptions {
                steps: check_steps,
                ..*options
            };
            // A check that fails (the coarser `Φ` singular) resolves nothing.
            let checked = (check_steps > 0)
                .then(|| period_map_with_monodromy(model, &coarse, &x).ok())
                .flatten();
            let multiplier_errors = match checked {
                Some((end, phi, _)) => {
                    periods += 1;
                    let a = scaled(coordinates.reduce(&phi, &x, &end), &s);
                    resolution::errors(&multipliers, &floquet::multipliers(&a))
                }
                None => vec![f64::INFINITY; multipliers.len()],
            };
            let resolved = multiplier_errors
                .iter()
                .map(|e| *e <= options.multiplier_tolerance)
                .collect();
            return Ok(PeriodicOrbit {
                t0: options.t0,
                period: options.period,
                x0: x,
                shifts: shifts.to_vec(),
                free_states,
                multipliers,
                multiplier_errors,
                resolved,
                check_steps,
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
        let mut end_shifted = end.clone();
        for sh in shifts {
            end_shifted[sh.state] -= sh.per_period;
        }
        // Levenberg–Marquardt damping of the Newton step: directions with singular
        // values below `mu` are shortened (gradient-like); `mu` grows while a step
        // fails to lower the residual and shrinks after one that does.
        let mut next: Vec<f64>;
        loop {
            let step = defect.step(&r, mu);
            next = if mu == 0.0 {
                // x + δ to first order, but reached from the period's end by `Φ δ`:
                // that is the shorter move where `Φ` contracts, and what a move
                // changes of the first integrals to second order shrinks with its
                // square (a tenth on the quick return, whose slowest in-plane
                // multiplier is 0.29).
                let moved = &defect.a * DVector::from_column_slice(&step);
                let dz: Vec<f64> = (0..step.len())
                    .map(|k| (moved[k] + step[k]) * s[k])
                    .collect();
                coordinates.apply(&end_shifted, &dz)
            } else {
                let dz: Vec<f64> = step.iter().zip(&s).map(|(y, si)| y * si).collect();
                coordinates.apply(&x, &dz)
            };
            periods += 1;
            // A step that leaves the model's domain (a rotation no longer one) is too
            // long: shorten it.
            let err_next = match period_map(model, options, &next) {
                Ok(end) => {
                    defect
                        .split(&scaled_residual(coordinates, &next, &end, shifted, &s))
                        .0
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
