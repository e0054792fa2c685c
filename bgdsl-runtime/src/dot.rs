//! Graphviz DOT export of a [`CausalGraph`], drawn the way bond graphs are drawn.
//!
//! ```
//! # use bgdsl_runtime::{CausalGraph, ElementCausality, ElementKind, GraphBond, GraphElement};
//! # const GRAPH: CausalGraph = CausalGraph {
//! #     model: "Push",
//! #     elements: &[
//! #         GraphElement { name: "force", group: "", kind: ElementKind::Se, modulated: false, causality: ElementCausality::Fixed },
//! #         GraphElement { name: "mass", group: "", kind: ElementKind::I, modulated: false, causality: ElementCausality::Integral },
//! #     ],
//! #     bonds: &[GraphBond { label: None, from: 0, to: 1, dimension: 1, stroke_at: 1 }],
//! #     loops: &[],
//! # };
//! let dot = GRAPH.to_dot(); // or `write!(file, "{}", GRAPH.dot())`
//! assert!(dot.contains(r#"e0 -> e1 [arrowhead="teelvee", arrowtail="none"];"#));
//! // `dot -Tsvg model.dot -o model.svg` draws it.
//! ```
//!
//! # Conventions
//!
//! - **Elements** are plain text, no box: `Se : supply`, `C : spring`, `TF : gear`.
//!   Junctions are their symbol, `0` or `1`, with their name in small type underneath.
//!   Nodes are named `e<index>` after their index in [`CausalGraph::elements`].
//! - **Bonds** are edges `from -> to` with `dir=both`, so both ends carry a symbol:
//!   - the **half arrow** (power direction) is at the `to` end: arrowhead `lvee`, a
//!     barb on the left of the direction of travel, as in `⇀` (barb up on a bond
//!     drawn rightwards, on the right of a bond drawn downwards, as in `⇂`);
//!   - the **causal stroke** is a `tee`, at the [`stroke_at`](crate::GraphBond::stroke_at)
//!     end: at the head it joins the half arrow, `arrowhead="teelvee"` (the stroke
//!     outermost, the arrow's tip against it); at the tail it is `arrowtail="tee"`
//!     (and the head is a bare `lvee`).
//!
//!   A bond whose `stroke_at` is neither of its ends gets no stroke, and a DOT comment
//!   says so.
//! - **Multibonds** (any dimension but 1) are drawn as a double line,
//!   `color="black:black"` (Graphviz draws one line per colour, 2 points apart; a third,
//!   invisible colour would also hide the tail's stroke, which Graphviz draws in the
//!   second colour), with their dimension as the edge label.
//! - A bond's **label**, when it has one, is the edge label (above the dimension of a
//!   multibond).
//! - **Submodel instances**: elements with a non-empty `group` sit in
//!   `subgraph cluster_<path>` (every character other than an ASCII letter, digit or `_`
//!   replaced by `_`, a numeric suffix when two paths would collide), labelled with the
//!   group path; `crank.A1` is a cluster inside `crank`'s, which exists even when no
//!   element sits directly in `crank`.
//! - Names, labels and paths are escaped for DOT (`"` and `\`, line breaks as `\n`) and,
//!   inside the junctions' HTML-like labels, for HTML.
//! - **Derivative causality** (dependent storage, `#[allow(derivative_causality)]`):
//!   the storage element's text is red (`fontcolor="red"`, its tooltip says
//!   "derivative causality"), and so are its bonds (`color="red"`, `red:red` for a
//!   multibond), causal stroke and all.
//! - **Algebraic loops** (`#[allow(algebraic_loops)]`, [`CausalGraph::loops`]): each
//!   member is outlined in orange (`shape=box, style="rounded,bold", color="orange"`,
//!   its tooltip says so), and a bond between two members of one loop is orange and
//!   bold (`color="orange", penwidth=2`; red wins on a bond that is both).
//! - A **legend** node (`legend`, at the end of the nodes) explains the two markings,
//!   each only when the graph has it; a graph with neither is drawn without.
//! - The output is deterministic: elements in declaration order within their cluster,
//!   clusters in the order their first element was declared, bonds in declaration order.

