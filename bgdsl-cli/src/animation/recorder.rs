//! Keeping the bodies' poses during a run, at evenly spaced samples.

use bgdsl_runtime::{BodyInfo, Recorder};

use super::{BodyTrack, Scene, Shape};

/// The most frames a [`BodyRecorder`] keeps (the run's last sample may add one): enough
/// for a smooth animation, few enough for a page of a megabyte or so.
pub const MAX_FRAMES: usize = 2000;

/// A [`Recorder`] that keeps the pose of each of a model's bodies at evenly spaced
/// samples: every sample at first; when it would hold more than `max_frames` frames it
/// drops every other frame kept and from then on keeps every other sample of those it
/// kept before (so the frames stay evenly spaced whatever the run's length, which it
/// need not know). The run's last sample is always kept.
///
/// It reads the poses from the state through the bodies' [`BodyInfo`], or is handed
/// them ([`BodyRecorder::named`], [`BodyRecorder::record_poses`]) for a model whose
/// bodies' poses follow from its state otherwise (the rigid quick return's from its
/// crank angle).
#[derive(Clone, Debug)]
pub struct BodyRecorder {
    names: Vec<String>,
    bodies: &'static [BodyInfo],
    angle: Option<(usize, String)>,
    max_frames: usize,
    stride: usize,
    seen: usize,
    times: Vec<f64>,
    poses: Vec<Pose>,
    last: Option<(f64, Vec<Pose1>, Option<f64>)>,
}

/// One frame: each body's position and orientation, and the angle if one is kept.
#[derive(Clone, Debug)]
struct Pose {
    bodies: Vec<Pose1>,
    angle: Option<f64>,
}

/// One body's pose: its centre of mass in frame 0 and its orientation, column by
/// column.
pub type BodyPose = ([f64; 3], [f64; 9]);

type Pose1 = BodyPose;

impl BodyRecorder {
    /// A recorder of `bodies` (a model's [`Model::BODIES`](bgdsl_runtime::Model::BODIES))
    /// keeping at most [`MAX_FRAMES`] frames.
    pub fn new(bodies: &'static [BodyInfo]) -> Self {
        BodyRecorder::with_max_frames(bodies, MAX_FRAMES)
    }

    /// A recorder keeping at most `max_frames` frames (at least 2).
    pub fn with_max_frames(bodies: &'static [BodyInfo], max_frames: usize) -> Self {
        BodyRecorder {
            names: bodies.iter().map(|b| b.name.to_string()).collect(),
            bodies,
            angle: None,
            max_frames: max_frames.max(2),
            stride: 1,
            seen: 0,
            times: Vec::new(),
            poses: Vec::new(),
            last: None,
        }
    }

    /// A recorder of bodies called `names` whose poses it is handed, in that order, by
    /// [`BodyRecorder::record_poses`] (as a [`Recorder`] it keeps nothing).
    pub fn named(names: &[&str]) -> Self {
        let mut recorder = BodyRecorder::new(&[]);
        recorder.names = names.iter().map(|n| n.to_string()).collect();
        recorder
    }

    /// Keeps the sample at `t` with the bodies' `poses` (one per name, in order) and
    /// the angle in radians, evenly spaced as [`BodyRecorder`] says.
    pub fn record_poses(&mut self, t: f64, poses: Vec<BodyPose>, angle: Option<f64>) {
        let k = self.seen;
        self.seen += 1;
        if !k.is_multiple_of(self.stride) {
            self.last = Some((t, poses, angle));
            return;
        }
        self.last = None;
        self.times.push(t);
        self.poses.push(Pose {
            bodies: poses,
            angle,
        });
        if self.times.len() > self.max_frames {
            // Keep frames 0, 2, 4, …: the samples at multiples of the doubled stride.
            let mut index = 0;
            self.times.retain(|_| {
                index += 1;
                index % 2 == 1
            });
            let mut index = 0;
            self.poses.retain(|_| {
                index += 1;
                index % 2 == 1
            });
            self.stride *= 2;
        }
    }

    /// Also keeps output `index` (an angle in radians) to show in degrees as `label`.
    pub fn with_angle(mut self, index: usize, label: &str) -> Self {
        self.angle = Some((index, label.to_string()));
        self
    }

