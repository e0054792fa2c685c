//! The stiff methods side by side: Rodas5P's convergence order, its accuracy on the
//! Bari test set (see `stiff_common` for the problems and the sources of their
//! reference values), the linear invariant of E5, and (ignored, run in release) the
//! work-precision study behind `docs/solvers.md`:
//!
//! ```sh
//! nice -n 10 cargo test --release -p bgdsl-runtime --test stiff_methods -- --ignored --nocapture
//! ```

mod stiff_common;

use std::time::{Duration, Instant};

use bgdsl_runtime::{
    DormandPrinceOptions, Model, Radau5Options, Rodas4Options, Rodas5POptions, Scalar, Simulation,
    Solver, Stats, Trajectory,
};
use stiff_common::*;

/// The stiff methods at tolerances `rtol`, `atol`.
fn methods(rtol: f64, atol: f64) -> [Solver; 3] {
    [
        Solver::Radau5(Radau5Options {
            rtol,
            atol,
            ..Default::default()
        }),
        Solver::Rodas4(Rodas4Options {
            rtol,
            atol,
            ..Default::default()
        }),
        Solver::Rodas5P(Rodas5POptions {
            rtol,
            atol,
            ..Default::default()
        }),
    ]
}

/// The Brusselator `x' = 1 + x² y - 4 x`, `y' = 3 x - x² y` (HW I, Sect. II.10), from
/// `(1.5, 3)`: smooth and nonlinear, for convergence orders.
struct Brusselator;

impl Model for Brusselator {
    type Params = ();
    const NAME: &'static str = "brusselator";
    const STATE_NAMES: &'static [&'static str] = &["x", "y"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[1.5, 3.0]);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, y: &[T], dy: &mut [T]) {
        let c = T::from_f64;
        let x2y = y[0] * y[0] * y[1];
        dy[0] = c(1.0) + x2y - c(4.0) * y[0];
        dy[1] = c(3.0) * y[0] - x2y;
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// Rodas5P with every step of size `h`: the error estimate is made irrelevant (`atol`
/// huge), so the steps are `max_step = initial_step = h`.
fn rodas5p_fixed(h: f64) -> Solver {
    Solver::Rodas5P(Rodas5POptions {
        rtol: 0.5,
        atol: 1e6,
        initial_step: Some(h),
        max_step: h,
        ..Default::default()
    })
}

/// The global error of Rodas5P at `t = 2` on the Brusselator falls like `h^5`: the
/// measured order between consecutive halvings of `h = 0.05 … 0.0125` is within 0.3
/// of 5. Reference: Dormand–Prince at rtol = atol = 1e-13 (an independent method;
/// its error is far below the smallest measured here, 1.5e-10). Measured: 5.19 and 5.08 (5.49 from `h = 0.1`, not yet asymptotic).
#[test]
fn rodas5p_converges_with_order_5() {
    let t_end = 2.0;
    let tight = Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-13,
        atol: 1e-13,
        ..Default::default()
    });
    let (reference, _) = solve(&Brusselator, tight, t_end);
    let errors: Vec<f64> = [40, 80, 160]
        .iter()
        .map(|&n| {
            let h = t_end / n as f64;
            let (x, stats) = solve(&Brusselator, rodas5p_fixed(h), t_end);
            assert_eq!(stats.accepted, n, "fixed steps: {stats:?}");
            assert_eq!(stats.rejected, 0);
            x.iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!(
            (4.7..=5.3).contains(&order),
            "order {order} from errors {errors:?}"
        );
    }
}

/// `|y2 - y3 - y4| / |y2|` at each of the sample times (`y2 != 0`), largest.
fn e5_invariant(traj: &Trajectory) -> f64 {
    (0..traj.len())
        .filter_map(|k| {
            let y: Vec<f64> = (0..4).map(|i| traj.state(k, i).unwrap()).collect();
            (y[1] != 0.0).then(|| ((y[1] - y[2] - y[3]) / y[1]).abs())
        })
        .fold(0.0, f64::max)
}

/// Sample times `10^(k/2)`, `k = 0..=26`, on E5's `[0, 1e13]`.
fn e5_times() -> Vec<f64> {
    (0..=26).map(|k| 10f64.powf(0.5 * k as f64)).collect()
}

