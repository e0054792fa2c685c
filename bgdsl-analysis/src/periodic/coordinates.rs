//! The unknowns of the shooting Newton step: every state, except that the nine entries
//! of a rigid body's rotation matrix ([`Model::BODIES`]) are moved as a rotation — three
//! angles `w` with `R ← R exp(ŵ)` — so that a step never leaves the rotations (the six
//! directions per body that would make `RᵀR ≠ I` are not unknowns at all).

use bgdsl_runtime::Model;
use nalgebra::{DMatrix, Matrix3, Rotation3, Vector3};

/// One unknown.
#[derive(Clone, Copy, Debug)]
enum Unknown {
    /// State `i` itself.
    State(usize),
    /// The rotation about body axis `axis` of the rotation matrix whose `R_11` is state
    /// `orientation`.
    Rotation { orientation: usize, axis: usize },
}

/// The unknowns of a model's state.
pub(super) struct Coordinates {
    unknowns: Vec<Unknown>,
}

/// `R` (column-major in `x[o..o + 9]`).
fn rotation_at(x: &[f64], o: usize) -> Matrix3<f64> {
    Matrix3::from_column_slice(&x[o..o + 9])
}

impl Coordinates {
    /// The unknowns of model `M`'s state.
    pub(super) fn new<M: Model>() -> Self {
        let n = M::N_STATES;
        let mut in_rotation = vec![None; n];
        for body in M::BODIES {
            if body.orientation + 9 <= n {
                for (k, slot) in in_rotation[body.orientation..body.orientation + 9]
                    .iter_mut()
                    .enumerate()
                {
                    *slot = Some(k);
                }
            }
        }
        let mut unknowns = Vec::with_capacity(n);
        for (i, slot) in in_rotation.iter().enumerate() {
            match slot {
                None => unknowns.push(Unknown::State(i)),
                Some(0) => {
                    for axis in 0..3 {
                        unknowns.push(Unknown::Rotation {
                            orientation: i,
                            axis,
                        })
                    }
                }
                Some(_) => {}
            }
        }
        Coordinates { unknowns }
    }

    /// The number of unknowns.
    pub(super) fn len(&self) -> usize {
        self.unknowns.len()
    }

    /// `∂x/∂z` at `x` (`n × len`): a unit column for a state, `R Ê_axis` for a
    /// rotation.
    pub(super) fn embedding(&self, x: &[f64]) -> DMatrix<f64> {
        let mut e = DMatrix::<f64>::zeros(x.len(), self.len());
        for (k, unknown) in self.unknowns.iter().enumerate() {
            match *unknown {
                Unknown::State(i) => e[(i, k)] = 1.0,
                Unknown::Rotation { orientation, axis } => {
                    let mut w = Vector3::zeros();
                    w[axis] = 1.0;
                    let dr = rotation_at(x, orientation) * w.cross_matrix();
                    for (j, v) in dr.as_slice().iter().enumerate() {
                        e[(orientation + j, k)] = *v;
                    }
                }
            }
        }
        e
    }

    /// `Φ` restricted to the unknowns: `E⁺ Φ E` with `E` the embedding at `x` (an orbit
    /// point, where `Φ` maps the tangent space of the rotations into itself), whose
    /// eigenvalues are the multipliers of the motions the model can make; the
    /// directions off the rotations (`RᵀR ≠ I`) are left out.
    pub(super) fn reduce(&self, phi: &DMatrix<f64>, x: &[f64]) -> DMatrix<f64> {
        let e = self.embedding(x);
        let et = e.transpose();
        let gram = &et * &e;
        let inverse = gram
            .try_inverse()
            .unwrap_or_else(|| DMatrix::identity(self.len(), self.len()));
        inverse * et * phi * e
    }

    /// The scale of each unknown: its state's for a state, 1 rad for a rotation.
    pub(super) fn scales(&self, d: &[f64]) -> Vec<f64> {
        self.unknowns
            .iter()
            .map(|u| match *u {
                Unknown::State(i) => d[i],
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
