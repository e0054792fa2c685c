//! The unknowns of the shooting Newton step: every state but the free ones, except that
//! the nine entries of a rigid body's rotation matrix ([`Model::BODIES`]) are one
//! rotation — three angles `w` with `R ← R exp(ŵ)` — so that a step never leaves the
//! rotations (the six directions per body that would make `RᵀR ≠ I` are not unknowns
//! at all), and the period map's residual of a rotation is the rotation vector
//! `log(Rᵀ R_end)`, in radians.

use bgdsl_runtime::Model;
use nalgebra::{DMatrix, Matrix3, Rotation3, Vector3};

/// One unknown.
#[derive(Clone, Copy, Debug)]
enum Unknown {
    /// State `i` itself.
    State(usize),
    /// The rotation about body axis `axis` of the rotation matrix whose `R_11` is state
    /// `orientation`, of body `body` (its index in [`Model::BODIES`]).
    Rotation {
        orientation: usize,
        axis: usize,
        body: usize,
    },
}

/// The unknowns of a model's state.
pub(super) struct Coordinates {
    unknowns: Vec<Unknown>,
}

/// `R` (column-major in `x[o..o + 9]`).
fn rotation_at(x: &[f64], o: usize) -> Matrix3<f64> {
    Matrix3::from_column_slice(&x[o..o + 9])
}

/// `ê` for the unit vector along `axis`.
fn generator(axis: usize) -> Matrix3<f64> {
    let mut w = Vector3::zeros();
    w[axis] = 1.0;
    w.cross_matrix()
}

impl Coordinates {
    /// The unknowns of model `M`'s state, leaving out the states with `fixed[i]` (all
    /// nine of a rotation's when any of them is fixed); `fixed` may be empty.
    pub(super) fn new<M: Model>(fixed: &[bool]) -> Self {
        let n = M::N_STATES;
        let is_fixed = |i: usize| fixed.get(i).copied().unwrap_or(false);
        let mut in_rotation = vec![None; n];
        for (b, body) in M::BODIES.iter().enumerate() {
            if body.orientation + 9 <= n {
                for (k, slot) in in_rotation[body.orientation..body.orientation + 9]
                    .iter_mut()
                    .enumerate()
                {
                    *slot = Some((k, b));
                }
            }
        }
        let mut unknowns = Vec::with_capacity(n);
        for (i, slot) in in_rotation.iter().enumerate() {
            match *slot {
                None if !is_fixed(i) => unknowns.push(Unknown::State(i)),
                Some((0, body)) if !(i..i + 9).any(is_fixed) => {
                    for axis in 0..3 {
                        unknowns.push(Unknown::Rotation {
                            orientation: i,
                            axis,
                            body,
                        })
                    }
                }
                _ => {}
            }
        }
        Coordinates { unknowns }
    }

    /// The number of unknowns.
    pub(super) fn len(&self) -> usize {
        self.unknowns.len()
    }

    /// The unknown that is state `i` itself, if any.
    pub(super) fn unknown_of_state(&self, i: usize) -> Option<usize> {
        self.unknowns
            .iter()
            .position(|u| matches!(*u, Unknown::State(s) if s == i))
    }

