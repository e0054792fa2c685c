//! Independent references for the rigid mechanisms of `textbook.rs`: closed-form
//! kinematics and Lagrange's equation of a one-degree-of-freedom mechanism,
//!
//!   M(θ) θ̈ + ½ M'(θ) θ̇² = τ(t) − V'(θ),
//!
//! with M(θ) = Σ mᵢ nᵢ(θ)² over every inertia (nᵢ = dqᵢ/dθ, the velocity ratio of its
//! coordinate) and M' = 2 Σ mᵢ nᵢ nᵢ', each nᵢ' differentiated by hand. Written as
//! hand models with states `[θ, θ̇]`, integrated by the runtime's DOPRI as the
//! reference. Nothing here goes through a bond graph; the hand derivatives are
//! checked against central differences of the closed-form positions in
//! `rigid_mechanisms.rs`.
#![allow(dead_code)]

use bgdsl_runtime::{Model, Scalar};

use crate::textbook::{FourBarParams, SliderCrankParams};

/// One coordinate's velocity ratio n = dq/dθ and its derivative n' = d²q/dθ².
#[derive(Clone, Copy, Debug)]
pub struct Ratio<T> {
    /// dq/dθ
    pub n: T,
    /// d²q/dθ²
    pub dn: T,
}

/// The slider-crank's closed-form positions at crank angle θ: the slider's x, the
/// rod centre's (x, y), the rod's angle φ.
pub fn slider_crank_positions(p: &SliderCrankParams, theta: f64) -> [f64; 4] {
    let (s_th, c_th) = theta.sin_cos();
    let s = (p.l * p.l - p.r * p.r * s_th * s_th).sqrt();
    let xb = p.r * c_th + s;
    let (ax, ay) = (p.r * c_th, p.r * s_th);
    [xb, 0.5 * (ax + xb), 0.5 * ay, (-p.r * s_th).atan2(s)]
}

/// The slider-crank's velocity ratios at θ, in the order of
/// [`slider_crank_positions`]: slider x, rod centre x and y, rod angle.
pub fn slider_crank_ratios<T: Scalar>(p: &SliderCrankParams, theta: T) -> [Ratio<T>; 4] {
    let k = T::from_f64;
    let (r, l) = (k(p.r), k(p.l));
    let (s_th, c_th) = (theta.sin(), theta.cos());
    let s = (l * l - r * r * s_th * s_th).sqrt();
    let sin2 = k(2.0) * s_th * c_th;
    let cos2 = c_th * c_th - s_th * s_th;
    // s' = −r² sin θ cos θ / s, s'' = −r² cos 2θ / s − (r² sin 2θ / 2)² / s³.
    let ds = -r * r * s_th * c_th / s;
    let half = r * r * sin2 * k(0.5);
    let dds = -r * r * cos2 / s - half * half / (s * s * s);
    let slider = Ratio {
        n: -r * s_th + ds,
        dn: -r * c_th + dds,
    };
    let centre_x = Ratio {
        n: k(0.5) * (-r * s_th + slider.n),
        dn: k(0.5) * (-r * c_th + slider.dn),
    };
    let centre_y = Ratio {
        n: k(0.5) * r * c_th,
        dn: -k(0.5) * r * s_th,
    };
    // φ' = −r cos θ / s, φ'' = r sin θ / s + r cos θ s' / s².
    let angle = Ratio {
        n: -r * c_th / s,
        dn: r * s_th / s + r * c_th * ds / (s * s),
    };
    [slider, centre_x, centre_y, angle]
}

/// The slider-crank's M(θ), M'(θ) and V'(θ).
pub fn slider_crank_mass<T: Scalar>(p: &SliderCrankParams, theta: T) -> (T, T, T) {
    let k = T::from_f64;
    let [slider, gx, gy, phi] = slider_crank_ratios(p, theta);
    let m = k(p.jc)
        + k(p.mr) * (gx.n * gx.n + gy.n * gy.n)
        + k(p.jr) * phi.n * phi.n
        + k(p.ms) * slider.n * slider.n;
    let dm = k(2.0)
        * (k(p.mr) * (gx.n * gx.dn + gy.n * gy.dn)
            + k(p.jr) * phi.n * phi.dn
            + k(p.ms) * slider.n * slider.dn);
    let dv = k(p.mr * p.g) * gy.n;
    (m, dm, dv)
}

/// The slider-crank's energy ½ M(θ) θ̇² + V(θ), V = mr g y_G.
pub fn slider_crank_energy(p: &SliderCrankParams, theta: f64, omega: f64) -> f64 {
    let (m, _, _) = slider_crank_mass(p, theta);
    0.5 * m * omega * omega + p.mr * p.g * slider_crank_positions(p, theta)[2]
}

/// The four-bar's closed-form coupler and rocker angles (θ3, θ4) at crank angle θ,
/// in the open assembly (B above the line A O4): B lies on the circles of radius b
/// about A and c about O4.
pub fn four_bar_angles(p: &FourBarParams, theta: f64) -> (f64, f64) {
    let (ax, ay) = (p.a * theta.cos(), p.a * theta.sin());
    let (dx, dy) = (p.d - ax, -ay);
    let e = dx.hypot(dy);
    let theta3 = dy.atan2(dx) + ((p.b * p.b + e * e - p.c * p.c) / (2.0 * p.b * e)).acos();
    let (bx, by) = (ax + p.b * theta3.cos(), ay + p.b * theta3.sin());
    (theta3, by.atan2(bx - p.d))
}

