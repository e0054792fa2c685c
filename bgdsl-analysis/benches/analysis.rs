//! The cost of the analyses (issue 16, "Speed"), each beside the plain simulation of
//! the same model and one `f64` evaluation of its right-hand side, measured in the same
//! run as thread CPU time (criterion's numbers below are CPU seconds, not wall time:
//! the machine is shared).
//!
//! The flagship (`QuickReturn`, 117 states):
//! - `derivatives_f64`: one `f64` evaluation of the right-hand side (the anchor);
//! - `simulate_0_5s`: the plain 0–5 s run (Radau5, the catalogue's defaults: rtol 1e-6,
//!   5001 samples);
//! - `linearize`: A, B, C, D exact at the initial state, B and D from three
//!   parameters (the drive speed and two joint stiffnesses), without the modes;
//! - `modes`: the eigenvalues, eigenvectors and participation factors of that A;
//! - `bode_200`: a 200-point frequency response (drive speed to the output slider's
//!   x-position) from that linear model: one Hessenberg reduction, 200 solves;
//! - `sensitivity_14`: one forward-sensitivity run, the 14 parameters of
//!   `tests/sensitivity_quick_return.rs` (link masses, joint stiffnesses) over its
//!   0–2.514 s on a 2 ms grid, Radau5 at rtol 1e-9 and 10 SDIRK substeps per interval;
//! - `simulate_sensitivity_span`: the plain run with the same solver, span and grid (the
//!   fair anchor of `sensitivity_14`);
//! - `forcing_workspace`, `forcing_fresh`: the forcing `∂f/∂p` (14 parameters) of one
//!   SDIRK stage of that run, as evaluated now (`ParameterDerivatives::df_dp`: a
//!   reused workspace, `∂f/∂p` alone) and as before (`parameter_partials`: fresh
//!   buffers, `∂f/∂p` and `∂g/∂p`).
//!
//! The DC motor (5 states): the same anchor, its plain 0–0.5 s run, and a sensitivity
//! run to all its parameter values over 0–0.5 s on a 1 ms grid beside the plain run
//! with the same solver and grid.
//!
//! The forced oscillator of `tests/periodic_oscillator.rs` (2 states): its periodic
//! orbit (shooting, monodromy, Floquet multipliers) beside the plain run over one
//! period with the same solver.
//!
//! The quick return's periodic variant (`k3c_point_under_slider = 1`, as in
//! `tests/periodic_quick_return.rs`: two periods of warm-up, 400 SDIRK steps per
//! period): one periodic-orbit search takes tens of seconds, too long for criterion's
//! ten samples, so it is timed once (thread CPU time) before criterion runs, beside the
//! plain run over as many periods as the search integrated; the table is printed
//! first. Its accuracy is being fixed (issue 16): the number will move.
//!
//! ```sh
//! cargo bench -p bgdsl-analysis --bench analysis
//! ```
//!
//! (about five minutes on two shared cores, two and a half of CPU;
//! `ANALYSIS_TABLE_ONLY=1` prints the periodic orbit's table alone,
//! `ANALYSIS_SKIP_TABLE=1` skips it). The ratios are in `docs/analysis.md`, "Speed".

use std::hint::black_box;
use std::time::Duration;

use bgdsl_analysis::periodic::{periodic_orbit, PeriodicOptions};
use bgdsl_analysis::sensitivity::{
    forward_sensitivities, parameter_index, ParameterDerivatives, SensitivityOptions,
};
use bgdsl_analysis::{bode::Sweep, linearize, log_grid, modes, parameter_partials, Channel};
use bgdsl_runtime::{simulate, FromParams, Model, Radau5Options, Scalar, Simulation, Solver};
use criterion::{BenchmarkGroup, Criterion};
use models::quick_return::{QuickReturn, QuickReturnParams};
use models::DcMotor;
use nalgebra::DMatrix;

/// This thread's CPU time.
fn cpu_now() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant of libc.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// Benchmarks `f` in `group` as `name`, in thread CPU time.
fn bench_cpu<M, R>(group: &mut BenchmarkGroup<'_, M>, name: &str, mut f: impl FnMut() -> R)
where
    M: criterion::measurement::Measurement<Value = Duration>,
{
    group.bench_function(name, |b| {
        b.iter_custom(|iters| {
            let start = cpu_now();
            for _ in 0..iters {
                black_box(f());
            }
            cpu_now() - start
        })
    });
}

/// The solver of the sensitivity runs and of their anchors.
fn tight() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-9,
        atol: 1e-11,
        ..Default::default()
    })
}

