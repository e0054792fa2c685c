//! The quarter car: static equilibrium, momentum and impulse, frequency response, and
//! agreement with the hand-written equations the benchmark compares it with.

mod common;

use bgdsl_runtime::{Model, Scalar, Simulation};
use common::{dopri5, initial_state, Rng};
use models::reference::{quarter_car_derivatives, quarter_car_road_velocity};
use models::{QuarterCar, QuarterCarParams};

const STATES: [&str; 4] = ["tyre.q", "unsprung.p", "spring.q", "sprung.p"];

/// Parameters spread over a factor of three around the defaults, with the bump and a
/// road undulation both active.
fn random_params(rng: &mut Rng) -> QuarterCarParams {
    let d = QuarterCarParams::default();
    let mut spread = |v: f64| v * rng.log_uniform(1.0 / 3.0, 3.0);
    QuarterCarParams {
        sprung_mass: spread(d.sprung_mass),
        unsprung_mass: spread(d.unsprung_mass),
        suspension_stiffness: spread(d.suspension_stiffness),
        suspension_damping: spread(d.suspension_damping),
        tyre_stiffness: spread(d.tyre_stiffness),
        g: spread(d.g),
        speed: spread(d.speed),
        bump_distance: spread(d.bump_distance),
        bump_height: spread(d.bump_height),
        bump_length: spread(d.bump_length),
        wave_amplitude: spread(0.02),
        wavelength: spread(d.wavelength),
    }
}

/// A random state: compressions up to 0.1 m either way, velocities up to 2 m/s.
fn random_state(rng: &mut Rng, p: &QuarterCarParams) -> [f64; 4] {
    [
        rng.symmetric(0.1),
        p.unsprung_mass * rng.symmetric(2.0),
        rng.symmetric(0.1),
        p.sprung_mass * rng.symmetric(2.0),
    ]
}

/// A random time, half of the time while the tyre is on the bump.
fn random_time(rng: &mut Rng, p: &QuarterCarParams) -> f64 {
    let start = p.bump_distance / p.speed;
    let end = (p.bump_distance + p.bump_length) / p.speed;
    if rng.unit() < 0.5 {
        rng.uniform(start, end)
    } else {
        rng.uniform(0.0, 2.0 * end)
    }
}

/// The sizes of the terms summed in each derivative (velocities, forces), against
/// which the rounding of that derivative is measured.
fn term_scales(p: &QuarterCarParams, t: f64, x: &[f64; 4]) -> [f64; 4] {
    let v_road = quarter_car_road_velocity(p, t).abs();
    let v_wheel = (x[1] / p.unsprung_mass).abs();
    let v_body = (x[3] / p.sprung_mass).abs();
    let suspension =
        (p.suspension_stiffness * x[2]).abs() + p.suspension_damping * (v_wheel + v_body);
    [
        v_road + v_wheel,
        (p.tyre_stiffness * x[0]).abs() + suspension + p.unsprung_mass * p.g,
        v_wheel + v_body,
        suspension + p.sprung_mass * p.g,
    ]
}

/// The quarter car with one more state: the impulse of the external forces on the two
/// masses, `∫ (k_t q_t − (m_s + m_u) g) dt`, computed here from the state.
struct WithImpulse(QuarterCar);