use core::fmt::{self, Display, Write};

use crate::graph::{CausalGraph, ElementCausality, ElementKind, GraphElement};

impl CausalGraph {
    /// The graph as a self-contained Graphviz DOT `digraph` (see [the module
    /// documentation](crate::dot) for how it is drawn).
    pub fn to_dot(&self) -> String {
        self.dot().to_string()
    }

    /// The graph in Graphviz DOT, as a value to format (`write!(out, "{}", graph.dot())`)
    /// without building a `String` first.
    pub fn dot(&self) -> Dot<'_> {
        Dot { graph: self }
    }
}

/// A [`CausalGraph`] formatted as Graphviz DOT; made by [`CausalGraph::dot`].
#[derive(Clone, Copy, Debug)]
pub struct Dot<'a> {
    graph: &'a CausalGraph,
}

impl Display for Dot<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let graph = self.graph;
        writeln!(f, "digraph {} {{", quoted(graph.model))?;
        writeln!(
            f,
            "  graph [label={}, labelloc=t, fontsize=16];",
            quoted(graph.model)
        )?;
        writeln!(f, "  node [shape=plaintext, fontsize=14];")?;
        writeln!(
            f,
            "  edge [dir=both, arrowhead=lvee, arrowtail=none, fontsize=10];"
        )?;
        let tree = Tree::new(graph);
        tree.write(f, graph, 0, 1)?;
        let has_derivative = graph.elements.iter().any(is_dependent);
        let has_loop = graph.loops.iter().any(|members| !members.is_empty());
        if has_derivative || has_loop {
            writeln!(f, "  legend {};", Legend(has_derivative, has_loop))?;
        }
        for (index, bond) in graph.bonds.iter().enumerate() {
            let ends = graph.elements.len();
            if bond.from >= ends || bond.to >= ends {
                writeln!(
                    f,
                    "  // bond {index} ({} -> {}) joins a missing element; not drawn",
                    bond.from, bond.to
                )?;
                continue;
            }
            let (arrowhead, arrowtail) = if bond.stroke_at == bond.to {
                ("teelvee", "none")
            } else if bond.stroke_at == bond.from {
                ("lvee", "tee")
            } else {
                writeln!(
                    f,
                    "  // bond {index}: stroke_at {} is neither of its ends; no stroke drawn",
                    bond.stroke_at
                )?;
                ("lvee", "none")
            };
            write!(
                f,
                "  e{} -> e{} [arrowhead=\"{arrowhead}\", arrowtail=\"{arrowtail}\"",
                bond.from, bond.to
            )?;
            let mut label = bond.label.map(str::to_owned);
            let dependent =
                is_dependent(&graph.elements[bond.from]) || is_dependent(&graph.elements[bond.to]);
            let looped = graph
                .loops
                .iter()
                .any(|members| members.contains(&bond.from) && members.contains(&bond.to));
            let colour = if dependent {
                "red"
            } else if looped {
                "orange"
            } else {
                "black"
            };
            if dependent {
                f.write_str(", tooltip=\"derivative causality\"")?;
            }
            if colour != "black" {
                if bond.dimension == 1 {
                    write!(f, ", color=\"{colour}\"")?;
                } else {
                    write!(f, ", color=\"{colour}:{colour}\"")?;
                }
            }
            if looped {
                f.write_str(", penwidth=2")?;
            }
            if bond.dimension != 1 {
                if colour == "black" {
                    f.write_str(", color=\"black:black\"")?;
                }
                let dimension = bond.dimension.to_string();
                label = Some(match label {
                    Some(label) => format!("{label}\n{dimension}"),
                    None => dimension,
                });
            }
            if let Some(label) = label {
                write!(f, ", label={}", quoted(&label))?;
            }
            f.write_str("];\n")?;
        }
        f.write_str("}\n")
    }
}

