//! `models graph`: the causal bond graph as DOT, or as SVG drawn by Graphviz.

use super::info::print;
use super::Failure;
use crate::catalog::{dot_svg, Catalogue, DotError, DOT_TIMEOUT};

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

/// Runs `dot -Tsvg` on `dot` ([`dot_svg`], as `index.html`'s graph section does).
fn to_svg(dot: &str) -> Result<String, Failure> {
    dot_svg(dot, DOT_TIMEOUT).map_err(|e| match e {
        DotError::Missing => Failure::Prerequisite(
            "--svg needs Graphviz's `dot` program, which is not on the PATH: install \
             Graphviz (e.g. `apt-get install graphviz`), or omit --svg to get the DOT text"
                .to_owned(),
        ),
        DotError::Failed(why) => Failure::Other(why),
        DotError::Interrupted => Failure::Other("interrupted while `dot` ran".to_owned()),
    })
}
