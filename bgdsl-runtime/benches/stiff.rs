//! The stiff solvers on a 120-state model of the kind mechanism models produce: a chain
//! of compliant joints with the parameters of the quick-return mechanism (0.1 kg links,
//! 1e5 N/m joints, 20 N·s/m joint damping), driven at one end by an offset slider-crank
//! and ending in a very stiff viscous guide (eigenvalue about -1e7 1/s).
//!
//! `cargo bench -p bgdsl-runtime --bench stiff` first prints a work-precision table
//! (Radau5, Rodas4 and Dormand–Prince at rtol 1e-4, 1e-6, 1e-8: wall time, steps,
//! evaluations, Jacobians, LUs, and the error achieved against a Radau5 run at rtol
//! 1e-11), then times the runs with criterion.

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::{Duration, Instant};

use bgdsl_runtime::{
    DormandPrinceOptions, JacobianEvaluator, Model, Radau5Options, Rodas4Options, Scalar,
    Simulation, Solver, SparsityPattern, Stats, Trajectory,
};
use criterion::{BenchmarkId, Criterion};

/// Point masses of the chain.
const MASSES: usize = 30;
/// States: per mass the joint deflection `(qx, qy)` and momentum `(px, py)`.
const N: usize = 4 * MASSES;
/// The run: 5 s, sampled every 0.1 s.
const T_END: f64 = 5.0;
const SAMPLES: usize = 51;

/// A planar chain of point masses. Joint `i` joins mass `i` to mass `i - 1` (joint 0 to
/// the slider of a crank mechanism): a spring `k (1 + kappa |q|^2)` (mildly stiffening)
/// in parallel with a damper `c`, in both directions. Gravity acts along `-y`; the last
/// mass slides in a viscous guide `c_guide` across the chain (`y`). State order: for
/// each mass, `qx, qy, px, py`.
#[derive(Clone, Debug, Default)]
struct Chain {
    params: ChainParams,
}

#[derive(Clone, Debug)]
struct ChainParams {
    /// Link mass, kg.
    m: f64,
    /// Joint stiffness, N/m.
    k: f64,
    /// Cubic stiffening, 1/m².
    kappa: f64,
    /// Joint damping, N·s/m.
    c: f64,
    /// Guide damping of the last mass, N·s/m: eigenvalue about `-c_guide / m`.
    c_guide: f64,
    /// Gravity, m/s².
    g: f64,
    /// Crank radius, rod length and slider offset, m; crank speed, rad/s.
    crank: f64,
    rod: f64,
    offset: f64,
    omega: f64,
}

impl Default for ChainParams {
    fn default() -> Self {
        ChainParams {
            m: 0.1,
            k: 1e5,
            kappa: 1e6,
            c: 20.0,
            c_guide: 1e6,
            g: 9.81,
            crank: 0.05,
            rod: 0.2,
            offset: 0.03,
            omega: 2.0 * PI,
        }
    }
}

impl ChainParams {
    /// Velocity of the slider of an offset slider-crank (a quick-return motion).
    fn slider_velocity(&self, t: f64) -> f64 {
        let (r, l, e, w) = (self.crank, self.rod, self.offset, self.omega);
        let (sin, cos) = (w * t).sin_cos();
        let s = r * sin - e;
        -r * w * sin - s * r * w * cos / (l * l - s * s).sqrt()
    }
}

/// The Jacobian's structure: one row per state, increasing columns.
const fn pattern() -> ([[usize; 7]; N], [usize; N]) {
    let mut rows = [[0usize; 7]; N];
    let mut lens = [0usize; N];
    let mut i = 0;
    while i < MASSES {
        let b = 4 * i;
        // qx' = vx_i - vx_{i-1}, qy' likewise.
        let mut d = 0;
        while d < 2 {
            let r = b + d;
            let mut len = 0;
            if i > 0 {
                rows[r][len] = b - 4 + 2 + d;
                len += 1;
            }
            rows[r][len] = b + 2 + d;
            lens[r] = len + 1;
            d += 1;
        }
        // px' = -F_i + F_{i+1}: the previous momentum, both own deflections, own
        // momentum, the next joint's deflections and momentum.
        let mut d = 0;
        while d < 2 {
            let r = b + 2 + d;
            let mut len = 0;
            if i > 0 {
                rows[r][len] = b - 4 + 2 + d;
                len += 1;
            }
            rows[r][len] = b;
            rows[r][len + 1] = b + 1;
            rows[r][len + 2] = b + 2 + d;
            len += 3;
            if i + 1 < MASSES {
                rows[r][len] = b + 4;
                rows[r][len + 1] = b + 5;
                rows[r][len + 2] = b + 6 + d;
                len += 3;
            }
            lens[r] = len;
            d += 1;
        }
        i += 1;
    }
    (rows, lens)
}

