//! The pose of the rigid quick return at crank angle θ, generic over the scalar: the
//! positions, directions and moduli the bond graph of [`super::model`] reads.
//!
//! Frame 0 as in the spec: the crank pivot O1 at the origin, X0 right, Y0 up, the
//! rocker pivot O3 at (0, −d). The crank pin A is at `crank (cos θ, sin θ)`; the rocker
//! points from O3 through A (unit vector ê, `s = |A − O3|`); its tip is
//! `T = O3 + rocker ê`; the connecting rod (unit vector ê₄, from T) reaches the output
//! slider's centre O5 on the guide y = 0 to the right of T.
//!
//! Every function here is a closed form of θ and the lengths: the mechanism has one
//! degree of freedom, so its configuration is the crank angle alone (see the
//! [model's documentation](super::model) for why that is the state).

use bgdsl_runtime::multibond::{vec3, Matrix3, SMatrix, SVector, Vector3};
use bgdsl_runtime::Scalar;

/// A 2-vector of the plane.
pub type Vector2<S> = SVector<S, 2>;

/// The 2-vector (x, y).
pub fn vec2<S: Scalar>(x: S, y: S) -> Vector2<S> {
    Vector2::new(x, y)
}

/// The plane vector `v` as a 3-vector of frame 0 (z = 0), for the spec's columns.
pub fn in_plane<S: Scalar>(v: Vector2<S>) -> Vector3<S> {
    vec3(v.x, v.y, S::from_f64(0.0))
}

/// `k v` as a 3-vector of frame 0: a momentum `m v` from a velocity, say.
pub fn in_plane_scaled<S: Scalar>(k: S, v: Vector2<S>) -> Vector3<S> {
    vec3(k * v.x, k * v.y, S::from_f64(0.0))
}

/// The z-axis 3-vector (0, 0, z): a torque or an angular momentum of the plane.
pub fn about_z<S: Scalar>(z: S) -> Vector3<S> {
    let zero = S::from_f64(0.0);
    vec3(zero, zero, z)
}

/// The lever of a point at `offset` from a link's centre of mass: the 2×1 modulus that
/// turns the link's angular velocity ω into the point's velocity relative to the centre,
/// `ω (−offset_y, offset_x)`, and (its transpose) a force F at the point into the
/// torque `offset × F`.
pub fn lever<S: Scalar>(offset: Vector2<S>) -> Vector2<S> {
    vec2(-offset.y, offset.x)
}

/// The pose at crank angle `theta` of the mechanism with crank, rocker and rod lengths
/// `crank`, `rocker`, `rod` and pivot distance `d`.
#[derive(Clone, Copy, Debug)]
pub struct Pose<S: Scalar> {
    /// The crank's unit vector, O1 → A.
    pub crank_dir: Vector2<S>,
    /// The crank pin A (the slider's centre).
    pub pin: Vector2<S>,
    /// The distance s = |A − O3| of the slider from the rocker's pivot.
    pub slide: S,
    /// The rocker's unit vector ê, O3 → A.
    pub rocker_dir: Vector2<S>,
    /// The rocker's pivot O3.
    pub pivot: Vector2<S>,
    /// The rocker's tip T.
    pub tip: Vector2<S>,
    /// The rod's unit vector ê₄, T → O5.
    pub rod_dir: Vector2<S>,
    /// The output slider's centre O5.
    pub output: Vector2<S>,
}

impl<S: Scalar> Pose<S> {
    /// The pose (see the [module documentation](self)).
    pub fn at(theta: S, crank: S, d: S, rocker: S, rod: S) -> Self {
        let crank_dir = crank_dir(theta);
        let (rocker_dir, slide) = rocker_frame(theta, crank, d);
        let (rod_dir, tip, output) = rod_frame(theta, crank, d, rocker, rod);
        Pose {
            crank_dir,
            pin: crank_dir * crank,
            slide,
            rocker_dir,
            pivot: vec2(S::from_f64(0.0), -d),
            tip,
            rod_dir,
            output,
        }
    }

    /// The centres of mass: crank, slider, rocker, rod, output slider.
    pub fn centres(&self) -> [Vector2<S>; 5] {
        let half = S::from_f64(0.5);
        [
            self.pin * half,
            self.pin,
            (self.pivot + self.tip) * half,
            (self.tip + self.output) * half,
            self.output,
        ]
    }

    /// The rocker's angle φ from X0.
    pub fn rocker_angle(&self) -> S {
        self.rocker_dir.y.atan2(self.rocker_dir.x)
    }

    /// The rod's angle ψ from X0 (negative: it points down to the right).
    pub fn rod_angle(&self) -> S {
        self.rod_dir.y.atan2(self.rod_dir.x)
    }

