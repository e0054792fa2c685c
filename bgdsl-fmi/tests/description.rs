//! `modelDescription.xml` of every model the library serves: well-formed, every
//! variable listed once with its own value reference, and consistent with the model.

use std::collections::BTreeSet;

use bgdsl_fmi::MODELS;
use bgdsl_fmi_core::{model_description_xml, ModelDescription, Role};
use bgdsl_runtime::Model;
use models::quick_return::QuickReturn;

fn parsed<'a>(xml: &'a str) -> roxmltree::Document<'a> {
    roxmltree::Document::parse(xml).unwrap_or_else(|e| panic!("not well-formed: {e}\n{xml}"))
}

fn child<'a, 'i>(node: roxmltree::Node<'a, 'i>, name: &str) -> roxmltree::Node<'a, 'i> {
    node.children()
        .find(|n| n.has_tag_name(name))
        .unwrap_or_else(|| panic!("no <{name}>"))
}

#[test]
fn every_model_description_is_well_formed_and_lists_every_variable_once() {
    for entry in MODELS {
        let description = entry.describe();
        let xml = model_description_xml(&description, entry.identifier());
        let doc = parsed(&xml);
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "fmiModelDescription");
        assert_eq!(root.attribute("fmiVersion"), Some("2.0"));
        assert_eq!(root.attribute("guid"), Some(description.guid.as_str()));
        for interface in ["ModelExchange", "CoSimulation"] {
            assert_eq!(
                child(root, interface).attribute("modelIdentifier"),
                Some(entry.identifier())
            );
        }
        let variables: Vec<_> = child(root, "ModelVariables")
            .children()
            .filter(|n| n.has_tag_name("ScalarVariable"))
            .collect();
        assert_eq!(
            variables.len(),
            description.variables.all().len(),
            "{}",
            entry.identifier()
        );
        let names: BTreeSet<_> = variables
            .iter()
            .map(|v| v.attribute("name").unwrap())
            .collect();
        assert_eq!(
            names.len(),
            variables.len(),
            "{}: names unique",
            entry.identifier()
        );
        let vrs: BTreeSet<u32> = variables
            .iter()
            .map(|v| v.attribute("valueReference").unwrap().parse().unwrap())
            .collect();
        assert_eq!(
            vrs.len(),
            variables.len(),
            "{}: value references unique",
            entry.identifier()
        );

        // Every unit used is defined.
        let defined: BTreeSet<_> = root
            .descendants()
            .filter(|n| n.has_tag_name("Unit"))
            .map(|n| n.attribute("name").unwrap())
            .collect();
        for real in root.descendants().filter(|n| n.has_tag_name("Real")) {
            if let Some(unit) = real.attribute("unit") {
                assert!(defined.contains(unit), "{unit} undefined");
            }
        }

        // Each derivative points at its state; ModelStructure lists every derivative
        // and output by index.
        let structure = child(root, "ModelStructure");
        let indices = |element: &str| -> Vec<usize> {
            structure
                .children()
                .find(|n| n.has_tag_name(element))
                .map(|list| {
                    list.children()
                        .filter(|n| n.has_tag_name("Unknown"))
                        .map(|u| u.attribute("index").unwrap().parse().unwrap())
                        .collect()
                })
                .unwrap_or_default()
        };
        let derivatives = indices("Derivatives");
        let mut initial_state = vec![0.0; description.variables.sizes().states];
        entry.create().initial_state(&mut initial_state);
        let outputs = indices("Outputs");
        let mut expected_derivatives = Vec::new();
        let mut expected_outputs = Vec::new();
        for (position, v) in description.variables.all().iter().enumerate() {
            let node = variables[position];
            let real = child(node, "Real");
            match v.role {
                Role::Derivative(i) => {
                    expected_derivatives.push(position + 1);
                    let state = description.variables.value_reference(Role::State(i)) as usize + 1;
                    assert_eq!(
                        real.attribute("derivative"),
                        Some(state.to_string().as_str())
                    );
                    let state_name = variables[state - 1].attribute("name").unwrap();
                    assert_eq!(v.name, format!("der({state_name})"));
                }
                Role::Output(_) => {
                    expected_outputs.push(position + 1);
                    assert_eq!(node.attribute("causality"), Some("output"));
                }
                Role::Parameter(_) => {
                    assert_eq!(node.attribute("causality"), Some("parameter"));
                    assert_eq!(node.attribute("variability"), Some("tunable"));
                    let start: f64 = real.attribute("start").unwrap().parse().unwrap();
                    assert_eq!(Some(start), v.start);
                }
                Role::State(i) => {
                    // Settable at initialisation: exact, starting at the initial state
                    // of the default parameters, and not an initial unknown.
                    assert_eq!(node.attribute("causality"), Some("local"));
                    assert_eq!(node.attribute("initial"), Some("exact"));
                    let start: f64 = real.attribute("start").unwrap().parse().unwrap();
                    assert_eq!(start, initial_state[i], "{}", v.name);
                    assert!(!indices("InitialUnknowns").contains(&(position + 1)));
                }
                Role::Input(_) => {}
            }
        }
        assert_eq!(derivatives, expected_derivatives, "{}", entry.identifier());
        assert_eq!(outputs, expected_outputs, "{}", entry.identifier());
    }
}

