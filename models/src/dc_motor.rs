//! A permanent-magnet DC motor driving an inertial load through a gearbox.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A permanent-magnet DC motor on a constant supply voltage, driving an inertial,
    /// viscously damped load through a reduction gearbox and a compliant output shaft,
    /// against a constant load torque.
    ///
    /// ```text
    ///   Se supply
    ///       │
    ///       ⇂
    ///   1 armature ───⇀ R winding          armature resistance R_a
    ///       │      ───⇀ I coil             armature inductance L_a
    ///       ⇂
    ///   GY motor                           torque constant k_t: τ = k_t i, u = k_t ω_m
    ///       │
    ///       ⇂
    ///   1 shaft ──────⇀ I rotor            rotor inertia J_m
    ///       │   ──────⇀ R bearing          rotor viscous friction b_m
    ///       ⇂
    ///   TF gear                            modulus 1/N: ω_out = ω_m / N, τ_m = τ_out / N
    ///       │
    ///       ⇂
    ///   0 coupling ───⇀ 1 twist ───⇀ C shaft_spring   output-shaft stiffness k_s
    ///       │                 ───⇀ R shaft_damper   its internal damping c_s
    ///       ⇂
    ///   1 load_side ──⇀ I load             load inertia J_l
    ///       ↿       ──⇀ R drag             load viscous friction b_l
    ///       │
    ///   Se brake                           load torque τ_L (effort −τ_L: it opposes ω_l)
    /// ```
    ///
    /// Effort is voltage on the electrical side and torque on the mechanical side; flow
    /// is current and angular velocity. Causal strokes (SCAP): at `armature` for the
    /// bonds from `supply`, to `winding` and to `motor`; at `coil`, `rotor` and `load`
    /// (integral causality); at `shaft` for the bonds from `motor`, to `bearing` and to
    /// `gear`; at `gear` for the bond to `coupling`; at `coupling` for the bond to
    /// `twist`; at `twist` for `shaft_spring` (integral) and `shaft_damper`; at
    /// `load_side` for the bonds from `coupling` and `brake` and to `drag`.
    ///
    /// The output shaft is compliant on purpose: a rigid gearbox between two inertias
    /// ties their velocities together, which forces one of them into derivative
    /// causality (`bond_graph!` rejects that). A stiff spring with a little damping is
    /// also the physics of a real gear train and shaft.
    ///
    /// States: `coil.p` (flux linkage `L_a i`, Wb), `rotor.p` (angular momentum
    /// `J_m ω_m`, N·m·s), `shaft_spring.q` (shaft twist, rad), `load.p` (angular
    /// momentum `J_l ω_l`, N·m·s).
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `voltage` | supply voltage | V |
    /// | `resistance` | armature resistance R_a | Ω |
    /// | `inductance` | armature inductance L_a | H |
    /// | `torque_constant` | torque constant k_t (= back-EMF constant) | N·m/A = V·s/rad |
    /// | `rotor_inertia` | rotor inertia J_m | kg·m² |
    /// | `rotor_friction` | rotor viscous friction b_m | N·m·s/rad |
    /// | `gear_ratio` | reduction N (motor turns per load turn) | – |
    /// | `shaft_stiffness` | output-shaft torsional stiffness k_s | N·m/rad |
    /// | `shaft_damping` | output-shaft internal damping c_s | N·m·s/rad |
    /// | `load_inertia` | load inertia J_l | kg·m² |
    /// | `load_friction` | load viscous friction b_l | N·m·s/rad |
    /// | `load_torque` | constant load torque τ_L | N·m |
    ///
    /// In steady state (all accelerations zero), with `b = b_m + b_l / N²`:
    /// `ω_m = (k_t V − R_a τ_L / N) / (R_a b + k_t²)`, `i = (b ω_m + τ_L / N) / k_t`.
    pub model DcMotor {
        /// supply voltage
        param voltage = 12.0 in "V";
        /// armature resistance
        param resistance = 1.0 in "Ω";
        /// armature inductance
        param inductance = 0.5e-3 in "H";
        /// torque constant (equal to the back-EMF constant in V·s/rad)
        param torque_constant = 0.05 in "N·m/A";
        /// rotor inertia
        param rotor_inertia = 1.0e-5 in "kg·m²";
        /// rotor viscous friction
        param rotor_friction = 1.0e-6 in "N·m·s/rad";
        /// gear reduction, motor turns per load turn
        param gear_ratio = 10.0 in "1";
        /// output-shaft torsional stiffness
        param shaft_stiffness = 50.0 in "N·m/rad";
        /// output-shaft internal damping
        param shaft_damping = 0.02 in "N·m·s/rad";
        /// load inertia
        param load_inertia = 1.0e-3 in "kg·m²";
        /// load viscous friction
        param load_friction = 1.0e-4 in "N·m·s/rad";
        /// constant load torque opposing the rotation
        param load_torque = 0.05 in "N·m";

        Se supply = voltage;
        1  armature;                               // the armature current
        R  winding = resistance;                   // u = R_a i
        I  coil = inductance, p in "Wb";           // i = λ / L_a
        GY motor = torque_constant;                // u = k_t ω_m, τ = k_t i
        1  shaft;                                  // the motor speed
        I  rotor = rotor_inertia, p in "N·m·s";
        R  bearing = rotor_friction;
        TF gear = 1.0 / gear_ratio;                // ω_out = ω_m / N
        0  coupling;                               // the torque in the output shaft
        1  twist;                                  // the shaft's twist rate
        C  shaft_spring = shaft_stiffness, q in "rad";
        R  shaft_damper = shaft_damping;
        1  load_side;                              // the load speed
        I  load = load_inertia, p in "N·m·s";
        R  drag = load_friction;
        Se brake = -load_torque;

        supply -> armature -> { winding, coil };
        armature -> motor -> shaft -> { rotor, bearing };
        shaft -> gear -> coupling -> twist -> { shaft_spring, shaft_damper };
        coupling -> load_side -> { load, drag };
        brake -> load_side;

        /// Armature current, A.
        output current = armature.f in "A";
        /// Motor speed ω_m, rad/s.
        output motor_speed = shaft.f in "rad/s";
        /// Load speed ω_l, rad/s.
        output load_speed = load_side.f in "rad/s";
        /// Electromagnetic torque k_t i, N·m.
        output motor_torque = motor.e2 in "N·m";
        /// Back-EMF k_t ω_m, V.
        output back_emf = motor.e1 in "V";
        /// Torque in the output shaft, N·m.
        output shaft_torque = coupling.e in "N·m";
        /// Electrical power drawn from the supply, W.
        output electrical_power = supply.e * supply.f in "W";
        /// Mechanical power delivered to the load torque, W.
        output load_power = -(brake.e * brake.f) in "W";
        /// Power dissipated in the winding, the bearing, the shaft and the load friction, W.
        output dissipated_power = winding.e * winding.f
            + bearing.e * bearing.f
            + shaft_damper.e * shaft_damper.f
            + drag.e * drag.f in "W";
        /// Stored energy, J: magnetic, kinetic (rotor and load) and elastic (shaft).
        output energy = 0.5 * coil.p * coil.p / inductance
            + 0.5 * rotor.p * rotor.p / rotor_inertia
            + 0.5 * shaft_stiffness * shaft_spring.q * shaft_spring.q
            + 0.5 * load.p * load.p / load_inertia in "J";
    }
}
