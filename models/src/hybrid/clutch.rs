//! Two shafts joined by the standard library's `Clutch`: slipping at its slip torque
//! until the speeds match, then locked.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// An engine shaft (inertia `j1`, spinning at `w1_0`, driven by `torque`) and an
    /// output shaft (inertia `j2`, starting at `w2_0 < w1_0`, braked by `load`) joined
    /// by a friction clutch (the standard library's `Clutch` instance `clutch`). While
    /// the speeds differ the clutch carries its slip torque `tk` from the faster
    /// shaft to the slower; when they match (event `clutch.plates.backward`) it locks,
    /// since the torque that keeps the shafts together,
    /// `(j2 torque + j1 load) / (j1 + j2)`, is below the holding torque `ts`; locked,
    /// both shafts accelerate as one inertia `j1 + j2` under `torque − load`.
    ///
    /// ```text
    ///   Se motor ─⇀ 1 w1 ─⇀ clutch ─⇀ 1 w2 ⇽─ Se brake
    ///                 │                  │
    ///                 ⇂                  ⇂
    ///              I engine           I driven
    /// ```
    ///
    /// Closed form while slipping: `w1' = (torque − tk) / j1`, `w2' = (tk − load) / j2`,
    /// so the speeds meet at `t_e = (w1_0 − w2_0) / ((tk − load) / j2 − (torque − tk) / j1)`;
    /// afterwards `w = w_e + (torque − load) / (j1 + j2) · (t − t_e)`.
    ///
    /// States: `engine.p`, `driven.p` (angular momenta, N·m·s); modes
    /// `clutch.plates.stuck`, `clutch.plates.forward`.
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `j1` | engine inertia | kg·m² |
    /// | `j2` | output inertia | kg·m² |
    /// | `torque` | engine torque | N·m |
    /// | `load` | braking torque on the output | N·m |
    /// | `tk` | clutch slip torque | N·m |
    /// | `ts` | clutch holding torque | N·m |
    /// | `w1_0` | engine's initial speed | rad/s |
    /// | `w2_0` | output's initial speed | rad/s |
    pub model ClutchEngagement {
        /// engine inertia
        param j1 = 0.5 in "kg·m²";
        /// output inertia
        param j2 = 1.5 in "kg·m²";
        /// engine torque
        param torque = 10.0 in "N·m";
        /// braking torque on the output
        param load = 2.0 in "N·m";
        /// clutch slip torque
        param tk = 20.0 in "N·m";
        /// clutch holding torque
        param ts = 25.0 in "N·m";
        /// engine's initial speed
        param w1_0 = 100.0 in "rad/s";
        /// output's initial speed
        param w2_0 = 0.0 in "rad/s";

        Se motor = torque;
        Se brake = load;
        I engine = j1, p in "N·m·s";
        I driven = j2, p in "N·m·s";
        1 w1;
        1 w2;
        motor -> w1 -> engine;
        w2 -> { driven, brake };
        Clutch clutch(a = w1, b = w2, tk = tk, ts = ts,
            held = (j2 * torque + j1 * load) / (j1 + j2));

        init engine.p = j1 * w1_0;
        init driven.p = j2 * w2_0;
        /// Engine speed, rad/s.
        output w_engine = w1.f in "rad/s";
        /// Output speed, rad/s.
        output w_output = w2.f in "rad/s";
        /// Clutch torque on the output shaft, N·m.
        output clutch_torque = clutch.plates.law.e in "N·m";
        /// Kinetic energy, J.
        output energy = 0.5 * engine.p * engine.p / j1 + 0.5 * driven.p * driven.p / j2 in "J";
    }
}
