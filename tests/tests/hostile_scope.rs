//! `bond_graph!` expands warning-free in a scope that shadows the prelude.
//!
//! The module below has no implicit prelude and declares its own `Result`, `Option`,
//! `Vec`, `Box`, `String`, `Ok`, `Some`, `None`, `Default`, `Clone`, `Debug` (as traits
//! and as macros), `Model`, `Scalar` and `assert_eq`, and modules named `core` and
//! `bgdsl_runtime`; then it invokes the macro with a model that uses every element kind,
//! labelled bonds, non-linear laws, initial conditions and outputs. Generated code that
//! names any of these without an absolute path fails to compile here, and any warning it
//! causes is an error.
#![deny(warnings)]
#![deny(missing_docs)]

/// Items that shadow the prelude, next to a model.
pub mod hostile {
    #![no_implicit_prelude]

    #[allow(dead_code)]
    struct Result;
    #[allow(dead_code)]
    struct Option;
    #[allow(dead_code)]
    struct Vec;
    #[allow(dead_code)]
    struct Box;
    #[allow(dead_code)]
    struct String;
    #[allow(dead_code)]
    struct Ok<T>(T);
    #[allow(dead_code)]
    struct Some<T>(T);
    #[allow(dead_code)]
    struct None;
    #[allow(dead_code)]
    trait Default {}
    #[allow(dead_code)]
    trait Clone {}
    #[allow(dead_code)]
    trait Debug {}
    #[allow(dead_code)]
    trait Model {}
    #[allow(dead_code)]
    trait Scalar {}
    #[allow(unused_macros)]
    macro_rules! assert_eq {
        ($($tokens:tt)*) => {
            ::core::compile_error!("the generated code used a shadowed `assert_eq!`")
        };
    }
    #[allow(unused_macros)]
    macro_rules! Clone {
        ($($tokens:tt)*) => {};
    }
    #[allow(unused_macros)]
    macro_rules! Debug {
        ($($tokens:tt)*) => {};
    }
    #[allow(unused_macros)]
    macro_rules! Default {
        ($($tokens:tt)*) => {};
    }
    #[allow(dead_code)]
    mod core {}
    #[allow(dead_code)]
    mod bgdsl_runtime {}

    ::bgdsl_runtime::bond_graph! {
        /// A DC motor driving a wheel through a gear and a torsion spring, with a leak
        /// into the spring's node: every element kind, on purpose.
        pub model Drive {
            /// supply voltage, V
            param volts_in = 12.0;
            /// coil inductance, H
            param l = 0.5;
            /// winding resistance, Ω
            param ra = 2.0;
            /// motor constant, N·m/A
            param kt = 0.1;
            /// rotor inertia, kg·m²
            param j_rotor = 0.01;
            /// bearing friction, linear and cubic
            param b = 0.001;
            param c3 = 0.0001;
            /// gear ratio
            param n = 5.0;
            /// spring stiffness, linear and cubic
            param k = 100.0;
            param k3 = 10.0;
            /// leak flow into the spring node
            param leak_flow = 0.2;
            /// wheel inertia and quadratic drag
            param j_wheel = 2.0;
            param d = 0.3;

            Se volts = volts_in;
            Sf leak = leak_flow;
            I  coil { f = p / l };
            R  winding = ra;
            GY motor = kt;
            I  rotor = j_rotor;
            R  bearing { e = b * f + c3 * f.powi(3) };
            TF gear = n;
            C  spring { e = k * q + k3 * q.powi(3) };
            I  wheel = j_wheel;
            R  drag { e = d * f * f.abs() };
            1  current;
            1  shaft;
            0  twist;
            1  load;

            volts -[b_in]-> current -> { coil, winding, motor };
            motor -> shaft -> { rotor, bearing, gear };
            gear -[b_out]-> twist -> { spring, load };
            leak -> twist;
            load -> { wheel, drag };

            init coil.p = 0.05;
            init spring.q = 0.1;

            /// current through the coil, A
            output i = coil.f;
            output power_in = b_in.e * b_in.f;
            output spring_rate = b_out.f;
            output omega = shaft.f;
            output gear_torque = gear.e1;
            output emf = motor.e1;
            output tension = twist.e;
            output drive = if t > 1.0 { 0.0 } else { (2.0 * t).sin() };
        }
    }
}

use bgdsl_runtime::Model;
use hostile::{Drive, DriveOutputs, DriveParams, DriveState};

/// A state away from equilibrium: `[coil.p, rotor.p, spring.q, wheel.p]`.
const X: [f64; 4] = [0.05, 0.002, 0.1, 0.4];

