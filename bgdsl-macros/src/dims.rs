//! Stage 2b: the dimension of every bond. Bonds meeting at a junction, and the two
//! ports of a TF or GY, share one dimension; an element declared `[n]` fixes the
//! dimension of its bonds (a `Split[n]`: its multibond; its components are scalar); what
//! nothing fixes is a scalar bond. Two declarations that
//! disagree are reported at the second, with a note at the first.

use crate::errors::Errors;
use crate::ir::{BondId, ElementId, ElementKind, Graph};

/// Fills `graph.bond_dims`, or reports every mismatch.
pub fn infer(graph: &mut Graph, errors: &mut Errors) {
    let mut groups = Groups::new(graph.bonds.len());
    for id in graph.element_ids() {
        let element = graph.element(id);
        let joins_its_bonds = matches!(
            element.kind,
            ElementKind::Zero | ElementKind::One | ElementKind::Tf | ElementKind::Gy
        );
        if joins_its_bonds {
            for pair in element.bonds.windows(2) {
                groups.union(pair[0], pair[1]);
            }
        }
    }
    // For each group: its dimension and the element that fixed it.
    let mut fixed: Vec<Option<(usize, ElementId)>> = vec![None; graph.bonds.len()];
    for id in graph.element_ids() {
        let element = graph.element(id);
        let Some((declared, span)) = element.dimension else {
            continue;
        };
        for (port, &bond) in element.bonds.iter().enumerate() {
            // A splitter's components (every port after its multibond) are scalar.
            let dimension = if element.kind == ElementKind::Split && port > 0 {
                1
            } else {
                declared
            };
            let root = groups.find(bond);
            match fixed[root.0] {
                None => fixed[root.0] = Some((dimension, id)),
                Some((other, first)) if other != dimension => {
                    let size = |n: usize| {
                        if n == 1 {
                            "scalar".to_string()
                        } else {
                            format!("{n}-dimensional")
                        }
                    };
                    let what = if element.kind == ElementKind::Split && port > 0 {
                        format!("component {} of {} is", port - 1, graph.describe(id))
                    } else {
                        format!("{} is declared", graph.describe(id))
                    };
                    errors.with_note(
                        span,
                        format!(
                            "dimension mismatch: {what} {}, but its bonds connect it to {}, which is {}; \
                             every bond at a junction, and both ports of a TF or GY, have one dimension",
                            size(dimension),
                            graph.describe(first),
                            size(other),
                        ),
                        graph.element(first).name.span(),
                        format!("{} is declared {} here", graph.describe(first), size(other)),
                    );
                    break;
                }
                Some(_) => {}
            }
        }
    }
    graph.bond_dims = graph
        .bond_ids()
        .map(|b| fixed[groups.find(b).0].map_or(1, |(n, _)| n))
        .collect();
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
            "model M { Se s = 1.0; I[3] m = 1.0; 1 v; TF t = 2.0; 0 w; C k = 1.0; Sf src = 1.0; C k2 = 1.0;
                       s -> v -> { m, t }; t -> w -> k; src -> k2; }",
        );
        assert_eq!(found.unwrap(), [3, 3, 3, 3, 3, 1]);
    }

    #[test]
    fn report_two_declarations_that_disagree() {
        let errors =
            dims("model M { Se[3] s = 1.0; I[2] m = 1.0; 1 v; s -> v -> m; }").unwrap_err();
        assert_eq!(errors.len(), 2, "{errors:?}");
        assert!(
            errors[0].starts_with("dimension mismatch: I `m` is declared 2-dimensional"),
            "{errors:?}"
        );
        assert!(
            errors[1].contains("Se `s` is declared 3-dimensional here"),
            "{errors:?}"
        );
    }
}
