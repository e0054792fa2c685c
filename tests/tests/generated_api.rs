//! What `bond_graph!` generates besides the equations, checked on real models: the
//! causal graph SCAP must produce, and the parameter struct's serde contract.

use bgdsl_runtime::{CausalGraph, ElementCausality, ElementKind, Model};
use models::{DcMotor, DcMotorParams, Oscillator, OscillatorParams, QuarterCarParams};

/// The element at the causal-stroke end of the bond `from -> to`.
fn stroke(graph: &CausalGraph, from: &str, to: &str) -> &'static str {
    let index = |name: &str| graph.elements.iter().position(|e| e.name == name).unwrap();
    let (from, to) = (index(from), index(to));
    let bond = graph
        .bonds
        .iter()
        .find(|b| b.from == from && b.to == to)
        .unwrap_or_else(|| panic!("no bond {from} -> {to}"));
    graph.elements[bond.stroke_at].name
}

fn causality(graph: &CausalGraph, name: &str) -> (ElementKind, ElementCausality) {
    let e = graph.elements.iter().find(|e| e.name == name).unwrap();
    (e.kind, e.causality)
}

mod should {
    use super::*;

    /// SCAP on the oscillator: the source's effort acts on the junction; the mass,
    /// chosen first among the storage elements, takes integral causality, so it
    /// receives the net force (stroke at the mass) and its velocity becomes the
    /// junction's flow; the spring and the damper then receive that velocity and
    /// answer with forces (strokes at the junction): the spring integral, the damper
    /// resistance.
    #[test]
    fn assign_the_oscillators_strokes_as_scap_does() {
        let graph = Oscillator::default()
            .causal_graph()
            .expect("generated models describe their graph");
        assert_eq!(graph, &Oscillator::GRAPH);
        assert_eq!(graph.model, "Oscillator");
        let names: Vec<&str> = graph.elements.iter().map(|e| e.name).collect();
        assert_eq!(names, ["push", "mass", "spring", "damper", "v"]);
        assert_eq!(graph.bonds.len(), 4);
        assert!(graph
            .bonds
            .iter()
            .all(|b| b.dimension == 1 && b.label.is_none()));
        assert_eq!(stroke(graph, "push", "v"), "v");
        assert_eq!(stroke(graph, "v", "mass"), "mass");
        assert_eq!(stroke(graph, "v", "spring"), "v");
        assert_eq!(stroke(graph, "v", "damper"), "v");
        use ElementCausality::*;
        assert_eq!(causality(graph, "push"), (ElementKind::Se, Fixed));
        assert_eq!(causality(graph, "mass"), (ElementKind::I, Integral));
        assert_eq!(causality(graph, "spring"), (ElementKind::C, Integral));
        assert_eq!(causality(graph, "damper"), (ElementKind::R, Resistance));
        assert_eq!(causality(graph, "v"), (ElementKind::One, Fixed));
    }

    /// The DC motor exercises a gyrator, a transformer and a 0-junction. The coil's
    /// current is the armature's flow, so the gyrator receives flows on both ports and
    /// answers with efforts (back-EMF at `armature`, torque at `shaft`); the
    /// transformer passes the rotor's speed through and receives the shaft torque from
    /// the coupling (stroke at `gear`); the shaft spring sets the coupling's torque.
    #[test]
    fn assign_the_dc_motors_strokes_as_scap_does() {
        let graph = DcMotor::default().causal_graph().unwrap();
        let expected = [
            ("supply", "armature", "armature"),
            ("armature", "winding", "armature"),
            ("armature", "coil", "coil"),
            ("armature", "motor", "armature"),
            ("motor", "shaft", "shaft"),
            ("shaft", "rotor", "rotor"),
            ("shaft", "bearing", "shaft"),
            ("shaft", "gear", "shaft"),
            ("gear", "coupling", "gear"),
            ("coupling", "twist", "coupling"),
            ("twist", "shaft_spring", "twist"),
            ("twist", "shaft_damper", "twist"),
            ("coupling", "load_side", "load_side"),
            ("load_side", "load", "load"),
            ("load_side", "drag", "load_side"),
            ("brake", "load_side", "load_side"),
        ];
        assert_eq!(graph.bonds.len(), expected.len());
        for (from, to, at) in expected {
            assert_eq!(stroke(graph, from, to), at, "stroke of {from} -> {to}");
        }
        use ElementCausality::*;
        for storage in ["coil", "rotor", "shaft_spring", "load"] {
            assert_eq!(causality(graph, storage).1, Integral, "{storage}");
        }
        for resistor in ["winding", "bearing", "shaft_damper", "drag"] {
            assert_eq!(
                causality(graph, resistor),
                (ElementKind::R, Resistance),
                "{resistor}"
            );
        }
        assert_eq!(causality(graph, "motor"), (ElementKind::Gy, Fixed));
        assert_eq!(causality(graph, "gear"), (ElementKind::Tf, Fixed));
        assert_eq!(causality(graph, "coupling"), (ElementKind::Zero, Fixed));
        assert_eq!(
            DcMotor::STATE_NAMES,
            ["coil.p", "rotor.p", "shaft_spring.q", "load.p"]
        );
    }

