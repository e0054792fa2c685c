//! The DC motor of [`DcMotor`](crate::DcMotor) as a plant for a controller: its
//! supply voltage and its load torque are inputs a host sets between steps, and a
//! discrete PI speed controller in plain Rust ([`PiController`]) closes the loop.

use bgdsl_runtime::bond_graph;

use crate::control::PiController;

bond_graph! {
    /// A permanent-magnet DC motor driving a compliant, geared, inertial load (the bond
    /// graph of [`DcMotor`](crate::DcMotor)), with the supply voltage and the load
    /// torque as inputs.
    ///
    /// States: `coil.p` (flux linkage, Wb), `rotor.p` (N·m·s), `shaft_spring.q`
    /// (twist, rad), `load.p` (N·m·s).
    pub model DcServo {
        /// armature resistance R_a
        param resistance = 1.0 in "Ω";
        /// armature inductance L_a
        param inductance = 0.5e-3 in "H";
        /// torque constant k_t (equal to the back-EMF constant)
        param torque_constant = 0.05 in "N·m/A";
        /// rotor inertia J_m
        param rotor_inertia = 1.0e-5 in "kg·m²";
        /// rotor viscous friction b_m
        param rotor_friction = 1.0e-6 in "N·m·s/rad";
        /// gear reduction N, motor turns per load turn
        param gear_ratio = 10.0 in "1";
        /// output-shaft torsional stiffness k_s
        param shaft_stiffness = 50.0 in "N·m/rad";
        /// output-shaft internal damping c_s
        param shaft_damping = 0.02 in "N·m·s/rad";
        /// load inertia J_l
        param load_inertia = 1.0e-3 in "kg·m²";
        /// load viscous friction b_l
        param load_friction = 1.0e-4 in "N·m·s/rad";

        /// supply voltage, from the controller
        input voltage = 6.0 in "V";
        /// load torque opposing the rotation, the disturbance
        input load_torque = 0.0 in "N·m";

        MSe supply = voltage;
        1  armature;
        R  winding = resistance;
        I  coil = inductance, p in "Wb";
        GY motor = torque_constant;
        1  shaft;
        I  rotor = rotor_inertia, p in "N·m·s";
        R  bearing = rotor_friction;
        TF gear = 1.0 / gear_ratio;
        0  coupling;
        1  twist;
        C  shaft_spring = shaft_stiffness, q in "rad";
        R  shaft_damper = shaft_damping;
        1  load_side;
        I  load = load_inertia, p in "N·m·s";
        R  drag = load_friction;
        MSe brake = -load_torque;

        supply -> armature -> { winding, coil };
        armature -> motor -> shaft -> { rotor, bearing };
        shaft -> gear -> coupling -> twist -> { shaft_spring, shaft_damper };
        coupling -> load_side -> { load, drag };
        brake -> load_side;

        /// Load speed ω_l, rad/s.
        output load_speed = load_side.f in "rad/s";
        /// Armature current, A.
        output current = armature.f in "A";
        /// Torque in the output shaft, N·m.
        output shaft_torque = coupling.e in "N·m";
    }
}

/// The speed loop of the example and its test: a 1 kHz PI controller on the load speed,
/// with PI gains chosen for a well-damped response of the default [`DcServo`]: no
/// overshoot, within 0.3 % of a set-point step after 0.3 s (higher gains excite the
/// 36 Hz shaft resonance).
pub const SPEED_LOOP: PiController = PiController::with_gains(0.3, 10.0, 1e-3);

/// One sample of the closed loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopSample {
    /// Time, s.
    pub t: f64,
    /// Speed set-point, rad/s.
    pub setpoint: f64,
    /// Measured load speed, rad/s.
    pub speed: f64,
    /// Voltage commanded for the next period, V.
    pub voltage: f64,
    /// Load torque during the next period, N·m.
    pub load_torque: f64,
}

/// Runs `servo` under `controller` from rest for `periods` sampling periods: at each
/// sample the load speed is measured, the controller computes the voltage, and the
/// plant is advanced one period with the voltage and `load_torque(t)` held. Returns
/// every sample (`periods + 1` of them).
///
/// # Errors
///
/// The solver fails.
pub fn run_speed_loop(
    servo: DcServo,
    solver: bgdsl_runtime::Solver,
    mut controller: PiController,
    setpoint: impl Fn(f64) -> f64,
    load_torque: impl Fn(f64) -> f64,
    periods: usize,
) -> Result<Vec<LoopSample>, bgdsl_runtime::SolverError> {
    let mut stepper = bgdsl_runtime::Stepper::new(servo, solver)?;
    let mut samples = Vec::with_capacity(periods + 1);
    let mut speed = stepper.outputs()[0];
    for k in 0..=periods {
        let t = k as f64 * controller.period;
        let reference = setpoint(t);
        let voltage = controller.update(reference, speed);
        let torque = load_torque(t);
        samples.push(LoopSample {
            t,
            setpoint: reference,
            speed,
            voltage,
            load_torque: torque,
        });
        if k < periods {
            let inputs = DcServoInputs {
                voltage,
                load_torque: torque,
            };
            speed = stepper.advance_with(t + controller.period, inputs)?[0];
        }
    }
    Ok(samples)
}
