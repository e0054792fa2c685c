//! The events of a run in the catalogue: kept while the model runs ([`EventCollector`],
//! a [`Recorder`]), written as `events.csv`, counted in the summary, and their energy
//! changes handed to the energy balance.
//!
//! `events.csv` has the header `t,event,state,before,after,event_energy` and one row
//! per state (continuous state or mode) that an event changed, in time order: the
//! event's time t* (s), its name (`Model::EVENTS`), the state's name and its values
//! just before and just after the event, and the change of stored energy the event
//! made (`bgdsl_runtime::event_energy`, J; the same on every row of one event, empty
//! for a model without an energy account). An event that changed no state has one row
//! with an empty `state`. Every number is written in the shortest form that reads back
//! to the same `f64`. The file is written only for models that have events.

use core::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

use bgdsl_runtime::record::{write_atomically, write_number};
use bgdsl_runtime::{event_energy, EventLog, EventRecord, Model, Recorder};

/// The name of the events file.
pub const FILE_NAME: &str = "events.csv";

/// Keeps every event of a run (with room for `capacity` up front).
pub(super) struct EventCollector {
    pub(super) log: EventLog,
}

impl EventCollector {
    /// A collector for the states of `M`.
    pub(super) fn new<M: Model>(capacity: usize) -> Self {
        EventCollector {
            log: EventLog::growing(M::N_STATES, capacity),
        }
    }
}

impl Recorder for EventCollector {
    fn record(&mut self, _t: f64, _x: &[f64], _y: &[f64]) {}

    fn event(&mut self, record: &EventRecord<'_>) {
        self.log.push(record);
    }
}

/// Each event's change of stored energy, in the log's order (`None` where the model
/// keeps no energy account).
pub(super) fn energies<M: Model>(model: &M, log: &EventLog) -> Vec<Option<f64>> {
    log.iter()
        .map(|e| event_energy(model, e.t, e.before, e.after))
        .collect()
}

/// Writes `events.csv` (see the [module documentation](self)) to `path`, whole or not
/// at all.
pub(super) fn write_csv(
    path: &Path,
    log: &EventLog,
    energies: &[Option<f64>],
    state_names: &[&str],
) -> Result<(), bgdsl_runtime::CsvError> {
    write_atomically(path, |out| write_to(out, log, energies, state_names))
}

fn write_to<W: Write>(
    out: &mut W,
    log: &EventLog,
    energies: &[Option<f64>],
    state_names: &[&str],
) -> io::Result<()> {
    out.write_all(b"t,event,state,before,after,event_energy\n")?;
    for (e, energy) in log.iter().zip(energies) {
        let changed: Vec<usize> = (0..e.before.len())
            .filter(|&i| e.before[i].to_bits() != e.after[i].to_bits())
            .collect();
        let row = |out: &mut W, state: Option<usize>| -> io::Result<()> {
            write_number(&mut *out, e.t)?;
            write!(out, ",{},", e.name)?;
            if let Some(i) = state {
                write!(out, "{},", state_names.get(i).copied().unwrap_or("?"))?;
                write_number(&mut *out, e.before[i])?;
                out.write_all(b",")?;
                write_number(&mut *out, e.after[i])?;
            } else {
                out.write_all(b",,")?;
            }
            out.write_all(b",")?;
            if let Some(energy) = energy {
                write_number(&mut *out, *energy)?;
            }
            out.write_all(b"\n")
        };
        if changed.is_empty() {
            row(out, None)?;
        }
        for i in changed {
            row(out, Some(i))?;
        }
    }
    out.flush()
}

/// The summary's lines on the events: how many of each (in the model's order, those
/// that fired), and the energy they changed in all.
pub(super) fn summary_lines(
    names: &[&'static str],
    log: &EventLog,
    energies: &[Option<f64>],
) -> String {
    let mut s = String::new();
    let counts: Vec<(&str, usize)> = names
        .iter()
        .map(|name| (*name, log.iter().filter(|e| e.name == *name).count()))
        .filter(|(_, n)| *n > 0)
        .collect();
    let list = counts
        .iter()
        .map(|(name, n)| format!("{name} {n}"))
        .collect::<Vec<_>>()
        .join(", ");
    let _ = write!(s, "events         {}", log.len());
    if !list.is_empty() {
        let _ = write!(s, " ({list})");
    }
    let _ = writeln!(s);
    if !log.is_empty() {
        let total: Option<f64> = energies.iter().copied().sum();
        match total {
            Some(total) => {
                let _ = writeln!(
                    s,
                    "event energy   {} J (the change of stored energy the events made, in all)",
                    super::params::format_significant(total)
                );
            }
            None => {
                let _ = writeln!(s, "event energy   n/a (the model keeps no energy account)");
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use bgdsl_runtime::EventAction;

    #[test]
    fn writes_one_row_per_changed_state() {
        let mut log = EventLog::growing(3, 4);
        let before = [1.0, 2.0, 0.0];
        let after = [1.0, -1.5, 1.0];
        log.push(&EventRecord {
            t: 0.25,
            index: 0,
            name: "hit",
            before: &before,
            after: &after,
            action: EventAction::Continue,
        });
        log.push(&EventRecord {
            t: 0.5,
            index: 1,
            name: "lift",
            before: &after,
            after: &after,
            action: EventAction::Continue,
        });
        let mut out = Vec::new();
        write_to(
            &mut out,
            &log,
            &[Some(-0.875), None],
            &["p", "v", "resting"],
        )
        .unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "t,event,state,before,after,event_energy\n\
             0.25,hit,v,2,-1.5,-0.875\n\
             0.25,hit,resting,0,1,-0.875\n\
             0.5,lift,,,,\n"
        );
        let lines = summary_lines(&["hit", "lift", "never"], &log, &[Some(-0.875), Some(0.0)]);
        assert_eq!(
            lines,
            "events         2 (hit 1, lift 1)\n\
             event energy   -0.875000 J (the change of stored energy the events made, in all)\n"
        );
    }
}
