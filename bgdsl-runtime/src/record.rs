//! Recording a run: the [`Recorder`] trait the driver calls at every sample, the
//! in-memory [`Trajectory`], and atomic CSV output.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{CsvError, CsvStage};
use crate::event::{EventAction, EventRecord};
use crate::model::Model;

/// Receives the samples of a run, in time order.
///
/// Implemented by [`Trajectory`], by `()` (which discards everything) and by every
/// closure `FnMut(f64, &[f64], &[f64])`.
pub trait Recorder {
    /// Called at sample time `t` with the state `x` (in the order of
    /// [`Model::STATE_NAMES`]) and the outputs `y` (in the order of
    /// [`Model::OUTPUT_NAMES`]).
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]);

    /// Asked after every sample: `true` ends the run there with
    /// [`SolverError::Stopped`](crate::SolverError::Stopped), keeping what was recorded
    /// (a host's interrupt, a progress bar's cancel button). Never, by default.
    fn stop_requested(&self) -> bool {
        false
    }

    /// Called at every event, after its action, before the samples that follow it (a
    /// sample at exactly the event's time records the state after it). Does nothing,
    /// by default.
    fn event(&mut self, record: &EventRecord<'_>) {
        let _ = record;
    }
}

impl<F: FnMut(f64, &[f64], &[f64])> Recorder for F {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        self(t, x, y)
    }
}

impl Recorder for () {
    fn record(&mut self, _t: f64, _x: &[f64], _y: &[f64]) {}
}

/// Samples kept in memory, one column per quantity: `t`, then the states
/// ([`Model::STATE_NAMES`]), then the outputs ([`Model::OUTPUT_NAMES`]).
///
/// Created with room for a number of samples, recording allocates nothing until that
/// room is used up (it then grows like a `Vec`).
///
/// It also keeps the run's events ([`Trajectory::events`]), in room reserved with
/// [`Trajectory::with_event_capacity`] (none by default; beyond it the log grows).
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    names: Vec<&'static str>,
    n_states: usize,
    columns: Vec<Vec<f64>>,
    events: EventLog,
}

impl Trajectory {
    /// An empty trajectory with the columns of model `M` and room for `capacity`
    /// samples.
    pub fn for_model<M: Model>(capacity: usize) -> Self {
        let names: Vec<&'static str> = core::iter::once("t")
            .chain(M::STATE_NAMES.iter().copied())
            .chain(M::OUTPUT_NAMES.iter().copied())
            .collect();
        let columns = names.iter().map(|_| Vec::with_capacity(capacity)).collect();
        Trajectory {
            names,
            n_states: M::N_STATES,
            columns,
            events: EventLog::growing(M::N_STATES, 0),
        }
    }

    /// The same trajectory with room for `capacity` events, so that a run with at most
    /// that many records them without allocating.
    pub fn with_event_capacity(mut self, capacity: usize) -> Self {
        self.events = EventLog::growing(self.n_states, capacity);
        self
    }

    /// The events of the run(s) recorded, in time order.
    pub fn events(&self) -> &EventLog {
        &self.events
    }

    /// The number of samples recorded.
    pub fn len(&self) -> usize {
        self.columns[0].len()
    }

    /// Whether no sample has been recorded.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The number of samples that fit without allocating.
    pub fn capacity(&self) -> usize {
        self.columns.iter().map(Vec::capacity).min().unwrap_or(0)
    }

    /// Forgets the samples and events, keeping the memory.
    pub fn clear(&mut self) {
        self.columns.iter_mut().for_each(Vec::clear);
        self.events.clear();
    }

    /// The column names: `t`, the states, the outputs.
    pub fn names(&self) -> &[&'static str] {
        &self.names
    }

    /// The sample times.
    pub fn times(&self) -> &[f64] {
        &self.columns[0]
    }