/// A plain run of `model` from its initial state through `times` with `solver`.
fn plain_run<M: Model>(model: &M, solver: Solver, times: &[f64]) -> usize {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, solver).expect("the solver sets up");
    sim.run(times[0], &x0, times, &mut ())
        .expect("the model runs")
        .accepted
}

fn flagship(c: &mut Criterion) {
    let model = QuickReturn::default();
    let mut x = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x);
    let channels: Vec<Channel> = ["w_drive", "K01", "K34"]
        .iter()
        .map(|name| Channel::named::<QuickReturn>(name).expect("a parameter of the flagship"))
        .collect();
    let mut group = c.benchmark_group("flagship");
    let mut dx = vec![0.0; QuickReturn::N_STATES];
    bench_cpu(&mut group, "derivatives_f64", || {
        model.derivatives(0.0, black_box(&x), black_box(&mut dx[..]))
    });
    group.sample_size(10);
    bench_cpu(&mut group, "simulate_0_5s", || {
        let solver = Solver::Radau5(Radau5Options::default());
        simulate(&model, solver, 0.0, 5.0, 5001).expect("the flagship runs")
    });
    group.sample_size(20);
    bench_cpu(&mut group, "linearize", || {
        linearize(&model, 0.0, black_box(&x), &channels).expect("linearises")
    });
    let linear = linearize(&model, 0.0, &x, &channels).expect("linearises");
    bench_cpu(&mut group, "modes", || modes(black_box(&linear.a)));
    let output = linear
        .output_index("r_C5_x")
        .expect("the output slider's x-position is an output");
    let omega = log_grid(0.1, 1e4, 200);
    bench_cpu(&mut group, "bode_200", || {
        let sweep = Sweep::new(&linear, 0, output);
        omega
            .iter()
            .map(|&w| sweep.at(w))
            .fold(0.0, |s, h| s + h.norm())
    });
    group.sample_size(10);
    let which: Vec<usize> = [
        "m1", "m2", "m3", "m4", "m5", "K01", "K12", "K03", "K3C[1]", "K23r", "K_C", "K34", "K45",
        "K5C[1]",
    ]
    .iter()
    .map(|n| parameter_index::<QuickReturn>(n).expect("a flagship parameter"))
    .collect();
    let times: Vec<f64> = (0..=1257).map(|k| 2e-3 * k as f64).collect();
    let options = SensitivityOptions {
        solver: tight(),
        ..Default::default()
    };
    bench_cpu(&mut group, "sensitivity_14", || {
        forward_sensitivities(&model, None, &which, &times, &options).expect("runs")
    });
    bench_cpu(&mut group, "simulate_sensitivity_span", || {
        plain_run(&model, tight(), &times)
    });
    // The forcing ∂f/∂p of one SDIRK stage, 14 parameters: as the sensitivity run now
    // evaluates it (a workspace, ∂f/∂p alone) and as it did before (a fresh evaluation
    // of ∂f/∂p and ∂g/∂p, allocating its buffers).
    group.sample_size(50);
    let mut derivatives = ParameterDerivatives::new(&model, &which).expect("valid indices");
    let mut forcing = DMatrix::zeros(QuickReturn::N_STATES, which.len());
    bench_cpu(&mut group, "forcing_workspace", || {
        derivatives.df_dp(0.0, black_box(&x), &mut forcing)
    });
    bench_cpu(&mut group, "forcing_fresh", || {
        parameter_partials(&model, 0.0, black_box(&x), &which).expect("partials")
    });
    group.finish();
}

fn dc_motor(c: &mut Criterion) {
    let model = DcMotor::default();
    let mut x = vec![0.0; DcMotor::N_STATES];
    model.initial_state(&mut x);
    let mut group = c.benchmark_group("dc_motor");
    let mut dx = [0.0; DcMotor::N_STATES];
    bench_cpu(&mut group, "derivatives_f64", || {
        model.derivatives(0.0, black_box(&x), black_box(&mut dx[..]))
    });
    group.sample_size(20);
    let times: Vec<f64> = (0..=500).map(|k| 1e-3 * k as f64).collect();
    bench_cpu(&mut group, "simulate_0_0.5s", || {
        plain_run(&model, model.default_solver(), &times)
    });
    let which: Vec<usize> = (0..DcMotor::N_PARAMETER_VALUES).collect();
    let options = SensitivityOptions {
        solver: tight(),
        ..Default::default()
    };
    bench_cpu(&mut group, "sensitivity_all", || {
        forward_sensitivities(&model, None, &which, &times, &options).expect("runs")
    });
    bench_cpu(&mut group, "simulate_sensitivity_span", || {
        plain_run(&model, tight(), &times)
    });
    group.finish();
}

