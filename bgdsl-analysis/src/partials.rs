//! Exact partial derivatives of a model's right-hand side `f(t, x, p, u)` and outputs
//! `g(t, x, p, u)`: in the state (∂f/∂x, ∂g/∂x), in chosen parameters (∂f/∂p, ∂g/∂p)
//! and in chosen inputs (∂f/∂u, ∂g/∂u).
//!
//! States are seeded as [`DualN`] numbers; parameters and inputs as
//! [`ParamDual`] numbers (see `bgdsl_runtime::param_dual`), [`LANES`] directions per
//! evaluation. A model that does not keep parameter tangents
//! ([`Model::EXACT_PARAMETER_DERIVATIVES`] is `false`: a hand-written one, or one whose
//! parameter expression calls a user's `f64` function) is differentiated in its
//! parameters and inputs by central differences instead, and [`Partials::method`] says
//! so.
//!
//! Parameter indices are those of [`Model::parameter_values`] (declaration order,
//! vectors component by component, matrices row by row); input indices those of
//! [`WithInputs::INPUTS`].

use bgdsl_runtime::param_dual::with_seeds;
use bgdsl_runtime::{DualN, Model, ParamDual, Scalar, WithInputs};
use nalgebra::DMatrix;

use crate::AnalysisError;

/// Directions evaluated together (tangent lanes per evaluation).
pub const LANES: usize = 8;

/// How a set of partial derivatives was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// By dual numbers: exact to round-off.
    Exact,
    /// By central differences (step `6e-6·|v|` for a value `v`, `6e-6` at 0): accurate to
    /// about 1e-10 relative for smooth laws, for models that do not keep parameter
    /// tangents.
    CentralDifferences,
}

impl Method {
    /// A short description for reports: `exact (dual numbers)` or `central differences`.
    pub fn describe(self) -> &'static str {
        match self {
            Method::Exact => "exact (dual numbers)",
            Method::CentralDifferences => "central differences",
        }
    }
}

/// Partial derivatives of the right-hand side and the outputs with respect to some
/// variables (states, parameters or inputs), one column per variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Partials {
    /// ∂f/∂v: `N_STATES` rows.
    pub df: DMatrix<f64>,
    /// ∂g/∂v: `N_OUTPUTS` rows.
    pub dg: DMatrix<f64>,
    /// How they were computed.
    pub method: Method,
}

/// Checks that `x` is a state of `M`.
pub(crate) fn check_state<M: Model>(x: &[f64]) -> Result<(), AnalysisError> {
    if x.len() != M::N_STATES {
        return Err(AnalysisError::Dimension {
            what: "state vector",
            expected: M::N_STATES,
            found: x.len(),
        });
    }
    Ok(())
}

fn check_indices(which: &[usize], bound: usize, what: &'static str) -> Result<(), AnalysisError> {
    match which.iter().find(|&&i| i >= bound) {
        Some(&found) => Err(AnalysisError::Dimension {
            what,
            expected: bound,
            found,
        }),
        None => Ok(()),
    }
}

/// Fails on the first non-finite entry of `values`, named from `names`.
pub(crate) fn check_finite(
    values: impl IntoIterator<Item = f64>,
    names: &[&str],
    what: &'static str,
) -> Result<(), AnalysisError> {
    match values.into_iter().position(|v| !v.is_finite()) {
        Some(i) => Err(AnalysisError::NonFinite {
            what,
            name: names.get(i).copied().unwrap_or("?").to_string(),
        }),
        None => Ok(()),
    }
}

/// ∂f/∂x and ∂g/∂x of `model` at `(t, x)`, exact (dense; `LANES` columns per
/// evaluation of `derivatives` and `outputs`).
///
/// # Errors
/// A state vector of the wrong length; non-finite derivatives.
pub fn state_partials<M: Model>(model: &M, t: f64, x: &[f64]) -> Result<Partials, AnalysisError> {
    check_state::<M>(x)?;
    let (n, m) = (M::N_STATES, M::N_OUTPUTS);
    let mut df = DMatrix::zeros(n, n);
    let mut dg = DMatrix::zeros(m, n);
    let mut xs = vec![DualN::<LANES>::default(); n];
    let mut dx = vec![DualN::<LANES>::default(); n];
    let mut y = vec![DualN::<LANES>::default(); m];
    for first in (0..n).step_by(LANES) {
        for (j, (xj, &value)) in xs.iter_mut().zip(x).enumerate() {
            *xj = DualN::constant(value);
            if (first..first + LANES).contains(&j) {
                xj.set_tangent(j - first, 1.0);
            }
        }
        model.derivatives(t, &xs, &mut dx);
        model.outputs(t, &xs, &mut y);
        let lanes = LANES.min(n - first);
        for k in 0..lanes {
            for (i, v) in dx.iter().enumerate() {
                df[(i, first + k)] = v.tangents()[k];
            }
            for (i, v) in y.iter().enumerate() {
                dg[(i, first + k)] = v.tangents()[k];
            }
        }
    }
    check_finite(df.iter().copied(), &[], "derivatives' Jacobian")?;
    Ok(Partials {
        df,
        dg,
        method: Method::Exact,
    })
}