    /// The position of column `name` in [`Trajectory::names`] (the first, if a state
    /// and an output share a name).
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| *n == name)
    }

    /// The values of column `name` (`"t"`, a state or an output), one per sample.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.column_index(name).map(|i| &self.columns[i][..])
    }

    /// The column at position `index` of [`Trajectory::names`].
    pub fn column_at(&self, index: usize) -> Option<&[f64]> {
        self.columns.get(index).map(|c| &c[..])
    }

    /// The value of column `name` at sample `row`.
    pub fn value(&self, row: usize, name: &str) -> Option<f64> {
        self.column(name)?.get(row).copied()
    }

    /// State number `i` of sample `row` (`i` indexes [`Model::STATE_NAMES`]).
    pub fn state(&self, row: usize, i: usize) -> Option<f64> {
        if i >= self.n_states {
            return None;
        }
        self.columns[1 + i].get(row).copied()
    }

    /// Writes the trajectory as CSV: a header row of the column names, then one row per
    /// sample, every number written so that it reads back to the same `f64`.
    pub fn write_csv_to<W: Write>(&self, mut out: W) -> io::Result<()> {
        for (i, name) in self.names.iter().enumerate() {
            if i > 0 {
                out.write_all(b",")?;
            }
            write_csv_field(&mut out, name)?;
        }
        out.write_all(b"\n")?;
        for row in 0..self.len() {
            for (i, column) in self.columns.iter().enumerate() {
                if i > 0 {
                    out.write_all(b",")?;
                }
                write_number(&mut out, column[row])?;
            }
            out.write_all(b"\n")?;
        }
        out.flush()
    }

    /// Writes the trajectory as a CSV file (see [`Trajectory::write_csv_to`]),
    /// atomically: into a temporary file in the same directory, which is flushed,
    /// synced and then renamed onto `path`. Either the whole file is written or `path`
    /// is left as it was, and no temporary file remains.
    pub fn write_csv(&self, path: impl AsRef<Path>) -> Result<(), CsvError> {
        write_atomically(path.as_ref(), |out| self.write_csv_to(out))
    }
}

/// Writes a file whole or not at all: `write` fills a new temporary file in the same
/// directory, which is then flushed, synced and renamed onto `path` (and the directory
/// synced, best effort, so the rename is durable too). On any error `path` is left as
/// it was and the temporary file is removed.
///
/// # Errors
///
/// [`CsvError`] with `path` and the stage that failed.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), CsvError> {
    let fail = |stage, source| CsvError {
        path: path.to_path_buf(),
        stage,
        source,
    };
    let (tmp_path, file) =
        create_temporary(path).map_err(|e| fail(CsvStage::CreateTemporary, e))?;
    let guard = RemoveOnDrop(Some(tmp_path.clone()));
    let mut writer = BufWriter::with_capacity(1 << 16, file);
    write(&mut writer)
        .and_then(|()| writer.into_inner().map_err(io::IntoInnerError::into_error))
        .and_then(|file| file.sync_all())
        .map_err(|e| fail(CsvStage::Write, e))?;
    fs::rename(&tmp_path, path).map_err(|e| fail(CsvStage::Rename, e))?;
    guard.disarm();
    if let Ok(dir) = File::open(directory_of(path)) {
        let _ = dir.sync_all();
    }
    Ok(())
}

impl Recorder for Trajectory {
    /// Appends a sample. Panics if `1 + x.len() + y.len()` is not the number of columns
    /// (a recorder made for another model).
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        assert_eq!(
            1 + x.len() + y.len(),
            self.columns.len(),
            "sample does not match the trajectory's columns"
        );
        let values = core::iter::once(&t).chain(x).chain(y);
        for (column, v) in self.columns.iter_mut().zip(values) {
            column.push(*v);
        }
    }

    /// Appends the event to [`Trajectory::events`].
    fn event(&mut self, record: &EventRecord<'_>) {
        self.events.push(record);
    }
}

/// A log of events: for each, its time, index, name, action and the state on both
/// sides, in storage reserved up front.
///
/// A log is either growing ([`Trajectory::events`]: beyond its capacity it grows like a
/// `Vec`) or bounded ([`Stepper::events`](crate::Stepper::events): beyond its capacity
/// it keeps the first events and counts the rest in [`EventLog::dropped`]), so that
/// recording within capacity never allocates.
#[derive(Clone, Debug, PartialEq)]
pub struct EventLog {
    n_states: usize,
    capacity: usize,
    bounded: bool,
    dropped: usize,
    t: Vec<f64>,
    index: Vec<usize>,
    name: Vec<&'static str>,
    action: Vec<EventAction>,
    /// `before` then `after`, `2 * n_states` numbers per event.
    states: Vec<f64>,
}

