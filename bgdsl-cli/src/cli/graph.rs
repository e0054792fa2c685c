//! `models graph`: the causal bond graph as DOT, or as SVG drawn by Graphviz.

use std::io::{Read, Write};
use std::process::{Command, Stdio};

use super::info::print;
use super::Failure;
use crate::catalog::Catalogue;

/// `models graph <model> [--svg]`.
pub(super) fn graph(catalogue: &Catalogue, name: &str, svg: bool) -> Result<(), Failure> {
    let entry = catalogue
        .find(name)
        .map_err(|e| Failure::Usage(e.to_string()))?;
    let graph = entry.model.causal_graph().ok_or_else(|| {
        Failure::Usage(format!("model `{name}` does not describe its causal graph"))
    })?;
    let dot = graph.to_dot();
    if svg {
        print(&to_svg(&dot)?)
    } else {
        print(&dot)
    }
}

/// Runs `dot -Tsvg` on `dot`.
fn to_svg(dot: &str) -> Result<String, Failure> {
    let mut child = Command::new("dot")
        .arg("-Tsvg")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                Failure::Prerequisite(
                    "--svg needs Graphviz's `dot` program, which is not on the PATH: install \
                     Graphviz (e.g. `apt-get install graphviz`), or omit --svg to get the DOT \
                     text"
                        .to_owned(),
                )
            } else {
                Failure::Other(format!("could not start `dot`: {e}"))
            }
        })?;
    // Write on another thread so a large graph cannot deadlock on full pipes.
    let mut stdin = child
        .stdin
        .take()
        .ok_or_else(|| Failure::Other("could not write to `dot`".to_owned()))?;
    let text = dot.to_owned();
    let writer = std::thread::spawn(move || stdin.write_all(text.as_bytes()));
    let mut svg = String::new();
    let mut errors = String::new();
    if let Some(mut out) = child.stdout.take() {
        out.read_to_string(&mut svg)
            .map_err(|e| Failure::Other(format!("reading from `dot` failed: {e}")))?;
    }
    if let Some(mut err) = child.stderr.take() {
        let _ = err.read_to_string(&mut errors);
    }
    let status = child
        .wait()
        .map_err(|e| Failure::Other(format!("waiting for `dot` failed: {e}")))?;
    let written = writer.join();
    if !status.success() || !matches!(written, Ok(Ok(()))) {
        return Err(Failure::Other(format!(
            "`dot -Tsvg` failed ({status}): {}",
            errors.trim()
        )));
    }
    Ok(svg)
}
