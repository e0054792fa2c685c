//! Linearisation at an operating point `(t, x, u)`:
//! `δẋ = A δx + B δu`, `δy = C δx + D δu`, with `A = ∂f/∂x`, `B = ∂f/∂u`,
//! `C = ∂g/∂x`, `D = ∂g/∂u`, exact by dual numbers and labelled by name.
//!
//! The "inputs" of a linear model are the model's declared inputs or any of its scalar
//! parameters ([`Channel`]): a catalogue model drives its circuit with a `param
//! voltage`, and a linear model from that voltage is as useful as from an input.

use bgdsl_runtime::{Model, WithInputs};
use nalgebra::DMatrix;

use crate::partials::{input_partials, parameter_partials, state_partials, Method};
use crate::AnalysisError;

/// A variable a linear model takes as input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    /// Declared input number `k` (in [`WithInputs::INPUTS`] order).
    Input(usize),
    /// Parameter value number `k` (in [`Model::parameter_values`] order).
    Parameter(usize),
}

impl Channel {
    /// The channel named `name`: an input of that name, else a parameter (a component
    /// of a vector parameter as `name[i]`, of a matrix as `name[i][j]`).
    ///
    /// # Errors
    /// [`AnalysisError::UnknownName`] listing the inputs and parameters.
    pub fn named<M: WithInputs>(name: &str) -> Result<Channel, AnalysisError> {
        if let Some(k) = M::INPUTS.iter().position(|i| i.name == name) {
            return Ok(Channel::Input(k));
        }
        parameter_index::<M>(name)
            .map(Channel::Parameter)
            .ok_or_else(|| AnalysisError::UnknownName {
                what: "input or parameter",
                name: name.to_string(),
                known: M::INPUTS
                    .iter()
                    .map(|i| i.name.to_string())
                    .chain(parameter_names::<M>())
                    .collect(),
            })
    }

    /// The channel's name, as [`Channel::named`] reads it.
    pub fn name<M: WithInputs>(self) -> String {
        match self {
            Channel::Input(k) => M::INPUTS[k].name.to_string(),
            Channel::Parameter(k) => parameter_names::<M>().nth(k).unwrap_or_default(),
        }
    }

    /// The channel's unit, empty when the model does not say.
    pub fn unit<M: WithInputs>(self) -> &'static str {
        match self {
            Channel::Input(k) => M::INPUTS[k].unit,
            Channel::Parameter(k) => {
                let mut at = 0;
                for p in M::PARAMETERS {
                    if k < at + p.len {
                        return p.unit;
                    }
                    at += p.len;
                }
                ""
            }
        }
    }
}

/// Every parameter value's name, in [`Model::parameter_values`] order: `m` for a
/// number, `l[0]`, `l[1]`, … for the components of a vector or matrix (a matrix row by
/// row).
pub fn parameter_names<M: Model>() -> impl Iterator<Item = String> {
    M::PARAMETERS.iter().flat_map(|p| {
        (0..p.len).map(move |i| match p.len {
            1 => p.name.to_string(),
            _ => format!("{}[{i}]", p.name),
        })
    })
}

/// The index of the parameter value called `name` (see [`parameter_names`]).
pub fn parameter_index<M: Model>(name: &str) -> Option<usize> {
    parameter_names::<M>().position(|n| n == name)
}

/// A linear model: matrices, names, units and the operating point.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearModel {
    /// The model's name.
    pub model: String,
    /// State names (rows and columns of `A`).
    pub states: Vec<String>,
    /// Input names (columns of `B` and `D`).
    pub inputs: Vec<String>,
    /// Output names (rows of `C` and `D`).
    pub outputs: Vec<String>,
    /// State units (empty where not declared).
    pub state_units: Vec<String>,
    /// Input units.
    pub input_units: Vec<String>,
    /// Output units.
    pub output_units: Vec<String>,
    /// The operating point's time.
    pub t: f64,
    /// The operating point's state.
    pub x: Vec<f64>,
    /// The operating point's inputs (values of the channels).
    pub u: Vec<f64>,
    /// `∂f/∂x`.
    pub a: DMatrix<f64>,
    /// `∂f/∂u`.
    pub b: DMatrix<f64>,
    /// `∂g/∂x`.
    pub c: DMatrix<f64>,
    /// `∂g/∂u`.
    pub d: DMatrix<f64>,
    /// How `B` and `D` were computed (`A` and `C` are always exact).
    pub method: Method,
}

