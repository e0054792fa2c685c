//! A mass on a spring that hits an end stop: the standard library's `Impact` with
//! restitution on a gap written in the model's states.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A mass `m` on a spring `k`, released from rest at `x = -amplitude`, swings
    /// towards an end stop at `x = x_stop` (0 < x_stop < amplitude) and rebounds from
    /// it with restitution (`Impact` instance `wall` on the gap `x_stop − x`, event
    /// `wall.hit`: `v+ = -restitution · v-`).
    ///
    /// ```text
    ///   I mass ⇽─| 1 v |─⇀ C spring
    ///               │
    ///               ↿
    ///        Se wall.support          (never resting: the spring pulls away)
    /// ```
    ///
    /// Closed form (`ω = √(k/m)`): the first impact at `acos(-x_stop / amplitude) / ω`
    /// with speed `u₁ = ω √(amplitude² − x_stop²)`; the k-th rebound speed
    /// `wₖ = restitution^k u₁`; the flight after it lasts `(2π − 2 φₖ) / ω` with
    /// `φₖ = atan2(wₖ / ω, x_stop)` and ends at the stop with speed `wₖ` (energy is
    /// conserved in flight). The impact speeds fall geometrically but the flights
    /// tend to a full period: no Zeno accumulation, no rest mode needed (`v_rest`
    /// stays 0).
    ///
    /// States: `mass.p` (momentum, kg·m/s), `spring.q` (position, m); mode
    /// `wall.resting`.
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `m` | mass | kg |
    /// | `k` | spring stiffness | N/m |
    /// | `amplitude` | initial distance from equilibrium (released at `-amplitude`) | m |
    /// | `x_stop` | position of the end stop | m |
    /// | `restitution` | coefficient of restitution | 1 |
    pub model EndStop {
        /// mass
        param m = 1.0 in "kg";
        /// spring stiffness
        param k = 100.0 in "N/m";
        /// initial distance from equilibrium
        param amplitude = 0.1 in "m";
        /// position of the end stop
        param x_stop = 0.05 in "m";
        /// coefficient of restitution
        param restitution = 0.7 in "1";

        I mass = m, p in "kg·m/s";
        /// position of the mass
        C spring = k, q in "m";
        1 v;
        v -> { mass, spring };

        Impact wall(at = v, body = mass, gap = x_stop - spring.q, dir = -1.0,
            restitution = restitution, held = k * spring.q);

        init spring.q = -amplitude;
        /// Position, m.
        output x = spring.q in "m";
        /// Velocity, m/s.
        output velocity = v.f in "m/s";
        /// Energy, J: kinetic plus elastic.
        output energy = 0.5 * mass.p * mass.p / m + 0.5 * k * spring.q * spring.q in "J";
    }
}
