//! Stage 2b: the dimension of every bond.
//!
//! The rule, so that an element is never silently a different element than written:
//!
//! - Bonds meeting at a junction share one dimension.
//! - A one-port (Se, Sf, C, I, R) has the dimension of its own `[n]`, else the one its
//!   law visibly has (`Se push = vec3(..)`, `C k = diag3(..)`, a coefficient parameter
//!   declared `Vector3`/`Matrix3`), else it is **scalar**. It never takes a dimension
//!   from the junction it meets: a scalar damper on a 3-D junction is an error that
//!   says to write `R[3]` or to project with an MTF.
//! - A two-port (TF, GY) declared `[n]`, or whose modulus is a number, joins its two
//!   bonds into one dimension. Otherwise its modulus is an n₂×n₁ matrix between a
//!   port-1 bond of dimension n₁ and a port-2 bond of dimension n₂: a modulus whose
//!   shape the text shows (see [`crate::value_shape`]) fixes both, one the macro cannot
//!   read passes a port's dimension on to the other when only one is known (it is
//!   taken to be square), and a shape that does not fit the bonds is reported.
//! - A `Split[n]`'s multibond is n-dimensional, its components scalar.
//! - What nothing fixes is scalar.
//!
//! A disagreement is reported at the element that meets a junction of another
//! dimension, naming that junction, both dimensions and the element that fixed the
//! junction's, with the fix.

use syn::Expr;

use crate::errors::Errors;
use crate::ir::{BondId, ElementId, ElementKind, Graph, Law};
use crate::value_shape::{self, ValueShape};

/// Why a group of bonds has its dimension.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Origin {
    /// `[n]` on the element.
    Declared,
    /// The element's law (a one-port's value or coefficient, a two-port's modulus)
    /// has this shape.
    Law(ValueShape),
    /// A one-port with no `[n]` and no vector law: scalar.
    Undeclared,
    /// A two-port whose modulus the macro cannot read passes its other port's on.
    Across,
}

/// One element's say on the dimension of one of its bonds.
#[derive(Clone, Copy)]
struct Claim {
    element: ElementId,
    bond: BondId,
    /// For a splitter's component, which one.
    component: Option<usize>,
    dimension: usize,
    origin: Origin,
}

/// A two-port: what its modulus looks like, and whether it joins its bonds into one
/// dimension.
struct TwoPort {
    element: ElementId,
    ports: (BondId, BondId),
    modulus: Option<ValueShape>,
    joins: bool,
}

fn is_one_port(kind: ElementKind) -> bool {
    matches!(
        kind,
        ElementKind::Se | ElementKind::Sf | ElementKind::C | ElementKind::I | ElementKind::R
    )
}

/// The modulus of a TF or GY, if it has a linear law.
fn modulus(graph: &Graph, id: ElementId) -> Option<&Expr> {
    match &graph.element(id).law {
        Law::Linear(expr) => Some(expr),
        _ => None,
    }
}

/// The dimension a one-port's law shows: a vector value for a source, a square matrix
/// coefficient for C, I and R.
fn law_dimension(graph: &Graph, id: ElementId) -> Option<(usize, ValueShape)> {
    let element = graph.element(id);
    let Law::Linear(expr) = &element.law else {
        return None;
    };
    let shape = value_shape::infer(expr, graph)?;
    let source = matches!(element.kind, ElementKind::Se | ElementKind::Sf);
    match shape {
        ValueShape::Matrix(n, 1) if source && n > 1 => Some((n, shape)),
        ValueShape::Matrix(r, c) if !source && r == c && r > 1 => Some((r, shape)),
        _ => None,
    }
}

fn size(n: usize) -> String {
    if n == 1 {
        "scalar".to_string()
    } else {
        format!("{n}-dimensional")
    }
}

