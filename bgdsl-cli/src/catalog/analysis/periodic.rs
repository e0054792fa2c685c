//! `models periodic`, the model's side: the periodic orbit of the model behind an
//! [`Entry`](crate::catalog::Entry) with a plan's parameters, and one period of it
//! sampled into the columns of a run.

use bgdsl_analysis::periodic::{periodic_orbit, PeriodicError, PeriodicOptions, PeriodicOrbit};
use bgdsl_runtime::{FromParams, Simulation};
use serde::de::DeserializeOwned;

use crate::catalog::{initial_state, params_from, Column, RunPlan};

/// What `models periodic` asks of a model, beside the plan (parameters, initial state,
/// start time = the orbit's phase `t0`).
#[derive(Clone, Copy, Debug)]
pub struct PeriodicRequest {
    /// The period, s.
    pub period: f64,
    /// Periods simulated from the initial state before Newton's method starts.
    pub warmup_periods: usize,
    /// Samples of `orbit.csv` per period (the period's end is one more row).
    pub points: usize,
    /// The shooting's convergence tolerance ([`PeriodicOptions::tolerance`]).
    pub tolerance: f64,
    /// Newton iterations at most.
    pub max_iterations: usize,
}

impl PeriodicRequest {
    /// The library's defaults for `period`, 200 samples per period.
    pub fn new(period: f64) -> Self {
        let options = PeriodicOptions::new(period);
        PeriodicRequest {
            period,
            warmup_periods: options.warmup_periods,
            points: 200,
            tolerance: options.tolerance,
            max_iterations: options.max_iterations,
        }
    }

    /// The library's options for an orbit starting at `t0`.
    pub fn options(&self, t0: f64) -> PeriodicOptions {
        PeriodicOptions {
            t0,
            warmup_periods: self.warmup_periods,
            tolerance: self.tolerance,
            max_iterations: self.max_iterations,
            ..PeriodicOptions::new(self.period)
        }
    }
}

/// A periodic orbit with one period of it sampled.
#[derive(Clone, Debug)]
pub struct PeriodicFound {
    /// The orbit, its monodromy matrix and multipliers.
    pub orbit: PeriodicOrbit,
    /// The sample times `t0 + k T / points`, `k = 0..=points`.
    pub times: Vec<f64>,
    /// One row per time: the asked columns' values.
    pub rows: Vec<Vec<f64>>,
}

/// Why `models periodic` found no orbit.
#[derive(Debug)]
pub enum PeriodicFailure {
    /// The plan's parameters do not fit the model (a bug: plans are validated).
    Params(String),
    /// The shooting failed.
    Orbit(PeriodicError),
}

impl core::fmt::Display for PeriodicFailure {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PeriodicFailure::Params(m) => write!(f, "invalid parameters: {m}"),
            PeriodicFailure::Orbit(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for PeriodicFailure {}

/// The periodic orbit of `M` with `plan`'s parameters through a state near the plan's
/// initial state, starting at the plan's first time, and `columns` over one period.
///
/// # Errors
///
/// [`PeriodicFailure`].
pub fn periodic_of<M>(
    plan: &RunPlan,
    columns: &[Column],
    request: &PeriodicRequest,
) -> Result<PeriodicFound, PeriodicFailure>
where
    M: FromParams,
    M::Params: DeserializeOwned,
{
    let params = params_from::<M::Params>(&plan.params)
        .map_err(|e| PeriodicFailure::Params(e.to_string()))?;
    let model = M::from_params(params);
    let guess = initial_state(&model, &plan.initial);
    let t0 = plan.span()[0];
    let options = request.options(t0);
    let orbit = periodic_orbit(&model, &guess, &[], &options).map_err(PeriodicFailure::Orbit)?;
    let points = request.points.max(2);
    let times: Vec<f64> = (0..=points)
        .map(|k| t0 + request.period * k as f64 / points as f64)
        .collect();
    let mut rows = Vec::with_capacity(times.len());
    let mut sim = Simulation::new(&model, options.solver)
        .map_err(|e| PeriodicFailure::Orbit(PeriodicError::from(e)))?;
    sim.run(t0, &orbit.x0, &times, &mut |_t: f64, x: &[f64], y: &[f64]| {
        rows.push(columns.iter().map(|c| c.value(x, y)).collect())
    })
    .map_err(|e| PeriodicFailure::Orbit(PeriodicError::from(e)))?;
    Ok(PeriodicFound {
        orbit,
        times,
        rows,
    })
}

/// How far a multiplier's modulus may be from 1 and still count as neutral: the
/// monodromy matrix is integrated at `rtol` 1e-9, so an exactly neutral multiplier
/// comes out within about 1e-8 of modulus 1.
pub const NEUTRAL_MODULUS: f64 = 1e-6;

/// The orbit's stability read from its Floquet multipliers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stability {
    /// Every multiplier inside the unit circle: nearby motions return to the orbit.
    Attracting,
    /// None outside, some on the unit circle (within [`NEUTRAL_MODULUS`]): nearby
    /// motions neither return nor depart along those directions.
    Neutral {
        /// Multipliers on the unit circle.
        on_circle: usize,
    },
    /// Some outside: nearby motions depart.
    Unstable {
        /// The largest modulus.
        largest: f64,
    },
}

impl Stability {
    /// The stability of `multipliers` (`(re, im)` pairs).
    pub fn of(multipliers: impl IntoIterator<Item = (f64, f64)>) -> Self {
        let mut on_circle = 0;
        let mut largest = 0.0f64;
        for (re, im) in multipliers {
            let modulus = re.hypot(im);
            largest = largest.max(modulus);
            if (modulus - 1.0).abs() <= NEUTRAL_MODULUS {
                on_circle += 1;
            }
        }
        if largest > 1.0 + NEUTRAL_MODULUS || largest.is_nan() {
            Stability::Unstable { largest }
        } else if on_circle > 0 {
            Stability::Neutral { on_circle }
        } else {
            Stability::Attracting
        }
    }

