//! The spec's results file (`shared/quick-return-spec.md`, "The results file"): its
//! columns, a [`Recorder`] that keeps exactly those columns of any model whose outputs
//! carry their names, and the atomic CSV writer.
//!
//! The file has a header row, the [`COLUMNS`] names separated by commas, then one row per
//! sample: [`N_ROWS`] rows at `t = k / 1000` s, `k = 0..=5000` (every 1 ms from 0 to
//! 5 s; [`sample_times`]). Every number is written in the shortest form that reads back
//! to the same `f64` (plain notation from 1e-5 to 1e16, scientific outside).
//!
//! Each column after `t` is the model's output of the same name, looked up once when the
//! recorder is made, and recorded unchanged. So `crank_angle`, which the spec defines as
//! `atan2(R1[1][0], R1[1][1])` *unwrapped, starting at π/2*, is the model's output of
//! that name, which is already unwrapped (see
//! [`QuickReturn`](super::QuickReturn)'s `crank_angle`): the file, the figures, a
//! `Stepper` and the FMU all read the same angle.

use std::io::{self, Write};
use std::path::Path;

use bgdsl_runtime::record::{write_atomically, RowWriter};
use bgdsl_runtime::{CsvStage, Model, Recorder};

use super::run::{Error, IoStage};

/// The results file's columns, in the spec's order: `t`, then 55 model outputs (all in
/// frame 0, SI units; each force or torque the one the named coupling exerts on the
/// named link).
pub const COLUMNS: [&str; N_COLUMNS] = [
    "t",
    "crank_angle",
    "R1_11",
    "R1_21",
    "R1_31",
    "R1_12",
    "R1_22",
    "R1_32",
    "R1_13",
    "R1_23",
    "R1_33",
    "h1_x",
    "h1_y",
    "h1_z",
    "F_O1_x",
    "F_O1_y",
    "F_O1_z",
    "Tc_x",
    "Tc_y",
    "Tc_z",
    "F_A2_x",
    "F_A2_y",
    "F_A2_z",
    "r_C3_x",
    "r_C3_y",
    "r_C3_z",
    "p3_x",
    "p3_y",
    "p3_z",
    "F_O3_x",
    "F_O3_y",
    "F_O3_z",
    "R4_11",
    "R4_21",
    "R4_31",
    "R4_12",
    "R4_22",
    "R4_32",
    "R4_13",
    "R4_23",
    "R4_33",
    "r_C5_x",
    "r_C5_y",
    "r_C5_z",
    "p5_x",
    "p5_y",
    "p5_z",
    "F_O5_x",
    "F_O5_y",
    "F_O5_z",
    "F_5C_x",
    "F_5C_y",
    "F_5C_z",
    "E_stored",
    "P_in",
    "P_diss",
];

/// The number of columns, `t` included.
pub const N_COLUMNS: usize = 56;

/// The crank angle's column (unwrapped by the model, see the [module
/// documentation](self)).
pub const CRANK_ANGLE: &str = "crank_angle";

/// The last sample time, s.
pub const T_END: f64 = 5.0;

/// Samples per second: one row every 1 ms.
pub const SAMPLES_PER_SECOND: u32 = 1000;

/// Rows of data (the header not counted): `t = 0, 0.001, …, 5`.
pub const N_ROWS: usize = 5001;

/// The name of the results file.
pub const FILE_NAME: &str = "quick_return.csv";

/// The header row, without its line break: the [`COLUMNS`] joined by commas.
pub fn header() -> String {
    COLUMNS.join(",")
}

/// The position of column `name` in [`COLUMNS`].
pub fn column_index(name: &str) -> Option<usize> {
    COLUMNS.iter().position(|c| *c == name)
}

/// Sample time number `k`: exactly `k / 1000` (the correctly rounded quotient, so that
/// `t = 0.001` is the `f64` nearest to 1 ms, not an accumulated sum).
pub fn sample_time(k: usize) -> f64 {
    k as f64 / f64::from(SAMPLES_PER_SECOND)
}

