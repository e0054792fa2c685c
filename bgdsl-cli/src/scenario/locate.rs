//! Finding where a key sits in a YAML text, for errors that serde cannot place (an
//! unknown parameter, a mass of zero, a tolerance out of range): given a key path such
//! as `parameters.m1` or `sweep.parameters[0].values`, [`locate`] returns the line and
//! column of that key in the source.
//!
//! # What it understands
//!
//! Block mappings (`key: value`, one per line, nested by indentation) and block
//! sequences (`- item`, also `- key: value` items and a sequence at the same indentation
//! as its parent key), comment lines, blank lines and a leading `---`. Keys may be plain
//! or quoted (`"m1":` or `'m1':`).
//!
//! # Limits
//!
//! Flow collections (`{a: 1}`, `[1, 2]`), anchors and aliases, merge keys, multi-line
//! keys and keys containing `": "` are not looked into: a path that goes through one is
//! located at the deepest key it reached (for `values: [1, 2]`, the key `values`). A
//! path none of whose keys is found gives `None`; callers then report the file without
//! a line.

/// One step of a key path: a mapping key or a sequence index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Segment {
    /// The value of this key in a mapping.
    Key(String),
    /// The item at this (0-based) position in a sequence.
    Index(usize),
}

/// A path of keys and indices from the document's root, e.g. `solver.rtol` or
/// `sweep.parameters[1].from`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct KeyPath(pub Vec<Segment>);

impl KeyPath {
    /// A path of mapping keys only.
    pub fn keys(keys: &[&str]) -> Self {
        KeyPath(keys.iter().map(|k| Segment::Key((*k).to_owned())).collect())
    }

    /// This path followed by `key`.
    pub fn key(&self, key: &str) -> Self {
        let mut path = self.clone();
        path.0.push(Segment::Key(key.to_owned()));
        path
    }

    /// This path followed by the sequence index `index`.
    pub fn index(&self, index: usize) -> Self {
        let mut path = self.clone();
        path.0.push(Segment::Index(index));
        path
    }
}

impl core::fmt::Display for KeyPath {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        for (i, segment) in self.0.iter().enumerate() {
            match segment {
                Segment::Key(k) if i == 0 => f.write_str(k)?,
                Segment::Key(k) => write!(f, ".{k}")?,
                Segment::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// A position in the source, both 1-based (as editors and compilers count).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Position {
    /// The line, from 1.
    pub line: usize,
    /// The column (in characters), from 1.
    pub column: usize,
}

/// A line of the source with content: its number (0-based), the column its text starts
/// at (0-based, in characters) and the text from there.
#[derive(Clone, Copy, Debug)]
struct Line<'a> {
    number: usize,
    indent: usize,
    text: &'a str,
}

/// Where the key at the end of `path` is in `source`, or, when the path cannot be
/// followed to its end, where the deepest key of it that was found is. `None` when not
/// even its first key was found (or `path` is empty).
pub fn locate(source: &str, path: &KeyPath) -> Option<Position> {
    let lines = content_lines(source);
    let mut block: Vec<Line<'_>> = lines;
    let mut found = None;
    for segment in &path.0 {
        let Some((position, child)) = step(&block, segment) else {
            break;
        };
        found = Some(position);
        match child {
            Some(child) => block = child,
            None => break,
        }
    }
    found
}

/// The lines that can hold keys: not blank, not a comment, not a document marker or
/// directive.
fn content_lines(source: &str) -> Vec<Line<'_>> {
    source
        .lines()
        .enumerate()
        .filter_map(|(number, raw)| {
            let text = raw.trim_start_matches([' ', '\t']);
            let indent = raw.chars().count() - text.chars().count();
            let text = text.trim_end();
            let skip = text.is_empty()
                || text.starts_with('#')
                || text == "---"
                || text == "..."
                || text.starts_with("--- ")
                || text.starts_with('%');
            (!skip).then_some(Line {
                number,
                indent,
                text,
            })
        })
        .collect()
}

/// Follows one segment inside `block` (lines whose first line sets the block's
/// indentation): the position of the key or item and the lines of its value, if that
/// value is a nested block.
fn step<'a>(block: &[Line<'a>], segment: &Segment) -> Option<(Position, Option<Vec<Line<'a>>>)> {
    let indent = block.first()?.indent;
    match segment {
        Segment::Key(key) => {
            for (at, line) in block.iter().enumerate() {
                if line.indent != indent {
                    continue;
                }
                let Some((name, rest)) = split_key(line.text) else {
                    continue;
                };
                if name != key {
                    continue;
                }
                let position = Position {
                    line: line.number + 1,
                    column: line.indent + 1,
                };
                let rest = strip_comment(rest);
                let child = if rest.is_empty() {
                    // The value is the following lines indented further, or a sequence
                    // at the key's own indentation.
                    let nested = children(&block[at + 1..], indent, true);
                    (!nested.is_empty()).then_some(nested)
                } else {
                    None
                };
                return Some((position, child));
            }
            None
        }
        Segment::Index(wanted) => {
            let mut seen = 0;
            for (at, line) in block.iter().enumerate() {
                if line.indent != indent || !is_item(line.text) {
                    continue;
                }
                if seen < *wanted {
                    seen += 1;
                    continue;
                }
                let position = Position {
                    line: line.number + 1,
                    column: line.indent + 1,
                };
                // The item's content starts after "- " on the same line (as if that
                // text were a line of its own, indented past the dash), then goes on
                // with the lines indented further than the dash.
                let after_dash = line.text[1..].trim_start_matches([' ', '\t']);
                let offset = line.text.chars().count() - after_dash.chars().count();
                let mut child = Vec::new();
                if !strip_comment(after_dash).is_empty() {
                    child.push(Line {
                        number: line.number,
                        indent: line.indent + offset,
                        text: after_dash,
                    });
                }
                child.extend(children(&block[at + 1..], indent, false));
                return Some((position, (!child.is_empty()).then_some(child)));
            }
            None
        }
    }
}