    /// The slider joint's closure: the 2×2 modulus taking the slider's velocity `v_A`
    /// to the rocker's angular velocity and the slide speed, `(ω₃, ṡ)`. With O3 fixed,
    /// `v_A = s ω₃ ê⊥ + ṡ ê`, whose inverse is `ω₃ = ê⊥·v_A / s`, `ṡ = ê·v_A`.
    pub fn slider_closure(&self) -> SMatrix<S, 2, 2> {
        let e = self.rocker_dir;
        let s = self.slide;
        SMatrix::<S, 2, 2>::new(-e.y / s, e.x / s, e.x, e.y)
    }

    /// The output slider's closure: the 2×2 modulus taking the rocker tip's velocity
    /// `v_T` to the rod's angular velocity and the output slider's speed, `(ω₄, ẋ₅)`.
    /// The rod's far end moves with the slider along X0,
    /// `v_T + rod ω₄ ê₄⊥ = (ẋ₅, 0)`, so `ω₄ = −v_Ty / (rod ê₄x)` and
    /// `ẋ₅ = v_Tx + ê₄y v_Ty / ê₄x` (ê₄x > 0 whenever the rod reaches the guide).
    pub fn output_closure(&self, rod: S) -> SMatrix<S, 2, 2> {
        output_closure_of(self.rod_dir, rod)
    }
}

/// The rotation about Z0 by `angle`, as the spec's 3×3 orientation matrices.
pub fn rotation<S: Scalar>(angle: S) -> Matrix3<S> {
    bgdsl_runtime::multibond::rot_z(angle)
}

/// Link numbers for [`centre_of`]: crank, slider, rocker, rod, output slider.
pub const CRANK: usize = 0;
/// The slider on the rocker.
pub const SLIDER: usize = 1;
/// The rocker arm.
pub const ROCKER: usize = 2;
/// The connecting rod.
pub const ROD: usize = 3;
/// The output slider.
pub const OUTPUT: usize = 4;

/// The crank's unit vector at crank angle `theta`.
fn crank_dir<S: Scalar>(theta: S) -> Vector2<S> {
    vec2(theta.cos(), theta.sin())
}

/// The rocker's unit vector ê and the slider's distance s from O3.
fn rocker_frame<S: Scalar>(theta: S, crank: S, d: S) -> (Vector2<S>, S) {
    let u = crank_dir(theta) * crank + vec2(S::from_f64(0.0), d);
    let slide = (u.x * u.x + u.y * u.y).sqrt();
    (u / slide, slide)
}

/// The rod's unit vector ê₄, the rocker's tip T and the output slider's centre O5.
fn rod_frame<S: Scalar>(
    theta: S,
    crank: S,
    d: S,
    rocker: S,
    rod: S,
) -> (Vector2<S>, Vector2<S>, Vector2<S>) {
    let (e, _) = rocker_frame(theta, crank, d);
    let tip = vec2(e.x * rocker, e.y * rocker - d);
    let reach = (rod * rod - tip.y * tip.y).sqrt();
    let output = vec2(tip.x + reach, S::from_f64(0.0));
    ((output - tip) / rod, tip, output)
}

/// The centre of mass of link `link` ([`CRANK`] … [`OUTPUT`]) at crank angle `theta`.
pub fn centre_of<S: Scalar>(
    link: usize,
    theta: S,
    crank: S,
    d: S,
    rocker: S,
    rod: S,
) -> Vector2<S> {
    let half = S::from_f64(0.5);
    match link {
        CRANK => crank_dir(theta) * (crank * half),
        SLIDER => crank_dir(theta) * crank,
        ROCKER => {
            let (e, _) = rocker_frame(theta, crank, d);
            vec2(e.x * (rocker * half), e.y * (rocker * half) - d)
        }
        ROD => {
            let (_, tip, output) = rod_frame(theta, crank, d, rocker, rod);
            (tip + output) * half
        }
        _ => rod_frame(theta, crank, d, rocker, rod).2,
    }
}

/// `Σ mᵢ yᵢ` over the links' centres of mass (the output slider's is on y = 0): the
/// weight's potential energy over g.
#[allow(clippy::too_many_arguments)]
pub fn mass_moment_y<S: Scalar>(theta: S, crank: S, d: S, rocker: S, rod: S, masses: [S; 4]) -> S {
    let half = S::from_f64(0.5);
    let (e, _) = rocker_frame(theta, crank, d);
    let (_, tip, _) = rod_frame(theta, crank, d, rocker, rod);
    let pin_y = theta.sin() * crank;
    masses[0] * pin_y * half
        + masses[1] * pin_y
        + masses[2] * (e.y * rocker * half - d)
        + masses[3] * tip.y * half
}

