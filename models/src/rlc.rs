//! A series RLC circuit driven by a voltage source.

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A resistor, an inductor and a capacitor in series across a constant voltage
    /// source switched on at `t = 0`: `L i' + R i + q / Cap = V`.
    ///
    /// ```text
    ///                      I inductor
    ///                         ─
    ///                         ↾
    ///                         │
    ///   Se source ─────⇀| 1 mesh |─────⇀ C capacitor
    ///                        ─
    ///                        │
    ///                        ⇂
    ///                    R resistor
    /// ```
    ///
    /// Effort is voltage, flow is current. The 1-junction `mesh` carries the one loop
    /// current; Kirchhoff's voltage law is its effort sum. The capacitor's linear law is
    /// a stiffness (`e = q / Cap`), so it is declared `C capacitor = 1.0 / capacitance`.
    /// Causality: the inductor integral (stroke at the inductor), the capacitor
    /// integral and the resistor in resistance causality (strokes at `mesh`).
    ///
    /// States: `inductor.p` (flux linkage `L i`, Wb = V·s) and `capacitor.q` (charge,
    /// C).
    ///
    /// | parameter | meaning | unit |
    /// |---|---|---|
    /// | `voltage` | source voltage | V |
    /// | `resistance` | series resistance R | Ω |
    /// | `inductance` | inductance L | H |
    /// | `capacitance` | capacitance Cap | F |
    ///
    /// The defaults (10 Ω, 10 mH, 10 µF) give an underdamped circuit: natural angular
    /// frequency `1/√(L Cap)` ≈ 3162 rad/s, decay rate `R / 2L` = 500 1/s.
    pub model SeriesRlc {
        /// source voltage
        param voltage = 1.0 in "V";
        /// series resistance
        param resistance = 10.0 in "Ω";
        /// inductance
        param inductance = 10.0e-3 in "H";
        /// capacitance
        param capacitance = 10.0e-6 in "F";

        Se source = voltage;
        R  resistor = resistance;               // v = R i
        I  inductor = inductance, p in "Wb";    // i = λ / L
        C  capacitor = 1.0 / capacitance, q in "C"; // v = q / Cap
        1  mesh;                                // the loop current

        source -> mesh -> { resistor, inductor, capacitor };

        /// Loop current, A.
        output current = mesh.f in "A";
        /// Voltage across the capacitor, V.
        output capacitor_voltage = capacitor.e in "V";
        /// Voltage across the inductor, V.
        output inductor_voltage = inductor.e in "V";
        /// Voltage across the resistor, V.
        output resistor_voltage = resistor.e in "V";
        /// Power delivered by the source, W.
        output source_power = source.e * source.f in "W";
        /// Power dissipated in the resistor, W.
        output resistor_power = resistor.e * resistor.f in "W";
        /// Stored energy, J: magnetic `λ²/2L` plus electric `q²/2Cap`.
        output energy = 0.5 * inductor.p * inductor.p / inductance
            + 0.5 * capacitor.q * capacitor.q / capacitance in "J";
    }
}
