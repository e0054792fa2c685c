//! The quick return's periodic orbit (the periodic variant, 2 warm-up periods, the
//! defaults otherwise) against its anchor, a plain run of 20 periods at the same
//! solver, in the same process: wall time, best of `N` (argument, default 3), and the
//! ratio. `cargo run --release -p bgdsl-analysis --example periodic_cost -- 3`.

use std::time::Instant;

use bgdsl_analysis::periodic::{periodic_orbit, PeriodicOptions};
use bgdsl_runtime::{FromParams, Model, Simulation};
use models::quick_return::{QuickReturn, QuickReturnParams};

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .map_or(3, |a| a.parse().expect("a number of repeats"));
    let model = QuickReturn::from_params(QuickReturnParams {
        k3c_point_under_slider: 1.0,
        ..Default::default()
    });
    let period = core::f64::consts::TAU / model.params().w_drive;
    let mut x0 = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x0);
    let mut options = PeriodicOptions::new(period);
    options.warmup_periods = 2;
    let (mut orbit_best, mut run_best) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..repeats {
        let start = Instant::now();
        let orbit = periodic_orbit(&model, &x0, &[], &options).expect("an orbit");
        orbit_best = orbit_best.min(start.elapsed().as_secs_f64());
        let start = Instant::now();
        let mut sim = Simulation::new(&model, options.solver).expect("a simulation");
        let mut last = 0.0;
        sim.run(
            0.0,
            &x0,
            &[20.0 * period],
            &mut |_t: f64, x: &[f64], _y: &[f64]| last = x[0],
        )
        .expect("a run");
        run_best = run_best.min(start.elapsed().as_secs_f64());
        assert!(last.is_finite() && orbit.iterations < options.max_iterations);
    }
    println!(
        "orbit {orbit_best:.3} s, 20 plain periods {run_best:.3} s, ratio {:.2}",
        orbit_best / run_best
    );
}
