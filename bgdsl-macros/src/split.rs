//! Stage 2c: splitters. A `Split[n]` joins an n-dimensional multibond to its n scalar
//! components, and the components may take different causalities: a point's velocity
//! prescribed along x while a spring holds it along y. Causality is one stroke per
//! bond, so a multibond whose components disagree cannot be drawn as one bond.
//!
//! The junction structure is separable by component (an n-dimensional 0-junction is n
//! scalar 0-junctions side by side), so this stage takes apart every junction reachable
//! from a splitter's multibond through junctions: each becomes n scalar junctions, each
//! multibond between two of them n scalar bonds, and each splitter n two-bond
//! 0-junctions joining its components to theirs. A TF or GY whose modulus is a plain
//! number (see [`scalar_modulus`]) acts on each component alike, so it is taken apart
//! too, into n scalar two-ports with the same modulus, and the region goes on through
//! it: its components may take different causalities. Where the taken-apart region
//! meets an element that acts on the whole vector (a C, I or R, a source, a TF or GY
//! with a matrix modulus), the multibond stays and a splitter is inserted in front of
//! the element: those splitters are the only ones the later stages see, and the
//! element's own causality is uniform across its components anyway.

use quote::format_ident;
use syn::{BinOp, Expr, Lit, UnOp};

use crate::errors::Errors;
use crate::ir::{Bond, BondId, Dissolved, Element, ElementId, ElementKind, Graph, Law, Shape};

/// Takes apart the junction structure around every splitter (see the module docs).
pub fn dissolve(graph: &mut Graph, errors: &mut Errors) {
    let region = region(graph);
    if region.is_empty() {
        return;
    }
    let inside = |id: ElementId| region.binary_search(&id).is_ok();
    let original_elements = graph.elements.len();
    // Which component each of a splitter's scalar bonds is (its ports after the first).
    let mut component_of_bond: Vec<Option<usize>> = vec![None; graph.bonds.len()];
    let mut components: Vec<Vec<ElementId>> = vec![Vec::new(); original_elements];
    for &id in &region {
        let element = graph.element(id);
        let n = dimension_of(graph, id);
        if element.kind == ElementKind::Split {
            for (i, bond) in element.bonds.iter().skip(1).enumerate() {
                component_of_bond[bond.0] = Some(i);
            }
        }
        let kind = match element.kind {
            ElementKind::Split => ElementKind::Zero,
            kind => kind,
        };
        let name = element.name.clone();
        // A two-port's components keep its modulus.
        let modulus = match &element.law {
            Law::Linear(modulus) => Some(modulus.clone()),
            _ => None,
        };
        for i in 0..n {
            let component = format_ident!("{}__{}", name, i, span = name.span());
            let part = push_element(graph, component, kind);
            if let Some(modulus) = &modulus {
                graph.elements[part.0].law = Law::Linear(modulus.clone());
            }
            components[id.0].push(part);
        }
    }
    let old_ports: Vec<Vec<BondId>> = graph
        .elements
        .iter_mut()
        .map(|element| std::mem::take(&mut element.bonds))
        .collect();
    let old_bonds = std::mem::take(&mut graph.bonds);
    let old_dims = std::mem::take(&mut graph.bond_dims);
    // The new bond each old bond became at its end outside the region.
    let mut outside_end: Vec<Option<BondId>> = vec![None; old_bonds.len()];
    for (index, bond) in old_bonds.into_iter().enumerate() {
        let n = old_dims[index];
        let component_at = |end: ElementId| match component_of_bond[index] {
            Some(i) if inside(end) => components[end.0][i],
            _ => end,
        };
        outside_end[index] = Some(match (inside(bond.from), inside(bond.to)) {
            (false, false) => connect(graph, bond.from, bond.to, bond.label, n),
            // A splitter's component: now a bond to that component's 0-junction.
            _ if component_of_bond[index].is_some() => connect(
                graph,
                component_at(bond.from),
                component_at(bond.to),
                bond.label,
                1,
            ),
            (true, true) => {
                if let Some(label) = &bond.label {
                    errors.at(
                        label.span(),
                        format!(
                            "bond `{label}` is taken apart into its components by a splitter, so it \
                             has no single effort or flow to read; label a bond outside the split \
                             junctions, or a component's bond"
                        ),
                    );
                }
                let pairs = components[bond.from.0].iter().zip(&components[bond.to.0]);
                for (&from, &to) in pairs.take(n) {
                    connect(graph, from, to, None, 1);
                }
                continue;
            }
            // Where the region meets an element acting on the whole vector: the
            // multibond stays, a splitter goes in front of the element.
            (from_inside, _) => {
                let (region_end, element_end) = if from_inside {
                    (bond.from, bond.to)
                } else {
                    (bond.to, bond.from)
                };
                let name = graph.element(region_end).name.clone();
                let splitter_name = format_ident!("{}__split{}", name, index, span = name.span());
                let splitter = push_element(graph, splitter_name, ElementKind::Split);
                let whole = if from_inside {
                    connect(graph, splitter, element_end, bond.label, n)
                } else {
                    connect(graph, element_end, splitter, bond.label, n)
                };
                for &component in &components[region_end.0] {
                    if from_inside {
                        connect(graph, component, splitter, None, 1);
                    } else {
                        connect(graph, splitter, component, None, 1);
                    }
                }
                whole
            }
        });
    }
    // Elements outside the region keep their ports in order (a TF's port 1 first).
    for (index, ports) in old_ports.into_iter().enumerate().take(original_elements) {
        graph.elements[index].bonds = if inside(ElementId(index)) {
            Vec::new()
        } else {
            ports.iter().filter_map(|old| outside_end[old.0]).collect()
        };
    }
    // A two-port's components take port 1 (the bond pointing in) first.
    for &id in &region {
        for &part in &components[id.0] {
            let bonds = &graph.elements[part.0].bonds;
            if matches!(
                graph.elements[part.0].kind,
                ElementKind::Tf | ElementKind::Gy
            ) && bonds.len() == 2
                && !graph.bonds[bonds[0].0].points_into(part)
            {
                graph.elements[part.0].bonds.swap(0, 1);
            }
        }
    }
    for &id in &region {
        graph.dissolved.push(Dissolved {
            element: id,
            components: components[id.0].clone(),
        });
    }
}

