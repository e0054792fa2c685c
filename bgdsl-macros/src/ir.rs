//! Stage 2's product: the bond graph with names resolved to dense, typed ids.
//!
//! Every node keeps the syntax it came from (identifiers, expressions, spans) so that
//! causality and code generation can point at the user's text.

use syn::{Attribute, Expr, Ident, Visibility};

pub use crate::allow::Lint;
pub use crate::syntax::{ElementKind, Shape};

/// Index of an element in [`Graph::elements`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ElementId(pub usize);

/// Index of a bond in [`Graph::bonds`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BondId(pub usize);

/// A resolved model.
pub struct Graph {
    /// Doc comments and attributes of the model.
    pub attrs: Vec<Attribute>,
    /// Visibility of the generated items.
    pub vis: Visibility,
    /// The model's name.
    pub name: Ident,
    /// Parameters in declaration order.
    pub params: Vec<Param>,
    /// Elements in declaration order.
    pub elements: Vec<Element>,
    /// Bonds in the order written.
    pub bonds: Vec<Bond>,
    /// Initial values of storage states that are not zero.
    pub inits: Vec<Init>,
    /// Named outputs in declaration order.
    pub outputs: Vec<Output>,
    /// Kinematic states in declaration order.
    pub kinematics: Vec<Kinematic>,
    /// The dimension of each bond (1 for scalar bonds), once inferred.
    pub bond_dims: Vec<usize>,
    /// Junctions and splitters taken apart into scalar components (see
    /// [`crate::split`]); they keep their names but no bonds.
    pub dissolved: Vec<Dissolved>,
    /// What the model says about the states of its C and I elements: a declared unit
    /// (`C spring = k, q in "m";`) and the element's doc comment.
    pub storage: Vec<StorageNote>,
    /// The bond-graph lints the model allows (`#[allow(derivative_causality)]`), in
    /// the order written.
    pub allowances: Vec<Allowance>,
    /// Discrete modes in declaration order: the last states.
    pub modes: Vec<crate::events::Mode>,
    /// Events (`when` blocks) in declaration order.
    pub events: Vec<crate::events::Event>,
    /// The flat names of the standard library's `RigidBody` instances (see
    /// [`crate::syntax::ModelDef::bodies`]).
    pub bodies: Vec<String>,
}

/// One bond-graph lint allowed somewhere in the model.
pub struct Allowance {
    /// The lint.
    pub lint: Lint,
    /// Its name in the attribute: where an unused allowance is reported.
    pub span: proc_macro2::Span,
    /// What it covers.
    pub scope: AllowScope,
}

/// What an [`Allowance`] covers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AllowScope {
    /// The whole model (written before `model`).
    Model,
    /// One element (written before its declaration); a junction taken apart into
    /// components covers its components.
    Element(ElementId),
    /// The bonds one bond statement makes (written before it).
    Bonds(Vec<BondId>),
}

/// The unit and documentation of a storage element's state.
pub struct StorageNote {
    /// The C or I element.
    pub element: ElementId,
    /// Its state's unit, if declared.
    pub unit: Option<syn::LitStr>,
    /// The element's doc comment, if it has one.
    pub doc: Option<String>,
}

/// A junction or splitter replaced by one scalar element per component (named
/// `name__0`, `name__1`, ..., shown as `name.0`, ...).
pub struct Dissolved {
    /// The element, now without bonds.
    pub element: ElementId,
    /// Its components, in order: a law that reads the junction's common variable gets
    /// theirs, assembled into a vector.
    pub components: Vec<ElementId>,
}

/// A kinematic state: integrated, but not the storage of an element.
pub struct Kinematic {
    /// Its name.
    pub name: Ident,
    /// Its shape.
    pub shape: Shape,
    /// The initial value, an expression in parameters.
    pub init: Expr,
    /// Its time derivative.
    pub der: Expr,
    /// Its unit as declared (`in "m"`).
    pub unit: Option<syn::LitStr>,
    /// Its doc comment, if any.
    pub doc: Option<String>,
}

/// A parameter: an `f64` field of the generated parameter struct.
pub struct Param {
    /// Doc comments (units) and other attributes.
    pub attrs: Vec<Attribute>,
    /// Its name.
    pub name: Ident,
    /// Its shape.
    pub shape: Shape,
    /// The default value, an expression in earlier parameters.
    pub default: Expr,
    /// Its unit as declared (`in "kg"`).
    pub unit: Option<syn::LitStr>,
    /// Declared `input`: a field of the inputs struct the host sets between steps,
    /// not of the parameter struct.
    pub input: bool,
}