/// The results file's [`N_ROWS`] sample times, [`sample_time`]`(k)` for `k = 0..=5000`.
pub fn sample_times() -> Vec<f64> {
    (0..N_ROWS).map(sample_time).collect()
}

/// The output names of `M` that the results file needs and `M` lacks, in the order of
/// [`COLUMNS`]. Empty when `M` can be recorded.
pub fn missing_outputs<M: Model>() -> Vec<&'static str> {
    COLUMNS[1..]
        .iter()
        .copied()
        .filter(|c| !M::OUTPUT_NAMES.contains(c))
        .collect()
}

/// The results-file columns of a run, in memory: a [`Recorder`] for one model type that
/// keeps, at every sample, the time and the 55 outputs the file needs, in the file's
/// order.
///
/// Made with room for a number of samples ([`Results::for_model`]), recording allocates
/// nothing until that room is used up (it then grows like a `Vec`).
#[derive(Clone, Debug, PartialEq)]
pub struct Results {
    model: &'static str,
    /// The model's number of outputs, to catch a recorder used with another model.
    n_outputs: usize,
    /// For each column after `t`, its index in the model's outputs.
    source: [usize; N_COLUMNS - 1],
    columns: Vec<Vec<f64>>,
    /// The run's events as (time, change of stored energy), for the energy balance.
    event_energy: Vec<(f64, f64)>,
}

impl Results {
    /// An empty recording of the results-file columns of model `M`, with room for
    /// `capacity` samples. Each column is looked up by name in `M::OUTPUT_NAMES` here,
    /// once (the first output of that name, if several share it).
    ///
    /// # Errors
    ///
    /// [`Error::MissingOutputs`] listing every column `M` has no output for.
    pub fn for_model<M: Model>(capacity: usize) -> Result<Self, Error> {
        let missing = missing_outputs::<M>();
        if !missing.is_empty() {
            return Err(Error::MissingOutputs {
                model: M::NAME,
                missing,
            });
        }
        let mut source = [0; N_COLUMNS - 1];
        for (slot, name) in source.iter_mut().zip(&COLUMNS[1..]) {
            *slot = M::OUTPUT_NAMES
                .iter()
                .position(|n| n == name)
                .expect("checked above");
        }
        Ok(Results {
            model: M::NAME,
            n_outputs: M::N_OUTPUTS,
            source,
            columns: (0..N_COLUMNS)
                .map(|_| Vec::with_capacity(capacity))
                .collect(),
            event_energy: Vec::new(),
        })
    }

    /// The name of the model recorded.
    pub fn model_name(&self) -> &'static str {
        self.model
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

    /// Forgets the samples (keeping the memory): the next sample starts a new run.
    pub fn clear(&mut self) {
        self.columns.iter_mut().for_each(Vec::clear);
        self.event_energy.clear();
    }

    /// Notes an event at `t` that changed the stored energy by `change` (J), for the
    /// energy balance (Fig. 21): `stored(t) − stored(0) = ∫ P_in − ∫ P_diss + Σ change`.
    pub fn push_event_energy(&mut self, t: f64, change: f64) {
        self.event_energy.push((t, change));
    }

    /// The events' (time, change of stored energy), in time order; empty for a model
    /// without events.
    pub fn event_energies(&self) -> &[(f64, f64)] {
        &self.event_energy
    }

    /// The sample times.
    pub fn times(&self) -> &[f64] {
        &self.columns[0]
    }