    /// How many frames it holds now.
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    /// The scene of what was recorded, each body drawn as `shape(name)` gives (a
    /// [`Shape::Marker`] where it gives `None`).
    pub fn into_scene(mut self, shape: impl Fn(&str) -> Option<Shape>) -> Scene {
        if let Some((t, bodies, angle)) = self.last.take() {
            if self.times.last() != Some(&t) {
                self.times.push(t);
                self.poses.push(Pose { bodies, angle });
            }
        }
        let tracks = self
            .names
            .iter()
            .enumerate()
            .filter(|(i, _)| self.poses.iter().all(|p| p.bodies.len() > *i))
            .map(|(i, name)| BodyTrack {
                name: name.clone(),
                shape: shape(name).unwrap_or(Shape::Marker),
                position: self.poses.iter().map(|p| p.bodies[i].0).collect(),
                orientation: self.poses.iter().map(|p| p.bodies[i].1).collect(),
            })
            .collect();
        let degrees: Vec<f64> = self
            .poses
            .iter()
            .filter_map(|p| p.angle.map(f64::to_degrees))
            .collect();
        let scene = Scene::new(self.times, tracks);
        match self.angle {
            Some((_, label)) if degrees.len() == scene.times.len() => {
                scene.with_angle(&label, degrees)
            }
            _ => scene,
        }
    }
}

impl Recorder for BodyRecorder {
    fn record(&mut self, t: f64, x: &[f64], y: &[f64]) {
        let poses = self
            .bodies
            .iter()
            .map(|b| (b.position_of(x), b.orientation_of(x)))
            .collect();
        let angle = self.angle.as_ref().and_then(|(i, _)| y.get(*i).copied());
        self.record_poses(t, poses, angle);
    }
}

#[cfg(test)]
mod should {
    use super::*;

    /// One body whose x position is the sample's index and whose R_11 is its time.
    static BODY: [BodyInfo; 1] = [BodyInfo {
        name: "b",
        orientation: 3,
        position: 0,
    }];

    fn run(samples: usize, max_frames: usize) -> Scene {
        let mut recorder = BodyRecorder::with_max_frames(&BODY, max_frames).with_angle(0, "θ");
        for k in 0..samples {
            let t = 0.01 * k as f64;
            let mut x = [0.0; 12];
            x[0] = k as f64;
            x[3] = t;
            recorder.record(t, &x, &[core::f64::consts::PI * k as f64]);
        }
        recorder.into_scene(|_| None)
    }

    #[test]
    fn take_poses_handed_and_leave_out_a_body_without_them() {
        let pose = |x: f64| ([x, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        let mut recorder = BodyRecorder::named(&["a", "b"]).with_angle(7, "θ");
        for k in 0..3 {
            let t = k as f64;
            recorder.record_poses(t, vec![pose(t), pose(-t)], Some(t));
        }
        let scene = recorder.clone().into_scene(|_| None);
        assert_eq!(scene.bodies.len(), 2);
        assert_eq!(scene.bodies[1].position[2], [-2.0, 0.0, 0.0]);
        assert_eq!(scene.angle.unwrap().1[1], 1.0_f64.to_degrees());
        // A sample that poses only the first body: the second has no track.
        recorder.record_poses(3.0, vec![pose(3.0)], None);
        let scene = recorder.into_scene(|_| None);
        let names: Vec<&str> = scene.bodies.iter().map(|b| b.name.as_str()).collect();
        assert_eq!(names, ["a"]);
        assert_eq!(scene.times.len(), 4);
        assert!(
            scene.angle.is_none(),
            "an angle missing at a frame is not shown"
        );
    }

    #[test]
    fn keep_every_sample_up_to_the_limit() {
        let scene = run(10, 10);
        let xs: Vec<f64> = scene.bodies[0].position.iter().map(|p| p[0]).collect();
        assert_eq!(xs, (0..10).map(f64::from).collect::<Vec<_>>());
        assert_eq!(scene.bodies[0].orientation[4][0], 0.04);
        assert_eq!(scene.bodies[0].shape, Shape::Marker);
        let (label, degrees) = scene.angle.unwrap();
        assert_eq!(label, "θ");
        assert_eq!(degrees[3], 540.0);
    }

    #[test]
    fn thin_evenly_beyond_the_limit_and_keep_the_last_sample() {
        // 10 001 samples into at most 2000 frames: every 8th (1251 frames) and the last.
        let scene = run(10_001, 2000);
        let xs: Vec<f64> = scene.bodies[0].position.iter().map(|p| p[0]).collect();
        assert_eq!(xs.len(), 1251);
        assert!(xs.iter().enumerate().all(|(i, &x)| x == (8 * i) as f64));
        assert_eq!(scene.times.len(), xs.len());
        // A run whose last sample falls between kept ones gets it appended.
        let scene = run(10_004, 2000);
        let xs: Vec<f64> = scene.bodies[0].position.iter().map(|p| p[0]).collect();
        assert_eq!(xs.len(), 1252);
        assert_eq!(xs[1250..], [10_000.0, 10_003.0]);
        assert!(scene.times.len() <= 2001);
    }
}