static PATTERN_DATA: ([[usize; 7]; N], [usize; N]) = pattern();

const PATTERN: [&[usize]; N] = {
    let mut out: [&[usize]; N] = [&[]; N];
    let mut r = 0;
    while r < N {
        out[r] = PATTERN_DATA.0[r].split_at(PATTERN_DATA.1[r]).0;
        r += 1;
    }
    out
};

const STATE_NAMES: [&str; N] = {
    // Names are static strings; generated models name them `joint3.qx` and so on.
    const LETTERS: [&str; 4] = ["qx", "qy", "px", "py"];
    let mut out = [""; N];
    let mut i = 0;
    while i < N {
        out[i] = LETTERS[i % 4];
        i += 1;
    }
    out
};

impl Model for Chain {
    type Params = ChainParams;
    const NAME: &'static str = "compliant_chain";
    const STATE_NAMES: &'static [&'static str] = &STATE_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&PATTERN);

    fn params(&self) -> &ChainParams {
        &self.params
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0);
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let p = &self.params;
        let c = T::from_f64;
        let inv_m = c(1.0 / p.m);
        let (k, kappa, damping) = (c(p.k), c(p.kappa), c(p.c));
        let one = c(1.0);
        // Joint forces, pulling mass i towards mass i - 1.
        let mut fx = [c(0.0); MASSES + 1];
        let mut fy = [c(0.0); MASSES + 1];
        let (mut vx_prev, mut vy_prev) = (c(p.slider_velocity(t)), c(0.0));
        for i in 0..MASSES {
            let b = 4 * i;
            let (qx, qy) = (x[b], x[b + 1]);
            let (vx, vy) = (x[b + 2] * inv_m, x[b + 3] * inv_m);
            let (dvx, dvy) = (vx - vx_prev, vy - vy_prev);
            dx[b] = dvx;
            dx[b + 1] = dvy;
            let spring = k * (one + kappa * (qx * qx + qy * qy));
            fx[i] = spring * qx + damping * dvx;
            fy[i] = spring * qy + damping * dvy;
            vx_prev = vx;
            vy_prev = vy;
        }
        let weight = c(p.m * p.g);
        for i in 0..MASSES {
            let b = 4 * i;
            dx[b + 2] = fx[i + 1] - fx[i];
            dx[b + 3] = fy[i + 1] - fy[i] - weight;
        }
        let last = 4 * (MASSES - 1) + 3;
        dx[last] -= c(p.c_guide) * x[last] * inv_m;
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// One timed run over `[0, T_END]` with `SAMPLES` samples.
struct Run {
    stats: Stats,
    wall: Duration,
    trajectory: Trajectory,
}

fn run(solver: Solver) -> Run {
    let model = Chain::default();
    let mut sim = Simulation::new(&model, solver).unwrap();
    let mut trajectory = Trajectory::for_model::<Chain>(SAMPLES);
    let x0 = [0.0; N];
    let started = Instant::now();
    let stats = sim
        .run_uniform(0.0, &x0, T_END, SAMPLES, &mut trajectory)
        .unwrap_or_else(|e| panic!("{}: {e}", solver.name()));
    Run {
        stats,
        wall: started.elapsed(),
        trajectory,
    }
}

/// The error against the reference: over all samples and states, the largest
/// deviation relative to the largest magnitude of that kind of state (joint deflection,
/// m; momentum, kg·m/s) in the reference run.
fn error(run: &Trajectory, reference: &Trajectory) -> f64 {
    let column = |t: &Trajectory, i: usize| t.column_at(1 + i).unwrap().to_vec();
    let is_deflection = |i: usize| i % 4 < 2;
    let mut scale = [0.0f64; 2];
    for i in 0..N {
        let kind = usize::from(is_deflection(i));
        let peak = column(reference, i)
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        scale[kind] = scale[kind].max(peak);
    }
    let mut worst = 0.0f64;
    for i in 0..N {
        let s = scale[usize::from(is_deflection(i))];
        for (x, r) in column(run, i).iter().zip(&column(reference, i)) {
            worst = worst.max((x - r).abs() / s);
        }
    }
    worst
}

