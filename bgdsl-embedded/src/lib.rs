//! A bond-graph model stepped without the standard library or a heap, as on a
//! microcontroller.
//!
//! This crate is `#![no_std]` and uses `bgdsl-runtime` without its `std` feature, so it
//! builds for targets that have only `core`, and it allocates nothing. It defines a DC
//! motor with [`bond_graph!`](bgdsl_runtime::bond_graph) ([`Motor`]), and
//! [`MotorDrive`], which holds the motor's time and state in arrays and integrates them
//! with the fixed-step RK4 of [`bgdsl_runtime::rk`] from one tick of a control loop to
//! the next, with the supply voltage and load torque the loop sets held over the tick.
//! It also defines a bouncing ball with events ([`BouncingBall`]: a `when` impact and
//! a `resting` mode), which [`BallDrop`] follows tick by tick with the adaptive
//! Dormand–Prince of [`bgdsl_runtime::rk`], impacts located and handled inside each
//! tick.
//!
//! ```
//! use bgdsl_embedded::{MotorDrive, MotorInputs, MotorParams, SUBSTEP};
//!
//! let mut drive = MotorDrive::new(MotorParams::default(), SUBSTEP)?;
//! let supply = MotorInputs { voltage: 12.0, load_torque: 0.0 };
//! // A 1 kHz loop, for 50 ms.
//! for _ in 0..50 {
//!     let outputs = drive.step(supply, 1e-3)?;
//!     // ... a controller would read `outputs.speed` here and set the next voltage.
//!     assert!(outputs.speed >= 0.0);
//! }
//! // Near the no-load speed, k V / (R b + k²).
//! assert!((drive.outputs().speed - 239.9).abs() < 1.0);
//! # Ok::<(), bgdsl_runtime::SolverError>(())
//! ```
#![no_std]
#![warn(missing_docs)]

mod ball;

pub use ball::{BallDrop, BallIntegrator, BouncingBall, BouncingBallParams, BouncingBallState};

use bgdsl_runtime::rk::Rk4;
use bgdsl_runtime::{bond_graph, FixedStep, Model, SolverError, WithInputs};

bond_graph! {
    /// A permanent-magnet DC motor on a supply voltage, against a load torque: its
    /// armature circuit (resistance and inductance), the gyrator of the motor constant,
    /// and a rotor with viscous friction.
    ///
    /// ```text
    ///   MSe supply ──⇀ 1 armature ──⇀ R winding, I coil
    ///                      │
    ///                      ⇂
    ///                   GY motor          τ = k_t i, back-EMF k_t ω
    ///                      │
    ///                      ⇂
    ///   MSe load ───⇀ 1 shaft ─────⇀ I rotor, R bearing
    /// ```
    ///
    /// States: `coil.p`, the flux linkage `L i` (Wb), and `rotor.p`, the angular
    /// momentum `J ω` (N·m·s). The model is linear: with the inputs held, the state
    /// relaxes to `ω = (k_t V − R τ_L) / (R b + k_t²)`, `i = (b ω + τ_L) / k_t` along two
    /// exponentials.
    pub model Motor {
        /// armature resistance R
        param resistance = 1.0 in "Ω";
        /// armature inductance L
        param inductance = 0.5e-3 in "H";
        /// torque constant k_t (equal to the back-EMF constant in V·s/rad)
        param torque_constant = 0.05 in "N·m/A";
        /// rotor inertia J
        param inertia = 1.0e-5 in "kg·m²";
        /// rotor viscous friction b
        param friction = 1.0e-6 in "N·m·s/rad";

        /// supply voltage, set by the controller
        input voltage = 0.0 in "V";
        /// load torque opposing the rotation
        input load_torque = 0.0 in "N·m";

        MSe supply = voltage;
        1  armature;
        R  winding = resistance;
        I  coil = inductance;
        GY motor = torque_constant;
        1  shaft;
        I  rotor = inertia;
        R  bearing = friction;
        MSe load = -load_torque;

        supply -> armature -> { winding, coil };
        armature -> motor -> shaft -> { rotor, bearing };
        load -> shaft;

        /// Rotor speed ω, rad/s.
        output speed = shaft.f;
        /// Armature current i, A.
        output current = armature.f;
    }
}

/// The RK4 step [`MotorDrive`] is meant to run with for the default parameters, s: a
/// tenth of the armature's electrical time constant `L / R` (0.5 ms), which keeps the
/// error of the start-up on 12 V below a millionth of the stall current and of the
/// no-load speed.
pub const SUBSTEP: f64 = 5e-5;

/// A [`Motor`] with its time, its state and a fixed-step integrator: what a control
/// loop on a microcontroller holds. All of it lives inline (a few hundred bytes), with
/// no heap.
#[derive(Clone, Debug)]
pub struct MotorDrive {
    motor: Motor,
    rk4: Rk4<{ Motor::N_STATES }>,
    t: f64,
    x: [f64; Motor::N_STATES],
}

impl MotorDrive {
    /// The motor with `params` in its declared initial state (at rest, no current) at
    /// `t = 0`, to be integrated in RK4 steps of `substep` seconds ([`SUBSTEP`] suits the
    /// default parameters). Fails if `substep` is not a finite positive number.
    pub fn new(params: MotorParams, substep: f64) -> Result<Self, SolverError> {
        let motor = Motor::new(params);
        let mut x = [0.0; Motor::N_STATES];
        motor.initial_state(&mut x);
        Ok(MotorDrive {
            motor,
            rk4: Rk4::new(FixedStep::new(substep))?,
            t: 0.0,
            x,
        })
    }

    /// The motor, with its parameters and the inputs of the last step.
    pub fn motor(&self) -> &Motor {
        &self.motor
    }

    /// The time reached, s.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The state at [`MotorDrive::time`], by name.
    pub fn state(&self) -> MotorState<f64> {
        MotorState::from_slice(&self.x)
    }

    /// Replaces the state (a measurement, or a saved state); the time stays.
    pub fn set_state(&mut self, state: MotorState<f64>) {
        state.write_to(&mut self.x);
    }

    /// The outputs at [`MotorDrive::time`] with the inputs of the last step.
    pub fn outputs(&self) -> MotorOutputs<f64> {
        let mut y = [0.0; Motor::N_OUTPUTS];
        self.motor.outputs(self.t, &self.x, &mut y);
        MotorOutputs::from_slice(&y)
    }

    /// Holds `inputs` for `dt` seconds: integrates from [`MotorDrive::time`] to
    /// `time() + dt` in RK4 steps of the drive's substep (the last one shortened to land
    /// on the end) and returns the outputs there.
    ///
    /// Fails if `dt` is negative or not finite, if the state becomes non-finite, or if
    /// the tick needs more than a million substeps; the drive then holds the last point
    /// it reached.
    pub fn step(&mut self, inputs: MotorInputs, dt: f64) -> Result<MotorOutputs<f64>, SolverError> {
        self.motor.set_inputs(inputs);
        let t_end = self.t + dt;
        self.rk4
            .advance_to(&self.motor, &mut self.t, &mut self.x, t_end)?;
        Ok(self.outputs())
    }
}

/// The panic handler of a bare-metal program, compiled only when `.ci/run` builds this
/// crate as a static library to prove that it does not need the standard library: were
/// `std` linked in by any dependency, its own panic handler would clash with this one.
#[cfg(bgdsl_no_std_check)]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {
        core::hint::spin_loop();
    }
}
