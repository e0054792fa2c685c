//! Which way a scene is looked at: face on to the plane of a planar motion, else in 3-D.

use bgdsl_runtime::multibond::{Matrix3, Vector3};

use super::BodyTrack;

/// How far (relative to the motion's extent) a centre of mass may stray from the plane,
/// and how far (in the rotation matrix's entries) a body's rotation axis from the
/// plane's normal, for the motion to count as planar. A compliant mechanism's
/// out-of-plane drift is at the integration error, far below.
pub const PLANAR_TOLERANCE: f64 = 1e-3;

/// How a scene is looked at.
#[derive(Clone, Debug, PartialEq)]
pub enum View {
    /// Face on to a plane of frame 0: a point `p` is drawn at `(p·u, p·v)`, `u`
    /// rightwards and `v` upwards (unit vectors, orthogonal).
    Plane {
        /// The plane's rightward axis in frame 0.
        u: [f64; 3],
        /// The plane's upward axis in frame 0.
        v: [f64; 3],
    },
    /// A 3-D view the reader turns by dragging (frame 0's Y starts upwards).
    Orbit,
}

impl View {
    /// The plane every centre of mass stays in (within [`PLANAR_TOLERANCE`] of the
    /// motion's extent) while every body turns only about its normal, seen face on;
    /// [`View::Orbit`] when there is none. The plane is the one the centres span most
    /// thinly (the principal axis of least variance), snapped to frame 0's planes when
    /// it is one of them, so the quick return is seen in X0–Y0 with Y0 up; frame 0's
    /// planes are tried as well when the centres do not fix one (a single point or a
    /// line).
    pub fn choose(bodies: &[BodyTrack]) -> View {
        let centres: Vec<Vector3<f64>> = bodies
            .iter()
            .flat_map(|b| b.position.iter().map(|p| Vector3::new(p[0], p[1], p[2])))
            .filter(|c| c.iter().all(|v| v.is_finite()))
            .collect();
        if centres.is_empty() {
            return View::plane(Vector3::z());
        }
        let mean = centres.iter().sum::<Vector3<f64>>() / centres.len() as f64;
        let mut covariance = Matrix3::zeros();
        for c in &centres {
            let d = c - mean;
            covariance += d * d.transpose();
        }
        let extent = centres
            .iter()
            .map(|c| (c - mean).norm())
            .fold(0.0, f64::max);
        let eigen = covariance.symmetric_eigen();
        let thinnest = eigen.eigenvalues.imin();
        let normal = snap(eigen.eigenvectors.column(thinnest).into_owned());
        let candidates = [normal, Vector3::z(), Vector3::y(), Vector3::x()];
        candidates
            .into_iter()
            .find(|n| {
                let flat = centres
                    .iter()
                    .all(|c| (c - mean).dot(n).abs() <= PLANAR_TOLERANCE * extent);
                flat && bodies.iter().all(|b| turns_about(b, n))
            })
            .map_or(View::Orbit, View::plane)
    }

    /// Face on to the plane with unit normal `n` (from its positive side).
    fn plane(n: Vector3<f64>) -> View {
        // Frame 0's planes keep its axes: X0–Y0 (Y0 up), Z0–X0, Y0–Z0.
        let (u, v) = if n.z.abs() == 1.0 {
            (Vector3::x() * n.z, Vector3::y())
        } else if n.y.abs() == 1.0 {
            (Vector3::z() * n.y, Vector3::x())
        } else if n.x.abs() == 1.0 {
            (Vector3::y() * n.x, Vector3::z())
        } else {
            // An oblique plane: rightwards along X0's part in it (or Y0's), up by n × u.
            let along = |axis: Vector3<f64>| axis - n * n.dot(&axis);
            let u = if along(Vector3::x()).norm() > 0.5 {
                along(Vector3::x()).normalize()
            } else {
                along(Vector3::y()).normalize()
            };
            (u, n.cross(&u))
        };
        View::Plane {
            u: [u.x, u.y, u.z],
            v: [v.x, v.y, v.z],
        }
    }
}

/// `n` made a coordinate axis when within round-off of one, its largest component
/// positive.
fn snap(n: Vector3<f64>) -> Vector3<f64> {
    let axis = n.iamax();
    let n = if n[axis] < 0.0 { -n } else { n };
    if n[axis] > 1.0 - 1e-9 {
        let mut e = Vector3::zeros();
        e[axis] = 1.0;
        e
    } else {
        n
    }
}

/// Whether `body` turns only about `n`: the normal seen in its own frame, `Rᵀ n`, stays
/// where it was at the first frame.
fn turns_about(body: &BodyTrack, n: &Vector3<f64>) -> bool {
    let in_body = |r: &[f64; 9]| Matrix3::from_column_slice(r).transpose() * n;
    let Some(first) = body.orientation.first().map(in_body) else {
        return true;
    };
    body.orientation
        .iter()
        .all(|r| (in_body(r) - first).amax() <= PLANAR_TOLERANCE)
}