/// An element of the graph.
pub struct Element {
    /// Its name.
    pub name: Ident,
    /// Its kind.
    pub kind: ElementKind,
    /// Written as MSe, MSf, MTF or MGY: treated as its kind, shown as written.
    pub modulated: bool,
    /// Its constitutive law.
    pub law: Law,
    /// The dimension declared with `[n]`, and where.
    pub dimension: Option<(usize, proc_macro2::Span)>,
    /// A two-port's inverse modulus, if given.
    pub inverse: Option<Expr>,
    /// Its bonds in the order written. For TF and GY: port 1 (the bond pointing in),
    /// then port 2 (the bond pointing out).
    pub bonds: Vec<BondId>,
}

/// A constitutive law, checked against the element's kind.
pub enum Law {
    /// Junctions have none.
    None,
    /// A coefficient (stiffness for C, inertia for I, resistance for R, modulus for TF and
    /// GY) or a source's value.
    Linear(Expr),
    /// Explicit forms: `e = φ(own variables)` and/or `f = φ(own variables)`.
    Forms {
        /// `e = ...` (C: of q; R: of f).
        effort: Option<Expr>,
        /// `f = ...` (I: of p; R: of e).
        flow: Option<Expr>,
    },
}

impl Law {
    /// Whether a resistor can compute its effort from its flow.
    pub fn has_effort_form(&self) -> bool {
        matches!(
            self,
            Law::Linear(_)
                | Law::Forms {
                    effort: Some(_),
                    ..
                }
        )
    }

    /// Whether a resistor can compute its flow from its effort.
    pub fn has_flow_form(&self) -> bool {
        matches!(self, Law::Linear(_) | Law::Forms { flow: Some(_), .. })
    }
}

/// A bond: power flows from `from` to `to`.
pub struct Bond {
    /// The element the bond leaves.
    pub from: ElementId,
    /// The element the half arrow points at.
    pub to: ElementId,
    /// The bond's label, if the model gave one.
    pub label: Option<Ident>,
}

impl Bond {
    /// The element at the other end from `end`.
    pub fn other(&self, end: ElementId) -> ElementId {
        if self.from == end {
            self.to
        } else {
            self.from
        }
    }

    /// Whether the half arrow points at `end`.
    pub fn points_into(&self, end: ElementId) -> bool {
        self.to == end
    }
}

/// `init element.q = value;`
pub struct Init {
    /// The storage element.
    pub element: ElementId,
    /// Where the element is named in the `init` statement.
    pub span: proc_macro2::Span,
    /// The value, an expression in parameters.
    pub value: Expr,
}

/// `output name = expr;`
pub struct Output {
    /// Doc comments and other attributes.
    pub attrs: Vec<Attribute>,
    /// The output's name.
    pub name: Ident,
    /// Its shape, if declared.
    pub shape: Option<Shape>,
    /// The expression.
    pub expr: Expr,
    /// Its unit as declared (`in "m"`).
    pub unit: Option<syn::LitStr>,
}

impl Graph {
    /// The declared unit and documentation of a C or I element's state.
    pub fn storage_note(&self, id: ElementId) -> Option<&StorageNote> {
        self.storage.iter().find(|note| note.element == id)
    }

    /// What `id` was taken apart into, if it was.
    pub fn dissolved(&self, id: ElementId) -> Option<&Dissolved> {
        self.dissolved.iter().find(|d| d.element == id)
    }

    /// The first allowance of `lint` that covers the model, one of `elements` or one of
    /// `bonds`: its index in [`Graph::allowances`].
    pub fn allowance(&self, lint: Lint, elements: &[ElementId], bonds: &[BondId]) -> Option<usize> {
        self.allowances.iter().position(|allowance| {
            allowance.lint == lint
                && match &allowance.scope {
                    AllowScope::Model => true,
                    AllowScope::Element(id) => elements.iter().any(|&e| {
                        e == *id
                            || self
                                .dissolved(*id)
                                .is_some_and(|d| d.components.contains(&e))
                    }),
                    AllowScope::Bonds(ids) => bonds.iter().any(|b| ids.contains(b)),
                }
        })
    }

    /// The element with this id.
    pub fn element(&self, id: ElementId) -> &Element {
        &self.elements[id.0]
    }

    /// The bond with this id.
    pub fn bond(&self, id: BondId) -> &Bond {
        &self.bonds[id.0]
    }

    /// Ids of all elements, in declaration order.
    pub fn element_ids(&self) -> impl Iterator<Item = ElementId> {
        (0..self.elements.len()).map(ElementId)
    }

    /// Ids of all bonds, in the order written.
    pub fn bond_ids(&self) -> impl Iterator<Item = BondId> {
        (0..self.bonds.len()).map(BondId)
    }

    /// "C spring", "1-junction v": how messages name an element.
    pub fn describe(&self, id: ElementId) -> String {
        let element = self.element(id);
        let name = crate::flatten::display(&element.name.to_string());
        match element.kind {
            ElementKind::Zero | ElementKind::One => format!("{} `{name}`", element.kind.describe()),
            kind => format!("{} `{name}`", kind.written(element.modulated)),
        }
    }
}