impl EventLog {
    /// A log for states of `n_states` numbers with room for `capacity` events, growing
    /// beyond it.
    pub fn growing(n_states: usize, capacity: usize) -> Self {
        EventLog {
            n_states,
            capacity,
            bounded: false,
            dropped: 0,
            t: Vec::with_capacity(capacity),
            index: Vec::with_capacity(capacity),
            name: Vec::with_capacity(capacity),
            action: Vec::with_capacity(capacity),
            states: Vec::with_capacity(capacity * 2 * n_states),
        }
    }

    /// A log with room for `capacity` events that keeps no more: later events are only
    /// counted ([`EventLog::dropped`]).
    pub fn bounded(n_states: usize, capacity: usize) -> Self {
        EventLog {
            bounded: true,
            ..EventLog::growing(n_states, capacity)
        }
    }

    /// Appends an event (or, full and bounded, counts it as dropped).
    pub fn push(&mut self, record: &EventRecord<'_>) {
        if self.bounded && self.t.len() >= self.capacity {
            self.dropped += 1;
            return;
        }
        self.t.push(record.t);
        self.index.push(record.index);
        self.name.push(record.name);
        self.action.push(record.action);
        let n = self.n_states;
        self.states.extend_from_slice(&record.before[..n]);
        self.states.extend_from_slice(&record.after[..n]);
    }

    /// Forgets the events (and the count of dropped ones), keeping the memory.
    pub fn clear(&mut self) {
        self.dropped = 0;
        self.t.clear();
        self.index.clear();
        self.name.clear();
        self.action.clear();
        self.states.clear();
    }

    /// The number of events kept.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether no event is kept.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// The events a bounded log could not keep.
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// Event number `i`.
    pub fn get(&self, i: usize) -> Option<EventRecord<'_>> {
        let t = *self.t.get(i)?;
        let n = self.n_states;
        let states = &self.states[2 * n * i..2 * n * (i + 1)];
        Some(EventRecord {
            t,
            index: self.index[i],
            name: self.name[i],
            before: &states[..n],
            after: &states[n..],
            action: self.action[i],
        })
    }

    /// The events in time order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = EventRecord<'_>> + '_ {
        (0..self.len()).map(|i| self.get(i).expect("within the length"))
    }

    /// The event times.
    pub fn times(&self) -> &[f64] {
        &self.t
    }
}

/// Writes a CSV field, quoted if it contains a separator, a quote or a line break.
fn write_csv_field<W: Write>(out: &mut W, field: &str) -> io::Result<()> {
    if field.contains([',', '"', '\n', '\r']) {
        write!(out, "\"{}\"", field.replace('"', "\"\""))
    } else {
        out.write_all(field.as_bytes())
    }
}

/// Writes the shortest decimal that reads back to `v`: plain notation for moderate
/// magnitudes, scientific otherwise (Rust's `{}` and `{:e}` both round-trip).
pub fn write_number<W: Write>(out: &mut W, v: f64) -> io::Result<()> {
    let a = v.abs();
    if a == 0.0 || (1e-5..1e16).contains(&a) || !v.is_finite() {
        write!(out, "{v}")
    } else {
        write!(out, "{v:e}")
    }
}

/// The directory `path` is in (`.` for a bare file name).
fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Creates a new, uniquely named temporary file in the directory of `path`.
fn create_temporary(path: &Path) -> io::Result<(PathBuf, File)> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(io::ErrorKind::InvalidInput, "the path does not name a file")
    })?;
    let dir = directory_of(path);
    let mut attempts = 0;
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".{}.{n}.tmp", std::process::id()));
        let tmp = dir.join(tmp_name);
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempts < 100 => {
                attempts += 1;
            }
            Err(e) => return Err(e),
        }
    }
}

/// Deletes a temporary file unless disarmed.
struct RemoveOnDrop(Option<PathBuf>);

impl RemoveOnDrop {
    fn disarm(mut self) {
        self.0 = None;
    }
}

impl Drop for RemoveOnDrop {
    fn drop(&mut self) {
        if let Some(path) = self.0.take() {
            // Best effort: the error being reported is the one that matters.
            let _ = fs::remove_file(path);
        }
    }
}
