//! Causality asserted on the IR: which bond got which stroke, which element forced which.
//! Test code only: declared `#[cfg(test)] mod tests;` in `causality/mod.rs`.

use super::*;
use crate::ir::Graph;

fn graph(text: &str) -> Graph {
    let file: crate::syntax::File = syn::parse_str(text).unwrap();
    crate::resolve::resolve(file.models.into_iter().next().unwrap()).unwrap()
}

fn id(graph: &Graph, name: &str) -> ElementId {
    graph
        .element_ids()
        .find(|&i| graph.element(i).name == name)
        .unwrap()
}

/// The element at the stroke end of the bond between `a` and `b`.
fn stroke(graph: &Graph, causality: &Causality, a: &str, b: &str) -> String {
    let (a, b) = (id(graph, a), id(graph, b));
    let bond = graph
        .bond_ids()
        .find(|&i| {
            let bond = graph.bond(i);
            (bond.from == a && bond.to == b) || (bond.from == b && bond.to == a)
        })
        .unwrap();
    graph.element(causality.stroke_at[bond.0]).name.to_string()
}

const OSCILLATOR: &str =
    "model M { Se push = 1.0; I mass = 1.0; C spring = 1.0; R damper = 1.0; 1 v;
                          push -> v -> { mass, spring, damper }; }";

#[test]
fn give_storage_integral_causality_around_a_one_junction() {
    let g = graph(OSCILLATOR);
    let c = assign(&g).unwrap();
    // The source and the spring impose efforts on the junction; the mass imposes the
    // common flow, so it receives the effort sum.
    assert_eq!(stroke(&g, &c, "push", "v"), "v");
    assert_eq!(stroke(&g, &c, "v", "mass"), "mass");
    assert_eq!(stroke(&g, &c, "v", "spring"), "v");
    assert_eq!(stroke(&g, &c, "v", "damper"), "v");
    assert_eq!(c.element[id(&g, "damper").0], ElementCausality::Resistance);
    assert_eq!(c.element[id(&g, "mass").0], ElementCausality::Integral);
}

#[test]
fn make_a_resistor_a_conductance_when_a_zero_junction_imposes_its_effort() {
    let g = graph("model M { Se s = 1.0; C c = 1.0; R r = 2.0; R l = 2.0; 0 j; 1 k; s -> k -> {l, j}; j -> {c, r}; }");
    let c = assign(&g).unwrap();
    assert_eq!(stroke(&g, &c, "j", "r"), "r");
    assert_eq!(c.element[id(&g, "r").0], ElementCausality::Conductance);
}

#[test]
fn pass_effort_through_a_transformer() {
    let g = graph("model M { Se s = 1.0; TF t = 2.0; I m = 1.0; s -> t -> m; }");
    let c = assign(&g).unwrap();
    assert_eq!(stroke(&g, &c, "s", "t"), "t");
    assert_eq!(stroke(&g, &c, "t", "m"), "m");
}

#[test]
fn turn_effort_into_flow_through_a_gyrator_and_flag_the_inertia() {
    // A voltage source through a gyrator fixes the flow of what is behind it: an
    // inertia there cannot integrate.
    let g = graph("model M { Se s = 1.0; GY g = 2.0; I m = 1.0; s -> g -> m; }");
    let errors = assign(&g).unwrap_err();
    assert_eq!(
        errors,
        [CausalityError::Derivative {
            element: id(&g, "m"),
            path: vec![id(&g, "s"), id(&g, "g"), id(&g, "m")],
        }]
    );
}

#[test]
fn name_the_inertia_that_forces_another_into_derivative_causality() {
    let g = graph("model M { Se s = 1.0; I a = 1.0; I b = 2.0; 1 v; s -> v -> { a, b }; }");
    let errors = assign(&g).unwrap_err();
    assert_eq!(
        errors,
        [CausalityError::Derivative {
            element: id(&g, "b"),
            path: vec![id(&g, "a"), id(&g, "v"), id(&g, "b")],
        }]
    );
    let message = render(&g, &errors[0]).to_string();
    assert!(
        message.contains("\nhelp: put a compliance between them"),
        "{message}"
    );
    assert!(
        message.contains("`C joint = k;` on it, k a stiffness (e = k q)"),
        "{message}"
    );
}

#[test]
fn report_the_second_of_two_effort_sources_with_the_first() {
    let g =
        graph("model M { Se s1 = 1.0; Se s2 = 2.0; R r = 1.0; 0 j; s1 -> j; s2 -> j; j -> r; }");
    let errors = assign(&g).unwrap_err();
    assert_eq!(
        errors,
        [CausalityError::Conflict {
            second: id(&g, "s2"),
            first: id(&g, "s1"),
            at: None,
            routes: [
                vec![id(&g, "s1"), id(&g, "j")],
                vec![id(&g, "s2"), id(&g, "j")]
            ],
            twice: Some(true),
        }]
    );
}

