//! The Graphviz DOT export of a causal graph, on hand-built graphs: where each bond's
//! half arrow and causal stroke go, multibonds, labels, clusters for submodel
//! instances, escaping, and determinism. With Graphviz installed, the output is also
//! fed to `dot -Tsvg`.

use std::io::Write as _;
use std::process::{Command, Stdio};

use bgdsl_runtime::{CausalGraph, ElementCausality, ElementKind, GraphBond, GraphElement};

const fn element(
    name: &'static str,
    group: &'static str,
    kind: ElementKind,
    causality: ElementCausality,
) -> GraphElement {
    GraphElement {
        name,
        group,
        kind,
        modulated: false,
        causality,
    }
}

const fn bond(
    from: usize,
    to: usize,
    stroke_at: usize,
    dimension: usize,
    label: Option<&'static str>,
) -> GraphBond {
    GraphBond {
        label,
        from,
        to,
        dimension,
        stroke_at,
    }
}

use ElementCausality::{Conductance, Derivative, Fixed, Integral, Resistance};
use ElementKind::{One, Se, Tf, Zero, C, I, R};

/// A crank driven through a lever: a top-level source and junction, a submodel
/// instance `crank` with a nested `crank.pin`, and `rod.end` whose parent `rod` holds
/// no element of its own. Bonds 2 and 3 are 2-dimensional multibonds; names with
/// quotes, backslashes and HTML's special characters test the escaping.
const CRANK: CausalGraph = CausalGraph {
    model: "Crank",
    elements: &[
        element("drive", "", Se, Fixed),                   // 0
        element("hub", "", One, Fixed),                    // 1
        element("inertia", "crank", I, Integral),          // 2
        element("pin", "crank.pin", Zero, Fixed),          // 3
        element("joint", "crank.pin", C, Integral),        // 4
        element("lever", "crank", Tf, Fixed),              // 5
        element("say \"dry\"", "rod.end", R, Resistance),  // 6
        element("a&b<c>", "rod.end", One, Fixed),          // 7
        element(r"back\slash", "rod.end", R, Conductance), // 8
    ],
    bonds: &[
        bond(0, 1, 1, 1, Some("torque")),    // stroke at the head
        bond(1, 2, 2, 1, None),              // stroke at the head
        bond(1, 3, 1, 2, None),              // multibond, stroke at the tail
        bond(3, 4, 4, 2, Some("q")),         // labelled multibond, stroke at the head
        bond(1, 5, 1, 1, None),              // stroke at the tail
        bond(5, 7, 5, 1, Some("say \"v\"")), // stroke at the tail, label to escape
        bond(7, 6, 7, 1, None),              // stroke at the tail
        bond(7, 8, 8, 1, Some(r"a\b")),      // stroke at the head, label to escape
    ],
    loops: &[],
};

/// Two shafts through a rigid gear (`shaft2` in derivative causality) and two dampers
/// in series (an algebraic loop through `d1`, `j` and `d2`); bond 6 is a multibond on
/// the loop.
const RIGID: CausalGraph = CausalGraph {
    model: "Rigid",
    elements: &[
        element("motor", "", Se, Fixed),      // 0
        element("w1", "", One, Fixed),        // 1
        element("shaft1", "", I, Integral),   // 2
        element("gear", "", Tf, Fixed),       // 3
        element("w2", "", One, Fixed),        // 4
        element("shaft2", "", I, Derivative), // 5
        element("d1", "", R, Resistance),     // 6
        element("j", "", Zero, Fixed),        // 7
        element("d2", "", R, Conductance),    // 8
    ],
    bonds: &[
        bond(0, 1, 1, 1, None),      // 0
        bond(1, 2, 2, 1, None),      // 1
        bond(1, 3, 3, 1, None),      // 2
        bond(3, 4, 3, 1, None),      // 3
        bond(4, 5, 4, 1, Some("p")), // 4: into the dependent inertia
        bond(1, 6, 6, 1, None),      // 5: w1 is not on the loop
        bond(6, 7, 7, 2, None),      // 6: a multibond on the loop
        bond(7, 8, 7, 1, None),      // 7: on the loop
    ],
    loops: &[&[6, 7, 8]],
};