/// The splitters, and every junction (and TF or GY with a scalar modulus) reachable
/// from a splitter's multibond through junctions and such two-ports, in id order.
fn region(graph: &Graph) -> Vec<ElementId> {
    let mut inside = vec![false; graph.elements.len()];
    let mut stack: Vec<ElementId> = graph
        .element_ids()
        .filter(|&id| graph.element(id).kind == ElementKind::Split)
        .collect();
    while let Some(id) = stack.pop() {
        if std::mem::replace(&mut inside[id.0], true) {
            continue;
        }
        let element = graph.element(id);
        // A splitter is entered from its multibond only (its first port).
        let bonds = match element.kind {
            ElementKind::Split => &element.bonds[..element.bonds.len().min(1)],
            _ => &element.bonds[..],
        };
        for &bond in bonds {
            let next = graph.bond(bond).other(id);
            let joins = match graph.element(next).kind {
                ElementKind::Zero | ElementKind::One | ElementKind::Split => true,
                ElementKind::Tf | ElementKind::Gy => separable(graph, next),
                _ => false,
            };
            if joins && graph.bond_dims[bond.0] > 1 && !inside[next.0] {
                stack.push(next);
            }
        }
    }
    graph.element_ids().filter(|id| inside[id.0]).collect()
}

/// Whether a two-port acts on each component of its multibonds alike: its modulus is
/// a plain number, and it has both its bonds.
fn separable(graph: &Graph, id: ElementId) -> bool {
    let element = graph.element(id);
    match &element.law {
        Law::Linear(modulus) => element.bonds.len() == 2 && scalar_modulus(graph, modulus),
        _ => false,
    }
}