/// The lever of the crank's point at signed distance `at` from its centre along the
/// crank (O1 at −crank/2, the pin A at +crank/2).
pub fn crank_lever<S: Scalar>(theta: S, at: S) -> Vector2<S> {
    lever(crank_dir(theta) * at)
}

/// The lever of the rocker's point at signed distance `at` from its centre along the
/// rocker (O3 at −rocker/2, the tip at +rocker/2).
pub fn rocker_lever<S: Scalar>(theta: S, crank: S, d: S, at: S) -> Vector2<S> {
    lever(rocker_frame(theta, crank, d).0 * at)
}

/// The lever of the rod's point at signed distance `at` from its centre along the rod
/// (its end at the rocker's tip at −rod/2).
pub fn rod_lever<S: Scalar>(theta: S, crank: S, d: S, rocker: S, rod: S, at: S) -> Vector2<S> {
    lever(rod_frame(theta, crank, d, rocker, rod).0 * at)
}

/// [`Pose::slider_closure`] at crank angle `theta`.
pub fn slider_closure<S: Scalar>(theta: S, crank: S, d: S) -> SMatrix<S, 2, 2> {
    let (e, s) = rocker_frame(theta, crank, d);
    SMatrix::<S, 2, 2>::new(-e.y / s, e.x / s, e.x, e.y)
}

/// [`Pose::output_closure`] at crank angle `theta`.
pub fn output_closure<S: Scalar>(theta: S, crank: S, d: S, rocker: S, rod: S) -> SMatrix<S, 2, 2> {
    let (e, _, _) = rod_frame(theta, crank, d, rocker, rod);
    output_closure_of(e, rod)
}

/// The output closure for the rod's unit vector `e` (see [`Pose::output_closure`]).
fn output_closure_of<S: Scalar>(e: Vector2<S>, rod: S) -> SMatrix<S, 2, 2> {
    let zero = S::from_f64(0.0);
    let one = S::from_f64(1.0);
    SMatrix::<S, 2, 2>::new(zero, -one / (rod * e.x), one, e.y / e.x)
}

/// The rod's angle ψ from X0 at crank angle `theta`.
pub fn rod_angle<S: Scalar>(theta: S, crank: S, d: S, rocker: S, rod: S) -> S {
    let (e, _, _) = rod_frame(theta, crank, d, rocker, rod);
    e.y.atan2(e.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lean helpers the moduli call agree with the whole pose.
    #[test]
    fn helpers_agree_with_the_pose() {
        for i in 0..12 {
            let theta = -3.0 + 0.5 * f64::from(i);
            let (crank, d, rocker, rod) = (0.2, 0.4, 0.7, 0.4);
            let pose = Pose::at(theta, crank, d, rocker, rod);
            let masses = [0.5, 0.1, 0.7, 0.3];
            let mut moment = 0.0;
            for (link, centre) in pose.centres().iter().enumerate() {
                let lean = centre_of(link, theta, crank, d, rocker, rod);
                assert!((lean - centre).norm() < 1e-15, "θ = {theta}, link {link}");
                if link < 4 {
                    moment += masses[link] * centre.y;
                }
            }
            let lean = mass_moment_y(theta, crank, d, rocker, rod, masses);
            assert!(
                (lean - moment).abs() < 1e-15,
                "θ = {theta}: {lean} vs {moment}"
            );
            assert!((rod_angle(theta, crank, d, rocker, rod) - pose.rod_angle()).abs() < 1e-15);
            assert_eq!(slider_closure(theta, crank, d), pose.slider_closure());
        }
    }

    /// The closures are the inverses of the forward kinematics: the velocity they give
    /// back reproduces the point's velocity (to rounding), at several crank angles.
    #[test]
    fn closures_invert_the_forward_kinematics() {
        for i in 0..12 {
            let theta = -3.0 + 0.5 * f64::from(i);
            let pose = Pose::at(theta, 0.2, 0.4, 0.7, 0.4);
            let v_a = vec2(0.3, -1.1);
            let w3s = pose.slider_closure() * v_a;
            let perp = vec2(-pose.rocker_dir.y, pose.rocker_dir.x);
            let back = perp * (pose.slide * w3s.x) + pose.rocker_dir * w3s.y;
            assert!((back - v_a).norm() < 1e-13, "θ = {theta}: {back:?}");
            let v_t = vec2(-0.4, 0.9);
            let w4x = pose.output_closure(0.4) * v_t;
            let rod_perp = vec2(-pose.rod_dir.y, pose.rod_dir.x);
            let end = v_t + rod_perp * (0.4 * w4x.x);
            assert!(
                (end - vec2(w4x.y, 0.0)).norm() < 1e-13,
                "θ = {theta}: {end:?}"
            );
        }
    }
}
