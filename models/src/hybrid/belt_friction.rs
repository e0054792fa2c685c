//! The stick-slip oscillator: a mass on a spring riding a moving belt, with Coulomb
//! friction and stiction (the standard library's `StickSlip`), and the same mass on a
//! steep smooth friction law for the benchmark against it.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A mass `m` on a spring `k` (to a wall; relaxed at x = 0) lying on a belt that
    /// moves at `v_belt > 0`, with Coulomb friction of kinetic level `fc = mu_k m g`
    /// and static limit `fs = mu_s m g` (`StickSlip` instance `friction` between the
    /// belt and the mass: its slip is `v_belt − v`). Slipping, the friction is `fc`
    /// against the slip and the mass swings harmonically about `±fc / k`; stuck, it
    /// moves with the belt and the friction holds the spring's force `k x` (`held =
    /// spring.e`: the belt's speed is constant, so no inertial term) until `|k x|`
    /// exceeds `fs`. From the default start (1 m behind the spring's rest, at rest)
    /// it slips slower than the belt, then faster, then falls into the textbook limit
    /// cycle of stick and slip.
    ///
    /// ```text
    ///   Sf belt ─⇀ 1 belt_v ─⇀ 0 friction.rel ─⇀ 1 v ─⇀ { I mass, C spring }
    ///                              │
    ///                              ⇀ R friction.law     (modes friction.stuck, friction.forward)
    /// ```
    ///
    /// States: `mass.p` (momentum, kg·m/s), `spring.q` (position x, m); modes
    /// `friction.stuck`, `friction.forward` (slipping with the mass slower than the
    /// belt).
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `m` | mass | kg |
    /// | `k` | spring stiffness | N/m |
    /// | `v_belt` | belt speed | m/s |
    /// | `mu_s`, `mu_k` | static and kinetic friction coefficients | 1 |
    /// | `g` | gravitational acceleration (the normal force is `m g`) | m/s² |
    /// | `x0` | initial position (released at rest) | m |
    pub model BeltFriction {
        /// mass
        param m = 1.0 in "kg";
        /// spring stiffness
        param k = 10.0 in "N/m";
        /// belt speed
        param v_belt = 0.1 in "m/s";
        /// static friction coefficient
        param mu_s = 0.6 in "1";
        /// kinetic friction coefficient
        param mu_k = 0.4 in "1";
        /// gravitational acceleration
        param g = 9.81 in "m/s²";
        /// initial position (the mass starts at rest)
        param x0 = -1.0 in "m";

        Sf belt = v_belt;
        1 belt_v;
        I mass = m, p in "kg·m/s";
        /// position of the mass (the spring's extension)
        C spring = k, q in "m";
        1 v;
        belt -> belt_v;
        StickSlip friction(a = belt_v, b = v, fc = mu_k * m * g, fs = mu_s * m * g,
            held = spring.e);
        v -> { mass, spring };

        init spring.q = x0;
        /// Position, m.
        output x = spring.q in "m";
        /// Velocity of the mass, m/s.
        output velocity = v.f in "m/s";
        /// Friction force of the belt on the mass, N.
        output friction_force = friction.law.e in "N";
        /// Contact mode: 0 slipping slower than the belt, 1 stuck, 2 slipping faster.
        output contact = if friction.stuck { 1.0 } else if friction.forward { 0.0 } else { 2.0 } in "1";
        /// Power the belt delivers through the contact, W.
        output belt_power = belt.e * belt.f in "W";
        /// Power the contact dissipates (friction loss), W.
        output friction_power = friction.law.e * friction.law.f in "W";
        /// Energy, J: kinetic plus elastic.
        output energy = 0.5 * mass.p * mass.p / m + 0.5 * k * spring.q * spring.q in "J";
    }
}

bond_graph! {
    /// [`BeltFriction`] with a steep smooth friction law instead of modes and events:
    /// `F = tanh(slip / v_s) · (fc + (fs − fc) · exp(−(slip / (100 v_s))²))` (the slip
    /// `v_belt − v`): within a few `v_s` of zero slip the force rises to nearly `fs`
    /// (the stiction: 0.1 % below it at 4 `v_s`), and it falls to `fc` over some 100
    /// `v_s` beyond. A small velocity
    /// scale `v_s` makes it close to the switched law (a "stuck" mass creeps at a slip
    /// of the order of `v_s`) and stiff (its slope at zero slip is `fc / v_s`, against
    /// the mass `m`): the model is for the stiff solver, and for the benchmark of
    /// events against a smooth law.
    ///
    /// States: `mass.p` (momentum, kg·m/s), `spring.q` (position x, m).
    pub model BeltFrictionSmooth {
        /// mass
        param m = 1.0 in "kg";
        /// spring stiffness
        param k = 10.0 in "N/m";
        /// belt speed
        param v_belt = 0.1 in "m/s";
        /// static friction coefficient
        param mu_s = 0.6 in "1";
        /// kinetic friction coefficient
        param mu_k = 0.4 in "1";
        /// gravitational acceleration
        param g = 9.81 in "m/s²";
        /// initial position (the mass starts at rest)
        param x0 = -1.0 in "m";
        /// velocity scale of the smooth law
        param v_s = 1.0e-6 in "m/s";

        Sf belt = v_belt;
        1 belt_v;
        I mass = m, p in "kg·m/s";
        /// position of the mass (the spring's extension)
        C spring = k, q in "m";
        1 v;
        0 rel;
        R law {
            e = (f / v_s).tanh()
                * (mu_k + (mu_s - mu_k) * (-(0.01 * f / v_s) * (0.01 * f / v_s)).exp()) * m * g
        };
        belt -> belt_v -> rel -> v;
        rel -> law;
        v -> { mass, spring };

        init spring.q = x0;
        /// Position, m.
        output x = spring.q in "m";
        /// Velocity of the mass, m/s.
        output velocity = v.f in "m/s";
        /// Friction force of the belt on the mass, N.
        output friction_force = law.e in "N";
        /// Energy, J: kinetic plus elastic.
        output energy = 0.5 * mass.p * mass.p / m + 0.5 * k * spring.q * spring.q in "J";
    }
}
