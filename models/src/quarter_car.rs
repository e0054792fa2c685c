//! The quarter-car model of a vehicle suspension.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// One corner of a car: the sprung mass (a quarter of the body) on the suspension
    /// spring and damper, the unsprung mass (wheel, hub, brake) on the tyre, driven by
    /// the vertical velocity of the road under the tyre, with gravity.
    ///
    /// ```text
    ///   Sf road                                  road velocity ż_r (the input)
    ///      │
    ///      ⇂
    ///   0 contact ───⇀ C tyre                    tyre stiffness k_t
    ///      │
    ///      ⇂
    ///   1 wheel ─────⇀ I unsprung                unsprung mass m_u
    ///      │   ↼──── Se wheel_weight             its weight −m_u g
    ///      ⇂
    ///   0 strut ─────⇀ 1 deflection ───⇀ C spring    suspension stiffness k_s
    ///      │                       ───⇀ R damper    suspension damping c_s
    ///      ⇂
    ///   1 body ──────⇀ I sprung                  sprung mass m_s
    ///          ↼──── Se body_weight              its weight −m_s g
    /// ```
    ///
    /// Effort is force (positive upwards on a mass), flow is vertical velocity. The
    /// 0-junctions carry the tyre force (`contact`) and the suspension force (`strut`);
    /// their flow balances give the compression rates `ż_r − ż_u` and `ż_u − ż_s`. The
    /// 1-junctions are the wheel and body velocities, and `deflection` the common
    /// compression rate of the parallel spring and damper. Causal strokes (SCAP): at
    /// `road` (the source imposes the flow), at `contact` for the tyre, at `wheel` for the
    /// bonds from `contact`, `wheel_weight` and to `strut`; at `unsprung` and `sprung`
    /// (integral causality); at `strut` for the bond to `deflection`; at `deflection` for
    /// the spring (integral) and the damper (resistance); at `body` for the bonds from
    /// `strut` and `body_weight`.
    ///
    /// States: `tyre.q` (tyre compression, m), `unsprung.p` (momentum `m_u ż_u`,
    /// kg·m/s), `spring.q` (suspension compression, m), `sprung.p` (momentum `m_s ż_s`,
    /// kg·m/s). They start at static equilibrium: compressions `(m_s + m_u) g / k_t` and
    /// `m_s g / k_s`, at rest.
    ///
    /// The road is flat with a cosine bump of height `bump_height` and length
    /// `bump_length` that starts `bump_distance` ahead, driven over at `speed`, plus a
    /// sinusoidal undulation `wave_amplitude · sin(2π speed t / wavelength)` (off by
    /// default). The Sf imposes the time derivative of that profile.
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `sprung_mass` | sprung mass m_s | kg |
    /// | `unsprung_mass` | unsprung mass m_u | kg |
    /// | `suspension_stiffness` | suspension spring rate k_s | N/m |
    /// | `suspension_damping` | suspension damping c_s | N·s/m |
    /// | `tyre_stiffness` | tyre vertical stiffness k_t | N/m |
    /// | `g` | gravitational acceleration (0 to switch gravity off) | m/s² |
    /// | `speed` | forward speed of the car | m/s |
    /// | `bump_distance` | distance to the start of the bump at `t = 0` | m |
    /// | `bump_height` | height of the bump | m |
    /// | `bump_length` | length of the bump | m |
    /// | `wave_amplitude` | amplitude of the sinusoidal undulation | m |
    /// | `wavelength` | wavelength of the undulation | m |
    pub model QuarterCar {
        /// sprung mass (a quarter of the body)
        param sprung_mass = 300.0 in "kg";
        /// unsprung mass (wheel, tyre, hub, brake)
        param unsprung_mass = 40.0 in "kg";
        /// suspension spring rate
        param suspension_stiffness = 20000.0 in "N/m";
        /// suspension damping coefficient
        param suspension_damping = 1500.0 in "N·s/m";
        /// tyre vertical stiffness
        param tyre_stiffness = 200000.0 in "N/m";
        /// gravitational acceleration
        param g = 9.81 in "m/s²";
        /// forward speed
        param speed = 10.0 in "m/s";
        /// distance to the start of the bump at t = 0
        param bump_distance = 5.0 in "m";
        /// bump height
        param bump_height = 0.05 in "m";
        /// bump length
        param bump_length = 2.0 in "m";
        /// amplitude of the sinusoidal road undulation
        param wave_amplitude = 0.0 in "m";
        /// wavelength of the road undulation
        param wavelength = 20.0 in "m";

        /// The vertical velocity of the road under the tyre.
        Sf road = {
            let bump = if t > bump_distance / speed && t < (bump_distance + bump_length) / speed {
                let w = 6.283185307179586 * speed / bump_length;
                0.5 * bump_height * w
                    * (6.283185307179586 * (speed * t - bump_distance) / bump_length).sin()
            } else {
                0.0
            };
            let w = 6.283185307179586 * speed / wavelength;
            bump + wave_amplitude * w * (w * t).cos()
        };
        0  contact;                          // the tyre force
        C  tyre = tyre_stiffness, q in "m";
        1  wheel;                            // the wheel velocity
        I  unsprung = unsprung_mass, p in "kg·m/s";
        Se wheel_weight = -unsprung_mass * g;
        0  strut;                            // the suspension force
        1  deflection;                       // the suspension compression rate
        C  spring = suspension_stiffness, q in "m";
        R  damper = suspension_damping;
        1  body;                             // the body velocity
        I  sprung = sprung_mass, p in "kg·m/s";
        Se body_weight = -sprung_mass * g;

        road -> contact -> { tyre, wheel };
        wheel -> { unsprung, strut };
        wheel_weight -> wheel;
        strut -> deflection -> { spring, damper };
        strut -> body -> sprung;
        body_weight -> body;

        init tyre.q = (sprung_mass + unsprung_mass) * g / tyre_stiffness;
        init spring.q = sprung_mass * g / suspension_stiffness;

        /// Height of the road under the tyre, m.
        output road_height = {
            let bump = if t > bump_distance / speed && t < (bump_distance + bump_length) / speed {
                let phase = 6.283185307179586 * (speed * t - bump_distance) / bump_length;
                0.5 * bump_height * (1.0 - phase.cos())
            } else {
                0.0
            };
            let profile = bump + wave_amplitude * (6.283185307179586 * speed / wavelength * t).sin();
            profile
        } in "m";
        /// Height of the wheel centre above its static position, m.
        output wheel_height = {
            let bump = if t > bump_distance / speed && t < (bump_distance + bump_length) / speed {
                let phase = 6.283185307179586 * (speed * t - bump_distance) / bump_length;
                0.5 * bump_height * (1.0 - phase.cos())
            } else {
                0.0
            };
            let profile = bump + wave_amplitude * (6.283185307179586 * speed / wavelength * t).sin();
            profile - (tyre.q - (sprung_mass + unsprung_mass) * g / tyre_stiffness)
        } in "m";
        /// Height of the body above its static position, m.
        output body_height = {
            let bump = if t > bump_distance / speed && t < (bump_distance + bump_length) / speed {
                let phase = 6.283185307179586 * (speed * t - bump_distance) / bump_length;
                0.5 * bump_height * (1.0 - phase.cos())
            } else {
                0.0
            };
            let profile = bump + wave_amplitude * (6.283185307179586 * speed / wavelength * t).sin();
            let wheel_z = profile - (tyre.q - (sprung_mass + unsprung_mass) * g / tyre_stiffness);
            wheel_z - (spring.q - sprung_mass * g / suspension_stiffness)
        } in "m";
        /// Vertical velocity of the body, m/s.
        output body_velocity = body.f in "m/s";
        /// Vertical velocity of the wheel, m/s.
        output wheel_velocity = wheel.f in "m/s";
        /// Vertical acceleration of the body (ride comfort), m/s².
        output body_acceleration = sprung.e / sprung_mass in "m/s²";
        /// Suspension compression from its static value (positive: bump), m.
        output suspension_travel = spring.q - sprung_mass * g / suspension_stiffness in "m";
        /// Tyre contact force, N (its static value is the corner's weight; below zero the
        /// wheel would lift off, which this linear tyre does not model).
        output tyre_force = tyre.e in "N";
        /// Power dissipated in the damper, W.
        output damper_power = damper.e * damper.f in "W";
    }
}