    /// Column `name` of [`COLUMNS`], one value per sample.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        column_index(name).map(|i| &self.columns[i][..])
    }

    /// Column number `index` of [`COLUMNS`].
    ///
    /// # Panics
    ///
    /// If `index >= N_COLUMNS`.
    pub fn column_at(&self, index: usize) -> &[f64] {
        &self.columns[index]
    }

    /// Writes the results file to `out`: the [`header`] row, then one row per sample,
    /// every number in the shortest form that reads back to the same `f64`; each row
    /// ends with `\n`.
    pub fn write_csv_to<W: Write>(&self, mut out: W) -> io::Result<()> {
        out.write_all(header().as_bytes())?;
        out.write_all(b"\n")?;
        let mut rows = RowWriter::new();
        for row in 0..self.len() {
            rows.write_row(&mut out, self.columns.iter().map(|column| column[row]))?;
        }
        out.flush()
    }

    /// Writes the results file to `path` (whose directory must exist), atomically: into
    /// a new temporary file in the same directory, which is flushed, synced and renamed
    /// onto `path`. Either the whole file is written or `path` is left as it was; no
    /// temporary file remains either way.
    ///
    /// # Errors
    ///
    /// [`Error::Io`] with the path and the operation that failed.
    pub fn write_csv(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        write_atomically(path.as_ref(), |out| self.write_csv_to(out)).map_err(|e| Error::Io {
            stage: match e.stage {
                CsvStage::CreateTemporary => IoStage::CreateTemporary,
                CsvStage::Write => IoStage::Write,
                CsvStage::Rename => IoStage::Rename,
            },
            path: e.path,
            source: e.source,
        })
    }
}