/// Fills `graph.bond_dims`, or reports every mismatch.
pub fn infer(graph: &mut Graph, errors: &mut Errors) {
    let mut groups = Groups::new(graph.bonds.len());
    let mut two_ports = Vec::new();
    for id in graph.element_ids() {
        let element = graph.element(id);
        let joins_its_bonds = match element.kind {
            ElementKind::Zero | ElementKind::One => true,
            ElementKind::Tf | ElementKind::Gy => {
                let shape = modulus(graph, id).and_then(|m| value_shape::infer(m, graph));
                let joins = element.dimension.is_some() || shape == Some(ValueShape::Number);
                if let [b1, b2] = element.bonds[..] {
                    two_ports.push(TwoPort {
                        element: id,
                        ports: (b1, b2),
                        modulus: shape,
                        joins,
                    });
                }
                joins
            }
            _ => false,
        };
        if joins_its_bonds {
            for pair in element.bonds.windows(2) {
                groups.union(pair[0], pair[1]);
            }
        }
    }
    // Declarations first, then what laws show, then undeclared one-ports: the
    // disagreement is reported at the weaker claim.
    let mut claims = Vec::new();
    for id in graph.element_ids() {
        let element = graph.element(id);
        if let Some((declared, _)) = element.dimension {
            for (port, &bond) in element.bonds.iter().enumerate() {
                // A splitter's components (every port after its multibond) are scalar.
                let component = (element.kind == ElementKind::Split && port > 0).then(|| port - 1);
                claims.push(Claim {
                    element: id,
                    bond,
                    component,
                    dimension: if component.is_some() { 1 } else { declared },
                    origin: Origin::Declared,
                });
            }
        }
    }
    let undeclared_one_ports: Vec<ElementId> = graph
        .element_ids()
        .filter(|&id| {
            let element = graph.element(id);
            is_one_port(element.kind) && element.dimension.is_none()
        })
        .collect();
    for &id in &undeclared_one_ports {
        if let Some((dimension, shape)) = law_dimension(graph, id) {
            claims.extend(graph.element(id).bonds.iter().map(|&bond| Claim {
                element: id,
                bond,
                component: None,
                dimension,
                origin: Origin::Law(shape),
            }));
        }
    }
    for &id in &undeclared_one_ports {
        if law_dimension(graph, id).is_none() {
            claims.extend(graph.element(id).bonds.iter().map(|&bond| Claim {
                element: id,
                bond,
                component: None,
                dimension: 1,
                origin: Origin::Undeclared,
            }));
        }
    }
    // For each group: the claim that fixed its dimension.
    let mut fixed: Vec<Option<Claim>> = vec![None; graph.bonds.len()];
    let mut reported = vec![false; graph.elements.len()];
    for claim in claims {
        let root = groups.find(claim.bond);
        match fixed[root.0] {
            None => fixed[root.0] = Some(claim),
            Some(first) if first.dimension != claim.dimension => {
                if !std::mem::replace(&mut reported[claim.element.0], true) {
                    mismatch(graph, errors, claim, first);
                }
            }
            Some(_) => {}
        }
    }
    across_two_ports(&mut groups, &mut fixed, &two_ports);
    graph.bond_dims = graph
        .bond_ids()
        .map(|b| fixed[groups.find(b).0].map_or(1, |claim| claim.dimension))
        .collect();
    for two_port in &two_ports {
        check_modulus(graph, errors, two_port);
    }
}

/// Two-ports between bonds of possibly different dimensions: a readable modulus
/// fixes what is still open on either side; an unreadable one passes a known side's
/// dimension on to an open one. Repeated until nothing changes, so chains settle.
fn across_two_ports(groups: &mut Groups, fixed: &mut [Option<Claim>], two_ports: &[TwoPort]) {
    loop {
        let mut changed = false;
        for two_port in two_ports.iter().filter(|two_port| !two_port.joins) {
            let (b1, b2) = two_port.ports;
            let (r1, r2) = (groups.find(b1), groups.find(b2));
            let known = |r: BondId| fixed[r.0].map(|claim| claim.dimension);
            // (port 1, port 2) dimensions the modulus wants, given what is known.
            let wanted = match (two_port.modulus, known(r1), known(r2)) {
                (_, Some(_), Some(_)) => None,
                (Some(ValueShape::Matrix(r, c)), n1, n2) => {
                    (n1.unwrap_or(c) == c && n2.unwrap_or(r) == r).then_some((c, r))
                }
                (_, Some(n), None) | (_, None, Some(n)) => Some((n, n)),
                _ => None,
            };
            let Some((n1, n2)) = wanted else {
                continue;
            };
            let origin = match two_port.modulus {
                Some(shape) => Origin::Law(shape),
                None => Origin::Across,
            };
            for (root, bond, dimension) in [(r1, b1, n1), (r2, b2, n2)] {
                if fixed[root.0].is_none() {
                    fixed[root.0] = Some(Claim {
                        element: two_port.element,
                        bond,
                        component: None,
                        dimension,
                        origin,
                    });
                    changed = true;
                }
            }
        }
        if !changed {
            return;
        }
    }
}

