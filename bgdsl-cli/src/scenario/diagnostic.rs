//! Errors in a scenario or on the command line, as data, each rendered as one line:
//! `file:line:column: message`, `--flag value: message`, or the message alone.

use core::fmt;
use std::path::PathBuf;

use super::locate::{locate, KeyPath, Position};

/// Where a diagnostic points.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Origin {
    /// A place in a scenario file (the position is missing when the key could not be
    /// found in the text).
    File {
        /// The scenario file, as given on the command line.
        path: PathBuf,
        /// The line and column.
        position: Option<Position>,
    },
    /// A command-line flag with its value, e.g. `--set m1=0`.
    Flag(String),
    /// Nowhere in particular (a default value, or the combination of several).
    Nowhere,
}

/// One thing wrong with a scenario or the command line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// Where.
    pub origin: Origin,
    /// What, and what was expected.
    pub message: String,
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.origin {
            Origin::File {
                path,
                position: Some(p),
            } => write!(f, "{}:{}:{}: ", path.display(), p.line, p.column)?,
            Origin::File {
                path,
                position: None,
            } => write!(f, "{}: ", path.display())?,
            Origin::Flag(flag) => write!(f, "{flag}: ")?,
            Origin::Nowhere => {}
        }
        f.write_str(&self.message)
    }
}

/// Every diagnostic of one validation, in the order found; `Display` prints one per
/// line.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl Diagnostics {
    /// Adds a diagnostic.
    pub fn push(&mut self, origin: Origin, message: impl Into<String>) {
        self.0.push(Diagnostic {
            origin,
            message: message.into(),
        });
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Puts them in the order a reader meets them: a file's by line and column (those
    /// without a position at the file's end), then the flags' in the order given, then
    /// the rest. The sort is stable, so diagnostics at one place keep their order.
    pub fn sort(&mut self) {
        self.0.sort_by_key(|d| match &d.origin {
            Origin::File {
                position: Some(p), ..
            } => (0, p.line, p.column),
            Origin::File { position: None, .. } => (1, 0, 0),
            Origin::Flag(_) => (2, 0, 0),
            Origin::Nowhere => (3, 0, 0),
        });
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{d}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostics {}

/// A scenario file's text, to point into.
#[derive(Clone, Debug)]
pub struct Source {
    /// The path as given.
    pub path: PathBuf,
    /// The whole text.
    pub text: String,
}

impl Source {
    /// The origin of the key at `path` in this file (the deepest key of it found).
    pub fn at(&self, path: &KeyPath) -> Origin {
        Origin::File {
            path: self.path.clone(),
            position: locate(&self.text, path),
        }
    }

    /// The origin of a serde_yaml error: its own location, if it has one.
    pub fn at_error(&self, error: &serde_yaml::Error) -> Origin {
        Origin::File {
            path: self.path.clone(),
            position: error.location().map(|l| Position {
                line: l.line(),
                column: l.column(),
            }),
        }
    }
}

/// A serde_yaml error's message without the first ` at line L column C` in it (the
/// diagnostic's prefix says where; a second location, where the enclosing construct
/// started, is kept).
pub fn yaml_message(error: &serde_yaml::Error) -> String {
    let text = error.to_string();
    let mut from = 0;
    while let Some(found) = text[from..].find(" at line ") {
        let at = from + found;
        let rest = &text[at + " at line ".len()..];
        let mut words = rest.splitn(4, ' ');
        let line = words.next().and_then(|w| w.parse::<usize>().ok());
        let column_word = words.next();
        let column = words
            .next()
            .map(|w| w.trim_end_matches(','))
            .and_then(|w| w.parse::<usize>().ok());
        if line.is_some() && column_word == Some("column") && column.is_some() {
            let end = at
                + " at line ".len()
                + rest
                    .char_indices()
                    .filter(|&(_, c)| c == ' ')
                    .nth(2)
                    .map(|(i, _)| i)
                    .unwrap_or(rest.len());
            let end = if text[..end].ends_with(',') {
                end - 1
            } else {
                end
            };
            return format!("{}{}", &text[..at], &text[end..]);
        }
        from = at + 1;
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_one_line_per_origin() {
        let file = Diagnostic {
            origin: Origin::File {
                path: "s.yaml".into(),
                position: Some(Position { line: 3, column: 5 }),
            },
            message: "bad".into(),
        };
        assert_eq!(file.to_string(), "s.yaml:3:5: bad");
        let flag = Diagnostic {
            origin: Origin::Flag("--rtol 2".into()),
            message: "bad".into(),
        };
        assert_eq!(flag.to_string(), "--rtol 2: bad");
    }

    #[test]
    fn strips_the_location_from_serde_messages() {
        let err = serde_yaml::from_str::<f64>("x").unwrap_err();
        let message = yaml_message(&err);
        assert!(!message.contains("line"), "{message}");
        let err = serde_yaml::from_str::<serde_yaml::Value>("a: [1, 2\nb: 3").unwrap_err();
        assert_eq!(
            yaml_message(&err),
            "did not find expected ',' or ']', while parsing a flow sequence at line 1 column 4"
        );
    }
}
