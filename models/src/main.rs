//! `cargo run --release`: the quarter car driving over a speed bump (the default
//! scenario of [`models::QuarterCar`]), written to `out/quarter_car/quarter_car.csv`.

use std::error::Error;
use std::time::Instant;

use bgdsl_runtime::{DormandPrinceOptions, Model, Simulation, Solver, Trajectory};
use models::QuarterCar;

const OUT_DIR: &str = "out/quarter_car";
const T_END: f64 = 5.0;
const SAMPLES: usize = 2001;
const RTOL: f64 = 1e-8;

fn main() -> Result<(), Box<dyn Error>> {
    let model = QuarterCar::default();
    let options = DormandPrinceOptions {
        rtol: RTOL,
        atol: 1e-10,
        ..Default::default()
    };
    let mut x0 = [0.0; QuarterCar::N_STATES];
    model.initial_state(&mut x0);
    let mut trajectory = Trajectory::for_model::<QuarterCar>(SAMPLES);

    let started = Instant::now();
    let mut sim = Simulation::new(&model, Solver::DormandPrince(options))?;
    let stats = sim.run_uniform(0.0, &x0, T_END, SAMPLES, &mut trajectory)?;
    let wall = started.elapsed();

    std::fs::create_dir_all(OUT_DIR)?;
    let path = format!("{OUT_DIR}/quarter_car.csv");
    trajectory.write_csv(&path)?;

    let range = |name| {
        let column = trajectory.column(name).expect("a declared output");
        column
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    };
    let (accel_lo, accel_hi) = range("body_acceleration");
    let (travel_lo, travel_hi) = range("suspension_travel");
    let (tyre_lo, _) = range("tyre_force");
    let p = &model.params;
    let name = QuarterCar::NAME;
    println!(
        "model        {name}, a {:.0} mm bump at {:.0} km/h",
        p.bump_height * 1e3,
        p.speed * 3.6
    );
    println!(
        "solver       {} (rtol {RTOL:e}), 0 to {T_END} s",
        sim.solver().name()
    );
    println!(
        "steps        {} accepted, {} rejected",
        stats.accepted, stats.rejected
    );
    println!("evaluations  {}", stats.n_rhs);
    println!("wall time    {:.3} ms", wall.as_secs_f64() * 1e3);
    println!(
        "body         peak acceleration {:.2} m/s²",
        accel_hi.max(-accel_lo)
    );
    println!(
        "suspension   travel {:+.1} mm (bump) to {:+.1} mm (rebound)",
        travel_hi * 1e3,
        travel_lo * 1e3
    );
    let lift_off = if tyre_lo < 0.0 {
        ": the wheel would leave the road"
    } else {
        ""
    };
    println!("tyre         smallest contact force {tyre_lo:.0} N{lift_off}");
    println!("wrote        {path} ({} samples)", trajectory.len());
    Ok(())
}
