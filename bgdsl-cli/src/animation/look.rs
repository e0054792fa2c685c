//! How an entry's bodies are drawn: shapes and ground points from the parameters.

use super::{BodyPose, Shape};

/// An entry's shapes of its bodies from its parameters: (body name, shape) pairs.
pub type ShapesFn<P> = fn(&P) -> Vec<(&'static str, Shape)>;

/// An entry's ground points (in frame 0, m) from its parameters.
pub type GroundFn<P> = fn(&P) -> Vec<[f64; 3]>;

/// The poses of an entry's bodies at a sample `(t, x, y)` (time, state, outputs), from
/// its parameters: for a model without [`Model::BODIES`](bgdsl_runtime::Model::BODIES)
/// whose bodies' poses follow from its state all the same (a planar mechanism of one
/// degree of freedom).
pub type PosesFn<P> = fn(&P, f64, &[f64], &[f64]) -> Vec<BodyPose>;

/// What [`EntryOf::shapes`](crate::catalog::EntryOf::shapes),
/// [`EntryOf::ground`](crate::catalog::EntryOf::ground) and
/// [`EntryOf::poses`](crate::catalog::EntryOf::poses) set, kept by the entry (as
/// [`Entry::look`](crate::catalog::Entry::look)) for the run's animation.
pub struct Look<P> {
    /// The bodies' shapes, if given.
    pub shapes: Option<ShapesFn<P>>,
    /// The ground points, if given.
    pub ground: Option<GroundFn<P>>,
    /// The names of bodies the model does not list in `BODIES` and their poses, if
    /// given.
    pub poses: Option<(&'static [&'static str], PosesFn<P>)>,
}

impl<P> Default for Look<P> {
    fn default() -> Self {
        Look {
            shapes: None,
            ground: None,
            poses: None,
        }
    }
}

impl<P> Look<P> {
    /// Whether it sets nothing.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_none() && self.ground.is_none() && self.poses.is_none()
    }
}
