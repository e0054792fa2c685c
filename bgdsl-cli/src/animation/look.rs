//! How an entry's bodies are drawn: shapes and ground points from the parameters.

use super::Shape;

/// An entry's shapes of its bodies from its parameters: (body name, shape) pairs.
pub type ShapesFn<P> = fn(&P) -> Vec<(&'static str, Shape)>;

/// An entry's ground points (in frame 0, m) from its parameters.
pub type GroundFn<P> = fn(&P) -> Vec<[f64; 3]>;

/// What [`EntryOf::shapes`](crate::catalog::EntryOf::shapes) and
/// [`EntryOf::ground`](crate::catalog::EntryOf::ground) set, kept by the entry (as
/// [`Entry::look`](crate::catalog::Entry::look)) for the run's animation.
pub struct Look<P> {
    /// The bodies' shapes, if given.
    pub shapes: Option<ShapesFn<P>>,
    /// The ground points, if given.
    pub ground: Option<GroundFn<P>>,
}

impl<P> Default for Look<P> {
    fn default() -> Self {
        Look {
            shapes: None,
            ground: None,
        }
    }
}

impl<P> Look<P> {
    /// Whether it sets nothing.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_none() && self.ground.is_none()
    }
}
