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
        let zero = S::from_f64(0.0);
        let crank_dir = vec2(theta.cos(), theta.sin());
        let pin = crank_dir * crank;
        let pivot = vec2(zero, -d);
        let u = pin - pivot;
        let slide = (u.x * u.x + u.y * u.y).sqrt();
        let rocker_dir = u / slide;
        let tip = pivot + rocker_dir * rocker;
        let reach = (rod * rod - tip.y * tip.y).sqrt();
        let output = vec2(tip.x + reach, zero);
        Pose {
            crank_dir,
            pin,
            slide,
            rocker_dir,
            pivot,
            tip,
            rod_dir: (output - tip) / rod,
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
        let e = self.rod_dir;
        let zero = S::from_f64(0.0);
        let one = S::from_f64(1.0);
        SMatrix::<S, 2, 2>::new(zero, -one / (rod * e.x), one, e.y / e.x)
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

/// The centre of mass of link `link` ([`CRANK`] … [`OUTPUT`]) at crank angle `theta`.
pub fn centre_of<S: Scalar>(
    link: usize,
    theta: S,
    crank: S,
    d: S,
    rocker: S,
    rod: S,
) -> Vector2<S> {
    Pose::at(theta, crank, d, rocker, rod).centres()[link]
}

/// The lever of the crank's point at signed distance `at` from its centre along the
/// crank (O1 at −crank/2, the pin A at +crank/2).
pub fn crank_lever<S: Scalar>(theta: S, at: S) -> Vector2<S> {
    lever(vec2(theta.cos(), theta.sin()) * at)
}

/// The lever of the rocker's point at signed distance `at` from its centre along the
/// rocker (O3 at −rocker/2, the tip at +rocker/2).
pub fn rocker_lever<S: Scalar>(theta: S, crank: S, d: S, at: S) -> Vector2<S> {
    let one = S::from_f64(1.0);
    lever(Pose::at(theta, crank, d, one, one).rocker_dir * at)
}

/// The lever of the rod's point at signed distance `at` from its centre along the rod
/// (its end at the rocker's tip at −rod/2).
pub fn rod_lever<S: Scalar>(theta: S, crank: S, d: S, rocker: S, rod: S, at: S) -> Vector2<S> {
    lever(Pose::at(theta, crank, d, rocker, rod).rod_dir * at)
}

/// [`Pose::slider_closure`] at crank angle `theta`.
pub fn slider_closure<S: Scalar>(theta: S, crank: S, d: S) -> SMatrix<S, 2, 2> {
    let one = S::from_f64(1.0);
    Pose::at(theta, crank, d, one, one).slider_closure()
}

/// [`Pose::output_closure`] at crank angle `theta`.
pub fn output_closure<S: Scalar>(theta: S, crank: S, d: S, rocker: S, rod: S) -> SMatrix<S, 2, 2> {
    Pose::at(theta, crank, d, rocker, rod).output_closure(rod)
}

/// The rocker's angle φ from X0 at crank angle `theta`.
pub fn rocker_angle<S: Scalar>(theta: S, crank: S, d: S) -> S {
    let one = S::from_f64(1.0);
    Pose::at(theta, crank, d, one, one).rocker_angle()
}

/// The rod's angle ψ from X0 at crank angle `theta`.
pub fn rod_angle<S: Scalar>(theta: S, crank: S, d: S, rocker: S, rod: S) -> S {
    Pose::at(theta, crank, d, rocker, rod).rod_angle()
}

#[cfg(test)]
mod tests {
    use super::*;

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
