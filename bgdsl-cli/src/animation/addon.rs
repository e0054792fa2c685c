//! The animation as an add-on of every run: a model with bodies gets the section in its
//! `index.html`.

use bgdsl_runtime::{Model, Recorder};

use super::{section, BodyRecorder, Look, Shape};
use crate::catalog::{Entry, ExtraRun};

/// One run's animation: the bodies' poses as the run goes, the section at the end.
pub struct AnimationRun {
    recorder: BodyRecorder,
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

/// The animation of a run of `model` (an entry `entry` of the catalogue), or `None` for
/// a model without bodies.
pub fn start<M: Model + 'static>(model: &M, entry: &Entry) -> Option<AnimationRun> {
    if M::BODIES.is_empty() {
        return None;
    }
    let look = entry
        .look
        .as_ref()
        .and_then(|look| look.downcast_ref::<Look<M::Params>>());
    let shapes = look
        .and_then(|l| l.shapes)
        .map(|f| f(model.params()))
        .unwrap_or_default();
    let ground = look
        .and_then(|l| l.ground)
        .map(|f| f(model.params()))
        .unwrap_or_default();
    let mut recorder = BodyRecorder::new(M::BODIES);
    if let Some((index, label)) = angle_output::<M>() {
        recorder = recorder.with_angle(index, &label);
    }
    Some(AnimationRun {
        recorder,
        shapes,
        ground,
    })
}

impl Recorder for AnimationRun {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        self.recorder.record(t, x, y);
    }
}

impl ExtraRun for AnimationRun {
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
