//! A description of a model's causal bond graph, as data: what the macro decided at
//! compile time, for drawing the graph and for inspecting causality.

/// The kind of a bond-graph element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ElementKind {
    /// Effort source.
    Se,
    /// Flow source.
    Sf,
    /// Capacitive storage (a spring, a capacitor).
    C,
    /// Inertial storage (a mass, an inductor).
    I,
    /// Resistor (a damper, a resistor).
    R,
    /// Transformer.
    Tf,
    /// Gyrator.
    Gy,
    /// 0-junction (common effort).
    Zero,
    /// 1-junction (common flow).
    One,
    /// Splitter: a multibond and its scalar components.
    Split,
}

impl ElementKind {
    /// The kind as written in a `bond_graph!` block.
    pub const fn keyword(self) -> &'static str {
        match self {
            ElementKind::Se => "Se",
            ElementKind::Sf => "Sf",
            ElementKind::C => "C",
            ElementKind::I => "I",
            ElementKind::R => "R",
            ElementKind::Tf => "TF",
            ElementKind::Gy => "GY",
            ElementKind::Zero => "0",
            ElementKind::One => "1",
            ElementKind::Split => "Split",
        }
    }
}

/// The causality an element ended up with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ElementCausality {
    /// Storage element integrating its input (its state is a state of the model).
    Integral,
    /// Resistor computing its effort from its flow (`e = φ(f)`).
    Resistance,
    /// Resistor computing its flow from its effort (`f = φ⁻¹(e)`).
    Conductance,
    /// Anything whose causality is fixed by its kind (sources, junctions, TF, GY).
    Fixed,
    /// Storage element in derivative causality (dependent storage, allowed by
    /// `#[allow(derivative_causality)]`): its co-energy variable follows from the
    /// independent states, and its state is not a state of the model.
    Derivative,
}

/// One element of the graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GraphElement {
    /// The element's name in the model (inside a submodel instance, its local name).
    pub name: &'static str,
    /// The submodel instance the element belongs to, as a path such as `"crank"` or
    /// `"crank.A1"`; empty for the model's own elements.
    pub group: &'static str,
    /// Its kind. A modulated element (MSe, MSf, MTF, MGY) has the kind of its
    /// unmodulated form, since it obeys the same causal rules.
    pub kind: ElementKind,
    /// Written in its modulated form (`MTF arm = ...`); only a source, TF or GY can be.
    pub modulated: bool,
    /// The causality it was assigned.
    pub causality: ElementCausality,
}

impl GraphElement {
    /// The kind as the model wrote it: `MTF` for a modulated transformer, else
    /// [`ElementKind::keyword`].
    pub const fn keyword(&self) -> &'static str {
        match (self.kind, self.modulated) {
            (ElementKind::Se, true) => "MSe",
            (ElementKind::Sf, true) => "MSf",
            (ElementKind::Tf, true) => "MTF",
            (ElementKind::Gy, true) => "MGY",
            (kind, _) => kind.keyword(),
        }
    }
}

/// One bond of the graph: power flows from `from` to `to` (the half arrow points at
/// `to`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GraphBond {
    /// The bond's label, if the model gave it one.
    pub label: Option<&'static str>,
    /// Index into [`CausalGraph::elements`] of the element the bond leaves.
    pub from: usize,
    /// Index into [`CausalGraph::elements`] of the element the half arrow points at.
    pub to: usize,
    /// 1 for a scalar bond, n for an n-dimensional multibond.
    pub dimension: usize,
    /// Index of the element at the causal-stroke end: the element the bond's effort acts
    /// on (it receives the effort and answers with the flow).
    pub stroke_at: usize,
}

/// A model's causal bond graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CausalGraph {
    /// The model's name.
    pub model: &'static str,
    /// Elements in declaration order.
    pub elements: &'static [GraphElement],
    /// Bonds in declaration order.
    pub bonds: &'static [GraphBond],
    /// The algebraic loops the model allows (`#[allow(algebraic_loops)]`), each as the
    /// indices into [`CausalGraph::elements`] of the elements on it; empty for a model
    /// whose equations are explicit.
    pub loops: &'static [&'static [usize]],
}