/// The submodel instances as a tree of clusters; cluster 0 is the top level.
struct Tree<'g> {
    clusters: Vec<Cluster<'g>>,
}

struct Cluster<'g> {
    /// The group path (empty for the top level).
    path: &'g str,
    /// The DOT identifier, `cluster_...` (empty for the top level).
    id: String,
    /// Indices of the elements directly in this group, in declaration order.
    elements: Vec<usize>,
    /// Indices of the clusters nested directly in this one, in order of appearance.
    children: Vec<usize>,
}

impl<'g> Tree<'g> {
    /// Junctions without bonds (a submodel's unused port, a junction or splitter taken
    /// apart into its components) are left out.
    fn new(graph: &'g CausalGraph) -> Self {
        let root = Cluster {
            path: "",
            id: String::new(),
            elements: Vec::new(),
            children: Vec::new(),
        };
        let mut tree = Tree {
            clusters: vec![root],
        };
        let connected = |index: usize| {
            graph
                .bonds
                .iter()
                .any(|bond| bond.from == index || bond.to == index)
        };
        for (index, element) in graph.elements.iter().enumerate() {
            let junction = matches!(
                element.kind,
                ElementKind::Zero | ElementKind::One | ElementKind::Split
            );
            if junction && !connected(index) {
                continue;
            }
            let cluster = tree.cluster(element.group);
            tree.clusters[cluster].elements.push(index);
        }
        tree
    }

    /// The index of the cluster of `path`, created (with its ancestors) if new.
    fn cluster(&mut self, path: &'g str) -> usize {
        if path.is_empty() {
            return 0;
        }
        if let Some(found) = self.clusters.iter().position(|c| c.path == path) {
            return found;
        }
        let parent = match path.rsplit_once('.') {
            Some((parent, _)) => self.cluster(parent),
            None => 0,
        };
        let id = self.unused_id(path);
        self.clusters.push(Cluster {
            path,
            id,
            elements: Vec::new(),
            children: Vec::new(),
        });
        let index = self.clusters.len() - 1;
        self.clusters[parent].children.push(index);
        index
    }

    /// `cluster_` and the path with anything but ASCII letters, digits and `_` replaced
    /// by `_`, with a suffix `_2`, `_3`, ... if another path already gave that name.
    fn unused_id(&self, path: &str) -> String {
        let sanitised: String = path
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        let base = format!("cluster_{sanitised}");
        let mut id = base.clone();
        let mut suffix = 2;
        while self.clusters.iter().any(|c| c.id == id) {
            id = format!("{base}_{suffix}");
            suffix += 1;
        }
        id
    }

    fn write(
        &self,
        f: &mut fmt::Formatter<'_>,
        graph: &CausalGraph,
        cluster: usize,
        depth: usize,
    ) -> fmt::Result {
        let cluster = &self.clusters[cluster];
        let indent = "  ".repeat(depth);
        for &index in &cluster.elements {
            let on_loop = graph.loops.iter().any(|members| members.contains(&index));
            let node = NodeAttributes(&graph.elements[index], on_loop);
            writeln!(f, "{indent}e{index} {node};")?;
        }
        for &child in &cluster.children {
            let nested = &self.clusters[child];
            writeln!(f, "{indent}subgraph {} {{", nested.id)?;
            writeln!(
                f,
                "{indent}  graph [label={}, style=\"rounded,dashed\", fontsize=11];",
                quoted(nested.path)
            )?;
            self.write(f, graph, child, depth + 1)?;
            writeln!(f, "{indent}}}")?;
        }
        Ok(())
    }
}

/// Whether `element` is a storage element in derivative causality.
fn is_dependent(element: &GraphElement) -> bool {
    element.causality == ElementCausality::Derivative
}