/// The line that draws the edge `e<from> -> e<to>`, exactly one.
fn edge_line(dot: &str, from: usize, to: usize) -> &str {
    let start = format!("e{from} -> e{to} [");
    let lines: Vec<&str> = dot
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with(&start))
        .collect();
    assert_eq!(lines.len(), 1, "edges e{from} -> e{to} in\n{dot}");
    lines[0]
}

/// The line that declares node `e<index>`, exactly one.
fn node_line(dot: &str, index: usize) -> &str {
    let start = format!("e{index} [");
    let lines: Vec<&str> = dot
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with(&start))
        .collect();
    assert_eq!(lines.len(), 1, "declarations of e{index} in\n{dot}");
    lines[0]
}

/// `e<digits> [...]`, not `edge [...]` nor an edge.
fn is_node_declaration(line: &str) -> bool {
    line.strip_prefix('e')
        .is_some_and(|rest| rest.starts_with(|c: char| c.is_ascii_digit()))
        && !line.contains("->")
}

/// For each node declared in `dot`, the stack of `(cluster id, cluster label)` it is
/// declared in, outermost first.
fn clusters_of_nodes(dot: &str) -> Vec<(String, Vec<(String, String)>)> {
    let mut stack: Vec<(String, String)> = Vec::new();
    let mut nodes = Vec::new();
    for line in dot.lines().map(str::trim).skip(1) {
        if let Some(rest) = line.strip_prefix("subgraph ") {
            let id = rest
                .strip_suffix(" {")
                .expect("`subgraph ID {` on one line");
            stack.push((id.to_owned(), String::new()));
        } else if let Some(rest) = line.strip_prefix("graph [label=") {
            if let Some(top) = stack.last_mut() {
                top.1 = rest.split(", style=").next().unwrap().to_owned();
            }
        } else if line == "}" {
            stack.pop();
        } else if is_node_declaration(line) {
            let id = line.split(' ').next().unwrap().to_owned();
            nodes.push((id, stack.clone()));
        }
    }
    nodes
}

/// Whether Graphviz's `dot` runs; when it does not, says loudly that `test` is skipped.
fn graphviz_available(test: &str) -> bool {
    match Command::new("dot").arg("-V").output() {
        Ok(output) if output.status.success() => true,
        _ => {
            // Straight to the process's stderr: `eprintln!` is captured, and so hidden,
            // for a test that passes.
            let _ = writeln!(
                std::io::stderr(),
                "SKIPPED {test}: Graphviz `dot` is not on PATH (install the graphviz \
                 package to check that the DOT output parses)"
            );
            false
        }
    }
}

/// Runs `dot -Tsvg` on `source`; panics unless it succeeds without a warning.
fn render_svg(source: &str) -> String {
    let mut child = Command::new("dot")
        .arg("-Tsvg")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn dot");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(source.as_bytes())
        .expect("write to dot");
    let output = child.wait_with_output().expect("run dot");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "dot failed ({}): {stderr}\n{source}",
        output.status
    );
    assert!(stderr.trim().is_empty(), "dot warned: {stderr}\n{source}");
    let svg = String::from_utf8(output.stdout).expect("UTF-8 SVG");
    assert!(
        svg.contains("<svg") && svg.trim_end().ends_with("</svg>"),
        "{svg}"
    );
    svg
}

mod should {
    use super::*;

