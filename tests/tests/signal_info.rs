//! `Model::STATES` and `Model::OUTPUTS` of generated models: one entry per number, in
//! the order of `STATE_NAMES` and `OUTPUT_NAMES`, with the declared unit and doc.

use bgdsl_runtime::{bond_graph, Model, SignalInfo};
use models::dc_servo::DcServo;
use models::quick_return::QuickReturn;
use models::{DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

fn names(infos: &[SignalInfo]) -> Vec<&str> {
    infos.iter().map(|i| i.name).collect()
}

fn info<'a>(infos: &'a [SignalInfo], name: &str) -> &'a SignalInfo {
    infos
        .iter()
        .find(|i| i.name == name)
        .unwrap_or_else(|| panic!("no {name}"))
}

fn consistent<M: Model>() {
    assert_eq!(names(M::STATES), M::STATE_NAMES, "{}", M::NAME);
    assert_eq!(names(M::OUTPUTS), M::OUTPUT_NAMES, "{}", M::NAME);
    // The catalogue declares a unit on every output.
    for output in M::OUTPUTS {
        assert!(!output.unit.is_empty(), "{}: {}", M::NAME, output.name);
        bgdsl_runtime::units::parse(output.unit).unwrap();
    }
}

#[test]
fn every_catalogue_model_describes_each_state_and_output() {
    consistent::<QuickReturn>();
    consistent::<Oscillator>();
    consistent::<SeriesRlc>();
    consistent::<DcMotor>();
    consistent::<DcServo>();
    consistent::<QuarterCar>();
    consistent::<Duffing>();
}

#[test]
fn vector_outputs_and_library_states_carry_their_units() {
    let outputs = QuickReturn::OUTPUTS;
    for name in ["F_O1_x", "F_O1_y", "F_O1_z"] {
        assert_eq!(info(outputs, name).unit, "N");
        assert_eq!(
            info(outputs, name).doc,
            "Force of joint O1 (ground) on the crank"
        );
    }
    assert_eq!(info(outputs, "R1_21").unit, "1");
    let states = QuickReturn::STATES;
    assert_eq!(info(states, "crank.translation.p_x").unit, "kg·m/s");
    assert_eq!(info(states, "crank.rotation.p_z").unit, "kg·m²/s");
    assert_eq!(info(states, "rod.r_y").unit, "m");
    assert_eq!(info(states, "rod.R_12").unit, "1");
    assert_eq!(
        info(states, "rod.r_y").doc,
        "centre-of-mass position in frame 0"
    );
    // Couplings join both points and rotations: their deflection has no unit.
    assert_eq!(info(states, "jC.spring.q_z").unit, "");
    assert_eq!(info(states, "j01.spring.q_x").unit, "");
}

bond_graph! {
    /// A tank filled through a valve, with a state of its own.
    model Tank {
        param area = 2.0 in "m²";
        /// the water held
        C tank = 1000.0 * 9.81 / area, q in "m³";
        R valve = 1.0e5;
        Se supply = 2.0e4;
        1 pipe;
        supply -> pipe -> { valve, tank };
        /// time the valve has been open
        state open_for: f64 = 0.0 in "s";
        der open_for = 1.0;
        /// volume held
        output volume = tank.q;
        output pressure = tank.e in "Pa";
    }
}

#[test]
fn a_model_of_ones_own_describes_its_states_and_outputs() {
    let states = Tank::STATES;
    assert_eq!(info(states, "tank.q").unit, "m³");
    assert_eq!(info(states, "tank.q").doc, "the water held");
    assert_eq!(info(states, "open_for").unit, "s");
    assert_eq!(info(states, "open_for").doc, "time the valve has been open");
    // A plain state lends the output its unit.
    assert_eq!(info(Tank::OUTPUTS, "volume").unit, "m³");
    assert_eq!(info(Tank::OUTPUTS, "volume").doc, "volume held");
    assert_eq!(info(Tank::OUTPUTS, "pressure").unit, "Pa");
    assert_eq!(info(Tank::OUTPUTS, "pressure").doc, "");
}