/// One row of the study: counters, best wall time of `repeats`, digits.
fn row<M: Model>(model: &M, solver: Solver, t_end: f64, reference: &[f64], repeats: usize) {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, solver).unwrap();
    let mut best = Duration::MAX;
    let mut outcome = Ok(Stats::default());
    for _ in 0..repeats {
        let started = Instant::now();
        outcome = sim.run(0.0, &x0, &[t_end], &mut ());
        best = best.min(started.elapsed());
    }
    let rtol = match solver {
        Solver::Radau5(o) => o.rtol,
        Solver::Rodas4(o) | Solver::Rodas5P(o) => o.rtol,
        _ => f64::NAN,
    };
    match outcome {
        Ok(s) => {
            // Components the reference has below 1e-100 (E5's `y1` near 1e-291 and `y4`)
            // are left out of the relative error.
            let err = sim
                .state()
                .iter()
                .zip(reference)
                .filter(|(_, r)| r.abs() > 1e-100)
                .map(|(x, r)| ((x - r) / r).abs())
                .fold(0.0, f64::max);
            println!(
                "{:<8} {:>6.0e} {:>6} {:>4} {:>7} {:>6} {:>6} {:>9.0} {:>9.2e} {:>6.1}",
                solver.name(),
                rtol,
                s.accepted,
                s.rejected,
                s.n_rhs + s.n_jac_rhs,
                s.n_jac,
                s.n_lu,
                best.as_secs_f64() * 1e6,
                err,
                -err.log10()
            );
        }
        Err(e) => println!("{:<8} {:>6.0e} failed: {e}", solver.name(), rtol),
    }
}

fn header(name: &str) {
    println!("\n{name}");
    println!(
        "{:<8} {:>6} {:>6} {:>4} {:>7} {:>6} {:>6} {:>9} {:>9} {:>6}",
        "method", "rtol", "steps", "rej", "f evals", "jac", "lu", "wall µs", "rel.err", "digits"
    );
}

fn table<M: Model>(model: &M, t_end: f64, reference: &[f64], atol_per_rtol: f64) {
    header(&format!("{} (atol = {atol_per_rtol:e} rtol)", M::NAME));
    for k in 3..=10 {
        let rtol = 10f64.powi(-k);
        for solver in methods(rtol, atol_per_rtol * rtol) {
            row(model, solver, t_end, reference, 3);
        }
    }
}

