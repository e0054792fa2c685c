//! A hand-written model with an algebraic loop, solved at each evaluation the way
//! `bond_graph!` generates it for `#[allow(algebraic_loops)]`: a diode in series with a
//! resistor and a capacitor, driven by a source. The diode voltage `v` is the unknown:
//! `(V(t) − q/C − v) / R − Is (exp(v / Vt) − 1) = 0`, and `dq/dt` is the loop current.
//!
//! The source `V(t) = V0 sqrt(1 − t / t_fail)` is undefined past `t_fail`, so the
//! solve fails there (a non-finite residual), and [`Model::evaluation_error`] says so.

use std::any::TypeId;

use bgdsl_runtime::implicit::{solve, FailureKind, ImplicitMemory};
use bgdsl_runtime::{DualN, Model, ModelError, Scalar};

/// What fails, and whether the model says why.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fails {
    /// The derivatives (and outputs), past `t_fail`.
    After,
    /// Only the derivatives on dual numbers (the Jacobian), as a singular constraint.
    OnDuals,
    /// Only the outputs, past `t_fail`.
    OutputsAfter,
}

/// The loop's elements, as a generated model names them.
pub const MEMBERS: &str = "source, r, d, c";

#[derive(Debug)]
pub struct DiodeLoop {
    pub t_fail: f64,
    pub fails: Fails,
    /// Whether [`Model::evaluation_error`] reports the failure (else it keeps the
    /// default `None`, as every model did before it existed).
    pub explains: bool,
    pub memory: ImplicitMemory<1>,
}

impl DiodeLoop {
    pub fn new(t_fail: f64, fails: Fails) -> Self {
        DiodeLoop {
            t_fail,
            fails,
            explains: true,
            memory: ImplicitMemory::new(),
        }
    }

    fn source(&self, t: f64, failing: bool) -> f64 {
        if failing {
            5.0 * (1.0 - t / self.t_fail).sqrt()
        } else {
            5.0
        }
    }

    /// The loop's residual at diode voltage `v`, charge `q`, source `source`.
    fn residual<T: Scalar>(source: f64, q: T, v: T) -> T {
        let (r, c, is, vt) = (1e3, 1e-6, 1e-12, 0.025852);
        let current = (T::from_f64(source) - q / T::from_f64(c) - v) / T::from_f64(r);
        current - T::from_f64(is) * ((v / T::from_f64(vt)).exp() - T::one())
    }

    /// The loop current at `(t, q)`: solve, remember or record, refine on `T`.
    fn current<T: Scalar>(&self, t: f64, q: T, failing: bool) -> Option<T> {
        let source = self.source(t, failing);
        let q0 = DualN::constant(q.to_f64());
        match solve(self.memory.guess(), false, |z, r| {
            r[0] = Self::residual(source, q0, z[0])
        }) {
            Ok(solution) => {
                self.memory.remember(&solution.z);
                let refined =
                    solution.refine(&[Self::residual(source, q, T::from_f64(solution.z[0]))]);
                let v = refined[0];
                Some((T::from_f64(source) - q / T::from_f64(1e-6) - v) / T::from_f64(1e3))
            }
            Err(mut failure) => {
                failure.t = t;
                self.memory.record(failure);
                None
            }
        }
    }
}

impl Model for DiodeLoop {
    type Params = ();
    const NAME: &'static str = "diode_loop";
    const STATE_NAMES: &'static [&'static str] = &["c.q"];
    const OUTPUT_NAMES: &'static [&'static str] = &["current"];
    const ALGEBRAIC_LOOPS: &'static [&'static [&'static str]] = &[&["source", "r", "d", "c"]];

    fn params(&self) -> &() {
        &()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 0.0;
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        if self.fails == Fails::OnDuals && TypeId::of::<T>() != TypeId::of::<f64>() {
            self.memory.record(bgdsl_runtime::implicit::Failure {
                kind: FailureKind::Singular,
                unknown: 0,
                t,
                residual: 0.0,
            });
            dx[0] = T::from_f64(f64::NAN);
            return;
        }
        let failing = self.fails == Fails::After && t > self.t_fail;
        dx[0] = self
            .current(t, x[0], failing)
            .unwrap_or(T::from_f64(f64::NAN));
    }

    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        let failing = self.fails != Fails::OnDuals && t > self.t_fail;
        y[0] = self
            .current(t, x[0], failing)
            .unwrap_or(T::from_f64(f64::NAN));
    }

    fn evaluation_error(&self) -> Option<ModelError> {
        if !self.explains {
            return None;
        }
        self.memory
            .failure()
            .map(|failure| failure.to_model_error(MEMBERS))
    }
}
