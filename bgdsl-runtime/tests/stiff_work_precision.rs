//! Work-precision data of the stiff methods on the Bari test-set problems (see
//! `stiff_common` for the problems and the sources of their reference values): the
//! Rust half of `docs/work-precision/run.sh`, which runs scipy and SUNDIALS on the same
//! problems and writes `docs/work-precision.md`. Not a check: run with
//!
//! ```sh
//! cargo test --release -p bgdsl-runtime --test stiff_work_precision -- --ignored --nocapture
//! ```
//!
//! For each problem, method and `rtol` in 1e-3…1e-10 (with `atol = c rtol`, `c` fixed
//! per problem, the same for every tool) it prints one tab-separated row starting with
//! `WP`: the work counters, the wall time (best of three runs) and the achieved
//! accuracy in two measures, defined in `docs/work-precision/problems.py` (and equal
//! there): the correct digits `-log10 max_i |x_i - ref_i| / (c + |ref_i|)` and the
//! factor `k = max_i |x_i - ref_i| / (atol + rtol |ref_i|)` by which the end point
//! misses (`k > 1`) or meets (`k <= 1`) the tolerance asked for.

// The published constants are quoted with all their digits, beyond what an f64 holds.
#![allow(clippy::excessive_precision)]

mod stiff_common;

use std::time::{Duration, Instant};

use bgdsl_runtime::{
    DormandPrinceOptions, Model, Radau5Options, Rodas4Options, Scalar, Simulation, Solver,
};
use stiff_common::*;

/// The tolerances of the table.
const RTOLS: [f64; 8] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

/// The stiff methods of the table at tolerances `rtol`, `atol`.
fn stiff(rtol: f64, atol: f64) -> Vec<Solver> {
    vec![
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
    ]
}

/// Dormand–Prince 5(4) at tolerances `rtol`, `atol`.
fn explicit(rtol: f64, atol: f64) -> Vec<Solver> {
    vec![Solver::DormandPrince(DormandPrinceOptions {
        rtol,
        atol,
        max_steps: 1_000_000,
        ..Default::default()
    })]
}

/// Prints the rows of `problem` (its name in the table), integrated to `t_end` with
/// `atol = c rtol` by the methods `methods` makes, against `reference`.
fn rows<M: Model>(
    problem: &str,
    model: &M,
    t_end: f64,
    reference: &[f64],
    c: f64,
    methods: fn(f64, f64) -> Vec<Solver>,
) {
    for rtol in RTOLS {
        let atol = c * rtol;
        for solver in methods(rtol, atol) {
            let mut x0 = vec![0.0; M::N_STATES];
            model.initial_state(&mut x0);
            let mut best = Duration::MAX;
            let mut sim = Simulation::new(model, solver).unwrap();
            let mut failed = None;
            for _ in 0..3 {
                let started = Instant::now();
                if let Err(e) = sim.run(0.0, &x0, &[t_end], &mut ()) {
                    failed = Some(e);
                    break;
                }
                best = best.min(started.elapsed());
            }
            let s = sim.stats();
            let (digits, k, status) = match failed {
                Some(e) => (
                    f64::NAN,
                    f64::NAN,
                    format!("failed: {e}").replace('\t', " "),
                ),
                None => {
                    let x = sim.state();
                    let mixed = x
                        .iter()
                        .zip(reference)
                        .map(|(x, r)| (x - r).abs() / (c + r.abs()))
                        .fold(0.0, f64::max);
                    let k = scaled_error(x, reference, rtol, atol);
                    (-mixed.log10(), k, "ok".to_owned())
                }
            };
            println!(
                "WP\t{problem}\tbgdsl\t{}\t{rtol:e}\t{atol:e}\t{}\t{}\t{}\t{}\t{}\t{:.6e}\t{digits:.3}\t{k:.3e}\t{status}",
                solver.name(),
                s.accepted,
                s.rejected,
                s.n_rhs,
                s.n_jac,
                s.n_lu,
                best.as_secs_f64(),
            );
        }
    }
}

#[test]
#[ignore = "prints work-precision rows for docs/work-precision/run.sh; run in release mode"]
fn work_precision_on_the_bari_test_set() {
    // The ratios `c = atol / rtol` are those of docs/work-precision/problems.py.
    rows("ROBER", &Robertson, 1e11, &ROBERTSON_REF, 1e-8, stiff);
    rows("VDPOL", &VanDerPol, 2.0, &VDP_REF, 1.0, stiff);
    rows("HIRES", &Hires, HIRES_T_END, &HIRES_REF, 1e-4, stiff);
    rows("OREGO", &Oregonator, 360.0, &OREGO_REF, 1.0, stiff);
    rows("POLLU", &Pollution, 60.0, &POLLU_REF, 1.0, stiff);
    rows("E5", &E5, E5_T_END, &E5_REF, 1e-24, stiff);
    // Not stiff: Dormand–Prince's tolerance against scipy's RK45 (the same method).
    rows(
        "AREN",
        &Arenstorf,
        ARENSTORF_PERIOD,
        &ARENSTORF_Y0,
        1.0,
        explicit,
    );
}

/// The Arenstorf orbit (HNW I, Sect. II.0, eq. (0.1)), as in `arenstorf.rs`: periodic
/// with period [`ARENSTORF_PERIOD`], so the reference at the end is the initial value.
struct Arenstorf;

const ARENSTORF_MU: f64 = 0.012277471;
const ARENSTORF_PERIOD: f64 = 17.0652165601579625588917206249;
const ARENSTORF_Y0: [f64; 4] = [0.994, 0.0, 0.0, -2.00158510637908252240537862224];

impl Model for Arenstorf {
    type Params = ();
    const NAME: &'static str = "arenstorf";
    const STATE_NAMES: &'static [&'static str] = &["y1", "y2", "v1", "v2"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&ARENSTORF_Y0);
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let mu = T::from_f64(ARENSTORF_MU);
        let mu1 = T::from_f64(1.0 - ARENSTORF_MU);
        let (y1, y2, v1, v2) = (x[0], x[1], x[2], x[3]);
        let r1 = (y1 + mu) * (y1 + mu) + y2 * y2;
        let r2 = (y1 - mu1) * (y1 - mu1) + y2 * y2;
        let d1 = r1 * r1.sqrt();
        let d2 = r2 * r2.sqrt();
        let two = T::from_f64(2.0);
        dx[0] = v1;
        dx[1] = v2;
        dx[2] = y1 + two * v2 - mu1 * (y1 + mu) / d1 - mu * (y1 - mu1) / d2;
        dx[3] = y2 - two * v1 - mu1 * y2 / d1 - mu * y2 / d2;
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}