/// A two-port's modulus whose shape the text shows must be n₂×n₁ between its bonds.
fn check_modulus(graph: &Graph, errors: &mut Errors, two_port: &TwoPort) {
    let (Some(shape), Some(expr)) = (two_port.modulus, modulus(graph, two_port.element)) else {
        return;
    };
    let (b1, b2) = two_port.ports;
    let (n1, n2) = (graph.bond_dims[b1.0], graph.bond_dims[b2.0]);
    let fits = match shape {
        ValueShape::Number => n1 == n2,
        ValueShape::Matrix(r, c) => (r, c) == (n2, n1) && (r, c) != (1, 1),
    };
    if fits {
        return;
    }
    let id = two_port.element;
    let meets = |bond: BondId| graph.describe(graph.bond(bond).other(id));
    let needed = if n1 == 1 && n2 == 1 {
        "a number".to_string()
    } else if n1 == n2 {
        format!("a number or a {n2}×{n1} matrix")
    } else {
        format!("a {n2}×{n1} matrix")
    };
    let laws = if graph.element(id).kind == ElementKind::Gy {
        "e2 = M f1, e1 = Mᵀ f2"
    } else {
        "f2 = M f1, e1 = Mᵀ e2"
    };
    errors.push(syn::Error::new_spanned(
        expr,
        format!(
            "{} joins a {} bond at port 1 (from {}) to a {} bond at port 2 (to {}), so its \
             modulus must be {needed} ({laws}), but this is {}\n\
             help: an r×c modulus takes a c-dimensional bond to an r-dimensional one: the \
             projection of a 3-D velocity on a direction `n` is `MTF proj = n.transpose();` \
             (1×3), a 3-D vector from a scalar along `n` is `MTF along = n;` (3×1)",
            graph.describe(id),
            size(n1),
            meets(b1),
            size(n2),
            meets(b2),
            shape.describe(),
        ),
    ));
}

/// Reports `claim`, which disagrees with the `first` claim on its bond's group.
fn mismatch(graph: &Graph, errors: &mut Errors, claim: Claim, first: Claim) {
    let element = graph.element(claim.element);
    let meets_id = graph.bond(claim.bond).other(claim.element);
    let meets = graph.describe(meets_id);
    let (here, other) = (claim.dimension, first.dimension);
    let what = match (claim.origin, claim.component) {
        (_, Some(i)) => format!(
            "component {i} of {} is scalar",
            graph.describe(claim.element)
        ),
        (Origin::Declared, None) => {
            format!(
                "{} is declared {}",
                graph.describe(claim.element),
                size(here)
            )
        }
        (Origin::Law(shape), None) => format!(
            "{} is {} (its law is {})",
            graph.describe(claim.element),
            size(here),
            shape.describe()
        ),
        (Origin::Undeclared | Origin::Across, None) => format!(
            "{} has no `[n]`, so it is a scalar element",
            graph.describe(claim.element)
        ),
    };
    let why = explain(graph, first);
    let junction = matches!(
        graph.element(meets_id).kind,
        ElementKind::Zero | ElementKind::One
    );
    let help = if claim.origin == Origin::Undeclared && is_one_port(element.kind) {
        let name = crate::flatten::display(&element.name.to_string());
        format!(
            "a one-port takes its dimension only from its own `[n]` (or a law that is visibly \
             a vector or matrix), never from the junction it meets\n\
             help: for an element acting alike on every component write `{}[{other}] {name}`; \
             to act along one direction `n` only, put a projection between {meets} and it: \
             `MTF proj = n.transpose();` with `param n: Vector3`",
            element.kind.word(),
        )
    } else if let Some(i) = claim.component {
        let name = crate::flatten::display(&element.name.to_string());
        format!(
            "a splitter's components are scalar\n\
             help: bond `{name}.{i}` to a scalar element, and a multibond to `{name}` itself"
        )
    } else {
        let mend = if junction {
            format!("give the elements meeting at {meets} one dimension (`[{other}]` here)")
        } else {
            "declare both ends of the bond alike".to_string()
        };
        format!(
            "every bond at a junction, and both ports of a TF or GY with a number for modulus, \
             have one dimension\n\
             help: {mend}, or put between them a splitter (`Split[n]`: a multibond and its \
             scalar components) or an MTF whose modulus is an r×c matrix (it takes a \
             c-dimensional bond to an r-dimensional one)"
        )
    };
    let meeting = if meets_id == first.element {
        format!("it is bonded to {meets}, which is {}", size(other))
    } else {
        format!("it meets {meets}, whose bonds are {} ({why})", size(other))
    };
    let span = match (claim.origin, element.dimension) {
        (Origin::Declared, Some((_, span))) if claim.component.is_none() => span,
        _ => element.name.span(),
    };
    errors.with_note(
        span,
        format!("dimension mismatch: {what}, but {meeting}; {help}"),
        graph.element(first.element).name.span(),
        format!("{why} here"),
    );
}

