//! The DC motor under a discrete PI speed controller written in plain Rust: a 1 kHz
//! loop, a step of the speed set-point to 10 rad/s at 50 ms and a load-torque step from
//! 0.02 to 0.1 N·m at 0.6 s. Prints the response and what it measured.
//!
//! `cargo run --release -p models --example dc_servo_pi`

use bgdsl_runtime::Solver;
use models::dc_servo::{run_speed_loop, DcServo, SPEED_LOOP};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let setpoint = |t: f64| if t >= 0.05 { 10.0 } else { 0.0 };
    let load = |t: f64| if t >= 0.6 { 0.1 } else { 0.02 };
    let samples = run_speed_loop(
        DcServo::default(),
        Solver::stiff(),
        SPEED_LOOP,
        setpoint,
        load,
        1200,
    )?;
    println!(
        "{:>8} {:>10} {:>10} {:>10}",
        "t [s]", "ref", "speed", "voltage"
    );
    for s in samples.iter().step_by(50) {
        println!(
            "{:8.3} {:10.4} {:10.4} {:10.4}",
            s.t, s.setpoint, s.speed, s.voltage
        );
    }
    let peak = samples
        .iter()
        .filter(|s| s.t < 0.6)
        .map(|s| s.speed)
        .fold(f64::NEG_INFINITY, f64::max);
    let dip = samples
        .iter()
        .filter(|s| s.t >= 0.6)
        .map(|s| s.speed)
        .fold(f64::INFINITY, f64::min);
    let last = samples.last().map_or(f64::NAN, |s| s.speed);
    println!("overshoot {:.2} %", (peak / 10.0 - 1.0) * 100.0);
    println!("speed dip after the load step: {dip:.4} rad/s; final speed {last:.5} rad/s");
    Ok(())
}