/// Which kind of variable the seeded and central partials differentiate in.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Parameters,
    Inputs,
}

/// Which of `f` and `g` to differentiate.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Parts {
    Both,
    /// `∂f/∂v` only (`dg` is left as it was): what a sensitivity integrator wants.
    Rhs,
    /// `∂g/∂v` only (`df` is left as it was).
    Outputs,
}

impl Parts {
    fn rhs(self) -> bool {
        self != Parts::Outputs
    }
    fn outputs(self) -> bool {
        self != Parts::Rhs
    }
}

/// Buffers for the central differences of a model that keeps no parameter tangents:
/// a copy of the model to move, the base and moved values, `f` and `g` on both sides.
struct Central<M> {
    copy: M,
    base: Vec<f64>,
    values: Vec<f64>,
    f_plus: Vec<f64>,
    f_minus: Vec<f64>,
    g_plus: Vec<f64>,
    g_minus: Vec<f64>,
}

/// The buffers of repeated parameter or input partials of one model type, prepared once
/// and reused, so that a hot loop (the variational equations' SDIRK stages, a fit's
/// iterations) does not allocate: [`PartialsWorkspace::parameter_partials`] and
/// [`PartialsWorkspace::input_partials`] allocate nothing after the first call with a
/// given number of columns, for a model with exact parameter derivatives
/// ([`Model::EXACT_PARAMETER_DERIVATIVES`]; `tests/partials_alloc_free.rs` counts).
/// A model differentiated by central differences is copied into the workspace on every
/// call (`Clone::clone_from`), which allocates if the model holds heap data.
///
/// ```
/// use bgdsl_analysis::partials::PartialsWorkspace;
/// use bgdsl_runtime::Model;
/// use models::Oscillator;
///
/// let model = Oscillator::default();
/// let mut x = vec![0.0; Oscillator::N_STATES];
/// model.initial_state(&mut x);
/// let mut work = PartialsWorkspace::new(&model);
/// for step in 0..3 {
///     x[0] += 0.01 * step as f64;
///     let partials = work.parameter_partials(&model, 0.0, &x, &[0, 1])?;
///     assert_eq!(partials.df.shape(), (Oscillator::N_STATES, 2));
/// }
/// # Ok::<(), bgdsl_analysis::AnalysisError>(())
/// ```
pub struct PartialsWorkspace<M> {
    xs: Vec<ParamDual<LANES>>,
    dx: Vec<ParamDual<LANES>>,
    y: Vec<ParamDual<LANES>>,
    central: Option<Central<M>>,
    partials: Partials,
}

impl<M: Model + Clone> PartialsWorkspace<M> {
    /// The buffers for partials of models of `model`'s type (`model` is copied only
    /// when it keeps no parameter tangents, for its central differences).
    pub fn new(model: &M) -> Self {
        let (n, m) = (M::N_STATES, M::N_OUTPUTS);
        let exact = M::EXACT_PARAMETER_DERIVATIVES;
        PartialsWorkspace {
            xs: vec![ParamDual::default(); n],
            dx: vec![ParamDual::default(); n],
            y: vec![ParamDual::default(); m],
            central: (!exact).then(|| Central {
                copy: model.clone(),
                base: Vec::new(),
                values: Vec::new(),
                f_plus: vec![0.0; n],
                f_minus: vec![0.0; n],
                g_plus: vec![0.0; m],
                g_minus: vec![0.0; m],
            }),
            partials: Partials {
                df: DMatrix::zeros(n, 0),
                dg: DMatrix::zeros(m, 0),
                method: if exact {
                    Method::Exact
                } else {
                    Method::CentralDifferences
                },
            },
        }
    }

    /// As [`parameter_partials`](fn@parameter_partials), into this workspace's buffers:
    /// the result lives until the next call.
    ///
    /// # Errors
    /// As [`parameter_partials`](fn@parameter_partials).
    pub fn parameter_partials(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        which: &[usize],
    ) -> Result<&Partials, AnalysisError> {
        self.parameters(model, t, x, which, Parts::Both)?;
        Ok(&self.partials)
    }