#[test]
fn vector_parameters_are_flattened_with_indices_from_one() {
    let description = ModelDescription::of::<QuickReturn>();
    let names: Vec<_> = description
        .variables
        .all()
        .iter()
        .map(|v| v.name.as_str())
        .collect();
    for (name, start) in [
        ("l1[1]", 0.2),
        ("l1[2]", 0.01),
        ("l1[3]", 0.01),
        ("K3C[1]", 0.0),
    ] {
        let v = description
            .variables
            .find(name)
            .unwrap_or_else(|| panic!("no {name} in {names:?}"));
        assert_eq!(v.start, Some(start), "{name}");
    }
    let parameters = description
        .variables
        .all()
        .iter()
        .filter(|v| matches!(v.role, Role::Parameter(_)))
        .count();
    assert_eq!(parameters, QuickReturn::N_PARAMETER_VALUES);
    assert_eq!(description.naming.as_str(), "structured");
}

#[test]
fn guids_are_stable_and_differ_between_models() {
    let guids: BTreeSet<_> = MODELS.iter().map(|e| e.describe().guid).collect();
    assert_eq!(guids.len(), MODELS.len());
    for entry in MODELS {
        assert_eq!(entry.describe().guid, entry.describe().guid);
    }
}

#[test]
fn the_shared_library_exports_every_fmi2_function() {
    const FUNCTIONS: [&str; 44] = [
        "fmi2GetTypesPlatform",
        "fmi2GetVersion",
        "fmi2SetDebugLogging",
        "fmi2Instantiate",
        "fmi2FreeInstance",
        "fmi2SetupExperiment",
        "fmi2EnterInitializationMode",
        "fmi2ExitInitializationMode",
        "fmi2Terminate",
        "fmi2Reset",
        "fmi2GetReal",
        "fmi2GetInteger",
        "fmi2GetBoolean",
        "fmi2GetString",
        "fmi2SetReal",
        "fmi2SetInteger",
        "fmi2SetBoolean",
        "fmi2SetString",
        "fmi2GetFMUstate",
        "fmi2SetFMUstate",
        "fmi2FreeFMUstate",
        "fmi2SerializedFMUstateSize",
        "fmi2SerializeFMUstate",
        "fmi2DeSerializeFMUstate",
        "fmi2GetDirectionalDerivative",
        "fmi2EnterEventMode",
        "fmi2NewDiscreteStates",
        "fmi2EnterContinuousTimeMode",
        "fmi2CompletedIntegratorStep",
        "fmi2SetTime",
        "fmi2SetContinuousStates",
        "fmi2GetDerivatives",
        "fmi2GetEventIndicators",
        "fmi2GetContinuousStates",
        "fmi2GetNominalsOfContinuousStates",
        "fmi2SetRealInputDerivatives",
        "fmi2GetRealOutputDerivatives",
        "fmi2DoStep",
        "fmi2CancelStep",
        "fmi2GetStatus",
        "fmi2GetRealStatus",
        "fmi2GetIntegerStatus",
        "fmi2GetBooleanStatus",
        "fmi2GetStringStatus",
    ];
    let library = bgdsl_fmi::find_library().expect("cargo test builds the library");
    let bytes = std::fs::read(&library).unwrap();
    for function in FUNCTIONS {
        let symbol = format!("{function}\0");
        assert!(
            bytes.windows(symbol.len()).any(|w| w == symbol.as_bytes()),
            "{} does not export {function}",
            library.display()
        );
    }
}

