//! Controllers written in plain Rust, for the examples that drive models from a host
//! loop (a `Stepper` advanced one sampling period at a time).

/// A discrete PI controller: `u_k = K_p e_k + K_i T Σ_{j ≤ k} e_j` with `e = r − y`,
/// sampled every `T` and held in between (what a microcontroller's control loop does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PiController {
    /// Proportional gain, output units per error unit.
    pub kp: f64,
    /// Integral gain, output units per error unit per second.
    pub ki: f64,
    /// Sampling period, s.
    pub period: f64,
    /// The integral so far: `T Σ e`.
    integral: f64,
}

impl PiController {
    /// A controller with the given gains and period, its integral at zero.
    pub const fn with_gains(kp: f64, ki: f64, period: f64) -> Self {
        PiController {
            kp,
            ki,
            period,
            integral: 0.0,
        }
    }

    /// One sample: the command for the error `setpoint − measured`.
    pub fn update(&mut self, setpoint: f64, measured: f64) -> f64 {
        let error = setpoint - measured;
        self.integral += self.period * error;
        self.kp * error + self.ki * self.integral
    }
}
