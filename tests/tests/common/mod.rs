//! Helpers shared by the physics tests: solvers with stated tolerances, a seeded
//! random-number generator, and closed-form solutions.
#![allow(dead_code)]

#[path = "../../../bgdsl-runtime/tests/support/counting.rs"]
pub mod counting;
pub mod implicit;
pub mod quick_return;

use bgdsl_runtime::{DormandPrinceOptions, Model, Simulation, Solver, Trajectory};

/// Adaptive Dormand–Prince with the given tolerances.
pub fn dopri5(rtol: f64, atol: f64) -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol,
        atol,
        ..DormandPrinceOptions::default()
    })
}

/// Runs `model` from `(0, x0)` to `t_end`, recording `n` uniform samples, and returns
/// the trajectory and the number of steps attempted.
pub fn run<M: Model>(
    model: &M,
    solver: Solver,
    x0: &[f64],
    t_end: f64,
    n: usize,
) -> (Trajectory, usize) {
    let mut sim = Simulation::new(model, solver).expect("valid solver options");
    let mut traj = Trajectory::for_model::<M>(n);
    let stats = sim
        .run_uniform(0.0, x0, t_end, n, &mut traj)
        .expect("the run reaches t_end");
    (traj, stats.steps())
}

/// The model's declared initial state.
pub fn initial_state<M: Model>(model: &M) -> Vec<f64> {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    x0
}

/// SplitMix64: a small, seeded generator, so every run tests the same states.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in [-scale, scale).
    pub fn symmetric(&mut self, scale: f64) -> f64 {
        self.uniform(-scale, scale)
    }

    /// Log-uniform in [lo, hi): for parameters that span decades.
    pub fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (self.uniform(lo.ln(), hi.ln())).exp()
    }
}

/// The underdamped second-order system `y'' + 2 α y' + ω0² y = ω0² y_eq` from
/// `y(0) = y0`, `y'(0) = v0`: returns `(y(t), y'(t))`. Requires `α < ω0`.
pub fn underdamped(y_eq: f64, y0: f64, v0: f64, omega0: f64, alpha: f64, t: f64) -> (f64, f64) {
    let wd = (omega0 * omega0 - alpha * alpha).sqrt();
    let d = y0 - y_eq;
    let (s, c) = (wd * t).sin_cos();
    let decay = (-alpha * t).exp();
    let y = y_eq + decay * (d * c + (v0 + alpha * d) / wd * s);
    let v = decay * (v0 * c - (omega0 * omega0 * d + alpha * v0) / wd * s);
    (y, v)
}

/// The largest absolute value in `values`.
pub fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// `count` seeded states with every entry uniform in [-1, 1): the same on every run.
pub fn seeded_states<const N: usize>(seed: u64, count: usize) -> Vec<[f64; N]> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| std::array::from_fn(|_| rng.symmetric(1.0)))
        .collect()
}

/// Asserts that generated values equal hand-written ones to rounding: within
/// 1e-13 relative (absolute below 1).
pub fn assert_close(generated: &[f64], hand: &[f64], what: &str) {
    assert_eq!(generated.len(), hand.len(), "{what}: lengths");
    for (i, (g, h)) in generated.iter().zip(hand).enumerate() {
        assert!(
            (g - h).abs() <= 1e-13 * h.abs().max(1.0),
            "{what}[{i}]: generated {g} vs hand {h} (all: {generated:?} vs {hand:?})"
        );
    }
}