fn close(actual: f64, expected: f64) -> bool {
    (actual - expected).abs() <= 1e-12 * expected.abs().max(1.0)
}

#[test]
fn name_the_states_and_outputs_in_declaration_order() {
    assert_eq!(
        Drive::STATE_NAMES,
        ["coil.p", "rotor.p", "spring.q", "wheel.p"]
    );
    assert_eq!(
        Drive::OUTPUT_NAMES,
        [
            "i",
            "power_in",
            "spring_rate",
            "omega",
            "gear_torque",
            "emf",
            "tension",
            "drive"
        ]
    );
    assert_eq!(<Drive as Model>::N_STATES, 4);
    assert_eq!(<Drive as Model>::N_OUTPUTS, 8);
}

#[test]
fn start_from_the_declared_initial_conditions() {
    let mut x0 = [f64::NAN; 4];
    Drive::default().initial_state(&mut x0);
    assert_eq!(x0, [0.05, 0.0, 0.1, 0.0]);
}

#[test]
fn compute_the_derivatives_worked_by_hand() {
    // i = p/l = 0.1, ω = 0.2, spring effort = 100·0.1 + 10·0.1³ = 10.01, wheel flow 0.2.
    // coil:   12 − 2·0.1 − 0.1·ω = 12 − 0.2 − 0.02            = 11.78
    // rotor:  0.1·i − (0.001·ω + 0.0001·ω³) − 5·10.01           = −50.0402008
    // spring: 5·ω + 0.2 − 0.2                                    = 1.0
    // wheel:  10.01 − 0.3·0.2·|0.2|                              = 9.998
    let mut dx = [f64::NAN; 4];
    Drive::default().derivatives(0.0, &X, &mut dx);
    let expected = [
        11.78,
        0.01 - (0.001 * 0.2 + 0.0001 * 0.008) - 50.05,
        1.0,
        9.998,
    ];
    for (i, (&actual, &expected)) in dx.iter().zip(&expected).enumerate() {
        assert!(
            close(actual, expected),
            "d{}/dt = {actual}, expected {expected}",
            Drive::STATE_NAMES[i]
        );
    }
}

#[test]
fn compute_the_outputs_worked_by_hand() {
    let mut y = [f64::NAN; 8];
    Drive::default().outputs(0.5, &X, &mut y);
    let y = DriveOutputs::from_slice(&y);
    let expected = DriveOutputs {
        i: 0.1,
        power_in: 1.2,
        spring_rate: 1.0,
        omega: 0.2,
        gear_torque: 50.05,
        emf: 0.02,
        tension: 10.01,
        drive: 1.0_f64.sin(),
    };
    let mut actual = [0.0; 8];
    let mut wanted = [0.0; 8];
    y.write_to(&mut actual);
    expected.write_to(&mut wanted);
    for (name, (&a, &w)) in Drive::OUTPUT_NAMES.iter().zip(actual.iter().zip(&wanted)) {
        assert!(close(a, w), "{name} = {a}, expected {w}");
    }
}

#[test]
fn take_parameters_and_name_the_state() {
    let params = DriveParams {
        volts_in: 0.0,
        ..DriveParams::default()
    };
    let model = Drive::new(params);
    let state = DriveState::from_slice(&X);
    assert_eq!(state.spring_q, 0.1);
    let mut dx = [f64::NAN; 4];
    model.derivatives(0.0, &X, &mut dx);
    assert!(close(dx[0], -0.2 - 0.02));
}

#[test]
fn assign_integral_causality_to_every_storage_element() {
    use bgdsl_runtime::{ElementCausality, ElementKind};
    let causality = |name: &str| {
        Drive::GRAPH
            .elements
            .iter()
            .find(|e| e.name == name)
            .map(|e| (e.kind, e.causality))
    };
    for name in ["coil", "rotor", "spring", "wheel"] {
        let (kind, causality) = causality(name).unwrap();
        assert!(matches!(kind, ElementKind::C | ElementKind::I), "{name}");
        assert_eq!(causality, ElementCausality::Integral, "{name}");
    }
    for name in ["winding", "bearing", "drag"] {
        assert_eq!(
            causality(name).unwrap(),
            (ElementKind::R, ElementCausality::Resistance),
            "{name}"
        );
    }
    let labels: Vec<_> = Drive::GRAPH.bonds.iter().filter_map(|b| b.label).collect();
    assert_eq!(labels, ["b_in", "b_out"]);
}