/// The four-bar's angular velocity ratios (θ3', θ4') and their derivatives by θ at
/// (θ, θ3, θ4), from the loop closure's velocity and acceleration equations with
/// θ̇ = 1, θ̈ = 0 (projected on e^{iθ4} and e^{iθ3}).
pub fn four_bar_ratios<T: Scalar>(
    p: &FourBarParams,
    theta: T,
    theta3: T,
    theta4: T,
) -> (Ratio<T>, Ratio<T>) {
    let k = T::from_f64;
    let (a, b, c) = (k(p.a), k(p.b), k(p.c));
    let w3 = a * (theta4 - theta).sin() / (b * (theta3 - theta4).sin());
    let w4 = a * (theta - theta3).sin() / (c * (theta4 - theta3).sin());
    let a3 = (c * w4 * w4 - a * (theta - theta4).cos() - b * w3 * w3 * (theta3 - theta4).cos())
        / (b * (theta3 - theta4).sin());
    let a4 = (a * (theta - theta3).cos() + b * w3 * w3 - c * w4 * w4 * (theta4 - theta3).cos())
        / (c * (theta4 - theta3).sin());
    (Ratio { n: w3, dn: a3 }, Ratio { n: w4, dn: a4 })
}

/// The four-bar's M, M', V' at (θ, θ3, θ4).
pub fn four_bar_mass<T: Scalar>(p: &FourBarParams, theta: T, theta3: T, theta4: T) -> (T, T, T) {
    let k = T::from_f64;
    let (a, b) = (k(p.a), k(p.b));
    let (r3, r4) = four_bar_ratios(p, theta, theta3, theta4);
    let (s, c) = (theta.sin(), theta.cos());
    let (s3, c3) = (theta3.sin(), theta3.cos());
    let half_b = k(0.5) * b;
    let gx = Ratio {
        n: -a * s - half_b * s3 * r3.n,
        dn: -a * c - half_b * (c3 * r3.n * r3.n + s3 * r3.dn),
    };
    let gy = Ratio {
        n: a * c + half_b * c3 * r3.n,
        dn: -a * s + half_b * (-s3 * r3.n * r3.n + c3 * r3.dn),
    };
    let m = k(p.j2)
        + k(p.m3) * (gx.n * gx.n + gy.n * gy.n)
        + k(p.j3) * r3.n * r3.n
        + k(p.j4) * r4.n * r4.n;
    let dm = k(2.0)
        * (k(p.m3) * (gx.n * gx.dn + gy.n * gy.dn)
            + k(p.j3) * r3.n * r3.dn
            + k(p.j4) * r4.n * r4.dn);
    let dv = k(p.m3 * p.g) * gy.n + k(p.m4 * p.g * 0.5 * p.c) * theta4.cos() * r4.n;
    (m, dm, dv)
}

/// The four-bar's coupler centre y at θ (for its potential energy).
pub fn four_bar_centre_y(p: &FourBarParams, theta: f64) -> f64 {
    let (theta3, _) = four_bar_angles(p, theta);
    p.a * theta.sin() + 0.5 * p.b * theta3.sin()
}

/// The four-bar's energy ½ M θ̇² + m3 g y_G3 + m4 g (c/2) sin θ4.
pub fn four_bar_energy(p: &FourBarParams, theta: f64, omega: f64) -> f64 {
    let (theta3, theta4) = four_bar_angles(p, theta);
    let (m, _, _) = four_bar_mass(p, theta, theta3, theta4);
    0.5 * m * omega * omega
        + p.m3 * p.g * four_bar_centre_y(p, theta)
        + p.m4 * p.g * 0.5 * p.c * theta4.sin()
}

/// Lagrange's equation of the slider-crank, states `[θ, θ̇]`.
pub struct SliderCrankLagrange(pub SliderCrankParams);

impl Model for SliderCrankLagrange {
    type Params = SliderCrankParams;
    const NAME: &'static str = "SliderCrankLagrange";
    const STATE_NAMES: &'static [&'static str] = &["theta", "omega"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];

    fn params(&self) -> &SliderCrankParams {
        &self.0
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[self.0.theta0, self.0.w0]);
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let p = &self.0;
        let (m, dm, dv) = slider_crank_mass(p, x[0]);
        let torque = T::from_f64(p.tau + p.tau1 * (p.omega_d * t).sin());
        dx[0] = x[1];
        dx[1] = (torque - dv - T::from_f64(0.5) * dm * x[1] * x[1]) / m;
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// Lagrange's equation of the four-bar, states `[θ, θ̇]`, the coupler and rocker
/// angles from the closed form.
pub struct FourBarLagrange(pub FourBarParams);

impl Model for FourBarLagrange {
    type Params = FourBarParams;
    const NAME: &'static str = "FourBarLagrange";
    const STATE_NAMES: &'static [&'static str] = &["theta", "omega"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];

    fn params(&self) -> &FourBarParams {
        &self.0
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&[self.0.theta0, self.0.w0]);
    }

    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let p = &self.0;
        // The closed form in f64 (the reference is integrated in f64 only), lifted.
        let (theta3, theta4) = four_bar_angles(p, x[0].to_f64());
        let (m, dm, dv) = four_bar_mass(p, x[0], T::from_f64(theta3), T::from_f64(theta4));
        dx[0] = x[1];
        dx[1] = (T::from_f64(p.tau) - dv - T::from_f64(0.5) * dm * x[1] * x[1]) / m;
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}