    /// ∂f/∂p alone (`dg` of the result is stale): for the variational equations and
    /// [`parameter_jacobian`].
    pub(crate) fn parameter_rhs_partials(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        which: &[usize],
    ) -> Result<&DMatrix<f64>, AnalysisError> {
        self.parameters(model, t, x, which, Parts::Rhs)?;
        Ok(&self.partials.df)
    }

    /// ∂g/∂p alone (`df` of the result is stale).
    pub(crate) fn parameter_output_partials(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        which: &[usize],
    ) -> Result<&DMatrix<f64>, AnalysisError> {
        self.parameters(model, t, x, which, Parts::Outputs)?;
        Ok(&self.partials.dg)
    }

    fn parameters(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        which: &[usize],
        parts: Parts,
    ) -> Result<(), AnalysisError> {
        check_state::<M>(x)?;
        check_indices(which, M::N_PARAMETER_VALUES, "parameter index")?;
        self.shape(which.len());
        if M::EXACT_PARAMETER_DERIVATIVES {
            self.seeded(model, t, x, which, Kind::Parameters, parts);
        } else {
            self.central(
                model,
                t,
                x,
                which,
                parts,
                |model, values| {
                    values.resize(M::N_PARAMETER_VALUES, 0.0);
                    model.parameter_values(values);
                },
                |model, values| model.set_parameter_values(values),
            );
        }
        self.check(parts, "parameter derivatives")
    }

    /// `df` and `dg` with `k` columns (allocates only when `k` changes).
    fn shape(&mut self, k: usize) {
        let (n, m) = (M::N_STATES, M::N_OUTPUTS);
        if self.partials.df.ncols() != k {
            self.partials.df = DMatrix::zeros(n, k);
            self.partials.dg = DMatrix::zeros(m, k);
        }
    }

    fn check(&self, parts: Parts, what: &'static str) -> Result<(), AnalysisError> {
        if parts.rhs() {
            check_finite(self.partials.df.iter().copied(), &[], what)
        } else {
            Ok(())
        }
    }

    /// ∂f/∂v and/or ∂g/∂v for the parameters or inputs `which`, by [`ParamDual`]
    /// evaluations, [`LANES`] at a time.
    fn seeded(&mut self, model: &M, t: f64, x: &[f64], which: &[usize], kind: Kind, parts: Parts) {
        for (xj, &v) in self.xs.iter_mut().zip(x) {
            *xj = ParamDual::from_f64(v);
        }
        let (xs, dx, y) = (&self.xs, &mut self.dx, &mut self.y);
        let Partials { df, dg, .. } = &mut self.partials;
        for (c, chunk) in which.chunks(LANES).enumerate() {
            let (params, inputs): (&[usize], &[usize]) = match kind {
                Kind::Parameters => (chunk, &[]),
                Kind::Inputs => (&[], chunk),
            };
            with_seeds(params, inputs, || {
                if parts.rhs() {
                    model.derivatives(t, xs, dx);
                }
                if parts.outputs() {
                    model.outputs(t, xs, y);
                }
            });
            for k in 0..chunk.len() {
                let col = c * LANES + k;
                if parts.rhs() {
                    for (i, v) in dx.iter().enumerate() {
                        df[(i, col)] = v.tangents()[k];
                    }
                }
                if parts.outputs() {
                    for (i, v) in y.iter().enumerate() {
                        dg[(i, col)] = v.tangents()[k];
                    }
                }
            }
        }
    }

    /// Central differences of `f` and/or `g` along the values `which` of a vector that
    /// `get`/`set` read and write, on the workspace's copy of `model`.
    #[allow(clippy::too_many_arguments)]
    fn central(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        which: &[usize],
        parts: Parts,
        get: impl Fn(&M, &mut Vec<f64>),
        set: impl Fn(&mut M, &[f64]),
    ) {
        let c = self
            .central
            .as_mut()
            .expect("a workspace for a model without parameter tangents has its copy");
        let Partials { df, dg, .. } = &mut self.partials;
        c.copy.clone_from(model);
        get(model, &mut c.base);
        c.values.clone_from(&c.base);
        for (col, &i) in which.iter().enumerate() {
            let base = c.base[i];
            let h = 6e-6 * if base == 0.0 { 1.0 } else { base.abs() };
            c.values[i] = base + h;
            set(&mut c.copy, &c.values);
            if parts.rhs() {
                c.copy.derivatives(t, x, &mut c.f_plus);
            }
            if parts.outputs() {
                c.copy.outputs(t, x, &mut c.g_plus);
            }
            c.values[i] = base - h;
            set(&mut c.copy, &c.values);
            if parts.rhs() {
                c.copy.derivatives(t, x, &mut c.f_minus);
            }
            if parts.outputs() {
                c.copy.outputs(t, x, &mut c.g_minus);
            }
            c.values[i] = base;
            if parts.rhs() {
                for (r, (plus, minus)) in c.f_plus.iter().zip(&c.f_minus).enumerate() {
                    df[(r, col)] = (plus - minus) / (2.0 * h);
                }
            }
            if parts.outputs() {
                for (r, (plus, minus)) in c.g_plus.iter().zip(&c.g_minus).enumerate() {
                    dg[(r, col)] = (plus - minus) / (2.0 * h);
                }
            }
        }
        set(&mut c.copy, &c.base);
    }