/// The legend node's label: one row per marking the graph has (derivative causality,
/// algebraic loops).
struct Legend(bool, bool);

impl Display for Legend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("[shape=plaintext, fontsize=10, tooltip=\"legend\", label=<")?;
        f.write_str("<TABLE BORDER=\"1\" CELLBORDER=\"0\" CELLSPACING=\"2\" COLOR=\"gray\">")?;
        if self.0 {
            f.write_str(
                "<TR><TD><FONT COLOR=\"red\">red</FONT></TD>\
                 <TD ALIGN=\"LEFT\">derivative causality (dependent storage)</TD></TR>",
            )?;
        }
        if self.1 {
            f.write_str(
                "<TR><TD><FONT COLOR=\"orange\">orange</FONT></TD>\
                 <TD ALIGN=\"LEFT\">algebraic loop (solved at each evaluation)</TD></TR>",
            )?;
        }
        f.write_str("</TABLE>>]")
    }
}

/// `[label=..., tooltip=...]` for one element, and whether it is on an algebraic loop.
struct NodeAttributes<'a>(&'a GraphElement, bool);

impl Display for NodeAttributes<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let element = self.0;
        let on_loop = self.1;
        let keyword = element.keyword();
        match element.kind {
            ElementKind::Zero | ElementKind::One if element.name.is_empty() => {
                write!(f, "[label={}", quoted(keyword))?
            }
            ElementKind::Zero | ElementKind::One => write!(
                f,
                "[label=<{keyword}<BR/><FONT POINT-SIZE=\"9\">{}</FONT>>",
                Html(element.name)
            )?,
            _ => write!(
                f,
                "[label={}",
                quoted(&format!("{keyword} : {}", element.name))
            )?,
        }
        let path = if element.group.is_empty() {
            element.name.to_owned()
        } else {
            format!("{}.{}", element.group, element.name)
        };
        let causality = match element.causality {
            ElementCausality::Integral => ", integral causality",
            ElementCausality::Resistance => ", resistance causality (e = R(f))",
            ElementCausality::Conductance => ", conductance causality (f = R⁻¹(e))",
            ElementCausality::Fixed => "",
            ElementCausality::Derivative => ", derivative causality (dependent storage)",
        };
        if is_dependent(element) {
            f.write_str(", fontcolor=\"red\"")?;
        }
        let loop_note = if on_loop {
            f.write_str(", shape=box, style=\"rounded,bold\", color=\"orange\"")?;
            ", on an algebraic loop solved at each evaluation"
        } else {
            ""
        };
        write!(
            f,
            ", tooltip={}]",
            quoted(&format!("{keyword} {path}{causality}{loop_note}"))
        )
    }
}

/// A DOT double-quoted string: `"` and `\` escaped, line breaks as `\n` (a centred
/// line break in a label), carriage returns dropped.
fn quoted(text: &str) -> Quoted<'_> {
    Quoted(text)
}

struct Quoted<'a>(&'a str);

impl Display for Quoted<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_char('"')?;
        for c in self.0.chars() {
            match c {
                '"' => f.write_str("\\\"")?,
                '\\' => f.write_str("\\\\")?,
                '\n' => f.write_str("\\n")?,
                '\r' => {}
                c => f.write_char(c)?,
            }
        }
        f.write_char('"')
    }
}

/// Text inside a Graphviz HTML-like label: `&`, `<`, `>`, `"` and `'` as entities,
/// line breaks as `<BR/>`.
struct Html<'a>(&'a str);

impl Display for Html<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for c in self.0.chars() {
            match c {
                '&' => f.write_str("&amp;")?,
                '<' => f.write_str("&lt;")?,
                '>' => f.write_str("&gt;")?,
                '"' => f.write_str("&quot;")?,
                '\'' => f.write_str("&#39;")?,
                '\n' => f.write_str("<BR/>")?,
                '\r' => {}
                c => f.write_char(c)?,
            }
        }
        Ok(())
    }
}
