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
        let mut rows = RowWriter::new();
        for row in 0..self.len() {
            rows.write_row(&mut out, self.columns.iter().map(|column| column[row]))?;
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
    let mut text = NumberText::default();
    out.write_all(text.format(v))
}

/// Writes rows of numbers as CSV lines: each number as [`write_number`] writes it,
/// separated by commas, the line ended by `\n`; each line is laid out in a buffer kept
/// from row to row and handed to the writer whole.
#[derive(Default)]
pub struct RowWriter {
    text: NumberText,
    line: Vec<u8>,
}

impl RowWriter {
    /// A writer with an empty line buffer.
    pub fn new() -> Self {
        RowWriter::default()
    }

    /// Writes `values` as one line.
    pub fn write_row<W: Write>(
        &mut self,
        out: &mut W,
        values: impl IntoIterator<Item = f64>,
    ) -> io::Result<()> {
        self.line.clear();
        for (i, v) in values.into_iter().enumerate() {
            if i > 0 {
                self.line.push(b',');
            }
            self.line.extend_from_slice(self.text.format(v));
        }
        self.line.push(b'\n');
        out.write_all(&self.line)
    }
}

/// The longest number [`NumberText`] lays out itself: a sign, 17 digits, a point and
/// "e-324", or a sign, "0.0000" and 17 digits.
const NUMBER_CAPACITY: usize = 32;

/// A number laid out as [`write_number`] writes it, byte for byte what
/// `format!("{v}")` (from 1e-5 to 1e16, zero and non-finite values) or
/// `format!("{v:e}")` (elsewhere) give, several times faster.
///
/// `ryu` writes the same shortest digits (the fewest that read back to `v`, the
/// nearest of those) in the same two layouts with the same thresholds, except that it
/// ends whole numbers with ".0" and breaks an exact tie between two nearest candidates
/// towards an even last digit where Rust's formatting takes the larger. So its text is
/// used with ".0" dropped, and the rare numbers that can be such a tie are laid out
/// here from their exact digits.
struct NumberText {
    ryu: ryu::Buffer,
    bytes: [u8; NUMBER_CAPACITY],
}

impl Default for NumberText {
    fn default() -> Self {
        NumberText {
            ryu: ryu::Buffer::new(),
            bytes: [0; NUMBER_CAPACITY],
        }
    }
}

impl NumberText {
    /// The text of `v`.
    fn format(&mut self, v: f64) -> &[u8] {
        if !v.is_finite() {
            return if v.is_nan() {
                b"NaN"
            } else if v > 0.0 {
                b"inf"
            } else {
                b"-inf"
            };
        }
        let a = v.abs();
        if let Some(exact) = ExactDecimal::tie_candidate(a) {
            return self.format_candidate(v, exact);
        }
        let text = self.ryu.format_finite(v).as_bytes();
        text.strip_suffix(b".0").unwrap_or(text)
    }

    /// The text of `v`, whose magnitude is exactly the decimal `exact`, laid out from
    /// its digits (rounded up where ryu's are a tie).
    #[cold]
    fn format_candidate(&mut self, v: f64, exact: ExactDecimal) -> &[u8] {
        let a = v.abs();
        let (mut digits, mut point) = shortest_digits(self.ryu.format_finite(a));
        if let Some(rounded) = exact.rounded_up_if_tie(digits.len) {
            (digits, point) = rounded;
        }
        let digits = digits.as_slice();
        let n = digits.len();
        let mut len = 0;
        let mut push = |b: u8| {
            self.bytes[len] = b;
            len += 1;
        };
        if v.is_sign_negative() {
            push(b'-');
        }
        if (1e-5..1e16).contains(&a) {
            // Plain: the value is 0.d1d2…dn × 10^point.
            if point <= 0 {
                push(b'0');
                push(b'.');
                for _ in 0..-point {
                    push(b'0');
                }
                digits.iter().for_each(|&d| push(d));
            } else {
                let point = point as usize;
                for (k, &d) in digits.iter().enumerate() {
                    if k == point {
                        push(b'.');
                    }
                    push(d);
                }
                for _ in n..point {
                    push(b'0');
                }
            }
        } else {
            // Scientific: d1[.d2…dn]e(point − 1).
            push(digits[0]);
            if n > 1 {
                push(b'.');
                digits[1..].iter().for_each(|&d| push(d));
            }
            push(b'e');
            let exponent = point - 1;
            if exponent < 0 {
                push(b'-');
            }
            let e = exponent.unsigned_abs();
            if e >= 100 {
                push(b'0' + (e / 100) as u8);
            }
            if e >= 10 {
                push(b'0' + (e / 10 % 10) as u8);
            }
            push(b'0' + (e % 10) as u8);
        }
        &self.bytes[..len]
    }
}

/// A positive number that is exactly `digits 10^exponent` with `digits` an integer of
/// at most 18 digits ending in 5: one that may lie halfway between two shortest
/// candidates.
#[derive(Clone, Copy)]
struct ExactDecimal {
    digits: u64,
    exponent: i32,
}