    /// One line for a person.
    pub fn describe(self) -> String {
        match self {
            Stability::Attracting => {
                "stable: every Floquet multiplier is inside the unit circle".to_owned()
            }
            Stability::Neutral { on_circle } => format!(
                "stable but not attracting in every direction: {on_circle} multiplier(s) on \
                 the unit circle (|μ| = 1 within {NEUTRAL_MODULUS:e}), the rest inside"
            ),
            Stability::Unstable { largest } => format!(
                "unstable: a Floquet multiplier of modulus {largest:.6} lies outside the unit \
                 circle"
            ),
        }
    }

    /// A short keyword: `attracting`, `neutral` or `unstable`.
    pub fn keyword(self) -> &'static str {
        match self {
            Stability::Attracting => "attracting",
            Stability::Neutral { .. } => "neutral",
            Stability::Unstable { .. } => "unstable",
        }
    }
}

/// `floquet.json`.
#[derive(serde::Serialize)]
struct FloquetFile<'a> {
    model: &'a str,
    period: f64,
    t0: f64,
    multipliers: Vec<[f64; 2]>,
    moduli: Vec<f64>,
    stability: &'static str,
    stability_text: String,
    iterations: usize,
    residual: f64,
    neutral_residual: f64,
    periods_integrated: usize,
    initial_state: Vec<(&'a str, f64)>,
    neutral: NeutralFile,
    free_states: Vec<FreeFile>,
}

/// `floquet.json`'s `neutral`.
#[derive(serde::Serialize)]
struct NeutralFile {
    dimension: usize,
    singular_values: Vec<f64>,
    along_flow: f64,
    flow_invariance: f64,
    states: Vec<(&'static str, f64)>,
    explanation: &'static str,
}

/// One of `floquet.json`'s `free_states`.
#[derive(serde::Serialize)]
struct FreeFile {
    name: &'static str,
    drift: f64,
    reason: &'static str,
}

/// The text of `floquet.json` for the orbit of `model` (its type name) with
/// `state_names`: `period` and `multipliers` as `[re, im]` pairs (the keys issue 16
/// fixes), then their moduli, the stability, the shooting's iterations and residuals,
/// the orbit's initial state, the neutral directions and the free states.
pub fn floquet_json(model: &str, state_names: &[&str], orbit: &PeriodicOrbit) -> String {
    let pairs: Vec<(f64, f64)> = orbit.multipliers.iter().map(|m| (m.re, m.im)).collect();
    let stability = Stability::of(pairs.iter().copied());
    let file = FloquetFile {
        model,
        period: orbit.period,
        t0: orbit.t0,
        multipliers: pairs.iter().map(|&(re, im)| [re, im]).collect(),
        moduli: pairs.iter().map(|&(re, im)| re.hypot(im)).collect(),
        stability: stability.keyword(),
        stability_text: stability.describe(),
        iterations: orbit.iterations,
        residual: orbit.residual,
        neutral_residual: orbit.neutral_residual,
        periods_integrated: orbit.periods_integrated,
        initial_state: state_names.iter().copied().zip(orbit.x0.iter().copied()).collect(),
        neutral: NeutralFile {
            dimension: orbit.neutral.dimension,
            singular_values: orbit.neutral.singular_values.clone(),
            along_flow: orbit.neutral.along_flow,
            flow_invariance: orbit.neutral.flow_invariance,
            states: orbit.neutral.states.clone(),
            explanation: "directions in which the period map neither attracts nor repels \
                (singular values of the scaled Φ − I below the neutral tolerance): along the \
                orbit for an autonomous model (along_flow near 1), a first integral, or a \
                free coordinate; Newton's method does not move the state along them",
        },
        free_states: orbit
            .free_states
            .iter()
            .map(|f| FreeFile {
                name: f.name,
                drift: f.drift,
                reason: "nothing depends on this state (its column of Φ is the unit \
                    vector), so it is not required to return; drift is its advance over \
                    one period",
            })
            .collect(),
    };
    let mut text = serde_json::to_string_pretty(&file).unwrap_or_default();
    text.push('\n');
    text
}

/// The text of `orbit.csv`: the header `t,<names>`, then one row per sample of `found`,
/// numbers as a run's CSV writes them.
pub fn orbit_csv(names: &[String], found: &PeriodicFound) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(b"t");
    for name in names {
        out.push(b',');
        out.extend_from_slice(name.as_bytes());
    }
    out.push(b'\n');
    let mut writer = bgdsl_runtime::record::RowWriter::new();
    for (t, row) in found.times.iter().zip(&found.rows) {
        // Writing to a Vec cannot fail.
        let _ = writer.write_row(&mut out, core::iter::once(*t).chain(row.iter().copied()));
    }
    out
}
