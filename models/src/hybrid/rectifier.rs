//! The half-wave rectifier: a sine source charging an RC load through a diode, with
//! the standard library's ideal `Diode` (events) and with Shockley's exponential law
//! (smooth).

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A half-wave rectifier: a sine source `amplitude · sin(2π frequency t)` feeds a
    /// capacitor `capacitance` in parallel with a load resistor `r_load` through an
    /// ideal diode (the standard library's `Diode` instance `diode`: `e = r_on f`
    /// while on, `f = g_off e` while off, switched when its voltage crosses 0). The
    /// source's internal resistance is the diode's on-resistance `r_on`.
    ///
    /// ```text
    ///   Se source ─⇀ 0 supply ─⇀ 1 diode.branch ─⇀ 0 out ─⇀ { R load, C cap }
    ///                                  │
    ///                                  ⇂
    ///                            R diode.law        (mode diode.on)
    /// ```
    ///
    /// Both nodes' voltages are fixed (by the source and by the capacitor), so the
    /// diode computes its current from its voltage. With the capacitor voltage `v`,
    /// each phase is the linear equation `C v' = g (Vs(t) − v) − v / r_load` with
    /// `g = 1 / r_on` (on) or `g_off` (off), whose solution is an exponential plus a
    /// sinusoid. The capacitor starts empty and the source at 0 rising, so the diode
    /// starts on (`on0`).
    ///
    /// States: `cap.q` (charge, C); mode `diode.on`.
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `amplitude` | source amplitude | V |
    /// | `frequency` | source frequency | Hz |
    /// | `r_on` | on-resistance of the diode (with the source's) | Ω |
    /// | `g_off` | off-conductance of the diode | S |
    /// | `r_load` | load resistance | Ω |
    /// | `capacitance` | smoothing capacitor | F |
    pub model HalfWaveRectifier {
        /// source amplitude
        param amplitude = 10.0 in "V";
        /// source frequency
        param frequency = 50.0 in "Hz";
        /// on-resistance of the diode (with the source's)
        param r_on = 10.0 in "Ω";
        /// off-conductance of the diode
        param g_off = 0.0 in "S";
        /// load resistance
        param r_load = 1000.0 in "Ω";
        /// smoothing capacitor
        param capacitance = 100.0e-6 in "F";

        Se source = amplitude * (2.0 * core::f64::consts::PI * frequency * t).sin();
        0 supply;
        0 out;
        R load = r_load;
        C cap = 1.0 / capacitance, q in "C";
        source -> supply;
        Diode diode(a = supply, b = out, r_on = r_on, g_off = g_off, on0 = true);
        out -> { load, cap };

        /// Source voltage, V.
        output source_voltage = supply.e in "V";
        /// Output (capacitor) voltage, V.
        output v_out = out.e in "V";
        /// Diode current, A.
        output current = diode.branch.f in "A";
    }
}

bond_graph! {
    /// The rectifier of [`HalfWaveRectifier`] with a smooth diode: Shockley's law
    /// `i = i_s (exp(v / n_vt) − 1)` in series with the source's resistance
    /// `r_source`, so the diode's forward drop (about 0.7 V at 1 A with the defaults)
    /// and its leakage (`i_s`) replace the ideal switch. The resistor and the diode
    /// share one current and split the voltage between them: an algebraic loop,
    /// solved at each evaluation. Above `v_knee` the exponential is continued by its
    /// tangent (the usual limiting of circuit simulators: value and slope continuous),
    /// so that a Newton iterate far up the exponential cannot overflow; the solution
    /// stays well below it (0.72 V at the crest's 1 A with the defaults).
    ///
    /// States: `cap.q` (charge, C).
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `amplitude` | source amplitude | V |
    /// | `frequency` | source frequency | Hz |
    /// | `r_source` | source resistance | Ω |
    /// | `i_s` | diode saturation current | A |
    /// | `n_vt` | ideality factor times the thermal voltage | V |
    /// | `v_knee` | voltage above which the exponential continues as its tangent | V |
    /// | `r_load` | load resistance | Ω |
    /// | `capacitance` | smoothing capacitor | F |
    pub model HalfWaveRectifierExp {
        /// source amplitude
        param amplitude = 10.0 in "V";
        /// source frequency
        param frequency = 50.0 in "Hz";
        /// source resistance
        param r_source = 10.0 in "Ω";
        /// diode saturation current
        param i_s = 1.0e-12 in "A";
        /// ideality factor times the thermal voltage (1 × 25.85 mV at 300 K)
        param n_vt = 0.02585 in "V";
        /// voltage above which the exponential continues as its tangent
        param v_knee = 0.9 in "V";
        /// load resistance
        param r_load = 1000.0 in "Ω";
        /// smoothing capacitor
        param capacitance = 100.0e-6 in "F";

        Se source = amplitude * (2.0 * core::f64::consts::PI * frequency * t).sin();
        0 supply;
        1 branch;
        0 out;
        #[allow(algebraic_loops)]
        R series = r_source;
        R diode {
            f = if e < v_knee {
                i_s * ((e / n_vt).exp() - 1.0)
            } else {
                i_s * ((v_knee / n_vt).exp() * (1.0 + (e - v_knee) / n_vt) - 1.0)
            }
        };
        R load = r_load;
        C cap = 1.0 / capacitance, q in "C";
        source -> supply -> branch -> out;
        branch -> { series, diode };
        out -> { load, cap };

        /// Source voltage, V.
        output source_voltage = supply.e in "V";
        /// Output (capacitor) voltage, V.
        output v_out = out.e in "V";
        /// Diode current, A.
        output current = branch.f in "A";
        /// Diode voltage, V.
        output v_diode = diode.e in "V";
    }
}