/// Why the first claim fixed its group: "Se `s` is declared 3-dimensional".
fn explain(graph: &Graph, claim: Claim) -> String {
    let who = graph.describe(claim.element);
    let n = size(claim.dimension);
    match (claim.origin, claim.component) {
        (_, Some(i)) => format!("component {i} of {who} is scalar"),
        (Origin::Declared, None) => format!("{who} is declared {n}"),
        (Origin::Law(shape), None) => format!("{who} is {n}: its law is {}", shape.describe()),
        (Origin::Undeclared, None) => format!("{who} has no `[n]`, so it is scalar"),
        (Origin::Across, None) => format!("{who} passes on its other port's dimension, {n}"),
    }
}

/// Union-find over bonds.
struct Groups {
    parent: Vec<usize>,
}

impl Groups {
    fn new(n: usize) -> Self {
        Groups {
            parent: (0..n).collect(),
        }
    }

    fn find(&mut self, bond: BondId) -> BondId {
        let mut i = bond.0;
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        BondId(i)
    }

    fn union(&mut self, a: BondId, b: BondId) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.parent[a.0.max(b.0)] = a.0.min(b.0);
        }
    }
}

#[cfg(test)]
mod should {
    fn dims(text: &str) -> Result<Vec<usize>, Vec<String>> {
        let file: crate::syntax::File = syn::parse_str(text).unwrap();
        crate::resolve::resolve(file.models.into_iter().next().unwrap())
            .map(|g| g.bond_dims)
            .map_err(|e| e.into_iter().map(|e| e.to_string()).collect())
    }