#[test]
#[ignore = "prints the work-precision study; run in release mode"]
fn work_precision_of_the_stiff_methods() {
    table(&Robertson, 1e11, &ROBERTSON_REF, 1e-8);
    table(&VanDerPol, 2.0, &VDP_REF, 1.0);
    table(&Hires, HIRES_T_END, &HIRES_REF, 1e-3);
    table(&Oregonator, 360.0, &OREGO_REF, 1.0);
    table(&Pollution, 60.0, &POLLU_REF, 1.0);
    table(&E5, E5_T_END, &E5_REF, 1e-24 / 1e-6);
    header("oregonator, tight (atol = rtol)");
    for rtol in [1e-11, 1e-12, 1e-13] {
        for solver in methods(rtol, rtol) {
            row(&Oregonator, solver, 360.0, &OREGO_REF, 1);
        }
    }
    let vdp = StiffVanDerPol(1e-12);
    // Radau5 (with issue 15's tolerance transformation) underflows its step at the
    // relaxation jump from rtol 1e-11 on; Rodas5P does not.
    let tight = Solver::Rodas5P(Rodas5POptions {
        rtol: 1e-11,
        atol: 1e-11,
        max_steps: 1_000_000,
        ..Default::default()
    });
    let (reference, _) = solve(&vdp, tight, 2.0);
    header("van der pol, mu = 1e6 to t = 2 (reference: rodas5p at rtol = atol = 1e-11)");
    for rtol in [1e-6, 1e-8, 1e-10] {
        for solver in methods(rtol, rtol) {
            row(&vdp, solver, 2.0, &reference, 1);
        }
    }
    println!(
        "\nE5 (atol 1e-24): largest |y2 - y3 - y4| / |y2| at t = 10^(k/2), k = 0..=26; \
         the end point's scaled error; +r: refine_stages"
    );
    println!(
        "{:<10} {:>6} {:>9} {:>9} {:>6} {:>9}",
        "method", "rtol", "invariant", "scaled", "steps", "wall µs"
    );
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let [radau, rodas4, rodas5p] = methods(rtol, 1e-24);
        let refined = |solver: Solver| match solver {
            Solver::Rodas4(o) => Solver::Rodas4(Rodas4Options {
                refine_stages: true,
                ..o
            }),
            Solver::Rodas5P(o) => Solver::Rodas5P(Rodas5POptions {
                refine_stages: true,
                ..o
            }),
            other => other,
        };
        let runs = [
            (radau, ""),
            (rodas4, ""),
            (refined(rodas4), "+r"),
            (rodas5p, ""),
            (refined(rodas5p), "+r"),
        ];
        for (solver, tag) in runs {
            let times = e5_times();
            let mut traj = Trajectory::for_model::<E5>(times.len());
            let mut x0 = [0.0; 4];
            E5.initial_state(&mut x0);
            let mut sim = Simulation::new(&E5, solver).unwrap();
            let mut best = Duration::MAX;
            let mut outcome = Ok(Stats::default());
            for _ in 0..3 {
                traj.clear();
                let started = Instant::now();
                outcome = sim.run(0.0, &x0, &times, &mut traj);
                best = best.min(started.elapsed());
            }
            let name = format!("{}{tag}", solver.name());
            match outcome {
                Ok(s) => println!(
                    "{name:<10} {rtol:>6.0e} {:>9.2e} {:>9.2e} {:>6} {:>9.0}",
                    e5_invariant(&traj),
                    scaled_error(sim.state(), &E5_REF, rtol, 1e-24),
                    s.accepted,
                    best.as_secs_f64() * 1e6
                ),
                Err(e) => println!("{name:<10} {rtol:>6.0e} failed: {e}"),
            }
        }
    }
}

fn rodas5p(rtol: f64, atol: f64) -> Solver {
    Solver::Rodas5P(Rodas5POptions {
        rtol,
        atol,
        ..Default::default()
    })
}

/// The counters in the order they are pinned.
fn counters(s: &Stats) -> [usize; 5] {
    [s.accepted, s.rejected, s.n_rhs, s.n_jac, s.n_lu]
}

/// Rodas5P on the Bari problems at the tolerances of `stiff_reference.rs`: every
/// component of the final state within `k (atol + rtol |ref|)` of the reference, and
/// the work counters pinned (a change of the algorithm must be deliberate). `k` is 1
/// except for HIRES, where the final error is 2.8 times the tolerance (measured; Radau5
/// misses it by more, 4.6–8.3x in issue 15's measurements): an error estimate controls
/// the local error of each step, not the global error that accumulates. Measured
/// scaled errors: ROBER 0.19, VDPOL 0.30, HIRES 2.8, OREGO 0.55, POLLU 0.024.
#[test]
fn rodas5p_on_the_bari_problems() {
    struct Case {
        name: &'static str,
        x: Vec<f64>,
        stats: Stats,
        reference: &'static [f64],
        rtol: f64,
        atol: f64,
        k: f64,
        pinned: [usize; 5],
    }
    let case = |name, (x, stats): (Vec<f64>, Stats), reference, rtol, atol, k, pinned| Case {
        name,
        x,
        stats,
        reference,
        rtol,
        atol,
        k,
        pinned,
    };
    let cases = [
        case(
            "robertson",
            solve(&Robertson, rodas5p(1e-6, 1e-14), 1e11),
            &ROBERTSON_REF[..],
            1e-6,
            1e-14,
            1.0,
            [280, 2, 2256, 280, 282],
        ),
        case(
            "van der pol",
            solve(&VanDerPol, rodas5p(1e-6, 1e-6), 2.0),
            &VDP_REF[..],
            1e-6,
            1e-6,
            1.0,
            [620, 13, 5053, 620, 633],
        ),
        case(
            "hires",
            solve(&Hires, rodas5p(1e-6, 1e-9), HIRES_T_END),
            &HIRES_REF[..],
            1e-6,
            1e-9,
            3.0,
            [155, 3, 1263, 155, 158],
        ),
        case(
            "oregonator",
            solve(&Oregonator, rodas5p(1e-6, 1e-6), 360.0),
            &OREGO_REF[..],
            1e-6,
            1e-6,
            1.0,
            [758, 9, 6129, 758, 767],
        ),
        case(
            "pollution",
            solve(&Pollution, rodas5p(1e-6, 1e-6), 60.0),
            &POLLU_REF[..],
            1e-6,
            1e-6,
            1.0,
            [20, 0, 162, 20, 20],
        ),
    ];
    for c in cases {
        let err = scaled_error(&c.x, c.reference, c.rtol, c.atol);
        assert!(err <= c.k, "{}: scaled error {err:e}, {:?}", c.name, c.x);
        assert_eq!(counters(&c.stats), c.pinned, "{}: {:?}", c.name, c.stats);
    }
}