fn radau5(rtol: f64) -> Solver {
    Solver::Radau5(Radau5Options {
        rtol,
        atol: 1e-3 * rtol,
        ..Default::default()
    })
}

fn rodas4(rtol: f64) -> Solver {
    Solver::Rodas4(Rodas4Options {
        rtol,
        atol: 1e-3 * rtol,
        ..Default::default()
    })
}

/// Dormand–Prince, with a budget large enough for the ~15 million steps its stability
/// region allows on the stiff guide mode.
fn dopri5(rtol: f64) -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol,
        atol: 1e-3 * rtol,
        max_steps: 100_000_000,
        ..Default::default()
    })
}

/// The compressed Jacobian must equal the dense one: the declared pattern is right.
fn check_pattern() {
    let model = Chain::default();
    let mut x = [0.0; N];
    for (i, v) in x.iter_mut().enumerate() {
        *v = 1e-4 * ((i as f64) * 0.7).sin();
    }
    let (mut sparse, mut dense) = (vec![0.0; N * N], vec![0.0; N * N]);
    let colours = JacobianEvaluator::new(&model).evaluate(&model, 0.3, &x, &mut sparse);
    JacobianEvaluator::with_pattern(SparsityPattern::dense(N))
        .evaluate(&model, 0.3, &x, &mut dense);
    assert_eq!(
        sparse, dense,
        "the declared sparsity pattern misses entries"
    );
    eprintln!("compliant chain: {N} states, Jacobian in {colours} dual evaluations");
}

fn work_precision_table() {
    let reference = run(radau5(1e-11));
    eprintln!(
        "reference: Radau5 rtol 1e-11, {} steps, {:.1} ms",
        reference.stats.accepted,
        reference.wall.as_secs_f64() * 1e3
    );
    eprintln!(
        "{:<8} {:>6} {:>10} {:>7} {:>5} {:>8} {:>7} {:>6} {:>6} {:>9}",
        "method", "rtol", "wall ms", "steps", "rej", "rhs", "jac.rhs", "jac", "lu", "error"
    );
    type Method = (&'static str, fn(f64) -> Solver, &'static [f64]);
    let methods: [Method; 3] = [
        ("radau5", radau5, &[1e-4, 1e-6, 1e-8]),
        ("rodas4", rodas4, &[1e-4, 1e-6, 1e-8]),
        ("dopri5", dopri5, &[1e-4, 1e-6]),
    ];
    for (name, solver, tolerances) in methods {
        for &rtol in tolerances {
            // The fastest of three runs (one for the slow explicit method).
            let repeats = if name == "dopri5" { 1 } else { 3 };
            let best = (0..repeats)
                .map(|_| run(solver(rtol)))
                .min_by_key(|r| r.wall)
                .unwrap();
            let s = best.stats;
            eprintln!(
                "{:<8} {:>6.0e} {:>10.2} {:>7} {:>5} {:>8} {:>7} {:>6} {:>6} {:>9.2e}",
                name,
                rtol,
                best.wall.as_secs_f64() * 1e3,
                s.accepted,
                s.rejected,
                s.n_rhs,
                s.n_jac_rhs,
                s.n_jac,
                s.n_lu,
                error(&best.trajectory, &reference.trajectory)
            );
        }
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("compliant_chain_120_states_5s");
    group.sample_size(10);
    for rtol in [1e-4, 1e-6, 1e-8] {
        group.bench_with_input(BenchmarkId::new("radau5", rtol), &rtol, |b, &rtol| {
            b.iter(|| black_box(run(radau5(rtol)).stats))
        });
        group.bench_with_input(BenchmarkId::new("rodas4", rtol), &rtol, |b, &rtol| {
            b.iter(|| black_box(run(rodas4(rtol)).stats))
        });
    }
    group.finish();
}

fn main() {
    check_pattern();
    // `cargo bench` passes `--bench`; `cargo test --benches` does not, and only checks
    // that the benchmarks run.
    if std::env::args().any(|a| a == "--bench") {
        work_precision_table();
    }
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c);
    c.final_summary();
}
