//! The animation as an add-on of every run: a model with bodies gets the section in its
//! `index.html`.

use bgdsl_runtime::{Model, Recorder};

use super::{section, BodyPose, BodyRecorder, Look, Shape};
use crate::catalog::{Entry, ExtraRun};

/// Poses of bodies at a sample `(t, x, y)`, the parameters bound.
type Posing<'a> = Box<dyn Fn(f64, &[f64], &[f64]) -> Vec<BodyPose> + 'a>;

/// One run's animation: the bodies' poses as the run goes, the section at the end.
pub struct AnimationRun<'a> {
    recorder: BodyRecorder,
    /// The entry's poses of bodies the model does not list, with the parameters.
    computed: Option<Posing<'a>>,
    angle: Option<usize>,
    shapes: Vec<(&'static str, Shape)>,
    ground: Vec<[f64; 3]>,
}

/// The output shown beside the time: the first whose name ends in `angle` and whose
/// unit is `rad` (the quick return's `crank_angle`), with its label (`crank angle`).
fn angle_output<M: Model>() -> Option<(usize, String)> {
    M::OUTPUTS
        .iter()
        .position(|o| o.name.ends_with("angle") && o.unit == "rad")
        .map(|i| (i, M::OUTPUTS[i].name.replace(['_', '.'], " ")))
}

/// The animation of a run of `model` (an entry `entry` of the catalogue): of its
/// [`Model::BODIES`], else of the bodies the entry poses
/// ([`EntryOf::poses`](crate::catalog::EntryOf::poses)); `None` when it has neither.
pub fn start<'a, M: Model + 'static>(model: &'a M, entry: &Entry) -> Option<AnimationRun<'a>> {
    let look = entry
        .look
        .as_ref()
        .and_then(|look| look.downcast_ref::<Look<M::Params>>());
    let params = model.params();
    let (mut recorder, computed) = match look.and_then(|l| l.poses) {
        _ if !M::BODIES.is_empty() => (BodyRecorder::new(M::BODIES), None),
        Some((names, poses)) => {
            let computed: Posing<'a> = Box::new(move |t, x, y| poses(params, t, x, y));
            (BodyRecorder::named(names), Some(computed))
        }
        None => return None,
    };
    let angle = angle_output::<M>();
    if let Some((index, label)) = &angle {
        recorder = recorder.with_angle(*index, label);
    }
    Some(AnimationRun {
        recorder,
        computed,
        angle: angle.map(|(index, _)| index),
        shapes: look
            .and_then(|l| l.shapes)
            .map(|f| f(params))
            .unwrap_or_default(),
        ground: look
            .and_then(|l| l.ground)
            .map(|f| f(params))
            .unwrap_or_default(),
    })
}

impl Recorder for AnimationRun<'_> {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        match &self.computed {
            None => self.recorder.record(t, x, y),
            Some(poses) => {
                let angle = self.angle.and_then(|i| y.get(i).copied());
                self.recorder.record_poses(t, poses(t, x, y), angle);
            }
        }
    }
}

impl ExtraRun for AnimationRun<'_> {
    fn sections(&self) -> Vec<String> {
        if self.recorder.frames() == 0 {
            return Vec::new();
        }
        let scene = self
            .recorder
            .clone()
            .into_scene(|name| {
                self.shapes
                    .iter()
                    .find(|(body, _)| *body == name)
                    .map(|(_, shape)| shape.clone())
            })
            .with_ground(self.ground.clone());
        vec![section(&scene)]
    }
}
