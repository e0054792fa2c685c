//! The third-order Butterworth low-pass filter as a doubly terminated LC ladder: a
//! voltage source behind `Rs`, series `L1`, shunt `C2`, series `L3`, into the load
//! `RL`. With `Rs = RL = 1 Ω`, `L1 = L3 = 1 H`, `C2 = 2 F` its transfer function from
//! the source voltage to the load voltage is
//! `H(s) = 1 / (2 (s + 1)(s² + s + 1))`: the normalised Butterworth polynomial, cut-off
//! 1 rad/s, halved by the two terminations (a reference for frequency responses).
//!
//! ```text
//!  Se source ─ 1 loop1 ─ 0 node ─ 1 loop2 ─ R load
//!              │    │     │         │
//!            R rs  I l1  C c2      I l3
//! ```

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// The third-order Butterworth ladder (see the module documentation).
    pub model Butterworth {
        /// source resistance
        param source_resistance = 1.0 in "Ω";
        /// first series inductance
        param l1 = 1.0 in "H";
        /// shunt capacitance
        param c2 = 2.0 in "F";
        /// second series inductance
        param l3 = 1.0 in "H";
        /// load resistance
        param load_resistance = 1.0 in "Ω";
        /// the source voltage
        input voltage = 1.0 in "V";

        MSe source = voltage;
        1 loop1;                                  // the source current
        R rs = source_resistance;
        I inductor1 = l1, p in "Wb";
        0 node;                                   // the capacitor voltage
        C capacitor = 1.0 / c2, q in "C";
        1 loop2;                                  // the load current
        I inductor3 = l3, p in "Wb";
        R load = load_resistance;

        source -> loop1 -> { rs, inductor1 };
        loop1 -> node -> capacitor;
        node -> loop2 -> { inductor3, load };

        output load_voltage = load.e in "V";
        output capacitor_voltage = capacitor.e in "V";
        output source_current = loop1.f in "A";
    }
}