#[cfg(test)]
mod should {
    use super::*;
    use crate::animation::Shape;

    fn rot_about(axis: usize, angle: f64) -> [f64; 9] {
        let (s, c) = angle.sin_cos();
        let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut m = Matrix3::identity();
        m[(i, i)] = c;
        m[(j, j)] = c;
        m[(j, i)] = s;
        m[(i, j)] = -s;
        let mut r = [0.0; 9];
        r.copy_from_slice(m.as_slice());
        r
    }

    fn body(positions: Vec<[f64; 3]>, orientations: Vec<[f64; 9]>) -> BodyTrack {
        BodyTrack {
            name: "b".into(),
            shape: Shape::Marker,
            position: positions,
            orientation: orientations,
        }
    }

    /// A crank turning about Z0 with its centre on a circle in X0–Y0.
    fn crank(axis: usize, tilt: f64) -> BodyTrack {
        let angles: Vec<f64> = (0..50).map(|k| 0.1 * k as f64).collect();
        let position = angles
            .iter()
            .map(|a| match axis {
                2 => [0.1 * a.cos(), 0.1 * a.sin(), tilt * a],
                1 => [0.1 * a.sin(), tilt * a, 0.1 * a.cos()],
                _ => [tilt * a, 0.1 * a.cos(), 0.1 * a.sin()],
            })
            .collect();
        let orientation = angles.iter().map(|&a| rot_about(axis, a)).collect();
        body(position, orientation)
    }

    #[test]
    fn look_face_on_at_each_plane_of_frame_0() {
        assert_eq!(
            View::choose(&[crank(2, 0.0)]),
            View::Plane {
                u: [1.0, 0.0, 0.0],
                v: [0.0, 1.0, 0.0]
            }
        );
        assert_eq!(
            View::choose(&[crank(1, 0.0)]),
            View::Plane {
                u: [0.0, 0.0, 1.0],
                v: [1.0, 0.0, 0.0]
            }
        );
        assert_eq!(
            View::choose(&[crank(0, 0.0)]),
            View::Plane {
                u: [0.0, 1.0, 0.0],
                v: [0.0, 0.0, 1.0]
            }
        );
    }

    #[test]
    fn turn_to_3d_when_a_centre_leaves_the_plane_or_a_body_tilts() {
        // A helix: 1e-2 m per rad out of the plane on a 0.1 m circle.
        assert_eq!(View::choose(&[crank(2, 1e-2)]), View::Orbit);
        // Just inside the tolerance (drift 1e-6 m per rad) it is still planar.
        assert!(matches!(
            View::choose(&[crank(2, 1e-6)]),
            View::Plane { .. }
        ));
        // Centres in X0–Y0 but the body turning about X0 as well.
        let mut tilted = crank(2, 0.0);
        tilted.orientation[10] = rot_about(0, 0.3);
        assert_eq!(View::choose(&[tilted]), View::Orbit);
    }

    #[test]
    fn find_an_oblique_plane_and_keep_its_axes_orthonormal() {
        // The X0–Y0 crank turned by 0.5 rad about X0: its plane is oblique.
        let tilt = Matrix3::from_column_slice(&rot_about(0, 0.5));
        let mut b = crank(2, 0.0);
        for (p, r) in b.position.iter_mut().zip(b.orientation.iter_mut()) {
            let q = tilt * Vector3::new(p[0], p[1], p[2]);
            *p = [q.x, q.y, q.z];
            let turned = tilt * Matrix3::from_column_slice(r);
            r.copy_from_slice(turned.as_slice());
        }
        let View::Plane { u, v } = View::choose(&[b]) else {
            panic!("an oblique plane is a plane");
        };
        let (u, v) = (Vector3::from(u), Vector3::from(v));
        let normal = tilt * Vector3::z();
        assert!((u.norm() - 1.0).abs() < 1e-12 && (v.norm() - 1.0).abs() < 1e-12);
        assert!(u.dot(&v).abs() < 1e-12);
        assert!(u.cross(&v).dot(&normal).abs() > 1.0 - 1e-9, "{u} {v}");
    }

    #[test]
    fn take_a_plane_of_frame_0_when_the_centres_do_not_fix_one() {
        // One body turning about Z0 in place: its centre is a single point.
        let spinning = body(
            vec![[0.0; 3]; 20],
            (0..20).map(|k| rot_about(2, 0.2 * k as f64)).collect(),
        );
        assert_eq!(
            View::choose(&[spinning]),
            View::Plane {
                u: [1.0, 0.0, 0.0],
                v: [0.0, 1.0, 0.0]
            }
        );
    }
}
