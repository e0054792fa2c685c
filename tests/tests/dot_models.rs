//! The Graphviz DOT drawing of generated models: every bond drawn once, its causal
//! stroke at the end SCAP chose; with Graphviz installed, every model's drawing parses.

use std::io::Write as _;
use std::process::{Command, Stdio};

use bgdsl_runtime::{CausalGraph, Model};
use models::{DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

/// The index of the element called `name` (the DC motor has no submodels, so names are
/// unique).
fn index(graph: &CausalGraph, name: &str) -> usize {
    graph
        .elements
        .iter()
        .position(|e| e.name == name)
        .unwrap_or_else(|| panic!("no element {name}"))
}

/// The edge lines of a DOT text (`eA -> eB [...]`).
fn edge_lines(dot: &str) -> Vec<&str> {
    dot.lines()
        .map(str::trim)
        .filter(|l| l.contains(" -> "))
        .collect()
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
    assert!(output.status.success(), "dot failed: {stderr}\n{source}");
    assert!(stderr.trim().is_empty(), "dot warned: {stderr}\n{source}");
    let svg = String::from_utf8(output.stdout).expect("UTF-8 SVG");
    assert!(svg.contains("<svg") && svg.trim_end().ends_with("</svg>"));
    svg
}

mod should {
    use super::*;

    /// The strokes SCAP assigns in the DC motor (as its documentation lists them),
    /// drawn: a stroke at the `to` end joins the half arrow (`teelvee` at the head), a
    /// stroke at the `from` end is the tail (`tee`), and each bond is drawn once.
    #[test]
    fn draw_each_dc_motor_bond_once_with_its_stroke_at_the_right_end() {
        let graph = &DcMotor::GRAPH;
        let dot = DcMotor::default()
            .causal_graph()
            .expect("generated models describe their graph")
            .to_dot();
        let expected = [
            ("supply", "armature", "armature"),
            ("armature", "winding", "armature"),
            ("armature", "coil", "coil"),
            ("armature", "motor", "armature"),
            ("motor", "shaft", "shaft"),
            ("shaft", "rotor", "rotor"),
            ("shaft", "bearing", "shaft"),
            ("shaft", "gear", "shaft"),
            ("gear", "coupling", "gear"),
            ("coupling", "twist", "coupling"),
            ("twist", "shaft_spring", "twist"),
            ("twist", "shaft_damper", "twist"),
            ("coupling", "load_side", "load_side"),
            ("load_side", "load", "load"),
            ("load_side", "drag", "load_side"),
            ("brake", "load_side", "load_side"),
        ];
        let edges = edge_lines(&dot);
        assert_eq!(edges.len(), graph.bonds.len(), "{dot}");
        assert_eq!(edges.len(), expected.len(), "{dot}");
        for (from, to, stroke) in expected {
            let (f, t) = (index(graph, from), index(graph, to));
            let start = format!("e{f} -> e{t} [");
            let matching: Vec<&&str> = edges.iter().filter(|l| l.starts_with(&start)).collect();
            assert_eq!(matching.len(), 1, "{from} -> {to} drawn once in\n{dot}");
            let ends = if stroke == to {
                r#"arrowhead="teelvee", arrowtail="none""#
            } else {
                assert_eq!(stroke, from);
                r#"arrowhead="lvee", arrowtail="tee""#
            };
            assert_eq!(
                *matching[0],
                format!("{start}{ends}];"),
                "{from} -> {to}, stroke at {stroke}"
            );
        }
    }

    #[test]
    fn label_the_dc_motors_elements_as_a_bond_graph_does() {
        let dot = DcMotor::GRAPH.to_dot();
        for (name, label) in [
            ("supply", r#"label="Se : supply""#),
            ("coil", r#"label="I : coil""#),
            ("motor", r#"label="GY : motor""#),
            ("gear", r#"label="TF : gear""#),
            ("shaft_spring", r#"label="C : shaft_spring""#),
            ("drag", r#"label="R : drag""#),
            (
                "coupling",
                r#"label=<0<BR/><FONT POINT-SIZE="9">coupling</FONT>>"#,
            ),
            (
                "armature",
                r#"label=<1<BR/><FONT POINT-SIZE="9">armature</FONT>>"#,
            ),
        ] {
            let declaration = format!("e{} [{label}, ", index(&DcMotor::GRAPH, name));
            assert_eq!(dot.matches(&declaration).count(), 1, "{name} in\n{dot}");
        }
        assert!(dot.starts_with("digraph \"DcMotor\" {\n"));
        assert!(!dot.contains("subgraph"), "no submodels, no clusters");
    }

    /// Graphviz parses every model's drawing without a warning.
    #[test]
    fn be_accepted_by_graphviz_for_every_model() {
        if !graphviz_available("dot_models::should::be_accepted_by_graphviz_for_every_model") {
            return;
        }
        for graph in [
            &DcMotor::GRAPH,
            &Oscillator::GRAPH,
            &SeriesRlc::GRAPH,
            &QuarterCar::GRAPH,
            &Duffing::GRAPH,
        ] {
            let svg = render_svg(&graph.to_dot());
            assert_eq!(
                svg.matches("class=\"edge\"").count(),
                graph.bonds.len(),
                "{}",
                graph.model
            );
        }
    }
}
