//! Your models. This one is a kitchen scale: a pan on a spring, with a dashpot to calm
//! it, and a load set down on the pan at `t = 0`. How much damping does a scale need to
//! read the load quickly without overshooting? A sweep over `damping` answers it
//! (`scenarios/damping_sweep.yaml`).
//!
//! The library is also the FMU's binary (`crate-type = ["cdylib", "rlib"]`): the
//! `export_fmi2!` below gives it the FMI 2.0 C functions, and `starter fmu scale` packs
//! it with the model's description into `scale.fmu`.

use bgdsl_cli::catalog::Checks;
use bgdsl_fmi_core::ModelEntry;
use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A kitchen scale: a pan on a spring with a dashpot, the load set down on the pan
    /// at `t = 0` from rest, the pan resting on the spring beforehand. The reading is
    /// tared (the pan alone reads 0): `stiffness * deflection / g - pan`.
    ///
    /// States: `platter.p` (momentum of pan and load, kg·m/s) and `spring.q` (the
    /// spring's compression, m). The reading follows the step response of a damped
    /// oscillator: with `m = pan + load`, `w = sqrt(stiffness / m)` and
    /// `z = damping / (2 sqrt(stiffness m))`, below critical damping (`z < 1`) it
    /// overshoots to `load (1 + exp(-z pi / sqrt(1 - z^2)))`.
    pub model Scale {
        /// mass of the empty pan
        param pan = 0.5 in "kg";
        /// mass of the load set down on it
        param load = 2.0 in "kg";
        /// stiffness of the spring under the pan
        param stiffness = 5000.0 in "N/m";
        /// damping of the dashpot
        param damping = 40.0 in "N·s/m";
        /// gravitational acceleration
        param g = 9.81 in "m/s²";

        Se weight = (pan + load) * g;
        I  platter = pan + load, p in "kg·m/s";
        C  spring = stiffness, q in "m";
        R  dashpot = damping;
        1  v;                    // the common velocity, downwards

        weight -> v -> { platter, spring, dashpot };

        // At rest under the empty pan: the load alone moves it.
        init spring.q = pan * g / stiffness;

        /// What the scale shows: the spring's force in kilograms, less the pan.
        output reading = stiffness * spring.q / g - pan in "kg";
        /// How far the pan has gone down from the spring's free length.
        output deflection = spring.q in "m";
        /// The pan's speed, downwards.
        output speed = v.f in "m/s";
    }
}

/// The scale's physical rules, checked before every run (and for each point of a
/// sweep): positive masses and stiffness, a damping that is not negative.
pub fn check(p: &ScaleParams, checks: &mut Checks) {
    checks.positive("pan", p.pan);
    checks.non_negative("load", p.load);
    checks.positive("stiffness", p.stiffness);
    checks.non_negative("damping", p.damping);
}

/// The models this library serves as FMUs (an FMU finds its model by the GUID in its
/// `modelDescription.xml`): list every model of `main.rs`'s catalogue here, each with
/// its rules for the parameter values an importer sets.
pub static FMI_MODELS: &[ModelEntry] = &[ModelEntry::new::<Scale>("scale").with_check(fmi_check)];

bgdsl_fmi_core::export_fmi2!(FMI_MODELS);

/// [`check`] for the values an FMU's importer sets: it refuses what `run` refuses.
fn fmi_check(values: &[f64]) -> Result<(), String> {
    bgdsl_cli::fmi::check_values::<Scale>(values, check)
}