    /// Parameters survive a YAML round trip unchanged, bit for bit (serde_yaml writes
    /// floats in shortest round-trip form).
    #[test]
    fn round_trip_parameters_through_yaml() {
        let params = DcMotorParams {
            voltage: 24.0,
            gear_ratio: 1.0 / 3.0,
            load_torque: 1e-300,
            ..Default::default()
        };
        let yaml = serde_yaml::to_string(&params).unwrap();
        assert!(yaml.contains("voltage: 24.0"), "{yaml}");
        let back: DcMotorParams = serde_yaml::from_str(&yaml).unwrap();
        assert_eq!(back, params);
        let quarter_car = QuarterCarParams::default();
        let back: QuarterCarParams =
            serde_yaml::from_str(&serde_yaml::to_string(&quarter_car).unwrap()).unwrap();
        assert_eq!(back, quarter_car);
    }

    /// A scenario file may set only some parameters: the others keep their declared
    /// defaults.
    #[test]
    fn take_missing_parameters_from_the_declared_defaults() {
        let params: OscillatorParams = serde_yaml::from_str("k: 400.0\n").unwrap();
        assert_eq!(
            params,
            OscillatorParams {
                k: 400.0,
                ..Default::default()
            }
        );
        assert_eq!(params.m, 1.0);
        let empty: OscillatorParams = serde_yaml::from_str("{}").unwrap();
        assert_eq!(empty, OscillatorParams::default());
    }

    /// A misspelt parameter is an error that names it, not a silently ignored line.
    #[test]
    fn reject_an_unknown_parameter() {
        let err = serde_yaml::from_str::<OscillatorParams>("m: 2.0\nstifness: 50.0\n").unwrap_err();
        let message = err.to_string();
        assert!(message.contains("unknown field `stifness`"), "{message}");
        assert!(
            message.contains("expected one of `m`, `k`, `c`, `force`"),
            "{message}"
        );
        assert!(serde_yaml::from_str::<OscillatorParams>("m: heavy\n").is_err());
    }
}

/// A generated model runs with its default solver (Radau IIA) and agrees with
/// Dormand–Prince on the oscillator's closed form: the default is a working choice,
/// not just a name.
#[test]
fn default_solver_is_the_stiff_one_and_solves_the_oscillator() {
    use bgdsl_runtime::{Model, Simulation, Trajectory};
    let model = models::Oscillator::default();
    assert_eq!(model.default_solver().name(), "radau5");
    let mut sim = Simulation::with_default_solver(&model).unwrap();
    let mut x0 = [0.0; 2];
    model.initial_state(&mut x0);
    let mut run = Trajectory::for_model::<models::Oscillator>(2);
    sim.run(0.0, &x0, &[0.0, 2.0], &mut run).unwrap();
    let reference =
        bgdsl_runtime::simulate(&model, bgdsl_runtime::Solver::dopri5(), 0.0, 2.0, 2).unwrap();
    for state in models::Oscillator::STATE_NAMES {
        let (a, b) = (
            run.value(1, state).unwrap(),
            reference.value(1, state).unwrap(),
        );
        // Both run at rtol 1e-6 on O(0.1) values: agreement to 1e-5 absolute.
        assert!((a - b).abs() < 1e-5, "{state}: {a} vs {b}");
    }
    assert!(sim.stats().n_jac > 0, "the stiff solver did the work");
}
