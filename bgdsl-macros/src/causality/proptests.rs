//! SCAP on random graphs: it never panics; on success every bond has one stroke and
//! every junction, two-port, source, storage element and resistor obeys its rule, and
//! the equations derived from it are ordered or reported as an algebraic loop; on
//! failure, an exhaustive search over all stroke assignments confirms that no
//! assignment meets every element's requirement.
//! Test code only: declared `#[cfg(test)] mod proptests;` in `causality/mod.rs`.

use proc_macro2::Span;
use proptest::prelude::*;
use syn::{parse_quote, Ident};

use super::*;
use crate::ir::{Bond, BondId, Element, Graph, Law};

/// A one-port to hang on a junction: its kind and, for resistors, which forms it has.
#[derive(Clone, Copy, Debug)]
enum Leaf {
    Se,
    Sf,
    C,
    I,
    /// (has `e = φ(f)`, has `f = φ(e)`)
    R(bool, bool),
}

#[derive(Clone, Debug)]
struct Recipe {
    junction_is_zero: Vec<bool>,
    /// (from junction, to junction): tree edges first, then extra ones.
    links: Vec<(usize, usize)>,
    /// (junction, kind, bond points into the leaf)
    leaves: Vec<(usize, Leaf, bool)>,
    /// (from junction, to junction, gyrator?)
    two_ports: Vec<(usize, usize, bool)>,
}

fn leaf() -> impl Strategy<Value = Leaf> {
    prop_oneof![
        1 => Just(Leaf::Se),
        1 => Just(Leaf::Sf),
        3 => Just(Leaf::C),
        3 => Just(Leaf::I),
        2 => Just(Leaf::R(true, true)),
        1 => Just(Leaf::R(true, false)),
        1 => Just(Leaf::R(false, true)),
    ]
}

fn recipe() -> impl Strategy<Value = Recipe> {
    (1usize..5).prop_flat_map(|junctions| {
        let tree = proptest::collection::vec(any::<prop::sample::Index>(), junctions - 1);
        let extra = proptest::collection::vec((0..junctions, 0..junctions), 0..2);
        let leaves = proptest::collection::vec((0..junctions, leaf(), any::<bool>()), 1..7);
        let two_ports =
            proptest::collection::vec((0..junctions, 0..junctions, any::<bool>()), 0..3);
        let kinds = proptest::collection::vec(any::<bool>(), junctions);
        (kinds, tree, extra, leaves, two_ports).prop_map(
            |(kinds, tree, extra, leaves, two_ports)| {
                let mut links: Vec<(usize, usize)> = tree
                    .iter()
                    .enumerate()
                    .map(|(i, parent)| (parent.index(i + 1), i + 1))
                    .collect();
                links.extend(extra.into_iter().filter(|(a, b)| a != b));
                Recipe {
                    junction_is_zero: kinds,
                    links,
                    leaves,
                    two_ports: two_ports.into_iter().filter(|(a, b, _)| a != b).collect(),
                }
            },
        )
    })
}

fn build(recipe: &Recipe) -> Graph {
    let mut graph = Graph {
        attrs: Vec::new(),
        vis: syn::Visibility::Inherited,
        name: Ident::new("Random", Span::call_site()),
        params: Vec::new(),
        elements: Vec::new(),
        bonds: Vec::new(),
        inits: Vec::new(),
        outputs: Vec::new(),
        kinematics: Vec::new(),
        bond_dims: Vec::new(),
        dissolved: Vec::new(),
        storage: Vec::new(),
        allowances: Vec::new(),
        modes: Vec::new(),
        events: Vec::new(),
        bodies: Vec::new(),
    };
    let add_element = |graph: &mut Graph, kind: ElementKind, law: Law| {
        let id = ElementId(graph.elements.len());
        let name = Ident::new(&format!("x{}", id.0), Span::call_site());
        graph.elements.push(Element {
            name,
            kind,
            modulated: false,
            law,
            dimension: None,
            inverse: None,
            bonds: Vec::new(),
        });
        id
    };
    let connect = |graph: &mut Graph, from: ElementId, to: ElementId| {
        let id = BondId(graph.bonds.len());
        graph.bonds.push(Bond {
            from,
            to,
            label: None,
        });
        graph.elements[from.0].bonds.push(id);
        graph.elements[to.0].bonds.push(id);
    };
    let linear = || Law::Linear(parse_quote!(1.0));
    let junctions: Vec<ElementId> = recipe
        .junction_is_zero
        .iter()
        .map(|&zero| {
            add_element(
                &mut graph,
                if zero {
                    ElementKind::Zero
                } else {
                    ElementKind::One
                },
                Law::None,
            )
        })
        .collect();
    for &(a, b) in &recipe.links {
        connect(&mut graph, junctions[a], junctions[b]);
    }
    for &(from, to, gyrator) in &recipe.two_ports {
        let kind = if gyrator {
            ElementKind::Gy
        } else {
            ElementKind::Tf
        };
        let two_port = add_element(&mut graph, kind, linear());
        connect(&mut graph, junctions[from], two_port);
        connect(&mut graph, two_port, junctions[to]);
    }
    for &(junction, leaf, inward) in &recipe.leaves {
        let (kind, law) = match leaf {
            Leaf::Se => (ElementKind::Se, linear()),
            Leaf::Sf => (ElementKind::Sf, linear()),
            Leaf::C => (ElementKind::C, linear()),
            Leaf::I => (ElementKind::I, linear()),
            Leaf::R(true, true) => (ElementKind::R, linear()),
            Leaf::R(effort, _) => (
                ElementKind::R,
                Law::Forms {
                    effort: effort.then(|| parse_quote!(f)),
                    flow: (!effort).then(|| parse_quote!(e)),
                },
            ),
        };
        let element = add_element(&mut graph, kind, law);
        if inward {
            connect(&mut graph, junctions[junction], element);
        } else {
            connect(&mut graph, element, junctions[junction]);
        }
    }
    // Junctions need two bonds: top up with resistors.
    for &junction in &junctions {
        while graph.element(junction).bonds.len() < 2 {
            let r = add_element(&mut graph, ElementKind::R, linear());
            connect(&mut graph, junction, r);
        }
    }
    graph.bond_dims = vec![1; graph.bonds.len()];
    graph
}

