//! Frequency response of a linear model from one input to one output:
//! `H(jω) = C (jωI − A)⁻¹ B + D`.
//!
//! `A` is reduced once to upper Hessenberg form `A = Q H Qᵀ` (nalgebra); each frequency
//! then costs one solve of the Hessenberg system `(jωI − H) z = Qᵀ b` by Gaussian
//! elimination with row pivoting, `O(n²)` rather than the `O(n³)` of a fresh LU.

use nalgebra::{Complex, DMatrix, DVector};

use crate::linear::LinearModel;

/// `points` frequencies spaced evenly in logarithm from `min` to `max` (both
/// included; one point gives `min`).
pub fn log_grid(min: f64, max: f64, points: usize) -> Vec<f64> {
    match points {
        0 => Vec::new(),
        1 => vec![min],
        _ => {
            let (a, b) = (min.ln(), max.ln());
            (0..points)
                .map(|k| (a + (b - a) * k as f64 / (points - 1) as f64).exp())
                .collect()
        }
    }
}

/// A frequency response: `H(jω)` at each `ω`.
#[derive(Clone, Debug, PartialEq)]
pub struct FrequencyResponse {
    /// The input's name.
    pub input: String,
    /// The output's name.
    pub output: String,
    /// The input's unit (empty when not declared).
    pub input_unit: String,
    /// The output's unit (empty when not declared).
    pub output_unit: String,
    /// Angular frequencies, rad/s.
    pub omega: Vec<f64>,
    /// `H(jω)`, in output units per input unit.
    pub h: Vec<Complex<f64>>,
}

impl FrequencyResponse {
    /// `20 log₁₀ |H|`, dB.
    pub fn magnitude_db(&self) -> Vec<f64> {
        self.h.iter().map(|h| 20.0 * h.norm().log10()).collect()
    }

    /// The phase of `H` in degrees, unwrapped along the grid (no jumps of 360°),
    /// starting in (−180°, 180°].
    pub fn phase_deg(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::with_capacity(self.h.len());
        for h in &self.h {
            let raw = h.arg().to_degrees();
            let value = match out.last() {
                Some(&previous) => raw + 360.0 * ((previous - raw) / 360.0).round(),
                None => raw,
            };
            out.push(value);
        }
        out
    }

    /// The frequencies in hertz.
    pub fn hertz(&self) -> Vec<f64> {
        self.omega
            .iter()
            .map(|w| w / (2.0 * core::f64::consts::PI))
            .collect()
    }
}

/// The reduced form of a linear model for frequency sweeps: `H`, `Q` and the input
/// and output vectors in `Q`'s basis.
pub struct Sweep {
    h: DMatrix<f64>,
    b: DVector<f64>,
    c: DVector<f64>,
    d: f64,
}

impl Sweep {
    /// Prepares the sweep from input `input` to output `output` of `linear` (panics
    /// if either index is out of range).
    pub fn new(linear: &LinearModel, input: usize, output: usize) -> Sweep {
        let hessenberg = linear.a.clone().hessenberg();
        let (q, h) = hessenberg.unpack();
        let b = q.transpose() * linear.b.column(input);
        let c = q.transpose() * linear.c.row(output).transpose();
        Sweep {
            h,
            b,
            c,
            d: linear.d[(output, input)],
        }
    }

    /// `H(jω)`.
    pub fn at(&self, omega: f64) -> Complex<f64> {
        let n = self.h.nrows();
        let s = Complex::new(0.0, omega);
        let mut m = DMatrix::from_fn(n, n, |i, j| {
            let diagonal = if i == j { s } else { Complex::new(0.0, 0.0) };
            diagonal - Complex::new(self.h[(i, j)], 0.0)
        });
        let mut z: Vec<Complex<f64>> = self.b.iter().map(|&v| Complex::new(v, 0.0)).collect();
        // Elimination of the one sub-diagonal entry per column, pivoting between the
        // two rows it involves.
        for k in 0..n.saturating_sub(1) {
            if m[(k + 1, k)].norm() > m[(k, k)].norm() {
                m.swap_rows(k, k + 1);
                z.swap(k, k + 1);
            }
            if m[(k + 1, k)] == Complex::new(0.0, 0.0) {
                continue;
            }
            let factor = m[(k + 1, k)] / m[(k, k)];
            for j in k..n {
                let above = m[(k, j)];
                m[(k + 1, j)] -= factor * above;
            }
            let above = z[k];
            z[k + 1] -= factor * above;
        }
        for k in (0..n).rev() {
            let mut sum = z[k];
            for j in k + 1..n {
                sum -= m[(k, j)] * z[j];
            }
            z[k] = sum / m[(k, k)];
        }
        z.iter()
            .zip(self.c.iter())
            .fold(Complex::new(self.d, 0.0), |acc, (z, &c)| acc + z * c)
    }
}

/// The frequency response of `linear` from input `input` to output `output` at the
/// angular frequencies `omega` (rad/s).
pub fn frequency_response(
    linear: &LinearModel,
    input: usize,
    output: usize,
    omega: &[f64],
) -> FrequencyResponse {
    let sweep = Sweep::new(linear, input, output);
    FrequencyResponse {
        input: linear.inputs[input].clone(),
        output: linear.outputs[output].clone(),
        input_unit: linear.input_units[input].clone(),
        output_unit: linear.output_units[output].clone(),
        omega: omega.to_vec(),
        h: omega.iter().map(|&w| sweep.at(w)).collect(),
    }
}
