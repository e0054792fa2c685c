//! A mass on a spring with a damper, pushed by a force.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A mass on a spring with a viscous damper, pushed by a constant force: the
    /// textbook single-degree-of-freedom oscillator `m x'' + c x' + k x = F`.
    ///
    /// ```text
    ///                    I mass
    ///                      ─
    ///                      ↾
    ///                      │
    ///   Se push ─────⇀| 1 v |─────⇀ C spring
    ///                     ─
    ///                     │
    ///                     ⇂
    ///                  R damper
    /// ```
    ///
    /// Half arrows point the way power flows (out of the source, into the storage and
    /// dissipative elements); `|` and `─` mark the causal strokes. The 1-junction `v` is
    /// the common velocity of the mass, the spring end and the damper; the force balance
    /// `F = m v' + k x + c v` is its effort sum. SCAP gives `mass` integral causality
    /// (stroke at the mass: it receives the net force and answers with the velocity),
    /// `spring` integral causality and `damper` resistance causality (both strokes at
    /// `v`: they receive the velocity and answer with a force).
    ///
    /// States: `mass.p` (momentum `m v`, kg·m/s) and `spring.q` (extension `x`, m).
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `m` | mass | kg |
    /// | `k` | spring stiffness | N/m |
    /// | `c` | damping coefficient | N·s/m |
    /// | `force` | applied force | N |
    pub model Oscillator {
        /// mass
        param m = 1.0 in "kg";
        /// stiffness
        param k = 100.0 in "N/m";
        /// damping coefficient
        param c = 0.4 in "N·s/m";
        /// applied force
        param force = 1.0 in "N";

        Se push = force;
        I  mass = m, p in "kg·m/s";   // f = p / m
        C  spring = k, q in "m";      // e = k q
        R  damper = c;                // e = c f
        1  v;                         // the common velocity

        push -> v -> { mass, spring, damper };

        // Released 4 cm beyond its equilibrium force / k (1 cm), so that the default run
        // shows the damped oscillation.
        init spring.q = 0.05;
        /// Position of the mass (spring extension), m.
        output x = spring.q in "m";
        /// Velocity of the mass, m/s.
        output speed = v.f in "m/s";
        /// Force of the spring on the mass, N (positive: pulls back towards x = 0).
        output spring_force = spring.e in "N";
        /// Power dissipated in the damper, W.
        output damper_power = damper.e * damper.f in "W";
        /// Power delivered by the applied force, W.
        output input_power = push.e * push.f in "W";
        /// Stored energy, J: kinetic `p²/2m` plus elastic `k x²/2`.
        output energy = 0.5 * mass.p * mass.p / m + 0.5 * k * spring.q * spring.q in "J";
    }
}