#[test]
fn an_fmu_is_written_whole_into_a_folder() {
    let library = bgdsl_fmi::find_library().expect("cargo test builds the library");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("write-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let written = bgdsl_fmi::write_fmu("dc_motor", &library, &dir).unwrap();
    assert_eq!(written, dir.join("dc_motor.fmu"));
    let bytes = std::fs::read(&written).unwrap();
    assert_eq!(&bytes[..4], b"PK\x03\x04");
    for name in [
        "modelDescription.xml",
        "binaries/linux64/dc_motor.so",
        "documentation/index.html",
    ] {
        assert!(
            bytes.windows(name.len()).any(|w| w == name.as_bytes()),
            "{name}"
        );
    }
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers, [std::ffi::OsString::from("dc_motor.fmu")]);

    let error = bgdsl_fmi::write_fmu("no_such_model", &library, &dir).unwrap_err();
    assert!(error.to_string().contains("oscillator"), "{error}");
    let not_a_library = dir.join("dc_motor.fmu");
    let error = bgdsl_fmi::write_fmu("oscillator", &not_a_library, &dir.join("x.fmu")).unwrap_err();
    assert!(
        error.to_string().contains("not an FMI 2.0 library"),
        "{error}"
    );
    assert!(!dir.join("x.fmu").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

bgdsl_runtime::bond_graph! {
    /// A model the library was not built with.
    pub model Stranger { param k = 2.0; I mass = 1.0; C spring = k; 1 v;
        v -> { mass, spring }; init spring.q = 1.0; output x = spring.q; }
}

#[test]
fn a_library_that_does_not_serve_the_model_is_refused() {
    let library = bgdsl_fmi::find_library().expect("cargo test builds the library");
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("stranger-{}.fmu", std::process::id()));
    let description = ModelDescription::of::<Stranger>();
    let error = bgdsl_fmi_core::write_fmu(&description, "stranger", &library, &out).unwrap_err();
    assert!(
        matches!(error, bgdsl_fmi_core::FmuError::WrongLibrary { .. }),
        "{error}"
    );
    assert!(
        error.to_string().contains("does not serve model Stranger"),
        "{error}"
    );
    assert!(!out.exists());
}

/// The FMU of `identifier`'s `modelDescription.xml`, as text.
fn xml_of(identifier: &str) -> String {
    let entry = MODELS
        .iter()
        .find(|e| e.identifier() == identifier)
        .unwrap_or_else(|| panic!("no model {identifier}"));
    model_description_xml(&entry.describe(), entry.identifier())
}

/// The `ScalarVariable` called `name` and its `Real`.
fn variable<'a, 'i>(
    doc: &'a roxmltree::Document<'i>,
    name: &str,
) -> (roxmltree::Node<'a, 'i>, roxmltree::Node<'a, 'i>) {
    let node = doc
        .descendants()
        .find(|n| n.has_tag_name("ScalarVariable") && n.attribute("name") == Some(name))
        .unwrap_or_else(|| panic!("no variable {name}"));
    (node, child(node, "Real"))
}

#[test]
fn states_outputs_and_derivatives_carry_the_declared_units_and_docs() {
    let xml = xml_of("oscillator");
    let doc = parsed(&xml);
    let (state, real) = variable(&doc, "spring.q");
    assert_eq!(real.attribute("unit"), Some("m"));
    assert_eq!(
        state.attribute("description"),
        Some("displacement q of C spring")
    );
    let (_, real) = variable(&doc, "der(mass.p)");
    assert_eq!(real.attribute("unit"), Some("kg·m/s/s"));
    let (output, real) = variable(&doc, "spring_force");
    assert_eq!(real.attribute("unit"), Some("N"));
    assert!(output
        .attribute("description")
        .is_some_and(|d| d.starts_with("Force of the spring on the mass")));

    // Vector outputs: every component has the unit; the standard library's states too.
    let xml = xml_of("quick_return");
    let doc = parsed(&xml);
    for name in ["Tc_x", "Tc_y", "Tc_z"] {
        assert_eq!(variable(&doc, name).1.attribute("unit"), Some("N·m"));
    }
    let (state, real) = variable(&doc, "crank.rotation.p_z");
    assert_eq!(real.attribute("unit"), Some("kg·m²/s"));
    assert!(state
        .attribute("description")
        .is_some_and(|d| d.contains("angular momentum")));
    // A coupling's deflection is metres or radians: no unit is claimed.
    assert_eq!(variable(&doc, "j01.spring.q_x").1.attribute("unit"), None);
}

#[test]
fn every_unit_is_defined_in_si_base_units() {
    let base = |xml: &str, unit: &str| -> Vec<(String, String)> {
        let doc = parsed(xml);
        let node = doc
            .descendants()
            .find(|n| n.has_tag_name("Unit") && n.attribute("name") == Some(unit))
            .unwrap_or_else(|| panic!("no unit {unit}"));
        child(node, "BaseUnit")
            .attributes()
            .map(|a| (a.name().to_owned(), a.value().to_owned()))
            .collect()
    };
    let pairs = |list: &[(&str, &str)]| -> Vec<(String, String)> {
        list.iter()
            .map(|(a, b)| ((*a).to_owned(), (*b).to_owned()))
            .collect()
    };
    let oscillator = xml_of("oscillator");
    assert_eq!(
        base(&oscillator, "N"),
        pairs(&[("kg", "1"), ("m", "1"), ("s", "-2")])
    );
    assert_eq!(
        base(&oscillator, "kg·m/s/s"),
        pairs(&[("kg", "1"), ("m", "1"), ("s", "-2")])
    );
    let motor = xml_of("dc_motor");
    assert_eq!(
        base(&motor, "N·m/rad"),
        pairs(&[("kg", "1"), ("m", "2"), ("s", "-2"), ("rad", "-1")])
    );
    // Every unit of every model is read: none is left without its BaseUnit.
    for entry in MODELS {
        let xml = model_description_xml(&entry.describe(), entry.identifier());
        let doc = parsed(&xml);
        for unit in doc.descendants().filter(|n| n.has_tag_name("Unit")) {
            assert!(
                unit.children().any(|n| n.has_tag_name("BaseUnit")),
                "{}: {:?} has no BaseUnit",
                entry.identifier(),
                unit.attribute("name")
            );
        }
    }
}
