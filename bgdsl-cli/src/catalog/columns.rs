//! Choosing states and outputs by name, recording the chosen ones into a table that is
//! written as CSV, and the units side file that describes a CSV's columns.
//!
//! A results file's header row holds plain names (scripts read it, and the quick
//! return's 56-column header is fixed by its spec); the units and meanings of its
//! columns go in `<stem>.units.csv` beside it: a header row `column,unit,description`,
//! then one row per column of the results file, `t` first (`t,s,time`). A unit is empty
//! where the model declares none.

use std::io::{self, Write};
use std::path::Path;

use bgdsl_runtime::record::{write_atomically, write_number};
use bgdsl_runtime::{CsvError, Recorder};

use super::CatalogModel;

/// A quantity of a run: a state or an output, by its index in the model's list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Column {
    /// State number `i` (of `Model::STATE_NAMES`).
    State(usize),
    /// Output number `i` (of `Model::OUTPUT_NAMES`).
    Output(usize),
}

impl Column {
    /// The value in a sample's state `x` and outputs `y`.
    pub fn value(self, x: &[f64], y: &[f64]) -> f64 {
        match self {
            Column::State(i) => x[i],
            Column::Output(i) => y[i],
        }
    }
}

/// The columns `name` stands for, with their names: an output or a state of that name,
/// or else every output (then every state) named `name_` and a component suffix (`x`,
/// `y`, `z`, or two digits as in `R1_21`), so that `F_O1` stands for `F_O1_x`, `F_O1_y`,
/// `F_O1_z`. `None` when nothing matches.
pub fn resolve_columns(model: &dyn CatalogModel, name: &str) -> Option<Vec<(String, Column)>> {
    let outputs = model.output_names();
    let states = model.state_names();
    if let Some(i) = outputs.iter().position(|n| *n == name) {
        return Some(vec![(name.to_owned(), Column::Output(i))]);
    }
    if let Some(i) = states.iter().position(|n| *n == name) {
        return Some(vec![(name.to_owned(), Column::State(i))]);
    }
    let prefix = format!("{name}_");
    let component = |n: &str| {
        n.strip_prefix(&prefix).is_some_and(|rest| {
            matches!(rest, "x" | "y" | "z")
                || (rest.len() == 2 && rest.chars().all(|c| c.is_ascii_digit()))
        })
    };
    let group: Vec<(String, Column)> = outputs
        .iter()
        .enumerate()
        .filter(|(_, n)| component(n))
        .map(|(i, n)| ((*n).to_owned(), Column::Output(i)))
        .collect();
    if !group.is_empty() {
        return Some(group);
    }
    let group: Vec<(String, Column)> = states
        .iter()
        .enumerate()
        .filter(|(_, n)| component(n))
        .map(|(i, n)| ((*n).to_owned(), Column::State(i)))
        .collect();
    (!group.is_empty()).then_some(group)
}

/// Every state, then every output, as [`resolve_columns`] names them.
pub(super) fn all_columns(model: &dyn CatalogModel) -> Vec<(String, Column)> {
    let states = model.state_names().iter().enumerate();
    let outputs = model.output_names().iter().enumerate();
    states
        .map(|(i, n)| ((*n).to_owned(), Column::State(i)))
        .chain(outputs.map(|(i, n)| ((*n).to_owned(), Column::Output(i))))
        .collect()
}

/// The unit and description of the column called `name` of a results file of `model`:
/// `t` is time in s; a state or output has what the model declares (empty when it
/// declares nothing).
pub fn column_unit(model: &dyn CatalogModel, name: &str) -> (&'static str, &'static str) {
    if name == "t" {
        return ("s", "time");
    }
    let find = |infos: &'static [bgdsl_runtime::SignalInfo]| {
        infos
            .iter()
            .find(|info| info.name == name)
            .map(|info| (info.unit, info.doc))
    };
    find(model.outputs())
        .or_else(|| find(model.states()))
        .unwrap_or(("", ""))
}

/// The units side file of the results file at `results` (`x.csv` → `x.units.csv`,
/// `x.partial.csv` → `x.partial.units.csv`).
pub fn units_path(results: &Path) -> std::path::PathBuf {
    let stem = results
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    results.with_file_name(format!("{stem}.units.csv"))
}

/// Writes the units side file `<stem>.units.csv` (a header row
/// `column,unit,description`, then one row per column, `t` first as `t,s,time`; a unit
/// is empty where the model declares none) of a results file with columns `names` (`t`
/// included) of `model` beside `results`, whole or not at all, and returns its path.
pub fn write_units(
    model: &dyn CatalogModel,
    results: &Path,
    names: &[&str],
) -> Result<std::path::PathBuf, CsvError> {
    let path = units_path(results);
    write_atomically(&path, |out| {
        out.write_all(b"column,unit,description\n")?;
        for name in names {
            let (unit, doc) = column_unit(model, name);
            let doc = doc.split_whitespace().collect::<Vec<_>>().join(" ");
            let fields = [*name, unit, doc.as_str()].map(csv_field);
            writeln!(out, "{}", fields.join(","))?;
        }
        Ok(())
    })?;
    Ok(path)
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// A recorder of chosen columns: `t`, then one column per choice.
#[derive(Clone, Debug)]
pub(super) struct Table {
    names: Vec<String>,
    sources: Vec<Column>,
    /// `t` first, then one vector per source.
    data: Vec<Vec<f64>>,
}

impl Table {
    /// An empty table of `columns`, with room for `capacity` samples.
    pub(super) fn new(columns: &[(String, Column)], capacity: usize) -> Self {
        Table {
            names: columns.iter().map(|(n, _)| n.clone()).collect(),
            sources: columns.iter().map(|(_, c)| *c).collect(),
            data: (0..=columns.len())
                .map(|_| Vec::with_capacity(capacity))
                .collect(),
        }
    }

    /// The number of samples.
    pub(super) fn len(&self) -> usize {
        self.data[0].len()
    }

    /// The number of columns, `t` included.
    pub(super) fn width(&self) -> usize {
        self.data.len()
    }

    /// The sample times.
    pub(super) fn times(&self) -> &[f64] {
        &self.data[0]
    }

    /// Every column's name, `t` first, as the header row has them.
    pub(super) fn names(&self) -> Vec<&str> {
        std::iter::once("t")
            .chain(self.names.iter().map(String::as_str))
            .collect()
    }

    /// The chosen columns' names and values (not `t`).
    pub(super) fn columns(&self) -> impl Iterator<Item = (&str, &[f64])> {
        self.names
            .iter()
            .zip(&self.data[1..])
            .map(|(n, v)| (n.as_str(), v.as_slice()))
    }

    fn write_to<W: Write>(&self, out: &mut W) -> io::Result<()> {
        out.write_all(b"t")?;
        for name in &self.names {
            out.write_all(b",")?;
            if name.contains([',', '"', '\n']) {
                write!(out, "\"{}\"", name.replace('"', "\"\""))?;
            } else {
                out.write_all(name.as_bytes())?;
            }
        }
        out.write_all(b"\n")?;
        for row in 0..self.len() {
            for (i, column) in self.data.iter().enumerate() {
                if i > 0 {
                    out.write_all(b",")?;
                }
                write_number(out, column[row])?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    }

    /// Writes the table as CSV to `path`, whole or not at all.
    pub(super) fn write_csv(&self, path: &Path) -> Result<(), CsvError> {
        write_atomically(path, |out| self.write_to(out))
    }
}

impl Recorder for Table {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        self.data[0].push(t);
        for (column, source) in self.data[1..].iter_mut().zip(&self.sources) {
            column.push(source.value(x, y));
        }
    }
}