/// Whether `stroke_at` satisfies every element's rule: junctions, two-ports, sources,
/// storage in integral causality and resistors in a form their law gives.
fn valid(graph: &Graph, stroke_at: &[ElementId]) -> Result<(), String> {
    for id in graph.element_ids() {
        let element = graph.element(id);
        let at_self = |b: BondId| stroke_at[b.0] == id;
        let ok = match element.kind {
            ElementKind::Zero => element.bonds.iter().filter(|&&b| at_self(b)).count() == 1,
            ElementKind::One => element.bonds.iter().filter(|&&b| !at_self(b)).count() == 1,
            ElementKind::Tf => at_self(element.bonds[0]) != at_self(element.bonds[1]),
            ElementKind::Gy => at_self(element.bonds[0]) == at_self(element.bonds[1]),
            // Effort in on the multibond exactly when it goes out on every component.
            ElementKind::Split => element.bonds[1..]
                .iter()
                .all(|&b| at_self(b) != at_self(element.bonds[0])),
            ElementKind::Se | ElementKind::C => !at_self(element.bonds[0]),
            ElementKind::Sf | ElementKind::I => at_self(element.bonds[0]),
            ElementKind::R => match &element.law {
                Law::Forms { effort: None, .. } => at_self(element.bonds[0]),
                Law::Forms { flow: None, .. } => !at_self(element.bonds[0]),
                _ => true,
            },
        };
        if !ok {
            return Err(format!("{} breaks its rule", graph.describe(id)));
        }
    }
    Ok(())
}

/// Exhaustive search: is there any stroke assignment meeting every rule?
fn some_valid_assignment_exists(graph: &Graph) -> bool {
    let n = graph.bonds.len();
    (0u32..1 << n).any(|mask| {
        let strokes: Vec<ElementId> = graph
            .bond_ids()
            .map(|b| {
                let bond = graph.bond(b);
                if mask >> b.0 & 1 == 1 {
                    bond.to
                } else {
                    bond.from
                }
            })
            .collect();
        valid(graph, &strokes).is_ok()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn scap_is_sound_on_random_graphs(recipe in recipe()) {
        let graph = build(&recipe);
        prop_assume!(graph.bonds.len() <= 16);
        match assign(&graph) {
            Ok(causality) => {
                prop_assert_eq!(causality.stroke_at.len(), graph.bonds.len());
                for b in graph.bond_ids() {
                    let at = causality.stroke_at[b.0];
                    let bond = graph.bond(b);
                    prop_assert!(at == bond.from || at == bond.to, "stroke off the bond");
                }
                if let Err(message) = valid(&graph, &causality.stroke_at) {
                    return Err(TestCaseError::fail(message));
                }
                match crate::equations::derive(&graph, &causality) {
                    Ok(equations) => {
                        // Every bond variable computed once, after everything it reads.
                        let mut known: Vec<crate::signals::Signal> =
                            (0..equations.states.len()).map(crate::signals::Signal::State).collect();
                        for eq in &equations.ordered {
                            for dep in &eq.deps {
                                prop_assert!(known.contains(dep), "{:?} read before it is computed", dep);
                            }
                            prop_assert!(!known.contains(&eq.defines), "{:?} computed twice", eq.defines);
                            known.push(eq.defines);
                        }
                        prop_assert_eq!(known.len(), equations.states.len() + 2 * graph.bonds.len());
                    }
                    Err(error) => {
                        let message = error.to_string();
                        prop_assert!(message.starts_with("algebraic loop: "), "{}", message);
                    }
                }
            }
            Err(errors) => {
                prop_assert!(!errors.is_empty());
                // The end-of-search junction check is an internal invariant.
                prop_assert!(
                    !errors.iter().any(|e| matches!(e, CausalityError::Junction { .. })),
                    "the junction invariant broke: {:?}", errors
                );
                prop_assert!(
                    !some_valid_assignment_exists(&graph),
                    "SCAP reported {:?} but a valid assignment exists", errors
                );
                for error in &errors {
                    // Rendering never panics and points somewhere.
                    let _ = render(&graph, error).to_string();
                }
            }
        }
    }
}

/// The generator must exercise both branches above, or the property says little.
#[test]
fn random_graphs_cover_success_failure_and_loops() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let (mut ok, mut failed, mut loops) = (0, 0, 0);
    for _ in 0..1000 {
        let graph = build(&recipe().new_tree(&mut runner).unwrap().current());
        match assign(&graph) {
            Ok(causality) => {
                ok += 1;
                if crate::equations::derive(&graph, &causality).is_err() {
                    loops += 1;
                }
            }
            Err(_) => failed += 1,
        }
    }
    assert!(
        ok > 150 && failed > 150 && loops > 20,
        "ok {ok}, failed {failed}, loops {loops}"
    );
}
