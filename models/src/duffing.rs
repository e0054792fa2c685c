//! The forced Duffing oscillator: a mass on a hardening (cubic) spring.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A mass on a non-linear spring with a cubic hardening term, a viscous damper and
    /// a harmonic driving force: `m x'' + c x' + k x + k3 x³ = F cos(ω t)`.
    ///
    /// ```text
    ///                    I mass
    ///                      ─
    ///                      ↾
    ///                      │
    ///   Se drive ─────⇀| 1 v |─────⇀ C spring      e = k q + k3 q³
    ///                     ─
    ///                     │
    ///                     ⇂
    ///                  R damper
    /// ```
    ///
    /// The graph of [`Oscillator`](crate::Oscillator) with an explicit, non-linear law
    /// for the spring. Causality as there: `mass` and `spring` integral, `damper`
    /// resistance.
    ///
    /// States: `mass.p` (momentum, kg·m/s) and `spring.q` (displacement, m).
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `m` | mass | kg |
    /// | `k` | linear stiffness | N/m |
    /// | `k3` | cubic stiffness | N/m³ |
    /// | `c` | damping coefficient | N·s/m |
    /// | `force` | amplitude of the driving force | N |
    /// | `omega` | angular frequency of the driving force | rad/s |
    /// | `x0` | initial displacement | m |
    ///
    /// With `c = 0` and `force = 0` the energy `p²/2m + k q²/2 + k3 q⁴/4` is conserved
    /// and the period of the oscillation from rest at `x0 = A` is
    /// `4 K(μ) / √(k/m + k3 A²/m)` with `μ = k3 A² / (2 (k + k3 A²))` (`K`: the complete
    /// elliptic integral of the first kind, parameter convention).
    pub model Duffing {
        /// mass
        param m = 1.0 in "kg";
        /// linear stiffness
        param k = 1.0 in "N/m";
        /// cubic stiffness
        param k3 = 1.0 in "N/m³";
        /// damping coefficient
        param c = 0.1 in "N·s/m";
        /// amplitude of the driving force
        param force = 0.5 in "N";
        /// angular frequency of the driving force
        param omega = 1.2 in "rad/s";
        /// initial displacement
        param x0 = 1.0 in "m";

        Se drive = force * (omega * t).cos();
        I  mass = m, p in "kg·m/s";
        C  spring { e = k * q + k3 * q.powi(3) }, q in "m";
        R  damper = c;
        1  v;

        drive -> v -> { mass, spring, damper };

        init spring.q = x0;
        /// Displacement, m.
        output x = spring.q in "m";
        /// Velocity, m/s.
        output velocity = v.f in "m/s";
        /// Spring force, N.
        output spring_force = spring.e in "N";
        /// Stored energy, J: kinetic plus the spring's potential `k q²/2 + k3 q⁴/4`.
        output energy = 0.5 * mass.p * mass.p / m
            + 0.5 * k * spring.q * spring.q
            + 0.25 * k3 * spring.q.powi(4) in "J";
    }
}