/// E5's linear invariant `y2 - y3 - y4 = 0` through the run (sampled at `t = 10^(k/2)`),
/// relative to `y2`, which falls from 1e-10 to 9e-23: an absolute violation of 1e-22
/// made while `y2` is near 1e-10 (1e-12 of it, far inside the tolerance then) is as large
/// as `y2` at the end. Rodas5P's stages are single linear solves with
/// `1/(h γ) I - J`, whose rounding along the invariant grows like `h γ |J|` (1e7 in
/// E5's fast transient) and which nothing corrects (Radau5's Newton iteration sees the
/// violation in its residual and removes it). Measured at rtol 1e-8, atol 1e-24: plain
/// Rodas5P breaks the invariant by 8.5e6 `y2` (scaled end error 1.7e3); with
/// `refine_stages` (each solve refined once against a compensated residual) by
/// 7.1e-3 `y2`, with the end point within the tolerance (scaled error 0.38).
#[test]
fn e5_invariant_with_refined_rosenbrock_stages() {
    let (rtol, atol) = (1e-8, 1e-24);
    let refined = Solver::Rodas5P(Rodas5POptions {
        rtol,
        atol,
        refine_stages: true,
        ..Default::default()
    });
    let times = e5_times();
    let mut traj = Trajectory::for_model::<E5>(times.len());
    let mut sim = Simulation::new(&E5, refined).unwrap();
    let mut x0 = [0.0; 4];
    E5.initial_state(&mut x0);
    let stats = sim.run(0.0, &x0, &times, &mut traj).unwrap();
    let invariant = e5_invariant(&traj);
    assert!(invariant <= 2e-2, "|y2 - y3 - y4| / |y2| = {invariant:e}");
    let err = scaled_error(sim.state(), &E5_REF, rtol, atol);
    assert!(err <= 1.0, "scaled error {err:e}, {:?}", sim.state());
    // Pinned: a change of the algorithm must be deliberate.
    assert_eq!(counters(&stats), [1928, 7, 15475, 1928, 1935], "{stats:?}");
}

/// The Jacobian pattern of a chain of `NS / 2` masses (see [`chain!`]): row `r` may
/// depend on the six states from `clamp(2 (r / 2) - 2, 0, NS - 6)` (a superset of the
/// true pattern at the ends).
const fn chain_rows<const NS: usize>() -> [[usize; 6]; NS] {
    let mut rows = [[0; 6]; NS];
    let mut r = 0;
    while r < NS {
        let mut start = 2 * (r / 2);
        start = start.saturating_sub(2);
        if start > NS - 6 {
            start = NS - 6;
        }
        let mut k = 0;
        while k < 6 {
            rows[r][k] = start + k;
            k += 1;
        }
        r += 1;
    }
    rows
}