/// Whether an expression is certainly a number, not a vector or matrix: literals,
/// `f64` parameters and inputs, a component of a vector or matrix parameter (`K.x`,
/// `R.m21`), time, and arithmetic and the usual scalar functions of these. Anything
/// else (a matrix parameter, a call of a helper, a signal) may be a matrix, and the
/// two-port then stays whole.
pub fn scalar_modulus(graph: &Graph, expr: &Expr) -> bool {
    let param_shape = |expr: &Expr| -> Option<Shape> {
        let Expr::Path(path) = expr else {
            return None;
        };
        let name = path.path.get_ident()?;
        graph
            .params
            .iter()
            .find(|p| p.name == *name)
            .map(|p| p.shape)
    };
    match expr {
        Expr::Lit(lit) => matches!(lit.lit, Lit::Float(_) | Lit::Int(_)),
        Expr::Path(path) => param_shape(expr) == Some(Shape::Scalar) || path.path.is_ident("t"),
        Expr::Field(field) => param_shape(&field.base).is_some_and(|s| s != Shape::Scalar),
        Expr::Paren(inner) => scalar_modulus(graph, &inner.expr),
        Expr::Group(inner) => scalar_modulus(graph, &inner.expr),
        Expr::Unary(unary) => {
            matches!(unary.op, UnOp::Neg(_)) && scalar_modulus(graph, &unary.expr)
        }
        Expr::Binary(binary) => {
            matches!(
                binary.op,
                BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Div(_)
            ) && scalar_modulus(graph, &binary.left)
                && scalar_modulus(graph, &binary.right)
        }
        Expr::MethodCall(call) => {
            const SCALAR_METHODS: &[&str] = &[
                "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
                "exp", "ln", "log10", "sqrt", "cbrt", "abs", "powi", "powf", "hypot", "min", "max",
                "recip",
            ];
            SCALAR_METHODS.contains(&call.method.to_string().as_str())
                && scalar_modulus(graph, &call.receiver)
                && call
                    .args
                    .iter()
                    .all(|arg| scalar_modulus(graph, arg) || matches!(arg, Expr::Lit(_)))
        }
        _ => false,
    }
}

/// The dimension of a junction's bonds, or a splitter's.
fn dimension_of(graph: &Graph, id: ElementId) -> usize {
    let element = graph.element(id);
    match (element.kind, element.dimension) {
        (ElementKind::Split, Some((n, _))) => n,
        _ => element
            .bonds
            .first()
            .map_or(1, |bond| graph.bond_dims[bond.0]),
    }
}

fn push_element(graph: &mut Graph, name: syn::Ident, kind: ElementKind) -> ElementId {
    let id = ElementId(graph.elements.len());
    graph.elements.push(Element {
        name,
        kind,
        modulated: false,
        law: Law::None,
        dimension: None,
        inverse: None,
        bonds: Vec::new(),
    });
    id
}

fn connect(
    graph: &mut Graph,
    from: ElementId,
    to: ElementId,
    label: Option<syn::Ident>,
    dimension: usize,
) -> BondId {
    let id = BondId(graph.bonds.len());
    graph.bonds.push(Bond { from, to, label });
    graph.bond_dims.push(dimension);
    graph.elements[from.0].bonds.push(id);
    graph.elements[to.0].bonds.push(id);
    id
}

#[cfg(test)]
mod should {
    use crate::ir::Graph;

    fn resolved(text: &str) -> Graph {
        let file: crate::syntax::File = syn::parse_str(text).unwrap();
        crate::resolve::resolve(file.models.into_iter().next().unwrap()).unwrap()
    }

    fn describe(graph: &Graph) -> Vec<String> {
        graph
            .element_ids()
            .map(|id| {
                let element = graph.element(id);
                let bonds: Vec<String> = element
                    .bonds
                    .iter()
                    .map(|&b| {
                        let bond = graph.bond(b);
                        format!(
                            "{}->{}",
                            graph.element(bond.from).name,
                            graph.element(bond.to).name
                        )
                    })
                    .collect();
                format!("{}: {}", element.name, bonds.join(" "))
            })
            .collect()
    }

