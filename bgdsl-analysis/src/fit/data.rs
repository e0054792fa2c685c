//! Measured signals: a CSV file whose first column is the time (`t` or `time`) and whose
//! other columns are named like the model's outputs; optionally, each column's known
//! noise standard deviation.

use super::FitError;

/// Measured signals on a common time base.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurements {
    /// The sample times, increasing.
    pub times: Vec<f64>,
    /// The signals' names, as in the header.
    pub names: Vec<String>,
    /// One column per name, one value per time (NaN where a cell is empty: not
    /// measured then).
    pub values: Vec<Vec<f64>>,
    /// Per column, the noise's standard deviation when it is known (in the column's
    /// unit): the fit then weighs the column by `1/σ²` as given and checks the
    /// residuals against it (χ²). `None`: estimated from the fit's residuals.
    pub sigma: Vec<Option<f64>>,
}

impl Measurements {
    /// Parses CSV text: a header line, then one line per sample; commas separate cells;
    /// an empty cell or `nan` is a sample not measured.
    ///
    /// # Errors
    /// [`FitError::Data`] naming the line of the first problem: no header, a time
    /// column that is not first, a line with the wrong number of cells, a number that
    /// does not parse, times not increasing, fewer than two samples.
    pub fn parse_csv(text: &str) -> Result<Self, FitError> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let bad = |line: usize, message: String| FitError::Data {
            line: line + 1,
            message,
        };
        let (_, header) = lines
            .next()
            .ok_or_else(|| bad(0, "the file is empty: expected a header line".into()))?;
        let cells: Vec<String> = header.split(',').map(|c| c.trim().to_string()).collect();
        if !matches!(cells.first().map(String::as_str), Some("t" | "time")) {
            return Err(bad(
                0,
                format!(
                    "the first column must be the time, named `t` or `time`; found `{}`",
                    cells.first().map_or("", String::as_str)
                ),
            ));
        }
        let names: Vec<String> = cells[1..].to_vec();
        if names.is_empty() {
            return Err(bad(0, "no measured column after the time".into()));
        }
        let mut times = Vec::new();
        let mut values = vec![Vec::new(); names.len()];
        for (number, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != names.len() + 1 {
                return Err(bad(
                    number,
                    format!("expected {} cells, found {}", names.len() + 1, cells.len()),
                ));
            }
            let parse = |cell: &str| -> Result<f64, FitError> {
                if cell.is_empty() || cell.eq_ignore_ascii_case("nan") {
                    return Ok(f64::NAN);
                }
                cell.parse::<f64>()
                    .map_err(|_| bad(number, format!("`{cell}` is not a number")))
            };
            let t = parse(cells[0])?;
            if !t.is_finite() || times.last().is_some_and(|&last: &f64| t <= last) {
                return Err(bad(
                    number,
                    format!("the time {t} is not finite or not after the one before"),
                ));
            }
            times.push(t);
            for (column, cell) in values.iter_mut().zip(&cells[1..]) {
                column.push(parse(cell)?);
            }
        }
        if times.len() < 2 {
            return Err(bad(0, "fewer than two samples".into()));
        }
        Ok(Measurements {
            times,
            sigma: vec![None; names.len()],
            names,
            values,
        })
    }

    /// States that column `name`'s noise has the standard deviation `sigma` (in the
    /// column's unit).
    ///
    /// # Errors
    /// [`FitError::BadNoise`] when there is no such column or `sigma` is not a positive
    /// finite number.
    pub fn set_sigma(&mut self, name: &str, sigma: f64) -> Result<(), FitError> {
        let bad = |message: String| FitError::BadNoise {
            column: name.to_owned(),
            message,
        };
        let c = self.names.iter().position(|n| n == name).ok_or_else(|| {
            bad(format!(
                "no such measured column (the columns: {})",
                self.names.join(", ")
            ))
        })?;
        if !(sigma.is_finite() && sigma > 0.0) {
            return Err(bad(format!(
                "the noise's standard deviation must be a positive number, not {sigma}"
            )));
        }
        self.sigma.resize(self.names.len(), None);
        self.sigma[c] = Some(sigma);
        Ok(())
    }

    /// Column `c`'s known noise standard deviation, if given.
    pub fn sigma_of(&self, c: usize) -> Option<f64> {
        self.sigma.get(c).copied().flatten()
    }
}