impl Recorder for Results {
    /// Appends a sample.
    ///
    /// # Panics
    ///
    /// If `y` does not have the recorded model's number of outputs (a recorder made for
    /// another model).
    fn record(&mut self, t: f64, _x: &[f64], y: &[f64]) {
        assert_eq!(
            y.len(),
            self.n_outputs,
            "the results of model `{}` were given another model's outputs",
            self.model
        );
        self.columns[0].push(t);
        for (column, &from) in self.columns[1..].iter_mut().zip(&self.source) {
            column.push(y[from]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bgdsl_runtime::record::write_number;
    use bgdsl_runtime::Scalar;

    /// A stand-in model with every column as an output (in reverse order, plus one
    /// more), whose crank turns at 5 rad/s from π/2, reported in (−π, π] (so that a
    /// recorder that unwrapped it would be seen).
    struct Stub;

    const fn stub_outputs() -> [&'static str; N_COLUMNS] {
        let mut names = [""; N_COLUMNS];
        let mut i = 1;
        while i < N_COLUMNS {
            names[i - 1] = COLUMNS[N_COLUMNS - i];
            i += 1;
        }
        names[N_COLUMNS - 1] = "extra";
        names
    }
    const STUB_OUTPUTS: [&str; N_COLUMNS] = stub_outputs();

    impl Model for Stub {
        type Params = ();
        const NAME: &'static str = "stub";
        const STATE_NAMES: &'static [&'static str] = &["angle"];
        const OUTPUT_NAMES: &'static [&'static str] = &STUB_OUTPUTS;
        fn params(&self) -> &() {
            &()
        }
        fn initial_state(&self, x0: &mut [f64]) {
            x0[0] = core::f64::consts::FRAC_PI_2;
        }
        fn derivatives<T: Scalar>(&self, _t: f64, _x: &[T], dx: &mut [T]) {
            dx[0] = T::from_f64(5.0);
        }
        fn outputs<T: Scalar>(&self, _t: f64, x: &[T], y: &mut [T]) {
            for (i, v) in y.iter_mut().enumerate() {
                *v = T::from_f64(i as f64);
            }
            let a = x[0].to_f64();
            let wrapped = a.sin().atan2(a.cos());
            let at = STUB_OUTPUTS.iter().position(|n| *n == CRANK_ANGLE).unwrap();
            y[at] = T::from_f64(wrapped);
        }
    }

    struct Incomplete;
    impl Model for Incomplete {
        type Params = ();
        const NAME: &'static str = "incomplete";
        const STATE_NAMES: &'static [&'static str] = &["x"];
        const OUTPUT_NAMES: &'static [&'static str] = &["t", "crank_angle", "R1_11"];
        fn params(&self) -> &() {
            &()
        }
        fn initial_state(&self, _x0: &mut [f64]) {}
        fn derivatives<T: Scalar>(&self, _t: f64, _x: &[T], _dx: &mut [T]) {}
        fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
    }

    #[test]
    fn has_the_specs_columns() {
        assert_eq!(COLUMNS.len(), 56);
        let distinct: std::collections::BTreeSet<_> = COLUMNS.iter().collect();
        assert_eq!(distinct.len(), COLUMNS.len());
        assert!(header().starts_with("t,crank_angle,R1_11,R1_21,R1_31,R1_12,"));
        assert!(header().ends_with(",F_5C_z,E_stored,P_in,P_diss"));
        let times = sample_times();
        assert_eq!(times.len(), N_ROWS);
        assert_eq!(times[1], 0.001);
        assert_eq!(times[N_ROWS - 1], T_END);
    }

    #[test]
    fn names_every_missing_output() {
        let err = Results::for_model::<Incomplete>(0).unwrap_err();
        let Error::MissingOutputs { model, missing } = &err else {
            panic!("{err}")
        };
        assert_eq!(*model, "incomplete");
        assert_eq!(missing.len(), 53);
        assert_eq!(missing[0], "R1_21");
        let message = err.to_string();
        assert!(message.contains("`incomplete`"), "{message}");
        assert!(message.contains("R1_21, R1_31"), "{message}");
        assert!(message.contains("P_diss"), "{message}");
    }

    #[test]
    fn picks_columns_by_name_and_records_them_unchanged() {
        let mut results = Results::for_model::<Stub>(N_ROWS).unwrap();
        let mut sim =
            bgdsl_runtime::Simulation::new(&Stub, bgdsl_runtime::Solver::rk4(1e-3)).unwrap();
        let times = sample_times();
        let mut x0 = [0.0];
        Stub.initial_state(&mut x0);
        sim.run(0.0, &x0, &times, &mut results).unwrap();
        assert_eq!(results.len(), N_ROWS);
        assert_eq!(results.capacity(), N_ROWS);
        assert_eq!(results.times(), &times[..]);
        for (i, name) in COLUMNS.iter().enumerate().skip(1) {
            if *name == CRANK_ANGLE {
                continue;
            }
            let at = STUB_OUTPUTS.iter().position(|n| n == name).unwrap();
            assert!(results
                .column(name)
                .unwrap()
                .iter()
                .all(|&v| v == at as f64));
            assert_eq!(results.column_at(i), results.column(name).unwrap());
        }
        // The model's angle as it gives it: wrapped, here.
        let angle = results.column(CRANK_ANGLE).unwrap();
        for (k, (&a, &t)) in angle.iter().zip(&times).enumerate() {
            let turned = core::f64::consts::FRAC_PI_2 + 5.0 * t;
            let expected = turned.sin().atan2(turned.cos());
            assert!((a - expected).abs() < 1e-9, "row {k}: {a} vs {expected}");
        }

        let mut csv = Vec::new();
        results.write_csv_to(&mut csv).unwrap();
        let text = String::from_utf8(csv).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next().unwrap(), header());
        for (k, line) in lines.enumerate() {
            let values: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
            assert_eq!(values.len(), N_COLUMNS);
            for (i, v) in values.iter().enumerate() {
                assert_eq!(v.to_bits(), results.column_at(i)[k].to_bits());
            }
        }

        results.clear();
        assert!(results.is_empty());
        sim.run(0.0, &x0, &times[..2], &mut results).unwrap();
        assert_eq!(
            results.column(CRANK_ANGLE).unwrap()[0],
            core::f64::consts::FRAC_PI_2
        );
    }

    #[test]
    fn numbers_round_trip() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -2.5,
            1e-5,
            9.99e-6,
            1e-300,
            5e-324,
            1e16,
            1.7976931348623157e308,
            0.1 + 0.2,
        ] {
            let mut s = Vec::new();
            write_number(&mut s, v).unwrap();
            let back: f64 = String::from_utf8(s).unwrap().parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits());
        }
    }
}