impl LinearModel {
    /// The index of the input called `name`.
    ///
    /// # Errors
    /// [`AnalysisError::UnknownName`].
    pub fn input_index(&self, name: &str) -> Result<usize, AnalysisError> {
        find(&self.inputs, name, "input")
    }

    /// The index of the output called `name`.
    ///
    /// # Errors
    /// [`AnalysisError::UnknownName`].
    pub fn output_index(&self, name: &str) -> Result<usize, AnalysisError> {
        find(&self.outputs, name, "output")
    }
}

fn find(names: &[String], name: &str, what: &'static str) -> Result<usize, AnalysisError> {
    names
        .iter()
        .position(|n| n == name)
        .ok_or_else(|| AnalysisError::UnknownName {
            what,
            name: name.to_string(),
            known: names.to_vec(),
        })
}

/// The linear model of `model` (with its current parameters and inputs) at time `t`
/// and state `x`, from the inputs `channels`.
///
/// # Errors
/// A state of the wrong length, a channel out of range, non-finite derivatives.
pub fn linearize<M: WithInputs + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    channels: &[Channel],
) -> Result<LinearModel, AnalysisError> {
    let states = state_partials(model, t, x)?;
    let inputs: Vec<usize> = channels
        .iter()
        .filter_map(|c| match c {
            Channel::Input(k) => Some(*k),
            Channel::Parameter(_) => None,
        })
        .collect();
    let params: Vec<usize> = channels
        .iter()
        .filter_map(|c| match c {
            Channel::Parameter(k) => Some(*k),
            Channel::Input(_) => None,
        })
        .collect();
    let by_input = input_partials(model, t, x, &inputs)?;
    let by_param = parameter_partials(model, t, x, &params)?;
    let (n, m, k) = (M::N_STATES, M::N_OUTPUTS, channels.len());
    let mut b = DMatrix::zeros(n, k);
    let mut d = DMatrix::zeros(m, k);
    let (mut next_input, mut next_param) = (0, 0);
    let mut values = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    let mut input_values = vec![0.0; M::INPUTS.len()];
    model.input_values(&mut input_values);
    let mut u = Vec::with_capacity(k);
    for (col, channel) in channels.iter().enumerate() {
        let (source, at) = match channel {
            Channel::Input(i) => {
                next_input += 1;
                u.push(input_values[*i]);
                (&by_input, next_input - 1)
            }
            Channel::Parameter(p) => {
                next_param += 1;
                u.push(values[*p]);
                (&by_param, next_param - 1)
            }
        };
        b.set_column(col, &source.df.column(at));
        d.set_column(col, &source.dg.column(at));
    }
    let method = if (inputs.is_empty() || by_input.method == Method::Exact)
        && (params.is_empty() || by_param.method == Method::Exact)
    {
        Method::Exact
    } else {
        Method::CentralDifferences
    };
    let names = |list: &[&str]| list.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let units = |infos: &[bgdsl_runtime::SignalInfo], len: usize| {
        (0..len)
            .map(|i| bgdsl_runtime::unit_of(infos, i).to_string())
            .collect::<Vec<_>>()
    };
    Ok(LinearModel {
        model: M::NAME.to_string(),
        states: names(M::STATE_NAMES),
        inputs: channels.iter().map(|c| c.name::<M>()).collect(),
        outputs: names(M::OUTPUT_NAMES),
        state_units: units(M::STATES, n),
        input_units: channels.iter().map(|c| c.unit::<M>().to_string()).collect(),
        output_units: units(M::OUTPUTS, m),
        t,
        x: x.to_vec(),
        u,
        a: states.df,
        b,
        c: states.dg,
        d,
        method,
    })
}