    /// The whole output for a two-element graph, to pin the format.
    #[test]
    fn write_a_self_contained_digraph() {
        const PUSH: CausalGraph = CausalGraph {
            model: "Push",
            elements: &[
                element("force", "", Se, Fixed),
                element("v", "", One, Fixed),
                element("mass", "", I, Integral),
            ],
            bonds: &[bond(0, 1, 1, 1, None), bond(1, 2, 2, 1, Some("p"))],
            loops: &[],
        };
        let expected = r#"digraph "Push" {
  graph [label="Push", labelloc=t, fontsize=16];
  node [shape=plaintext, fontsize=14];
  edge [dir=both, arrowhead=lvee, arrowtail=none, fontsize=10];
  e0 [label="Se : force", tooltip="Se force"];
  e1 [label=<1<BR/><FONT POINT-SIZE="9">v</FONT>>, tooltip="1 v"];
  e2 [label="I : mass", tooltip="I mass, integral causality"];
  e0 -> e1 [arrowhead="teelvee", arrowtail="none"];
  e1 -> e2 [arrowhead="teelvee", arrowtail="none", label="p"];
}
"#;
        assert_eq!(PUSH.to_dot(), expected);
    }

    /// The half arrow (`lvee`) is always at the head, `to`; the stroke (`tee`) joins it
    /// at the head when `stroke_at == to`, and is the tail when `stroke_at == from`.
    #[test]
    fn put_the_half_arrow_at_to_and_the_stroke_at_stroke_at() {
        let dot = CRANK.to_dot();
        let head = r#"arrowhead="teelvee", arrowtail="none""#;
        let tail = r#"arrowhead="lvee", arrowtail="tee""#;
        for (index, b) in CRANK.bonds.iter().enumerate() {
            let line = edge_line(&dot, b.from, b.to);
            let expected = if b.stroke_at == b.to { head } else { tail };
            assert!(
                line.starts_with(&format!("e{} -> e{} [{expected}", b.from, b.to)),
                "bond {index}: {line}"
            );
        }
        assert_eq!(
            dot.matches("->").count(),
            CRANK.bonds.len(),
            "one edge per bond"
        );
        // Spelled out, so that a swap of head and tail in both places cannot pass.
        assert!(edge_line(&dot, 0, 1).starts_with(&format!("e0 -> e1 [{head}")));
        assert!(edge_line(&dot, 1, 3).starts_with(&format!("e1 -> e3 [{tail}")));
        assert!(edge_line(&dot, 7, 6).starts_with(&format!("e7 -> e6 [{tail}")));
        assert!(edge_line(&dot, 7, 8).starts_with(&format!("e7 -> e8 [{head}")));
    }

    /// Multibonds are a double line labelled with their dimension (under the bond's
    /// own label, if any); scalar bonds have neither.
    #[test]
    fn draw_multibonds_as_double_lines_labelled_with_their_dimension() {
        let dot = CRANK.to_dot();
        assert_eq!(
            edge_line(&dot, 1, 3),
            r#"e1 -> e3 [arrowhead="lvee", arrowtail="tee", color="black:black", label="2"];"#
        );
        assert_eq!(
            edge_line(&dot, 3, 4),
            r#"e3 -> e4 [arrowhead="teelvee", arrowtail="none", color="black:black", label="q\n2"];"#
        );
        assert_eq!(
            edge_line(&dot, 1, 2),
            r#"e1 -> e2 [arrowhead="teelvee", arrowtail="none"];"#
        );
        assert_eq!(dot.matches("color=").count(), 2);
    }

    #[test]
    fn label_bonds_that_have_a_label() {
        let dot = CRANK.to_dot();
        assert_eq!(
            edge_line(&dot, 0, 1),
            r#"e0 -> e1 [arrowhead="teelvee", arrowtail="none", label="torque"];"#
        );
        assert!(!edge_line(&dot, 1, 5).contains("label="));
    }

    #[test]
    fn label_elements_with_their_kind_and_name_and_junctions_with_their_symbol() {
        let dot = CRANK.to_dot();
        assert_eq!(
            node_line(&dot, 0),
            r#"e0 [label="Se : drive", tooltip="Se drive"];"#
        );
        assert_eq!(
            node_line(&dot, 1),
            r#"e1 [label=<1<BR/><FONT POINT-SIZE="9">hub</FONT>>, tooltip="1 hub"];"#
        );
        assert_eq!(
            node_line(&dot, 3),
            r#"e3 [label=<0<BR/><FONT POINT-SIZE="9">pin</FONT>>, tooltip="0 crank.pin.pin"];"#
        );
        assert_eq!(
            node_line(&dot, 4),
            r#"e4 [label="C : joint", tooltip="C crank.pin.joint, integral causality"];"#
        );
        assert_eq!(
            node_line(&dot, 5),
            r#"e5 [label="TF : lever", tooltip="TF crank.lever"];"#
        );
    }

    /// A modulated element is drawn with the kind the model wrote (MTF, MSe), not its
    /// base kind.
    #[test]
    fn label_modulated_elements_as_written() {
        const fn modulated(name: &'static str, kind: ElementKind) -> GraphElement {
            GraphElement {
                modulated: true,
                ..element(name, "", kind, Fixed)
            }
        }
        const GRAPH: CausalGraph = CausalGraph {
            model: "Arm",
            elements: &[
                modulated("push", Se),
                modulated("arm", Tf),
                element("load", "", R, Resistance),
            ],
            bonds: &[bond(0, 1, 1, 1, None), bond(1, 2, 1, 1, None)],
            loops: &[],
        };
        let graph = GRAPH;
        let dot = graph.to_dot();
        assert_eq!(
            node_line(&dot, 0),
            r#"e0 [label="MSe : push", tooltip="MSe push"];"#
        );
        assert_eq!(
            node_line(&dot, 1),
            r#"e1 [label="MTF : arm", tooltip="MTF arm"];"#
        );
        assert_eq!(graph.elements[1].kind, Tf);
    }

    /// `"` and `\` are escaped in quoted strings (names, labels, tooltips), and `&`,
    /// `<`, `>` in the junctions' HTML labels.
    #[test]
    fn escape_names_and_labels() {
        let dot = CRANK.to_dot();
        assert_eq!(
            node_line(&dot, 6),
            r#"e6 [label="R : say \"dry\"", tooltip="R rod.end.say \"dry\", resistance causality (e = R(f))"];"#
        );
        assert_eq!(
            node_line(&dot, 7),
            r#"e7 [label=<1<BR/><FONT POINT-SIZE="9">a&amp;b&lt;c&gt;</FONT>>, tooltip="1 rod.end.a&b<c>"];"#
        );
        assert_eq!(
            node_line(&dot, 8),
            r#"e8 [label="R : back\\slash", tooltip="R rod.end.back\\slash, conductance causality (f = R⁻¹(e))"];"#
        );
        assert_eq!(
            edge_line(&dot, 5, 7),
            r#"e5 -> e7 [arrowhead="lvee", arrowtail="tee", label="say \"v\""];"#
        );
        assert_eq!(
            edge_line(&dot, 7, 8),
            r#"e7 -> e8 [arrowhead="teelvee", arrowtail="none", label="a\\b"];"#
        );
    }

    #[test]
    fn escape_the_model_name_and_line_breaks() {
        const ODD: CausalGraph = CausalGraph {
            model: "say \"hi\"\\\n",
            elements: &[element("two\nlines", "g\"1\"", C, Integral)],
            bonds: &[],
            loops: &[],
        };
        let dot = ODD.to_dot();
        assert!(
            dot.starts_with("digraph \"say \\\"hi\\\"\\\\\\n\" {\n"),
            "{dot}"
        );
        assert!(
            dot.contains(
                r#"e0 [label="C : two\nlines", tooltip="C g\"1\".two\nlines, integral causality"];"#
            ),
            "{dot}"
        );
        assert!(dot.contains(r#"graph [label="g\"1\"", "#), "{dot}");
        assert!(dot.contains("subgraph cluster_g_1_ {"), "{dot}");
    }

    /// Every element sits in the cluster of its group, nested by path; `rod` gets a
    /// cluster though no element is directly in it; top-level elements are in none.
    #[test]
    fn nest_clusters_by_group_path() {
        let dot = CRANK.to_dot();
        let crank = ("cluster_crank".to_owned(), "\"crank\"".to_owned());
        let pin = ("cluster_crank_pin".to_owned(), "\"crank.pin\"".to_owned());
        let rod = ("cluster_rod".to_owned(), "\"rod\"".to_owned());
        let end = ("cluster_rod_end".to_owned(), "\"rod.end\"".to_owned());
        let expected = vec![
            ("e0".to_owned(), vec![]),
            ("e1".to_owned(), vec![]),
            ("e2".to_owned(), vec![crank.clone()]),
            ("e5".to_owned(), vec![crank.clone()]),
            ("e3".to_owned(), vec![crank.clone(), pin.clone()]),
            ("e4".to_owned(), vec![crank, pin]),
            ("e6".to_owned(), vec![rod.clone(), end.clone()]),
            ("e7".to_owned(), vec![rod.clone(), end.clone()]),
            ("e8".to_owned(), vec![rod, end]),
        ];
        assert_eq!(clusters_of_nodes(&dot), expected, "{dot}");
        assert_eq!(dot.matches("subgraph ").count(), 4);
    }

    /// Paths that sanitise to the same identifier still get distinct clusters.
    #[test]
    fn keep_clusters_apart_when_their_sanitised_paths_collide() {
        const CLASH: CausalGraph = CausalGraph {
            model: "Clash",
            elements: &[
                element("x", "a.b", C, Integral),
                element("y", "a_b", C, Integral),
                element("z", "a-b", C, Integral),
            ],
            bonds: &[],
            loops: &[],
        };
        let dot = CLASH.to_dot();
        let clusters: Vec<Vec<String>> = clusters_of_nodes(&dot)
            .into_iter()
            .map(|(_, stack)| stack.into_iter().map(|(id, _)| id).collect())
            .collect();
        assert_eq!(
            clusters,
            [
                vec!["cluster_a", "cluster_a_b"],
                vec!["cluster_a_b_2"],
                vec!["cluster_a_b_3"],
            ],
            "{dot}"
        );
    }

    #[test]
    fn write_the_same_text_every_time() {
        let first = CRANK.to_dot();
        assert_eq!(CRANK.to_dot(), first);
        assert_eq!(CRANK.dot().to_string(), first);
        assert_eq!(format!("{}", CRANK.dot()), first);
        // An equal graph built separately (other addresses) gives the same text.
        let elements: Vec<GraphElement> = CRANK.elements.to_vec();
        let bonds: Vec<GraphBond> = CRANK.bonds.to_vec();
        let copy = CausalGraph {
            model: "Crank",
            elements: Box::leak(elements.into_boxed_slice()),
            bonds: Box::leak(bonds.into_boxed_slice()),
            loops: &[],
        };
        assert_eq!(copy.to_dot(), first);
    }

    /// A bond whose stroke is at neither end, or whose end is not an element, is
    /// reported in a comment rather than drawn wrong (or drawn to a phantom node).
    #[test]
    fn say_so_in_a_comment_when_a_bond_is_malformed() {
        const BAD: CausalGraph = CausalGraph {
            model: "Bad",
            elements: &[
                element("a", "", C, Integral),
                element("b", "", One, Fixed),
                element("c", "", R, Resistance),
            ],
            bonds: &[bond(1, 0, 2, 1, None), bond(1, 7, 1, 1, None)],
            loops: &[],
        };
        let dot = BAD.to_dot();
        assert!(
            dot.contains("// bond 0: stroke_at 2 is neither of its ends; no stroke drawn"),
            "{dot}"
        );
        assert_eq!(
            edge_line(&dot, 1, 0),
            r#"e1 -> e0 [arrowhead="lvee", arrowtail="none"];"#
        );
        assert!(
            dot.contains("// bond 1 (1 -> 7) joins a missing element; not drawn"),
            "{dot}"
        );
        assert!(!dot.contains("e7"), "{dot}");
    }

    /// A storage element in derivative causality is red, with its bonds; the tooltip
    /// says what it is.
    #[test]
    fn draw_derivative_causality_in_red() {
        let dot = RIGID.to_dot();
        assert_eq!(
            node_line(&dot, 5),
            r#"e5 [label="I : shaft2", fontcolor="red", tooltip="I shaft2, derivative causality (dependent storage)"];"#
        );
        assert_eq!(
            edge_line(&dot, 4, 5),
            r#"e4 -> e5 [arrowhead="lvee", arrowtail="tee", tooltip="derivative causality", color="red", label="p"];"#
        );
        // The independent inertia and its bond are drawn as always.
        assert_eq!(
            node_line(&dot, 2),
            r#"e2 [label="I : shaft1", tooltip="I shaft1, integral causality"];"#
        );
        assert!(!edge_line(&dot, 1, 2).contains("color"), "{dot}");
        assert_eq!(
            dot.matches("red").count(),
            3 + 1,
            "the node, the bond, the legend:\n{dot}"
        );
    }

    /// The members of a loop are outlined in orange; a bond between two members is
    /// orange and bold (a double orange line for a multibond), one to a non-member is
    /// not.
    #[test]
    fn outline_the_members_of_a_loop_in_orange() {
        let dot = RIGID.to_dot();
        let outline = r#"shape=box, style="rounded,bold", color="orange""#;
        for index in [6, 7, 8] {
            let line = node_line(&dot, index);
            assert!(line.contains(outline), "{line}");
            assert!(
                line.ends_with(r#", on an algebraic loop solved at each evaluation"];"#),
                "{line}"
            );
        }
        for index in [0, 1, 2, 3, 4, 5] {
            assert!(!node_line(&dot, index).contains("orange"), "{dot}");
        }
        assert_eq!(
            edge_line(&dot, 7, 8),
            r#"e7 -> e8 [arrowhead="lvee", arrowtail="tee", color="orange", penwidth=2];"#
        );
        assert_eq!(
            edge_line(&dot, 6, 7),
            r#"e6 -> e7 [arrowhead="teelvee", arrowtail="none", color="orange:orange", penwidth=2, label="2"];"#
        );
        assert_eq!(
            edge_line(&dot, 1, 6),
            r#"e1 -> e6 [arrowhead="teelvee", arrowtail="none"];"#
        );
    }

    /// The legend explains what the graph marks, and only that.
    #[test]
    fn show_a_legend_only_for_what_is_marked() {
        let legend = |dot: &str| {
            dot.lines()
                .map(str::trim)
                .filter(|l| l.starts_with("legend ["))
                .map(str::to_owned)
                .collect::<Vec<_>>()
        };
        let both = legend(&RIGID.to_dot());
        assert_eq!(both.len(), 1, "{both:?}");
        assert!(both[0].contains("derivative causality (dependent storage)"));
        assert!(both[0].contains("algebraic loop (solved at each evaluation)"));
        let mut elements = RIGID.elements.to_vec();
        elements[5].causality = Integral;
        let loops_only = CausalGraph {
            elements: Box::leak(elements.into_boxed_slice()),
            ..RIGID
        };
        assert!(!loops_only.to_dot().contains("red"));
        let only = legend(&loops_only.to_dot());
        assert!(!only[0].contains("derivative"), "{only:?}");
        let derivative_only = CausalGraph {
            loops: &[],
            ..RIGID
        };
        let only = legend(&derivative_only.to_dot());
        assert!(!only[0].contains("loop"), "{only:?}");
        assert!(legend(&CRANK.to_dot()).is_empty());
        // An empty loop list entry marks nothing.
        let empty = CausalGraph {
            loops: &[&[]],
            ..CRANK
        };
        assert_eq!(empty.to_dot(), CRANK.to_dot());
    }

    /// The markings parse in Graphviz without a warning, the legend as one more node.
    #[test]
    fn have_markings_graphviz_accepts() {
        if !graphviz_available("dot::should::have_markings_graphviz_accepts") {
            return;
        }
        let svg = render_svg(&RIGID.to_dot());
        assert_eq!(
            svg.matches("class=\"node\"").count(),
            RIGID.elements.len() + 1
        );
        assert_eq!(svg.matches("class=\"edge\"").count(), RIGID.bonds.len());
        assert!(svg.contains("stroke=\"red\"") && svg.contains("stroke=\"orange\""));
    }

    /// Graphviz parses the output without a warning (an unknown arrow name would
    /// warn) and sees every cluster.
    #[test]
    fn be_accepted_by_graphviz() {
        if !graphviz_available("dot::should::be_accepted_by_graphviz") {
            return;
        }
        let svg = render_svg(&CRANK.to_dot());
        for cluster in [
            "cluster_crank",
            "cluster_crank_pin",
            "cluster_rod",
            "cluster_rod_end",
        ] {
            assert!(
                svg.contains(&format!("<title>{cluster}</title>")),
                "{cluster} in\n{svg}"
            );
        }
        assert_eq!(svg.matches("class=\"cluster\"").count(), 4, "{svg}");
        assert_eq!(svg.matches("class=\"edge\"").count(), CRANK.bonds.len());
        assert_eq!(svg.matches("class=\"node\"").count(), CRANK.elements.len());
    }
}
