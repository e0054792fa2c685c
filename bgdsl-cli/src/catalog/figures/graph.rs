//! The causal bond graph of a run's model in its `index.html`: drawn by Graphviz's
//! `dot` as inline SVG when `dot` is on the `PATH`, else the DOT text in a `<pre>`
//! block with a note on what to install. The same [`dot_svg`] serves `graph --svg`.

use std::io::{Read, Write};
use std::process::{Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

use crate::report::{escape, inline_svg};

/// How long `dot` may take before the page shows the DOT text instead.
pub const DOT_TIMEOUT: Duration = Duration::from_secs(60);

/// Why `dot` gave no SVG.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DotError {
    /// `dot` is not on the `PATH`.
    Missing,
    /// It could not be started, failed, or took longer than allowed (what happened).
    Failed(String),
    /// An interrupt was requested while it ran (it was stopped).
    Interrupted,
}

/// Runs `dot -Tsvg` on `dot` and returns the SVG; stops it after `timeout` or on an
/// interrupt ([`crate::interrupt`]).
///
/// # Errors
///
/// [`DotError`].
pub fn dot_svg(dot: &str, timeout: Duration) -> Result<String, DotError> {
    let mut child = Command::new("dot")
        .arg("-Tsvg")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => DotError::Missing,
            _ => DotError::Failed(format!("could not start `dot`: {e}")),
        })?;
    // Write and read on threads so that a large graph cannot deadlock on full pipes.
    let stdin = child.stdin.take();
    let text = dot.to_owned();
    let writer = thread::spawn(move || stdin.map(|mut s| s.write_all(text.as_bytes())));
    let read = |pipe: Option<Box<dyn Read + Send>>| {
        thread::spawn(move || {
            let mut out = String::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_string(&mut out);
            }
            out
        })
    };
    let stdout = read(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let stderr = read(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) => {}
            Err(e) => return Err(DotError::Failed(format!("waiting for `dot` failed: {e}"))),
        }
        let stop = if crate::interrupt::requested() {
            Some(DotError::Interrupted)
        } else if started.elapsed() > timeout {
            Some(DotError::Failed(format!(
                "`dot -Tsvg` took longer than {} s",
                timeout.as_secs()
            )))
        } else {
            None
        };
        if let Some(error) = stop {
            let _ = child.kill();
            let _ = child.wait();
            return Err(error);
        }
        thread::sleep(Duration::from_millis(5));
    };
    let written = writer.join();
    let svg = stdout.join().unwrap_or_default();
    let errors = stderr.join().unwrap_or_default();
    if !status.success() || !matches!(written, Ok(Some(Ok(())))) {
        return Err(DotError::Failed(format!(
            "`dot -Tsvg` failed ({status}): {}",
            errors.trim()
        )));
    }
    Ok(svg)
}

/// The page's section on the causal graph whose DOT text is `dot`: the drawing, or
/// the text and why there is no drawing.
pub fn section(dot: &str) -> String {
    section_from(dot, dot_svg(dot, DOT_TIMEOUT))
}

/// [`section`] with `dot`'s answer given.
fn section_from(dot: &str, svg: Result<String, DotError>) -> String {
    let intro = "<section id=\"causal-graph\">\n<h2>Causal bond graph</h2>\n";
    let caption = "The model's bond graph with the causality the compiler assigned \
                   (the stroke at the end of a bond that receives the effort), as \
                   <code>graph</code> prints it.";
    match svg {
        Ok(svg) => format!(
            "{intro}<div class=\"graph\" style=\"overflow-x:auto\">\n{}\n</div>\n<p>{caption} \
             Drawn by Graphviz's <code>dot</code>.</p>\n</section>\n",
            inline_svg(&svg).trim_end()
        ),
        Err(e) => {
            let why = match e {
                DotError::Missing => "Graphviz's <code>dot</code> is not on the PATH \
                                      (install Graphviz, e.g. <code>apt-get install \
                                      graphviz</code>, to see it drawn)"
                    .to_owned(),
                DotError::Interrupted => "drawing it was interrupted".to_owned(),
                DotError::Failed(why) => escape(&why),
            };
            format!(
                "{intro}<p>{caption} Its DOT text follows: {why}.</p>\n<pre>{}</pre>\n</section>\n",
                escape(dot)
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOT: &str = "digraph g {\n  a -> b [label=\"<e>\"];\n}\n";

    #[test]
    fn without_dot_the_page_shows_the_text() {
        let html = section_from(DOT, Err(DotError::Missing));
        assert!(html.contains("<pre>digraph g {\n  a -&gt; b [label=&quot;&lt;e&gt;&quot;];"));
        assert!(html.contains("apt-get install graphviz"));
        assert!(!html.contains("<svg"));
        let html = section_from(DOT, Err(DotError::Failed("it <broke>".into())));
        assert!(html.contains("it &lt;broke&gt;"), "{html}");
    }

    #[test]
    fn with_dot_the_page_inlines_its_svg() {
        let svg = "<?xml version=\"1.0\"?>\n<!DOCTYPE svg>\n<svg width=\"8pt\" \
                   xmlns=\"http://www.w3.org/2000/svg\"><g/></svg>\n";
        let html = section_from(DOT, Ok(svg.to_owned()));
        assert!(html.contains("<svg width=\"8pt\"><g/></svg>"), "{html}");
        assert!(!html.contains("<?xml") && !html.contains("DOCTYPE") && !html.contains("<pre>"));
    }

    #[test]
    fn dot_draws_when_installed() {
        match dot_svg(DOT, DOT_TIMEOUT) {
            Ok(svg) => assert!(svg.contains("<svg") && svg.contains("</svg>"), "{svg}"),
            Err(DotError::Missing) => eprintln!("Graphviz is not installed: not checked"),
            Err(e) => panic!("{e:?}"),
        }
    }
}