    #[test]
    fn take_apart_the_junctions_behind_a_splitter() {
        let graph = resolved(
            "model M { I[3] mass = 1.0; Sf a = 1.0; Sf b = 0.0; Se c = 2.0; 1 v; Split[3] s;
                       a -> s.0; b -> s.1; c -> s.2; s -> v -> mass; }",
        );
        assert_eq!(
            describe(&graph),
            [
                "mass: v__split4->mass",
                "a: a->s__0",
                "b: b->s__1",
                "c: c->s__2",
                "v: ",
                "s: ",
                "v__0: s__0->v__0 v__0->v__split4",
                "v__1: s__1->v__1 v__1->v__split4",
                "v__2: s__2->v__2 v__2->v__split4",
                "s__0: a->s__0 s__0->v__0",
                "s__1: b->s__1 s__1->v__1",
                "s__2: c->s__2 s__2->v__2",
                "v__split4: v__split4->mass v__0->v__split4 v__1->v__split4 v__2->v__split4",
            ]
        );
    }

    #[test]
    fn take_apart_a_transformer_with_a_scalar_modulus_and_the_junction_beyond() {
        let graph = resolved(
            "model M { param n = 2.0; I[3] mass = 1.0; Sf a = 1.0; Sf b = 0.0; Se c = 2.0;
                       TF lever = 3.0 * n; 1 v; Split[3] s;
                       a -> s.0; b -> s.1; c -> s.2; s -> lever -> v -> mass; }",
        );
        let described = describe(&graph);
        // Each component of the lever: port 1 from the splitter's component, port 2 to
        // the 1-junction's component, with the lever's modulus.
        assert!(
            described.contains(&"lever__0: s__0->lever__0 lever__0->v__0".to_string()),
            "{described:#?}"
        );
        assert!(
            described.contains(&"lever__2: s__2->lever__2 lever__2->v__2".to_string()),
            "{described:#?}"
        );
        assert!(described.contains(&"lever: ".to_string()), "{described:#?}");
        let lever_0 = graph
            .element_ids()
            .find(|&id| graph.element(id).name == "lever__0")
            .unwrap();
        assert!(matches!(
            graph.element(lever_0).law,
            crate::ir::Law::Linear(_)
        ));
    }

    #[test]
    fn take_apart_a_gyrator_with_a_scalar_modulus_keeping_port_1_first() {
        // Port 2 is written first: each component still takes port 1 first.
        let graph = resolved(
            "model M { I[3] mass = 1.0; Sf a = 1.0; Sf b = 0.0; Se c = 2.0; GY g = 0.5; 1 v;
                       Split[3] s; g -> v -> mass; a -> s.0; b -> s.1; c -> s.2; s -> g; }",
        );
        let described = describe(&graph);
        assert!(
            described.contains(&"g__1: s__1->g__1 g__1->v__1".to_string()),
            "{described:#?}"
        );
    }

    #[test]
    fn keep_a_transformer_whose_modulus_may_be_a_matrix_whole() {
        let graph = resolved(
            "model M { param M: Matrix3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
                       I[3] mass = 1.0; Sf a = 1.0; Sf b = 0.0; Sf c = 2.0;
                       MTF lever = M, inverse = M; 1 v; Split[3] s;
                       a -> s.0; b -> s.1; c -> s.2; s -> lever -> v -> mass; }",
        );
        let described = describe(&graph);
        assert!(
            described.contains(&"lever: s__split3->lever lever->v".to_string()),
            "{described:#?}"
        );
    }

    #[test]
    fn tell_a_plain_number_from_what_may_be_a_matrix() {
        let graph = resolved(
            "model M { param n = 2.0; param K: [f64; 3] = [1.0, 2.0, 3.0];
                       param R: Matrix3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
                       input u = 0.0; Se s = 1.0; I m = 1.0; s -> m; }",
        );
        let scalar = |text: &str| super::scalar_modulus(&graph, &syn::parse_str(text).unwrap());
        for text in [
            "2.0",
            "3",
            "n",
            "-n * (0.5 + K.x) / 2.0",
            "R.m21",
            "u",
            "(t * n).sin()",
            "n.powi(2)",
        ] {
            assert!(scalar(text), "{text} is a number");
        }
        for text in ["R", "K", "R.transpose()", "diag3(n, n, n)", "m.e", "n * R"] {
            assert!(!scalar(text), "{text} may be a matrix");
        }
    }
}