impl ExactDecimal {
    /// `a` as such a decimal, if it is one.
    ///
    /// With `a = m 2^e`, `m` odd, `a = M 10^k` with `M` ending in 5 (so odd) needs
    /// `k = e`: for `e >= 0`, `M = m / 5^e` (`e <= 22`, as `5^e` divides `m < 2^53`);
    /// for `e < 0`, `M = m 5^-e` (`-e <= 25`, as `M < 10^18`). Whole numbers near 1e16
    /// and short binary fractions; almost nothing a simulation writes.
    #[inline]
    fn tie_candidate(a: f64) -> Option<Self> {
        const POW5: [u64; 28] = {
            let mut table = [1u64; 28];
            let mut k = 1;
            while k < 28 {
                table[k] = table[k - 1] * 5;
                k += 1;
            }
            table
        };
        let bits = a.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i32;
        let fraction = bits & ((1u64 << 52) - 1);
        let (mut m, mut e) = if biased == 0 {
            (fraction, -1074)
        } else {
            (fraction | (1u64 << 52), biased - 1075)
        };
        if m == 0 {
            return None;
        }
        let zeros = m.trailing_zeros();
        m >>= zeros;
        e += zeros as i32;
        let digits = if e >= 0 {
            let five = *POW5.get(e as usize)?;
            (m % five == 0).then(|| m / five)?
        } else {
            m.checked_mul(*POW5.get((-e) as usize)?)?
        };
        (digits % 10 == 5 && digits < 1_000_000_000_000_000_000).then_some(ExactDecimal {
            digits,
            exponent: e,
        })
    }

    /// When this number has `n + 1` digits (it lies halfway between two numbers of `n`
    /// digits), those `n` digits rounded up and the point's position (as
    /// [`shortest_digits`] gives them).
    fn rounded_up_if_tie(self, n: usize) -> Option<(Digits, i32)> {
        let count = |v: u64| v.checked_ilog10().map_or(1, |d| d as usize + 1);
        if count(self.digits) != n + 1 {
            return None;
        }
        let mut up = self.digits / 10 + 1;
        let mut p = self.exponent + 1;
        while up.is_multiple_of(10) {
            up /= 10;
            p += 1;
        }
        let mut digits = Digits::default();
        let len = count(up);
        let mut rest = up;
        for k in (0..len).rev() {
            digits.bytes[k] = b'0' + (rest % 10) as u8;
            rest /= 10;
        }
        digits.len = len;
        Some((digits, len as i32 + p))
    }
}

/// Up to 17 significant digits (ASCII), without leading or trailing zeros.
#[derive(Default)]
struct Digits {
    bytes: [u8; 17],
    len: usize,
}

impl Digits {
    fn as_slice(&self) -> &[u8] {
        &self.bytes[..self.len]
    }
}

/// The significant digits of ryu's text for a positive finite number (`"1.0"`,
/// `"0.001"`, `"1.5e-7"`, `"1e16"`) and the position of the decimal point: the value is
/// `0.d1d2…dn × 10^point`.
fn shortest_digits(text: &str) -> (Digits, i32) {
    let (mantissa, exponent) = match text.find(['e', 'E']) {
        Some(at) => {
            let (sign, magnitude) = match text[at + 1..].strip_prefix('-') {
                Some(rest) => (-1, rest),
                None => (1, &text[at + 1..]),
            };
            let value = magnitude
                .bytes()
                .fold(0i32, |v, b| 10 * v + i32::from(b - b'0'));
            (&text[..at], sign * value)
        }
        None => (text, 0),
    };
    let mut digits = Digits::default();
    // Digits before the point, counted from the first significant one.
    let mut point = 0i32;
    let mut seen_point = false;
    for &b in mantissa.as_bytes() {
        match b {
            b'.' => seen_point = true,
            // A leading zero after the point moves the point left.
            b'0' if digits.len == 0 && seen_point => point -= 1,
            b'0' if digits.len == 0 => {}
            b'0'..=b'9' => {
                if digits.len < digits.bytes.len() {
                    digits.bytes[digits.len] = b;
                    digits.len += 1;
                }
                if !seen_point {
                    point += 1;
                }
            }
            _ => {}
        }
    }
    while digits.len > 1 && digits.bytes[digits.len - 1] == b'0' {
        digits.len -= 1;
    }
    (digits, point + exponent)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// What `write_number` wrote before it had its own layout: Rust's formatting.
    fn reference(v: f64) -> String {
        let a = v.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) || !v.is_finite() {
            format!("{v}")
        } else {
            format!("{v:e}")
        }
    }

    fn written(v: f64) -> String {
        let mut out = Vec::new();
        write_number(&mut out, v).unwrap();
        String::from_utf8(out).unwrap()
    }

    /// Byte for byte Rust's `{}` / `{:e}` on the edges of the two layouts, on powers of
    /// ten and their neighbours, and on 800,000 numbers with random bit patterns
    /// (every exponent) and random values of the magnitudes a results file holds.
    #[test]
    fn numbers_are_laid_out_as_rusts_formatting() {
        let mut special = vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            1e-5,
            9.999999999999999e-6,
            1e16,
            9999999999999998.0,
            0.1 + 0.2,
            core::f64::consts::PI,
            123456789.0,
            1.5,
            -2.5e-7,
            // A tie: exactly …182.25, written …182.3 (ryu alone writes …182.2).
            f64::from_bits(0x431e_3be3_3fa2_cd99),
            2.5,
            0.125,
            1e15 + 0.5,
        ];
        for e in -330..=310 {
            let p = 10f64.powi(e);
            special.extend([p, -p, p.next_up(), p.next_down(), 1.5 * p, 9.87654321 * p]);
        }
        for v in special {
            assert_eq!(written(v), reference(v), "{v:?}");
        }
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            // xorshift64*
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            state.wrapping_mul(0x2545_F491_4F6C_DD1D)
        };
        for _ in 0..400_000 {
            let v = f64::from_bits(next());
            assert_eq!(written(v), reference(v), "{v:?} ({:#x})", v.to_bits());
            let scale = 10f64.powi((next() % 24) as i32 - 12);
            let v = (next() as f64 / u64::MAX as f64 - 0.5) * scale;
            assert_eq!(written(v), reference(v), "{v:?} ({:#x})", v.to_bits());
        }
    }
}
