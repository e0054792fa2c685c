//! The quick return mechanism with its crank driven by a motor torque that a 1 kHz
//! controller in plain Rust sets to hold 5 rad/s, the speed the spec's speed source
//! imposes: the rigid mechanism's torque at the measured angle as feedforward, and a
//! PI on the speed error. Prints the torque the motor needs and how well the speed is
//! held over the settled part of the run (2.5–5 s).
//!
//! `cargo run --release -p models --example quick_return_speed_control`

use models::quick_return::torque_driven::{hold_speed, QuickReturnTorque};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let run = hold_speed(QuickReturnTorque::default(), 5.0, 5.0)?;
    println!("crank speed held at 5 rad/s by a 1 kHz feedforward + PI torque controller, 2.5–5 s:");
    println!(
        "  speed: min {:.4}, max {:.4} rad/s",
        run.speed_min, run.speed_max
    );
    println!(
        "  motor torque: peak {:.4} N·m, mean {:.4} N·m, RMS {:.4} N·m",
        run.torque_peak, run.torque_mean, run.torque_rms
    );
    println!(
        "  energy over the window: motor {:.4} J, dissipated {:.4} J, stored change {:.4} J",
        run.motor_energy, run.dissipated_energy, run.stored_change
    );
    Ok(())
}