/// The lines after a key or item that belong to its value: those indented more than
/// `indent`, up to the first that is not; with `same_level_items`, also a block sequence
/// at `indent` itself (`key:\n- a\n- b`).
fn children<'a>(rest: &[Line<'a>], indent: usize, same_level_items: bool) -> Vec<Line<'a>> {
    let sequence_here = same_level_items
        && rest
            .first()
            .is_some_and(|l| l.indent == indent && is_item(l.text));
    rest.iter()
        .take_while(|l| {
            l.indent > indent || (sequence_here && l.indent == indent && is_item(l.text))
        })
        .copied()
        .collect()
}

/// Whether the text starts a block sequence item (`-` then a space or the end).
fn is_item(text: &str) -> bool {
    text == "-" || text.starts_with("- ") || text.starts_with("-\t")
}

/// The key of a `key: value` line (unquoted) and the text after the colon.
fn split_key(text: &str) -> Option<(&str, &str)> {
    if is_item(text) {
        return None;
    }
    for quote in ['"', '\''] {
        if let Some(inner) = text.strip_prefix(quote) {
            let end = inner.find(quote)?;
            let rest = inner[end + 1..].trim_start().strip_prefix(':')?;
            return Some((&inner[..end], rest));
        }
    }
    let colon = text
        .char_indices()
        .find(|&(i, c)| {
            c == ':'
                && text[i + 1..]
                    .chars()
                    .next()
                    .is_none_or(|n| n == ' ' || n == '\t')
        })?
        .0;
    Some((text[..colon].trim_end(), &text[colon + 1..]))
}

/// The text without a trailing comment (a `#` after whitespace), trimmed.
fn strip_comment(text: &str) -> &str {
    let text = text.trim();
    if text.starts_with('#') {
        return "";
    }
    match text.find(" #") {
        Some(at) => text[..at].trim_end(),
        None => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOURCE: &str = "\
# a scenario
model: quick_return
parameters:
  m1: 0.5     # crank
  \"l1\": [0.2, 0.01, 0.01]
  nested:
    deep: 1
time: {start: 0, end: 5}
sweep:
  parameters:
    - name: w_drive
      from: 2
    - name: K01
      values:
        - 1
        - 2
  peaks:
  - Tc
  - F_O1
";

    fn at(path: &KeyPath) -> Option<(usize, usize)> {
        locate(SOURCE, path).map(|p| (p.line, p.column))
    }

    fn path(text: &str) -> KeyPath {
        let mut path = KeyPath::default();
        for part in text.split('.') {
            match part.split_once('[') {
                Some((key, index)) => {
                    path = path.key(key);
                    path = path.index(index.trim_end_matches(']').parse().unwrap());
                }
                None => path = path.key(part),
            }
        }
        path
    }

    #[test]
    fn finds_keys_in_nested_block_mappings() {
        assert_eq!(at(&path("model")), Some((2, 1)));
        assert_eq!(at(&path("parameters.m1")), Some((4, 3)));
        assert_eq!(at(&path("parameters.l1")), Some((5, 3)));
        assert_eq!(at(&path("parameters.nested.deep")), Some((7, 5)));
    }

    #[test]
    fn finds_items_of_block_sequences() {
        assert_eq!(at(&path("sweep.parameters[0]")), Some((11, 5)));
        assert_eq!(at(&path("sweep.parameters[0].name")), Some((11, 7)));
        assert_eq!(at(&path("sweep.parameters[0].from")), Some((12, 7)));
        assert_eq!(at(&path("sweep.parameters[1].values[1]")), Some((16, 9)));
        assert_eq!(at(&path("sweep.peaks[1]")), Some((19, 3)));
    }

    #[test]
    fn stops_at_the_deepest_key_found() {
        // A flow mapping is not looked into.
        assert_eq!(at(&path("time.end")), Some((8, 1)));
        // A key that is not there.
        assert_eq!(at(&path("parameters.m9")), Some((3, 1)));
        assert_eq!(at(&path("sweep.parameters[5]")), Some((10, 3)));
        assert_eq!(at(&path("nothing")), None);
        assert_eq!(at(&KeyPath::default()), None);
    }

    #[test]
    fn displays_paths_like_serde_yaml() {
        assert_eq!(
            path("sweep.parameters[1].values").to_string(),
            "sweep.parameters[1].values"
        );
    }
}
