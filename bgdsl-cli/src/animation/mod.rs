//! Mechanisms seen moving: an animated view of a run's rigid bodies for `index.html`.
//!
//! A model with rigid bodies ([`Model::BODIES`](bgdsl_runtime::Model::BODIES): every
//! instance of the standard library's `RigidBody`) has each body's orientation and
//! position in its state. A [`BodyRecorder`] keeps them at the run's samples (at most
//! about [`MAX_FRAMES`] of them, evenly spaced), [`BodyRecorder::into_scene`] gives each
//! body a [`Shape`] (in its own frame, about its centre of mass), and [`section`] turns
//! the [`Scene`] into a self-contained HTML fragment: a `<canvas>`, the data as JSON and
//! a small player in inline JavaScript (no network, no file beside the page) with play,
//! pause, a scrub slider, speed, the time and an angle (the quick return's crank angle).
//!
//! The view is a plane when the motion is planar ([`View::choose`]), seen face on; else
//! a 3-D view the reader turns by dragging. [`write_page`] writes a scene as a page of
//! its own. A page opened as `page.html#t=0.3` starts paused at t = 0.3 s (a still for a
//! document or a test); `&yaw=0.5&pitch=0.2` (radians) turns the 3-D view.

mod addon;
mod html;
mod look;
mod recorder;
mod view;

pub use addon::{start, AnimationRun};
pub use html::{section, write_page, SECTION_ID};
pub use look::{GroundFn, Look, PosesFn, ShapesFn};
pub use recorder::{BodyPose, BodyRecorder, MAX_FRAMES};
pub use view::{View, PLANAR_TOLERANCE};

/// How a body is drawn, in its own frame with the origin at its centre of mass.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A box with these edge lengths along the body's X, Y, Z, centred on the centre
    /// of mass: drawn as its projected outline (a link of the quick return).
    Box {
        /// Edge lengths in m.
        size: [f64; 3],
    },
    /// A thick line between two points of the body, in m.
    Segment {
        /// One end, in the body frame.
        from: [f64; 3],
        /// The other end, in the body frame.
        to: [f64; 3],
    },
    /// A dot at the centre of mass, the body's name in the legend.
    Marker,
}

/// One body's motion: its pose at every frame of the [`Scene`].
#[derive(Clone, Debug, PartialEq)]
pub struct BodyTrack {
    /// The body's name (`crank`, `arm.upper`), shown in the legend.
    pub name: String,
    /// How it is drawn.
    pub shape: Shape,
    /// Its centre of mass in frame 0, per frame, in m.
    pub position: Vec<[f64; 3]>,
    /// Its orientation (body frame to frame 0), per frame, column by column
    /// (`R_11, R_21, R_31, R_12, …`).
    pub orientation: Vec<[f64; 9]>,
}

impl BodyTrack {
    /// The points of its shape in frame 0 at frame `k`: the box's 8 corners, the
    /// segment's 2 ends, or the centre of mass.
    pub fn points(&self, k: usize) -> Vec<[f64; 3]> {
        let local: Vec<[f64; 3]> = match &self.shape {
            Shape::Box { size } => {
                let h = size.map(|s| 0.5 * s);
                (0..8)
                    .map(|c| {
                        let sign = |bit: usize| if c >> bit & 1 == 1 { 1.0 } else { -1.0 };
                        [sign(0) * h[0], sign(1) * h[1], sign(2) * h[2]]
                    })
                    .collect()
            }
            Shape::Segment { from, to } => vec![*from, *to],
            Shape::Marker => vec![[0.0; 3]],
        };
        let (r, p) = (&self.orientation[k], &self.position[k]);
        local
            .iter()
            .map(|b| {
                let mut w = *p;
                for (i, wi) in w.iter_mut().enumerate() {
                    *wi += r[i] * b[0] + r[3 + i] * b[1] + r[6 + i] * b[2];
                }
                w
            })
            .collect()
    }
}

/// What the animation shows: the bodies' poses at each frame's time, an angle to
/// display beside the time, fixed ground points and the view.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The frames' times in s, increasing.
    pub times: Vec<f64>,
    /// Every body, with one pose per frame.
    pub bodies: Vec<BodyTrack>,
    /// An angle shown with the time: its label and its value in degrees per frame.
    pub angle: Option<(String, Vec<f64>)>,
    /// Points fixed in frame 0 (pivots, guides' ends), drawn as ground symbols over
    /// the bodies.
    pub ground: Vec<[f64; 3]>,
    /// How the scene is looked at.
    pub view: View,
}

impl Scene {
    /// A scene of `bodies` at `times`, with no angle and no ground points, seen in the
    /// view [`View::choose`] picks for the motion.
    pub fn new(times: Vec<f64>, bodies: Vec<BodyTrack>) -> Self {
        let view = View::choose(&bodies);
        Scene {
            times,
            bodies,
            angle: None,
            ground: Vec::new(),
            view,
        }
    }

    /// The same scene with `label`'s values (in degrees, one per frame) shown.
    pub fn with_angle(mut self, label: &str, degrees: Vec<f64>) -> Self {
        self.angle = Some((label.to_string(), degrees));
        self
    }

    /// The same scene with these ground points drawn.
    pub fn with_ground(mut self, points: Vec<[f64; 3]>) -> Self {
        self.ground = points;
        self
    }
}