const M: f64 = 1.0;
const C: f64 = 0.4;
const K: f64 = 4.0;
const W: f64 = 1.5;

/// `m x'' + c x' + k x = sin(ω t)` (`tests/periodic_oscillator.rs`'s model).
#[derive(Default)]
struct Forced;

impl Model for Forced {
    type Params = ();
    const NAME: &'static str = "forced";
    const STATE_NAMES: &'static [&'static str] = &["x", "v"];
    const OUTPUT_NAMES: &'static [&'static str] = &["x"];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0)
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[1];
        dx[1] = (T::from_f64((W * t).sin()) - T::from_f64(C) * x[1] - T::from_f64(K) * x[0])
            / T::from_f64(M);
    }
    fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
        y[0] = x[0]
    }
}

fn oscillator(c: &mut Criterion) {
    let period = core::f64::consts::TAU / W;
    let mut options = PeriodicOptions::new(period);
    options.tolerance = 1e-9;
    let mut group = c.benchmark_group("forced_oscillator");
    let x = [0.1, 0.2];
    let mut dx = [0.0; 2];
    bench_cpu(&mut group, "derivatives_f64", || {
        Forced.derivatives(0.3, black_box(&x), black_box(&mut dx[..]))
    });
    group.sample_size(20);
    bench_cpu(&mut group, "simulate_one_period", || {
        plain_run(&Forced, options.solver, &[0.0, period])
    });
    bench_cpu(&mut group, "periodic_orbit", || {
        periodic_orbit(&Forced, &[0.0, 0.0], &[], &options).expect("an orbit")
    });
    group.finish();
}

/// The quick return's periodic orbit, timed once, beside its plain run over as many
/// periods and one right-hand side.
fn quick_return_orbit_table() {
    let model = QuickReturn::from_params(QuickReturnParams {
        k3c_point_under_slider: 1.0,
        ..Default::default()
    });
    let period = core::f64::consts::TAU / model.params().w_drive;
    let mut x0 = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x0);
    let mut options = PeriodicOptions::new(period);
    options.warmup_periods = 2;
    let mut dx = vec![0.0; QuickReturn::N_STATES];
    let evaluations = 20_000;
    let start = cpu_now();
    for _ in 0..evaluations {
        model.derivatives(0.0, black_box(&x0), black_box(&mut dx[..]));
    }
    let rhs = (cpu_now() - start).as_secs_f64() / evaluations as f64;
    let start = cpu_now();
    let orbit = periodic_orbit(&model, &x0, &[], &options);
    let search = (cpu_now() - start).as_secs_f64();
    let periods = match &orbit {
        Ok(orbit) => orbit.periods_integrated,
        Err(e) => {
            println!("quick return periodic orbit: failed after {search:.2} s CPU: {e:?}");
            return;
        }
    };
    let times: Vec<f64> = (0..=periods).map(|k| k as f64 * period).collect();
    let mut plain = f64::INFINITY;
    for _ in 0..3 {
        let start = cpu_now();
        black_box(plain_run(&model, options.solver, &times));
        plain = plain.min((cpu_now() - start).as_secs_f64());
    }
    let one_period = plain / periods as f64;
    let orbit = orbit.expect("checked above");
    println!(
        "\n| quick return periodic orbit | CPU s | / plain run over {periods} periods | / plain run over one period | / RHS |\n|---|---:|---:|---:|---:|"
    );
    println!(
        "| search ({} Newton iterations, {periods} periods integrated, {} multipliers) | {search:.2} | {:.1} | {:.0} | {:.2e} |",
        orbit.iterations,
        orbit.multipliers.len(),
        search / plain,
        search / one_period,
        search / rhs,
    );
    println!(
        "| plain run over {periods} periods (Radau5, rtol 1e-9; best of 3) | {plain:.3} | 1 | {periods} | {:.2e} |",
        plain / rhs
    );
    println!("| one f64 right-hand side (mean of {evaluations}) | {rhs:.2e} | | | 1 |\n");
}

fn main() {
    if std::env::var_os("ANALYSIS_SKIP_TABLE").is_none() {
        quick_return_orbit_table();
    }
    if std::env::var_os("ANALYSIS_TABLE_ONLY").is_some() {
        return;
    }
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    flagship(&mut c);
    dc_motor(&mut c);
    oscillator(&mut c);
    c.final_summary();
}