impl Model for WithImpulse {
    type Params = QuarterCarParams;
    const NAME: &'static str = "QuarterCarWithImpulse";
    const STATE_NAMES: &'static [&'static str] =
        &["tyre.q", "unsprung.p", "spring.q", "sprung.p", "impulse"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];

    fn params(&self) -> &QuarterCarParams {
        &self.0.params
    }

    fn initial_state(&self, x0: &mut [f64]) {
        self.0.initial_state(&mut x0[..4]);
        x0[4] = 0.0;
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.0.derivatives(t, &x[..4], &mut dx[..4]);
        let p = &self.0.params;
        let c = T::from_f64;
        dx[4] = c(p.tyre_stiffness) * x[0] - c((p.sprung_mass + p.unsprung_mass) * p.g);
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// A complex number, enough for a 2x2 frequency response.
#[derive(Clone, Copy, Debug)]
struct C(f64, f64);

impl C {
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
    fn sub(self, o: C) -> C {
        C(self.0 - o.0, self.1 - o.1)
    }
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: C) -> C {
        let d = o.0 * o.0 + o.1 * o.1;
        C(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn abs(self) -> f64 {
        self.0.hypot(self.1)
    }
}

/// The body's displacement per unit road displacement at angular frequency ω, from
/// the linear equations of motion about equilibrium,
/// `m_s z_s'' = k_s (z_u − z_s) + c_s (z_u' − z_s')` and
/// `m_u z_u'' = k_t (z_r − z_u) − k_s (z_u − z_s) − c_s (z_u' − z_s')`:
/// `H = k_t (k_s + iωc_s) / (D_u D_s − (k_s + iωc_s)²)` with
/// `D_s = k_s + iωc_s − ω² m_s`, `D_u = k_s + k_t + iωc_s − ω² m_u`.
fn body_transmissibility(p: &QuarterCarParams, omega: f64) -> C {
    let coupling = C(p.suspension_stiffness, omega * p.suspension_damping);
    let d_s = coupling.sub(C(omega * omega * p.sprung_mass, 0.0));
    let d_u = coupling.add(C(p.tyre_stiffness - omega * omega * p.unsprung_mass, 0.0));
    C(p.tyre_stiffness, 0.0)
        .mul(coupling)
        .div(d_u.mul(d_s).sub(coupling.mul(coupling)))
}

mod should {
    use super::*;

    /// The declared initial state is the static equilibrium: on a flat road (no bump,
    /// no undulation) nothing moves and the spring forces carry the weights. The
    /// derivatives are sums of forces that cancel exactly; against the weight
    /// `(m_s + m_u) g` the residual is rounding, so 1e-12 relative. Random parameters.
    #[test]
    fn rests_in_static_equilibrium_on_a_flat_road() {
        assert_eq!(QuarterCar::STATE_NAMES, STATES);
        let mut rng = Rng::new(1);
        for _ in 0..500 {
            let p = QuarterCarParams {
                bump_height: 0.0,
                wave_amplitude: 0.0,
                ..random_params(&mut rng)
            };
            let model = QuarterCar::new(p.clone());
            let x = initial_state(&model);
            let mut dx = [0.0; 4];
            model.derivatives(rng.uniform(0.0, 10.0), &x, &mut dx);
            let weight = (p.sprung_mass + p.unsprung_mass) * p.g;
            assert_eq!([dx[0], dx[2]], [0.0, 0.0], "velocities at rest");
            assert!(
                dx[1].abs() <= 1e-12 * weight && dx[3].abs() <= 1e-12 * weight,
                "{dx:?} for {p:?}"
            );
            let mut y = [0.0; QuarterCar::N_OUTPUTS];
            model.outputs(0.0, &x, &mut y);
            let out = |name: &str| {
                y[QuarterCar::OUTPUT_NAMES
                    .iter()
                    .position(|n| *n == name)
                    .unwrap()]
            };
            assert!(
                (out("tyre_force") - weight).abs() <= 1e-12 * weight,
                "the tyre carries the weight"
            );
            for name in [
                "body_height",
                "wheel_height",
                "suspension_travel",
                "body_acceleration",
            ] {
                assert!(
                    out(name).abs() <= 1e-12,
                    "{name} = {} at equilibrium",
                    out(name)
                );
            }
        }
    }

    /// The suspension's forces are internal to the two masses, so the total momentum
    /// changes only by the tyre force and the weights:
    /// `d(p_u + p_s)/dt = k_t q_t − (m_s + m_u) g`, at every state and time. Rounding
    /// only, so 1e-12 relative to the forces involved.
    #[test]
    fn total_momentum_changes_by_the_external_forces_only() {
        let mut rng = Rng::new(2);
        for _ in 0..2000 {
            let p = random_params(&mut rng);
            let x = random_state(&mut rng, &p);
            let t = random_time(&mut rng, &p);
            let mut dx = [0.0; 4];
            QuarterCar::new(p.clone()).derivatives(t, &x, &mut dx);
            let external = p.tyre_stiffness * x[0] - (p.sprung_mass + p.unsprung_mass) * p.g;
            let scale = term_scales(&p, t, &x);
            assert!((dx[1] + dx[3] - external).abs() <= 1e-12 * (scale[1] + scale[3]));
        }
    }

    /// Over the default bump scenario (3 s: the bump at 0.5–0.7 s, then the ringing),
    /// the change of total momentum equals the impulse of the tyre force and the weights
    /// integrated alongside. Both are integrated to rtol 1e-10 (atol 1e-12 against
    /// momenta and an impulse of up to about 150 N·s), so after N steps they agree to
    /// N·(rtol · peak + atol), with `peak` the largest of them seen during the run.
    #[test]
    fn momentum_change_equals_the_impulse_of_the_external_forces() {
        let (rtol, atol) = (1e-10, 1e-12);
        let model = WithImpulse(QuarterCar::default());
        let mut x0 = [0.0; 5];
        model.initial_state(&mut x0);
        let mut sim = Simulation::new(&model, dopri5(rtol, atol)).unwrap();
        let mut peak: f64 = 0.0;
        let mut last = [0.0; 5];
        let stats = sim
            .run_uniform(
                0.0,
                &x0,
                3.0,
                3001,
                &mut |_t: f64, x: &[f64], _y: &[f64]| {
                    peak = peak.max(x[4].abs()).max((x[1] + x[3]).abs());
                    last.copy_from_slice(x);
                },
            )
            .unwrap();
        let momentum_change = (last[1] + last[3]) - (x0[1] + x0[3]);
        let impulse = last[4];
        let bound = stats.steps() as f64 * (rtol * peak + atol);
        eprintln!(
            "peak impulse {peak:.3} N·s; Δp = {momentum_change:e}, impulse {impulse:e}, \
             mismatch {:e} (bound {bound:e}, {} steps)",
            (momentum_change - impulse).abs(),
            stats.steps()
        );
        assert!(peak > 1.0, "the bump pushed the car");
        assert!((momentum_change - impulse).abs() <= bound);
    }

    /// After the bump the car comes back to its static equilibrium. The slowest mode
    /// (the body bounce, −2.12 ± 7.61i 1/s with the default parameters) has decayed by
    /// e^−2.12·(15−0.7) ≈ 7e-14 by t = 15 s, so what remains of the 5 cm bump is far
    /// below 1e-9 m.
    #[test]
    fn returns_to_equilibrium_after_the_bump() {
        let model = QuarterCar::default();
        let x0 = initial_state(&model);
        let (traj, _) = common::run(&model, dopri5(1e-10, 1e-13), &x0, 15.0, 1501);
        for name in [
            "body_height",
            "wheel_height",
            "suspension_travel",
            "body_velocity",
        ] {
            let end = traj.value(1500, name).unwrap();
            assert!(end.abs() < 1e-9, "{name} = {end:e} at t = 15 s");
        }
        let body = traj.column("body_height").unwrap();
        let highest = body.iter().cloned().fold(f64::MIN, f64::max);
        assert!(
            highest > 0.01,
            "the body rose over the bump (peak {highest} m)"
        );
    }

    /// On a sinusoidal road the body's steady motion is the road's times the analytic
    /// transmissibility `H(ω)`; at low frequency `|H| → 1` (the car follows the road).
    /// After 20 s every transient has decayed by e^−42 (slowest mode −2.12 1/s); one
    /// period is then sampled at 64 points and projected on e^{iωt}, which is exact for
    /// a pure sinusoid. Checked on the body's velocity (a state) and on its height (an
    /// output that adds the analytic road profile), each to 1e-7 relative: the solver
    /// runs at rtol 1e-10, its dense output is fourth order, and errors of a damped
    /// system do not accumulate beyond a few hundred steps' worth.
    #[test]
    fn body_follows_a_slow_road_and_matches_the_analytic_transmissibility() {
        let amplitude = 0.01;
        for frequency in [0.05, 0.5, 1.2, 3.0, 11.8] {
            let omega = std::f64::consts::TAU * frequency;
            let params = QuarterCarParams {
                bump_height: 0.0,
                wave_amplitude: amplitude,
                wavelength: QuarterCarParams::default().speed / frequency,
                ..Default::default()
            };
            let expected = body_transmissibility(&params, omega);
            let model = QuarterCar::new(params);
            let settle = 20.0;
            let n = 64;
            let period = 1.0 / frequency;
            let times: Vec<f64> = (0..n)
                .map(|j| settle + period * j as f64 / n as f64)
                .collect();
            let mut sim = Simulation::new(&model, dopri5(1e-10, 1e-13)).unwrap();
            let mut traj = bgdsl_runtime::Trajectory::for_model::<QuarterCar>(n);
            sim.run(0.0, &initial_state(&model), &times, &mut traj)
                .unwrap();
            // y(t) = Re(Y e^{iωt}) with Y = (2/n) Σ y_j e^{−iωt_j}.
            let phasor = |name: &str| {
                let y = traj.column(name).unwrap();
                let (mut re, mut im) = (0.0, 0.0);
                for (&t, &v) in times.iter().zip(y) {
                    re += v * (omega * t).cos();
                    im -= v * (omega * t).sin();
                }
                C(2.0 * re / n as f64, 2.0 * im / n as f64)
            };
            // Road: z_r = a sin ωt = Re(−i a e^{iωt}); its velocity a ω cos ωt = Re(a ω e^{iωt}).
            let from_height = phasor("body_height").div(C(0.0, -amplitude));
            let from_velocity = phasor("body_velocity").div(C(amplitude * omega, 0.0));
            for (what, h) in [("height", from_height), ("velocity", from_velocity)] {
                let error = h.sub(expected).abs() / expected.abs();
                eprintln!(
                    "{frequency} Hz, body {what}: |H| = {:.6}, relative error {error:e}",
                    h.abs()
                );
                assert!(
                    error < 1e-7,
                    "{frequency} Hz, body {what}: H = {h:?}, expected {expected:?}"
                );
            }
            if frequency <= 0.05 {
                assert!(
                    (from_height.abs() - 1.0).abs() < 0.01,
                    "slow road: |H| = {}",
                    from_height.abs()
                );
            }
        }
    }

    /// The generated derivative equals the hand-written one (`models::reference`,
    /// written from Newton's laws, which the benchmark times against it) at random
    /// states, times and parameters. The two add the same forces in different orders,
    /// so they differ by rounding: 1e-12 relative to the terms summed.
    #[test]
    fn generated_derivatives_equal_the_hand_written_equations() {
        let mut rng = Rng::new(3);
        for _ in 0..5000 {
            let p = random_params(&mut rng);
            let x = random_state(&mut rng, &p);
            let t = random_time(&mut rng, &p);
            let (mut generated, mut by_hand) = ([0.0; 4], [0.0; 4]);
            QuarterCar::new(p.clone()).derivatives(t, &x, &mut generated);
            quarter_car_derivatives(&p, t, &x, &mut by_hand);
            let scale = term_scales(&p, t, &x);
            for i in 0..4 {
                assert!(
                    (generated[i] - by_hand[i]).abs() <= 1e-12 * scale[i],
                    "d{}/dt: generated {} vs by hand {} at t = {t}, x = {x:?}, {p:?}",
                    STATES[i],
                    generated[i],
                    by_hand[i]
                );
            }
        }
    }
}