    #[test]
    fn spread_a_declared_dimension_through_junctions_and_two_ports() {
        // Bonds: 0 s->v, 1 v->m, 2 v->t, 3 t->w, 4 w->k, 5 src->k2.
        let found = dims(
            "model M { Se[3] s = 1.0; I[3] m = 1.0; 1 v; TF t = 2.0; 0 w; C[3] k = 1.0; Sf src = 1.0; C k2 = 1.0;
                       s -> v -> { m, t }; t -> w -> k; src -> k2; }",
        );
        assert_eq!(found.unwrap(), [3, 3, 3, 3, 3, 1]);
    }

    #[test]
    fn take_a_one_port_dimension_from_a_law_that_shows_it() {
        // Bonds: 0 s->v, 1 v->m, 2 v->k.
        let found = dims(
            "model M { param K: Matrix3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
                       Se s = vec3(1.0, 0.0, 0.0); I m = diag3(1.0, 1.0, 1.0); C k = K; 1 v;
                       s -> v -> { m, k }; }",
        );
        assert_eq!(found.unwrap(), [3, 3, 3]);
    }

    #[test]
    fn refuse_an_undeclared_one_port_on_a_multibond_junction() {
        let errors = dims("model M { I[3] m = 1.0; R d = 2.0; 1 v; v -> { m, d }; }").unwrap_err();
        assert_eq!(errors.len(), 2, "{errors:?}");
        let message = &errors[0];
        assert!(
            message.starts_with(
                "dimension mismatch: R `d` has no `[n]`, so it is a scalar element, but it meets \
                 1-junction `v`, whose bonds are 3-dimensional (I `m` is declared 3-dimensional)"
            ),
            "{message}"
        );
        assert!(message.contains("`R[3] d`"), "{message}");
        assert!(message.contains("MTF proj = n.transpose()"), "{message}");
    }

    #[test]
    fn give_each_side_of_a_rectangular_modulus_its_own_dimension() {
        // Bonds: 0 v->m, 1 v->proj, 2 proj->d: a 3-D junction projected on a scalar
        // damper; then 3 s->along, 4 along->w, 5 w->k: a scalar side taken to 3-D.
        let found = dims(
            "model M { param n: Vector3 = [0.0, 0.0, 1.0];
                       I[3] m = 1.0; 1 v; MTF proj = n.transpose(); R d = 2.0;
                       I s = 1.0; MTF along = n; 1 w; C[3] k = 1.0;
                       v -> { m, proj }; proj -> d; s -> along -> w -> k; }",
        );
        assert_eq!(found.unwrap(), [3, 3, 1, 1, 3, 3]);
    }

    #[test]
    fn pass_a_known_dimension_across_a_modulus_it_cannot_read() {
        // Bonds: 0 v->m, 1 v->turn, 2 turn->w, 3 w->k: nothing but the mass fixes w.
        let found = dims(
            "model M { I[3] m = 1.0; 1 v; MTF turn = my_rotation(t); 0 w; C[3] k = 1.0;
                       v -> { m, turn }; turn -> w -> k; }",
        );
        assert_eq!(found.unwrap(), [3, 3, 3, 3]);
    }

    #[test]
    fn report_a_modulus_of_the_wrong_shape_for_its_bonds() {
        let errors = dims(
            "model M { param n: Vector3 = [0.0, 0.0, 1.0];
                       I[3] m = 1.0; 1 v; MTF proj = n; R d = 2.0; v -> { m, proj }; proj -> d; }",
        )
        .unwrap_err();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(
            errors[0].starts_with(
                "MTF `proj` joins a 3-dimensional bond at port 1 (from 1-junction `v`) to a scalar \
                 bond at port 2 (to R `d`), so its modulus must be a 1×3 matrix"
            ),
            "{errors:?}"
        );
        assert!(
            errors[0].contains("but this is a 3×1 matrix (a 3-vector)"),
            "{errors:?}"
        );
    }

    #[test]
    fn report_a_rectangular_modulus_on_a_two_port_declared_square() {
        let errors = dims(
            "model M { param n: Vector3 = [0.0, 0.0, 1.0];
                       I[3] m = 1.0; 1 v; MTF[3] proj = n.transpose(); C[3] k = 1.0;
                       v -> { m, proj }; proj -> k; }",
        )
        .unwrap_err();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(
            errors[0].contains("so its modulus must be a number or a 3×3 matrix"),
            "{errors:?}"
        );
    }

    #[test]
    fn report_two_declarations_that_disagree_where_they_meet() {
        let errors =
            dims("model M { Se[3] s = 1.0; I[2] m = 1.0; 1 v; s -> v -> m; }").unwrap_err();
        assert_eq!(errors.len(), 2, "{errors:?}");
        assert!(
            errors[0].starts_with(
                "dimension mismatch: I `m` is declared 2-dimensional, but it meets 1-junction \
                 `v`, whose bonds are 3-dimensional (Se `s` is declared 3-dimensional)"
            ),
            "{errors:?}"
        );
        assert!(errors[0].contains("help: "), "{errors:?}");
        assert!(
            errors[1].contains("Se `s` is declared 3-dimensional here"),
            "{errors:?}"
        );
    }
}