/// A chain of masses `m = 1` joined by stiffening springs `k (1 + d²) d` (`k = 1e4`)
/// and dampers `c = 1e3` (real eigenvalues down to about `-4 c / m`), the first tied to
/// a wall, the last driven by `sin t`; states `q_i, v_i` per mass. Sparse, with a
/// declared pattern: the kind of large model the stiff solvers are for.
macro_rules! chain {
    ($name:ident, $rows:ident, $refs:ident, $ns:expr) => {
        static $rows: [[usize; 6]; $ns] = chain_rows::<$ns>();
        const $refs: [&'static [usize]; $ns] = {
            let mut refs: [&'static [usize]; $ns] = [&[]; $ns];
            let mut r = 0;
            while r < $ns {
                refs[r] = &$rows[r];
                r += 1;
            }
            refs
        };
        struct $name;
        impl Model for $name {
            type Params = ();
            const NAME: &'static str = stringify!($name);
            const STATE_NAMES: &'static [&'static str] = &[""; $ns];
            const OUTPUT_NAMES: &'static [&'static str] = &[];
            const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&$refs);
            fn params(&self) -> &() {
                &()
            }
            fn initial_state(&self, x0: &mut [f64]) {
                x0.fill(0.0);
            }
            fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
                let c = T::from_f64;
                let masses = $ns / 2;
                // The force of the joint between mass i - 1 (the wall for i = 0) and i.
                let joint = |i: usize| {
                    let (q0, v0) = if i == 0 {
                        (c(0.0), c(0.0))
                    } else {
                        (x[2 * i - 2], x[2 * i - 1])
                    };
                    let d = x[2 * i] - q0;
                    c(1e4) * (c(1.0) + d * d) * d + c(1e3) * (x[2 * i + 1] - v0)
                };
                let mut left = joint(0);
                for i in 0..masses {
                    let right = if i + 1 < masses {
                        joint(i + 1)
                    } else {
                        c(t.sin())
                    };
                    dx[2 * i] = x[2 * i + 1];
                    dx[2 * i + 1] = right - left;
                    left = right;
                }
            }
            fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
        }
    };
}

chain!(Chain500, CHAIN_500_ROWS, CHAIN_500, 500);
chain!(Chain2000, CHAIN_2000_ROWS, CHAIN_2000, 2000);
chain!(Chain10000, CHAIN_10000_ROWS, CHAIN_10000, 10000);

fn chain_table<M: Model>(model: &M) {
    let tight = Solver::Radau5(Radau5Options {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    });
    let (reference, _) = solve(model, tight, 10.0);
    // The error relative to the largest |state| (most states are near zero).
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    header(&format!(
        "{} ({} states) to t = 10, atol = 1e-3 rtol",
        M::NAME,
        M::N_STATES
    ));
    for rtol in [1e-3, 1e-4, 1e-6] {
        for solver in methods(rtol, 1e-3 * rtol) {
            let scaled: Vec<f64> = reference.iter().map(|_| scale).collect();
            let mut x0 = vec![0.0; M::N_STATES];
            model.initial_state(&mut x0);
            let mut sim = Simulation::new(model, solver).unwrap();
            let mut wall = Duration::MAX;
            let mut s = Stats::default();
            for _ in 0..5 {
                let started = Instant::now();
                s = sim.run(0.0, &x0, &[10.0], &mut ()).unwrap();
                wall = wall.min(started.elapsed());
            }
            let err = sim
                .state()
                .iter()
                .zip(&reference)
                .zip(&scaled)
                .map(|((x, r), s)| (x - r).abs() / s)
                .fold(0.0, f64::max);
            println!(
                "{:<8} {:>6.0e} {:>6} {:>4} {:>7} {:>6} {:>6} {:>9.0} {:>9.2e} {:>6.1}",
                solver.name(),
                rtol,
                s.accepted,
                s.rejected,
                s.n_rhs + s.n_jac_rhs,
                s.n_jac,
                s.n_lu,
                wall.as_secs_f64() * 1e6,
                err,
                -err.log10()
            );
        }
    }
}

/// Radau5 against the Rosenbrock methods on large sparse chains: run with
/// `nice -n 10 cargo test --release -p bgdsl-runtime --test stiff_methods large -- --ignored --nocapture`
/// (best of five runs; the error is relative to the largest |state| of a Radau5 run at
/// rtol 1e-10).
#[test]
#[ignore = "prints a work-precision table on large models; run in release mode"]
fn large_chains() {
    chain_table(&Chain500);
    chain_table(&Chain2000);
    chain_table(&Chain10000);
}