#[test]
fn ask_for_the_missing_form_of_a_nonlinear_resistor() {
    let g = graph("model M { Se s = 1.0; R c = 1.0; R r { e = f * f }; 0 j; s -> j -> { c, r }; }");
    let errors = assign(&g).unwrap_err();
    assert_eq!(
        errors,
        [CausalityError::MissingForm {
            element: id(&g, "r"),
            needs_flow_form: true,
            forced_by: id(&g, "s"),
            path: vec![id(&g, "s"), id(&g, "j"), id(&g, "r")],
        }]
    );
}

#[test]
fn prefer_the_form_a_free_resistor_is_given() {
    // Two resistors in series with a source leave one of them free to choose; the one
    // given only as f = φ(e) must get conductance causality.
    let g =
        graph("model M { Se s = 1.0; R a = 1.0; R b { f = e / 2.0 }; 1 v; s -> v -> { a, b }; }");
    let c = assign(&g).unwrap();
    assert_eq!(c.element[id(&g, "b").0], ElementCausality::Conductance);
    assert_eq!(c.element[id(&g, "a").0], ElementCausality::Resistance);
}

#[test]
fn keep_independent_conflicts_independent() {
    // Two separate mistakes in one graph: each reported once, neither masking the other.
    let g = graph(
        "model M { Se s1 = 1.0; Se s2 = 2.0; R r = 1.0; 0 j; s1 -> j; s2 -> j; j -> r;
                   Sf f1 = 1.0; Sf f2 = 1.0; I m = 1.0; 1 k; f1 -> k; f2 -> k; k -> m; }",
    );
    let errors = assign(&g).unwrap_err();
    assert_eq!(errors.len(), 3, "{errors:?}");
    assert!(
        matches!(errors[0], CausalityError::Conflict { second, first, .. } if second == id(&g, "s2") && first == id(&g, "s1"))
    );
    assert!(
        matches!(errors[1], CausalityError::Conflict { second, first, .. } if second == id(&g, "f2") && first == id(&g, "f1"))
    );
    // The flow sources fix the 1-junction's flow before the inertia is considered: an
    // inertia behind an ideal flow source is in derivative causality (a real mistake).
    assert!(
        matches!(&errors[2], CausalityError::Derivative { element, path } if *element == id(&g, "m") && path[0] == id(&g, "f1"))
    );
}

#[test]
fn assign_the_same_strokes_every_time() {
    let g = graph(OSCILLATOR);
    let first = assign(&g).unwrap().stroke_at;
    for _ in 0..10 {
        assert_eq!(assign(&g).unwrap().stroke_at, first);
    }
}

#[test]
fn follow_a_conflict_through_a_gyrator() {
    // The source's effort becomes the shaft's flow behind the gyrator, where the flow
    // source sets it too: the route names the gyrator.
    let g = graph(
        "model M { Se s = 1.0; GY g = 0.1; Sf d = 5.0; R r = 0.01; 1 k; s -> g -> k -> r; d -> k; }",
    );
    let errors = assign(&g).unwrap_err();
    let [CausalityError::Conflict {
        second,
        first,
        routes,
        twice,
        ..
    }] = errors.as_slice()
    else {
        panic!("{errors:?}")
    };
    assert_eq!(
        (*second, *first, *twice),
        (id(&g, "d"), id(&g, "s"), Some(true))
    );
    assert_eq!(routes[0], [id(&g, "s"), id(&g, "g"), id(&g, "k")]);
    assert_eq!(routes[1], [id(&g, "d"), id(&g, "k")]);
}

#[test]
fn tell_a_junction_nobody_can_set_from_one_set_twice() {
    let g = graph("model M { Sf a = 1.0; Sf b = 2.0; 0 j; a -> j; b -> j; }");
    let errors = assign(&g).unwrap_err();
    assert!(
        matches!(
            errors.as_slice(),
            [CausalityError::Conflict {
                twice: Some(false),
                ..
            }]
        ),
        "{errors:?}"
    );
    let message = render(&g, &errors[0]).to_string();
    assert!(
        message.starts_with("causal conflict at 0-junction `j`: nothing sets its effort"),
        "{message}"
    );
}

#[test]
fn say_a_broken_junction_invariant_is_a_bug_in_bgdsl() {
    let g = graph("model M { Se s = 1.0; R r = 2.0; 1 v; s -> v -> r; }");
    let error = CausalityError::Junction {
        junction: id(&g, "v"),
        setters: 2,
    };
    let message = render(&g, &error).to_string();
    assert!(message.starts_with("internal error in bgdsl's causality assignment: 1-junction `v` ended with 2 bonds setting its common flow"), "{message}");
    assert!(message.contains("not in your model"), "{message}");
}
