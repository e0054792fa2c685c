//! Names as the model writes them: Rust keywords as raw identifiers (`r#loop`), shown
//! without their `r#` in state, output, parameter and graph names, and modulated
//! elements (MTF, MSe) shown with the kind the model wrote.

use bgdsl_runtime::{bond_graph, ElementKind, Model};

bond_graph! {
    /// An oscillator whose every name is a Rust keyword, driving a damper through a
    /// modulated transformer.
    pub model Keywords {
        /// mass
        param r#type = 2.0;
        /// stiffness
        param k = 100.0;

        MSe r#in = 1.0 + 0.0 * t;
        I r#loop = r#type;
        C r#match = k;
        MTF r#ref = 2.0;
        R r#box = 0.5;
        1 r#for;

        r#in -[r#as]-> r#for -> { r#loop, r#match, r#ref };
        r#ref -> r#box;

        init r#match.q = 0.01;
        output r#fn = r#loop.f;
        output speed = r#for.f + 0.0 * r#type;
    }
}

bond_graph! {
    /// A damper whose names are keywords, for an instance named by a keyword too.
    submodel Damping(c) {
        R r#box = c;
        1 r#in;
        r#in -> r#box;
    }

    /// A submodel instance, a kinematic state and an input named by keywords.
    pub model KeywordParts {
        input r#do = 1.0;
        Se push = r#do;
        I mass = 1.0;
        1 v;
        Damping r#use(c = 0.5);
        push -> v -> { mass, r#use.r#in };
        state r#mod: f64 = 0.0;
        der r#mod = v.f;
        output r#while = r#use.r#box.e;
    }
}

mod should {
    use super::*;

    /// The equations, by hand: v = p / m; the TF gives f2 = n v, the damper e2 = r f2,
    /// and back e1 = n e2 = n² r v; so dp/dt = F - k q - n² r v, dq/dt = v.
    #[test]
    fn compute_a_model_named_with_keywords() {
        let model = Keywords::default();
        let mut x = [0.0; 2];
        model.initial_state(&mut x);
        assert_eq!(x, [0.0, 0.01]);
        let x = [0.4, 0.01];
        let mut dx = [0.0; 2];
        model.derivatives(0.0, &x, &mut dx);
        let (m, k, n, r, force) = (2.0, 100.0, 2.0, 0.5, 1.0);
        let v = x[0] / m;
        let expected = [force - k * x[1] - n * n * r * v, v];
        assert!(
            dx.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12),
            "{dx:?} != {expected:?}"
        );
        let mut y = [0.0; 2];
        model.outputs(0.0, &x, &mut y);
        assert_eq!(y, [v, v]);
    }

    #[test]
    fn show_keyword_names_without_their_raw_prefix() {
        assert_eq!(Keywords::STATE_NAMES, ["loop.p", "match.q"]);
        let outputs: Vec<&str> = Keywords::OUTPUTS.iter().map(|o| o.name).collect();
        assert_eq!(outputs, ["fn", "speed"]);
        let params: Vec<&str> = Keywords::PARAMETERS.iter().map(|p| p.name).collect();
        assert_eq!(params, ["type", "k"]);
        let names: Vec<&str> = Keywords::GRAPH.elements.iter().map(|e| e.name).collect();
        assert_eq!(names, ["in", "loop", "match", "ref", "box", "for"]);
        assert_eq!(Keywords::GRAPH.bonds[0].label, Some("as"));
        let dot = Keywords::GRAPH.to_dot();
        assert!(!dot.contains("r#"), "{dot}");
    }

    /// The parameter struct's fields are raw identifiers in Rust and plain names in
    /// serialised form.
    #[test]
    fn read_keyword_parameters_by_their_plain_names() {
        let params: KeywordsParams = serde_yaml::from_str("type: 3.0\nk: 50.0\n").unwrap();
        assert_eq!((params.r#type, params.k), (3.0, 50.0));
        let state = KeywordsState {
            loop_p: 1.0,
            match_q: 2.0,
        };
        assert_eq!(state.loop_p + state.match_q, 3.0);
    }

    /// Inside an instance a raw name is a plain part of the path (`use.box`), and a
    /// kinematic state and an input named by keywords are named without `r#`.
    #[test]
    fn name_keyword_parts_of_instances_states_and_inputs_plainly() {
        assert_eq!(KeywordParts::STATE_NAMES, ["mass.p", "mod"]);
        let outputs: Vec<&str> = KeywordParts::OUTPUTS.iter().map(|o| o.name).collect();
        assert_eq!(outputs, ["while"]);
        let inputs: Vec<&str> = <KeywordParts as bgdsl_runtime::WithInputs>::INPUTS
            .iter()
            .map(|i| i.name)
            .collect();
        assert_eq!(inputs, ["do"]);
        let damper = KeywordParts::GRAPH
            .elements
            .iter()
            .find(|e| e.kind == ElementKind::R)
            .unwrap();
        assert_eq!((damper.group, damper.name), ("use", "box"));
        // The damper's effort is c times the common velocity p / m.
        let model = KeywordParts::default();
        let (x, mut y) = ([2.0, 0.0], [0.0]);
        model.outputs(0.0, &x, &mut y);
        assert_eq!(y, [0.5 * 2.0]);
        let state = KeywordPartsState {
            mass_p: 1.0,
            r#mod: 2.0,
        };
        assert_eq!(state.r#mod, 2.0);
    }

    /// MTF and MSe keep the kind the compiler gives them (TF, Se) and the word the
    /// model wrote, for drawings and listings.
    #[test]
    fn keep_the_modulated_kind_as_written() {
        let arm = &Keywords::GRAPH.elements[3];
        assert_eq!(
            (arm.kind, arm.modulated, arm.keyword()),
            (ElementKind::Tf, true, "MTF")
        );
        let push = &Keywords::GRAPH.elements[0];
        assert_eq!((push.kind, push.keyword()), (ElementKind::Se, "MSe"));
        let mass = &Keywords::GRAPH.elements[1];
        assert_eq!((mass.modulated, mass.keyword()), (false, "I"));
        assert!(Keywords::GRAPH.to_dot().contains(r#"label="MTF : ref""#));
    }
}