    /// The result of the last call, moved out.
    fn into_partials(self) -> Partials {
        self.partials
    }
}

impl<M: WithInputs + Clone> PartialsWorkspace<M> {
    /// As [`input_partials`](fn@input_partials), into this workspace's buffers: the
    /// result lives until the next call.
    ///
    /// # Errors
    /// As [`input_partials`](fn@input_partials).
    pub fn input_partials(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        which: &[usize],
    ) -> Result<&Partials, AnalysisError> {
        check_state::<M>(x)?;
        check_indices(which, M::INPUTS.len(), "input index")?;
        self.shape(which.len());
        if M::EXACT_PARAMETER_DERIVATIVES {
            self.seeded(model, t, x, which, Kind::Inputs, Parts::Both);
        } else {
            self.central(
                model,
                t,
                x,
                which,
                Parts::Both,
                |model, values| {
                    values.resize(M::INPUTS.len(), 0.0);
                    model.input_values(values);
                },
                |model, values| model.set_input_values(values),
            );
        }
        self.check(Parts::Both, "input derivatives")?;
        Ok(&self.partials)
    }
}

/// ∂f/∂p and ∂g/∂p of `model` at `(t, x)` for the parameters `which` (indices into
/// [`Model::parameter_values`]), one column each: exact when the model keeps parameter
/// tangents ([`Model::EXACT_PARAMETER_DERIVATIVES`]), else central differences. In a
/// loop, [`PartialsWorkspace::parameter_partials`] does the same without allocating.
///
/// # Errors
/// A state vector of the wrong length or an index out of range; non-finite results.
pub fn parameter_partials<M: Model + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
) -> Result<Partials, AnalysisError> {
    let mut work = PartialsWorkspace::new(model);
    work.parameter_partials(model, t, x, which)?;
    Ok(work.into_partials())
}

/// ∂f/∂u and ∂g/∂u of `model` at `(t, x)` and its current inputs, for the inputs
/// `which` (indices into [`WithInputs::INPUTS`]), one column each; exact or by central
/// differences as [`parameter_partials`]. In a loop,
/// [`PartialsWorkspace::input_partials`] does the same without allocating.
///
/// # Errors
/// A state vector of the wrong length or an index out of range; non-finite results.
pub fn input_partials<M: WithInputs + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
) -> Result<Partials, AnalysisError> {
    let mut work = PartialsWorkspace::new(model);
    work.input_partials(model, t, x, which)?;
    Ok(work.into_partials())
}

/// ∂f/∂p for the parameters `which` written into `out` column by column
/// (`out[k * N_STATES + i]` = ∂fᵢ/∂p_which[k]), the form a sensitivity integrator
/// wants; returns how it was computed.
///
/// # Errors
/// As [`parameter_partials`]; also an `out` of the wrong length.
pub fn parameter_jacobian<M: Model + Clone>(
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
    out: &mut [f64],
) -> Result<Method, AnalysisError> {
    parameter_jacobian_in(&mut PartialsWorkspace::new(model), model, t, x, which, out)
}

/// [`parameter_jacobian`] in a [`PartialsWorkspace`]: no allocation after set-up
/// (only ∂f/∂p is evaluated, not ∂g/∂p).
///
/// # Errors
/// As [`parameter_jacobian`].
pub fn parameter_jacobian_in<M: Model + Clone>(
    work: &mut PartialsWorkspace<M>,
    model: &M,
    t: f64,
    x: &[f64],
    which: &[usize],
    out: &mut [f64],
) -> Result<Method, AnalysisError> {
    if out.len() != M::N_STATES * which.len() {
        return Err(AnalysisError::Dimension {
            what: "output slice",
            expected: M::N_STATES * which.len(),
            found: out.len(),
        });
    }
    let method = work.partials.method;
    out.copy_from_slice(work.parameter_rhs_partials(model, t, x, which)?.as_slice());
    Ok(method)
}
