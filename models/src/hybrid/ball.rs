//! A ball dropped on a floor: the impact with restitution and the rest mode of the
//! standard library's `Impact`, and the same ball on a smooth penalty contact.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A ball of mass `m` dropped from rest at height `h0` onto a rigid floor: free
    /// flight under gravity between impacts, and at each impact Newton's law of
    /// restitution, `v+ = -restitution · v-` (the standard library's `Impact`
    /// instance `floor`, event `floor.hit`). The bounces form a geometric series whose
    /// impact times accumulate at a finite time (Zeno); an impact whose rebound speed
    /// would be below `v_rest` puts the ball at rest on the floor instead (mode
    /// `floor.resting`: momentum 0, the floor carrying the weight `m g`).
    ///
    /// ```text
    ///   I ball ⇽─| 1 v |─⇀ C gravity       (e = m g, q = height)
    ///               │
    ///               ↿
    ///        Se floor.support              (m g while resting, 0 otherwise)
    /// ```
    ///
    /// Gravity is a C element with the constant law `e = m g` on the height, so the
    /// stored energy is `p²/2m + m g h` and the energy account closes with the impact
    /// losses alone.
    ///
    /// States: `ball.p` (momentum, kg·m/s), `gravity.q` (height, m); mode
    /// `floor.resting`.
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `m` | mass | kg |
    /// | `g` | gravitational acceleration | m/s² |
    /// | `h0` | initial height (dropped from rest) | m |
    /// | `restitution` | coefficient of restitution | 1 |
    /// | `v_rest` | rebound speed below which the ball comes to rest | m/s |
    ///
    /// Closed form: first impact at `√(2 h0 / g)` with speed `u₁ = √(2 g h0)`; the
    /// k-th rebound speed is `wₖ = restitution^k u₁`, the flight after it lasts
    /// `2 wₖ / g` and peaks at `wₖ² / 2g`.
    pub model BouncingBall {
        /// mass
        param m = 1.0 in "kg";
        /// gravitational acceleration
        param g = 9.81 in "m/s²";
        /// initial height
        param h0 = 1.0 in "m";
        /// coefficient of restitution
        param restitution = 0.8 in "1";
        /// rebound speed below which the ball comes to rest
        param v_rest = 0.01 in "m/s";

        I ball = m, p in "kg·m/s";
        /// height above the floor
        C gravity { e = m * g }, q in "m";
        1 v;
        v -> { ball, gravity };

        Impact floor(at = v, body = ball, gap = gravity.q, dir = 1.0,
            restitution = restitution, v_rest = v_rest, held = m * g);

        init gravity.q = h0;
        /// Height above the floor, m.
        output height = gravity.q in "m";
        /// Velocity (up positive), m/s.
        output velocity = v.f in "m/s";
        /// Energy, J: kinetic plus potential.
        output energy = 0.5 * ball.p * ball.p / m + m * g * gravity.q in "J";
    }
}

bond_graph! {
    /// The ball of [`BouncingBall`] on a steep smooth penalty contact instead of
    /// events: a floor spring `k` and damper `c` whose force fades in smoothly over
    /// a penetration scale `s` (a softplus spring `k s ln(1 + exp(-h/s))` and a
    /// damper switched on by the logistic `1 / (1 + exp(h/s))`, both written in their
    /// overflow-free forms), so the right-hand side is smooth and stiff. The default
    /// `c` gives the linear spring-damper the restitution `restitution`
    /// (`ζ = -ln e / √(π² + ln² e)`, `c = 2 ζ √(k m)`); each contact lasts about
    /// `π / √(k/m)` (3 ms with the defaults), where the event model's impact is
    /// instantaneous.
    ///
    /// States: `ball.p` (momentum, kg·m/s), `gravity.q` (height, m).
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `m` | mass | kg |
    /// | `g` | gravitational acceleration | m/s² |
    /// | `h0` | initial height (dropped from rest) | m |
    /// | `k` | contact stiffness | N/m |
    /// | `restitution` | restitution the default `c` is chosen for | 1 |
    /// | `c` | contact damping | N·s/m |
    /// | `s` | penetration scale of the smooth switch | m |
    pub model BallPenalty {
        /// mass
        param m = 1.0 in "kg";
        /// gravitational acceleration
        param g = 9.81 in "m/s²";
        /// initial height
        param h0 = 1.0 in "m";
        /// contact stiffness
        param k = 1.0e6 in "N/m";
        /// restitution the default damping is chosen for
        param restitution = 0.8 in "1";
        /// contact damping
        param c = 2.0 * (k * m).sqrt() * -restitution.ln()
            / (core::f64::consts::PI.powi(2) + restitution.ln().powi(2)).sqrt() in "N·s/m";
        /// penetration scale of the smooth switch
        param s = 1.0e-4 in "m";

        I ball = m, p in "kg·m/s";
        /// height above the floor
        C gravity { e = m * g }, q in "m";
        R floor_damper {
            e = {
                let x = gravity.q / s;
                let on = if x > 0.0 {
                    (-x).exp() / (1.0 + (-x).exp())
                } else {
                    1.0 / (1.0 + x.exp())
                };
                c * f * on
            }
        };
        MSe floor_spring = {
            let x = -gravity.q / s;
            if x > 0.0 {
                k * s * (x + (1.0 + (-x).exp()).ln())
            } else {
                k * s * (1.0 + x.exp()).ln()
            }
        };
        1 v;
        floor_spring -> v -> { ball, gravity, floor_damper };

        init gravity.q = h0;
        /// Height above the floor, m.
        output height = gravity.q in "m";
        /// Velocity (up positive), m/s.
        output velocity = v.f in "m/s";
    }
}