    /// The name of unknown `k`: its state's, or its body's for a rotation.
    pub(super) fn name<M: Model>(&self, k: usize) -> &'static str {
        match self.unknowns[k] {
            Unknown::State(i) => M::STATE_NAMES.get(i).copied().unwrap_or("?"),
            Unknown::Rotation { body, .. } => M::BODIES[body].name,
        }
    }

    /// The state that unknown `k` moves (a rotation's `R_11`).
    pub(super) fn state_of(&self, k: usize) -> usize {
        match self.unknowns[k] {
            Unknown::State(i) => i,
            Unknown::Rotation { orientation, .. } => orientation,
        }
    }

    /// `∂x/∂z` at `x` (`n × len`): a unit column for a state, `R ê_axis` for a
    /// rotation.
    pub(super) fn embedding(&self, x: &[f64]) -> DMatrix<f64> {
        let mut e = DMatrix::<f64>::zeros(x.len(), self.len());
        for (k, unknown) in self.unknowns.iter().enumerate() {
            match *unknown {
                Unknown::State(i) => e[(i, k)] = 1.0,
                Unknown::Rotation {
                    orientation, axis, ..
                } => {
                    let dr = rotation_at(x, orientation) * generator(axis);
                    for (j, v) in dr.as_slice().iter().enumerate() {
                        e[(orientation + j, k)] = *v;
                    }
                }
            }
        }
        e
    }

    /// The unknowns' part of a change `dx` (rows of an `n × m` matrix) of the state at
    /// `x`: its entry for a state, `½ ⟨R ê_axis, dR⟩` (the body-frame rotation that
    /// moves `R` by `dR`, to first order) for a rotation; the left inverse of
    /// [`Coordinates::embedding`] at `x`.
    pub(super) fn tangent(&self, x: &[f64], dx: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = DMatrix::<f64>::zeros(self.len(), dx.ncols());
        for (k, unknown) in self.unknowns.iter().enumerate() {
            match *unknown {
                Unknown::State(i) => out.row_mut(k).copy_from(&dx.row(i)),
                Unknown::Rotation {
                    orientation, axis, ..
                } => {
                    let dr = rotation_at(x, orientation) * generator(axis);
                    for c in 0..dx.ncols() {
                        let dot: f64 = dr
                            .as_slice()
                            .iter()
                            .enumerate()
                            .map(|(j, v)| v * dx[(orientation + j, c)])
                            .sum();
                        out[(k, c)] = 0.5 * dot;
                    }
                }
            }
        }
        out
    }

    /// `Φ` in the unknowns: `∂z(t₀ + T)/∂z(t₀)`, the tangent of `Φ E(x)` at the end
    /// state `end` (`len × len`). At an orbit point (`end = x`) its eigenvalues are the
    /// multipliers of the motions the model can make: the directions off the
    /// rotations (`RᵀR ≠ I`) and the fixed states are left out.
    pub(super) fn reduce(&self, phi: &DMatrix<f64>, x: &[f64], end: &[f64]) -> DMatrix<f64> {
        self.tangent(end, &(phi * self.embedding(x)))
    }

    /// The change of the unknowns from `x` to `y`: `y_i − x_i` for a state, the rotation
    /// vector `log(R_xᵀ R_y)` for a rotation (so that `apply(x, difference(x, y))` is
    /// `y` but for round-off and the states left out).
    pub(super) fn difference(&self, x: &[f64], y: &[f64]) -> Vec<f64> {
        let mut dz = vec![0.0; self.len()];
        let mut k = 0;
        while k < self.unknowns.len() {
            match self.unknowns[k] {
                Unknown::State(i) => {
                    dz[k] = y[i] - x[i];
                    k += 1;
                }
                Unknown::Rotation { orientation, .. } => {
                    let relative =
                        rotation_at(x, orientation).transpose() * rotation_at(y, orientation);
                    let w = Rotation3::from_matrix(&relative).scaled_axis();
                    dz[k..k + 3].copy_from_slice(w.as_slice());
                    k += 3;
                }
            }
        }
        dz
    }

    /// The scale of each unknown: `state_scale(i)` for a state, 1 rad for a rotation.
    pub(super) fn scales(&self, state_scale: impl Fn(usize) -> f64) -> Vec<f64> {
        self.unknowns
            .iter()
            .map(|u| match *u {
                Unknown::State(i) => state_scale(i),
                Unknown::Rotation { .. } => 1.0,
            })
            .collect()
    }

    /// `x` moved by `dz`: states added, rotations composed (`R exp(ŵ)`).
    pub(super) fn apply(&self, x: &[f64], dz: &[f64]) -> Vec<f64> {
        let mut next = x.to_vec();
        let mut k = 0;
        while k < self.unknowns.len() {
            match self.unknowns[k] {
                Unknown::State(i) => {
                    next[i] += dz[k];
                    k += 1;
                }
                Unknown::Rotation { orientation, .. } => {
                    let w = Vector3::new(dz[k], dz[k + 1], dz[k + 2]);
                    let r = rotation_at(x, orientation) * Rotation3::new(w).into_inner();
                    next[orientation..orientation + 9].copy_from_slice(r.as_slice());
                    k += 3;
                }
            }
        }
        next
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `R exp(ŵ)` and back: `difference` inverts `apply` for a rotation (to round-off),
    /// and `tangent` inverts `embedding`.
    #[test]
    fn difference_inverts_apply_and_tangent_inverts_embedding() {
        let r = Rotation3::new(Vector3::new(0.3, -1.1, 0.7)).into_inner();
        let mut x = r.as_slice().to_vec();
        x.push(2.5);
        let coordinates = Coordinates {
            unknowns: (0..3)
                .map(|axis| Unknown::Rotation {
                    orientation: 0,
                    axis,
                    body: 0,
                })
                .chain([Unknown::State(9)])
                .collect(),
        };
        let dz = [1e-3, -2e-2, 0.4, -0.25];
        let y = coordinates.apply(&x, &dz);
        for (got, want) in coordinates.difference(&x, &y).iter().zip(dz) {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        let e = coordinates.embedding(&x);
        let back = coordinates.tangent(&x, &e);
        assert!((back - DMatrix::<f64>::identity(4, 4)).norm() < 1e-14);
    }
}
