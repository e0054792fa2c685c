//! Equilibria, linear models, modes and frequency responses against closed forms:
//! matrices written by hand from each model's bond graph, the characteristic
//! polynomial's coefficients, published transfer functions, a time-domain sine
//! response, and central differences.

use bgdsl_analysis::{
    equilibrium, frequency_response, linearize, log_grid, modes, state_partials, AnalysisError,
    Channel, LinearModel, Method, SteadyOptions,
};
use bgdsl_runtime::{bond_graph, simulate, Model, Radau5Options, Solver, WithInputs};
use models::quick_return::QuickReturn;
use models::{Butterworth, DcMotor, Duffing, QuarterCar, SeriesRlc};
use nalgebra::{Complex, DMatrix};

fn index<M: Model>(name: &str) -> usize {
    M::STATE_NAMES
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("no state {name} in {:?}", M::STATE_NAMES))
}

/// `found` against `expected` entry by entry, to `rel` of the largest entry of
/// `expected`.
fn assert_matrix(what: &str, found: &DMatrix<f64>, expected: &DMatrix<f64>, rel: f64) {
    assert_eq!(found.shape(), expected.shape(), "{what}");
    let tol = rel * expected.amax();
    for ((i, j), e) in expected
        .iter()
        .enumerate()
        .map(|(k, e)| ((k % expected.nrows(), k / expected.nrows()), e))
    {
        let f = found[(i, j)];
        assert!(
            (f - e).abs() <= tol,
            "{what}[{i},{j}] = {f}, expected {e} (tolerance {tol:e})"
        );
    }
}

/// `a` with rows and columns in the order of the state names `order`.
fn permuted<M: Model>(order: &[&str], rows: &[&[f64]]) -> DMatrix<f64> {
    let n = M::N_STATES;
    let mut m = DMatrix::zeros(n, n);
    for (r, row) in rows.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            m[(index::<M>(order[r]), index::<M>(order[c]))] = *v;
        }
    }
    m
}

#[test]
fn the_quarter_car_rests_at_its_static_deflection() {
    let car = QuarterCar::default();
    let p = car.params.clone();
    let eq = equilibrium(&car, &[0.0; 4], &[], SteadyOptions::default()).unwrap();
    let tyre = (p.sprung_mass + p.unsprung_mass) * p.g / p.tyre_stiffness;
    let spring = p.sprung_mass * p.g / p.suspension_stiffness;
    let x = &eq.x;
    assert!((x[index::<QuarterCar>("tyre.q")] - tyre).abs() <= 1e-14 * tyre);
    assert!((x[index::<QuarterCar>("spring.q")] - spring).abs() <= 1e-14 * spring);
    assert!(x[index::<QuarterCar>("sprung.p")].abs() <= 1e-12);
    assert!(x[index::<QuarterCar>("unsprung.p")].abs() <= 1e-12);
    assert!(eq.residual <= 1e-9, "{}", eq.residual);
}

/// Steady state of the DC motor: with `b = b_m + b_L/N²`, the motor speed is
/// `ω_m = (V − R τ_L/(N k_t)) / (R b / k_t + k_t)`, the current
/// `i = (b ω_m + τ_L/N) / k_t`, the load turns at `ω_m/N` and the shaft carries
/// `τ = b_L ω_m/N + τ_L`.
#[test]
fn the_dc_motor_runs_at_its_closed_form_speed_and_current() {
    let motor = DcMotor::default();
    let p = motor.params.clone();
    let eq = equilibrium(&motor, &[0.0; 4], &[], SteadyOptions::default()).unwrap();
    let n = p.gear_ratio;
    let b = p.rotor_friction + p.load_friction / (n * n);
    let speed = (p.voltage - p.resistance * p.load_torque / (n * p.torque_constant))
        / (p.resistance * b / p.torque_constant + p.torque_constant);
    let current = (b * speed + p.load_torque / n) / p.torque_constant;
    let torque = p.load_friction * speed / n + p.load_torque;
    let x = &eq.x;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(x[index::<DcMotor>("coil.p")] / p.inductance, current));
    assert!(close(
        x[index::<DcMotor>("rotor.p")] / p.rotor_inertia,
        speed
    ));
    assert!(close(
        x[index::<DcMotor>("load.p")] / p.load_inertia,
        speed / n
    ));
    assert!(close(
        x[index::<DcMotor>("shaft_spring.q")] * p.shaft_stiffness,
        torque
    ));
}

bond_graph! {
    /// A mass pushed by a constant force, its position integrated: nothing holds it.
    model FreeMass {
        param m = 2.0 in "kg";
        param force = 1.0 in "N";
        Se push = force;
        I mass = m;
        1 v;
        push -> v -> mass;
        state position: f64 = 0.0;
        der position = v.f;
    }
}

#[test]
fn a_free_mass_has_no_equilibrium_and_the_error_names_its_states() {
    let error = equilibrium(
        &FreeMass::default(),
        &[0.0, 0.0],
        &[],
        SteadyOptions::default(),
    )
    .unwrap_err();
    let AnalysisError::Singular {
        states,
        rates,
        motions,
    } = &error
    else {
        panic!("{error}");
    };
    assert_eq!(states, &["position".to_string()], "{error}");
    assert_eq!(rates, &["mass.p".to_string()], "{error}");
    assert_eq!(motions, &[vec!["position".to_string()]], "{error}");
    assert!(
        error.to_string().starts_with(
            "the Jacobian ∂f/∂x is singular: the equilibrium does not determine \
                          `position` (nothing pulls them back"
        ),
        "{error}"
    );
}

bond_graph! {
    /// Two tanks joined by a pipe: the charge moves between them, its total is free.
    model Tanks {
        param c1 = 2.0 in "F";
        param c2 = 3.0 in "F";
        param r = 0.5 in "Ω";
        C left = c1;
        C right = c2;
        R pipe = r;
        0 a;
        0 b;
        1 flow;
        a -> left;
        b -> right;
        a -> flow -> b;
        flow -> pipe;
    }
}

/// Charge conservation: the total charge of two tanks joined by a pipe is free (any
/// split with equal pressures q1/c1 = q2/c2 is an equilibrium), so the null space is
/// the one motion (c1, c2) of both states together, and the left null space the sum of
/// their rates (d(q1 + q2)/dt = 0: no state changes it).
#[test]
fn two_joined_tanks_have_one_free_motion_of_both_charges() {
    let error = equilibrium(
        &Tanks::default(),
        &[1.0, 0.0],
        &[],
        SteadyOptions::default(),
    )
    .unwrap_err();
    let AnalysisError::Singular {
        states,
        rates,
        motions,
    } = &error
    else {
        panic!("{error}");
    };
    let both = vec!["left.q".to_string(), "right.q".to_string()];
    assert_eq!(motions, std::slice::from_ref(&both), "{error}");
    assert_eq!(states, &both, "{error}");
    assert_eq!(rates, &both, "{error}");
    assert!(
        error
            .to_string()
            .contains("; free motions of several states: `left.q` with `right.q`, and"),
        "{error}"
    );
}

#[test]
fn the_series_rlc_matrices_are_the_hand_written_ones() {
    let rlc = SeriesRlc::default();
    let p = rlc.params.clone();
    let voltage = Channel::named::<SeriesRlc>("voltage").unwrap();
    let lin = linearize(&rlc, 0.0, &[0.0, 0.0], &[voltage]).unwrap();
    let (r, l, c) = (p.resistance, p.inductance, p.capacitance);
    let order = ["inductor.p", "capacitor.q"];
    let a = permuted::<SeriesRlc>(&order, &[&[-r / l, -1.0 / c], &[1.0 / l, 0.0]]);
    assert_matrix("A", &lin.a, &a, 1e-15);
    let mut b = DMatrix::zeros(2, 1);
    b[(index::<SeriesRlc>("inductor.p"), 0)] = 1.0;
    assert_matrix("B", &lin.b, &b, 0.0);
    let current = lin.output_index("current").unwrap();
    let vc = lin.output_index("capacitor_voltage").unwrap();
    assert!((lin.c[(current, index::<SeriesRlc>("inductor.p"))] - 1.0 / l).abs() < 1e-12);
    assert!((lin.c[(vc, index::<SeriesRlc>("capacitor.q"))] - 1.0 / c).abs() < 1e-6);
    assert_eq!((lin.d[(current, 0)], lin.d[(vc, 0)]), (0.0, 0.0));
    assert_eq!(lin.method, Method::Exact);
    assert_eq!(lin.inputs, ["voltage"]);
}

#[test]
fn the_dc_motor_matrices_are_the_hand_written_ones() {
    let motor = DcMotor::default();
    let p = motor.params.clone();
    let x = [0.01, 2e-5, 0.003, 0.02];
    let lin = linearize(
        &motor,
        0.0,
        &x,
        &[
            Channel::named::<DcMotor>("voltage").unwrap(),
            Channel::named::<DcMotor>("load_torque").unwrap(),
        ],
    )
    .unwrap();
    let (l, r, kt, jm, bm, n) = (
        p.inductance,
        p.resistance,
        p.torque_constant,
        p.rotor_inertia,
        p.rotor_friction,
        p.gear_ratio,
    );
    let (ks, cs, jl, bl) = (
        p.shaft_stiffness,
        p.shaft_damping,
        p.load_inertia,
        p.load_friction,
    );
    // States λ, p_m, θ, p_L; i = λ/L, ω_m = p_m/J_m, ω_L = p_L/J_L,
    // τ = k_s θ + c_s (ω_m/N − ω_L).
    let order = ["coil.p", "rotor.p", "shaft_spring.q", "load.p"];
    let a = permuted::<DcMotor>(
        &order,
        &[
            &[-r / l, -kt / jm, 0.0, 0.0],
            &[kt / l, -bm / jm - cs / (n * n * jm), -ks / n, cs / (n * jl)],
            &[0.0, 1.0 / (n * jm), 0.0, -1.0 / jl],
            &[0.0, cs / (n * jm), ks, -cs / jl - bl / jl],
        ],
    );
    assert_matrix("A", &lin.a, &a, 1e-14);
    let mut b = DMatrix::zeros(4, 2);
    b[(index::<DcMotor>("coil.p"), 0)] = 1.0;
    b[(index::<DcMotor>("load.p"), 1)] = -1.0;
    assert_matrix("B", &lin.b, &b, 0.0);
}

fn quarter_car_a(car: &QuarterCar) -> DMatrix<f64> {
    let p = car.params.clone();
    let (ms, mu, ks, c, kt) = (
        p.sprung_mass,
        p.unsprung_mass,
        p.suspension_stiffness,
        p.suspension_damping,
        p.tyre_stiffness,
    );
    // States q_t, p_u, q_s, p_b: q̇_t = v_r − p_u/m_u, ṗ_u = k_t q_t − F_s − m_u g,
    // q̇_s = p_u/m_u − p_b/m_s, ṗ_b = F_s − m_s g, F_s = k_s q_s + c (p_u/m_u − p_b/m_s).
    permuted::<QuarterCar>(
        &["tyre.q", "unsprung.p", "spring.q", "sprung.p"],
        &[
            &[0.0, -1.0 / mu, 0.0, 0.0],
            &[kt, -c / mu, -ks, c / ms],
            &[0.0, 1.0 / mu, 0.0, -1.0 / ms],
            &[0.0, c / mu, ks, -c / ms],
        ],
    )
}

/// The quarter car's A by hand, and its eigenvalues against the characteristic
/// polynomial `m_s m_u s⁴ + c (m_s + m_u) s³ + (k_s m_s + k_s m_u + k_t m_s) s² +
/// c k_t s + k_s k_t`: each a root, and their sum and product those of Vieta.
#[test]
fn the_quarter_car_matrix_and_modes_match_its_characteristic_polynomial() {
    let car = QuarterCar::default();
    let p = car.params.clone();
    let lin = linearize(&car, 0.0, &[0.0; 4], &[]).unwrap();
    assert_matrix("A", &lin.a, &quarter_car_a(&car), 1e-15);
    let (ms, mu, ks, c, kt) = (
        p.sprung_mass,
        p.unsprung_mass,
        p.suspension_stiffness,
        p.suspension_damping,
        p.tyre_stiffness,
    );
    let coefficients = [
        ks * kt / (ms * mu),
        c * kt / (ms * mu),
        (ks * ms + ks * mu + kt * ms) / (ms * mu),
        c * (ms + mu) / (ms * mu),
        1.0,
    ];
    let found = modes(&lin.a);
    assert_eq!(found.len(), 2, "two oscillating modes: {found:?}");
    let mut roots = Vec::new();
    for mode in &found {
        let l = mode.eigenvalue;
        assert!(l.im > 0.0);
        roots.extend([l, l.conj()]);
        let value = coefficients
            .iter()
            .rev()
            .fold(Complex::new(0.0, 0.0), |acc, &a| acc * l + a);
        let scale = coefficients
            .iter()
            .enumerate()
            .map(|(k, a)| a * l.norm().powi(k as i32))
            .fold(0.0, f64::max);
        // The eigenvalues of the Schur form are accurate to about ε‖A‖ = 4e-11 (‖A‖ =
        // k_t = 2e5): p(λ) to about that times p'(λ), 1e-9 of its largest term.
        assert!(
            value.norm() <= 1e-8 * scale,
            "p({l}) = {value}, scale {scale:e}"
        );
        assert!((mode.natural_frequency - l.norm()).abs() <= 1e-12 * l.norm());
        assert!((mode.damping_ratio + l.re / l.norm()).abs() <= 1e-12);
    }
    let sum: Complex<f64> = roots.iter().sum();
    let product: Complex<f64> = roots.iter().product();
    assert!(
        (sum.re + coefficients[3]).abs() <= 1e-8 * coefficients[3],
        "{sum}"
    );
    assert!(
        (product.re - coefficients[0]).abs() <= 1e-8 * coefficients[0],
        "{product}"
    );
    // The body bounce (about 1.2 Hz) moves the body, the wheel hop (about 11 Hz) the
    // wheel.
    let body = index::<QuarterCar>("spring.q");
    let wheel = index::<QuarterCar>("tyre.q");
    assert!(found[0].natural_frequency / (2.0 * std::f64::consts::PI) < 2.0);
    assert!(
        found[0].dominant.contains(&body)
            || found[0].dominant.contains(&index::<QuarterCar>("sprung.p"))
    );
    assert!(
        found[1].dominant.contains(&wheel)
            || found[1]
                .dominant
                .contains(&index::<QuarterCar>("unsprung.p"))
    );
}

/// A against central differences of the model's `f64` code (step `1e-6·max(|x|, 1e-3)`),
/// to `1e-6` of the column's largest entry plus the round-off `1e3·ε·max|f|/h`.
fn check_a_by_central_differences<M: Model>(model: &M, t: f64, x: &[f64]) {
    let a = state_partials(model, t, x).unwrap().df;
    let n = M::N_STATES;
    let mut f0 = vec![0.0; n];
    model.derivatives(t, x, &mut f0);
    let fmax = f0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for j in 0..n {
        let h = 1e-6 * x[j].abs().max(1e-3);
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[j] += h;
        xm[j] -= h;
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        model.derivatives(t, &xp, &mut fp);
        model.derivatives(t, &xm, &mut fm);
        let column: Vec<f64> = (0..n).map(|i| (fp[i] - fm[i]) / (2.0 * h)).collect();
        let big = column.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let tol = 1e-6 * big + 1e3 * f64::EPSILON * fmax / h;
        for i in 0..n {
            assert!(
                (a[(i, j)] - column[i]).abs() <= tol,
                "{}: A[{i},{j}] = {}, central differences {} ({tol:e})",
                M::NAME,
                a[(i, j)],
                column[i]
            );
        }
    }
}

#[test]
fn the_duffing_and_flagship_linearisations_match_central_differences() {
    let duffing = Duffing::default();
    check_a_by_central_differences(&duffing, 1.3, &[0.7, -0.4]);
    let flagship = QuickReturn::default();
    let mut x = vec![0.0; QuickReturn::N_STATES];
    flagship.initial_state(&mut x);
    for (i, v) in x.iter_mut().enumerate() {
        *v += 1e-3 * (1.0 + i as f64).cos();
    }
    check_a_by_central_differences(&flagship, 0.2, &x);
}

/// `H(s) = 1 / (2 (s + 1)(s² + s + 1))`.
fn butterworth(s: Complex<f64>) -> Complex<f64> {
    let one = Complex::new(1.0, 0.0);
    one / ((s + one) * (s * s + s + one) * 2.0)
}

fn butterworth_linear() -> LinearModel {
    let filter = Butterworth::default();
    let voltage = Channel::named::<Butterworth>("voltage").unwrap();
    assert_eq!(voltage, Channel::Input(0));
    linearize(&filter, 0.0, &[0.0; 3], &[voltage]).unwrap()
}

#[test]
fn the_butterworth_ladder_has_its_transfer_function() {
    let lin = butterworth_linear();
    let output = lin.output_index("load_voltage").unwrap();
    let omega = log_grid(1e-2, 1e2, 200);
    let response = frequency_response(&lin, 0, output, &omega);
    for (w, h) in omega.iter().zip(&response.h) {
        let expected = butterworth(Complex::new(0.0, *w));
        assert!(
            (h - expected).norm() <= 1e-12 * expected.norm(),
            "ω = {w}: {h} vs {expected}"
        );
    }
    // −3 dB below the low-frequency −6 dB at the cut-off, −60 dB/decade beyond.
    let at_cutoff = frequency_response(&lin, 0, output, &[1.0]);
    assert!((at_cutoff.magnitude_db()[0] - (-6.0206 - 3.0103)).abs() < 1e-3);
    // The phase, unwrapped: −atan ω − atan2(ω, 1 − ω²), from 0 towards −270°.
    let phase = response.phase_deg();
    for (w, p) in omega.iter().zip(&phase) {
        let expected = -(w.atan() + w.atan2(1.0 - w * w)).to_degrees();
        assert!((p - expected).abs() < 1e-9, "ω = {w}: {p}° vs {expected}°");
    }
    assert_eq!(
        (response.input_unit.as_str(), response.output_unit.as_str()),
        ("V", "V")
    );
}

bond_graph! {
    /// The quarter car with the road's vertical velocity as an input.
    model DrivenQuarterCar {
        param ms = 300.0 in "kg";
        param mu = 40.0 in "kg";
        param ks = 20000.0 in "N/m";
        param c = 1500.0 in "N·s/m";
        param kt = 200000.0 in "N/m";
        input road_velocity = 0.0 in "m/s";
        MSf road = road_velocity;
        0 contact; C tyre = kt; 1 wheel; I unsprung = mu;
        0 strut; 1 deflection; C spring = ks; R damper = c; 1 body; I sprung = ms;
        road -> contact -> { tyre, wheel };
        wheel -> { unsprung, strut };
        strut -> deflection -> { spring, damper };
        strut -> body -> sprung;
        output body_velocity = body.f in "m/s";
    }
}

/// Transmissibility road → body: `k_t (c s + k_s) / ((m_s s² + c s + k_s)(m_u s² + c s
/// + k_s + k_t) − (c s + k_s)²)` (the same for displacements and velocities).
#[test]
fn the_quarter_car_transmissibility_is_its_transfer_function() {
    let car = DrivenQuarterCar::default();
    let p = car.params.clone();
    let lin = linearize(&car, 0.0, &[0.0; 4], &[Channel::Input(0)]).unwrap();
    let omega = log_grid(0.1, 1000.0, 200);
    let response = frequency_response(&lin, 0, 0, &omega);
    for (w, h) in omega.iter().zip(&response.h) {
        let s = Complex::new(0.0, *w);
        let coupling = s * p.c + p.ks;
        let expected = coupling * p.kt
            / ((s * s * p.ms + coupling) * (s * s * p.mu + coupling + p.kt) - coupling * coupling);
        assert!(
            (h - expected).norm() <= 1e-10 * expected.norm(),
            "ω = {w}: {h} vs {expected}"
        );
    }
}

bond_graph! {
    /// The Butterworth ladder driven by a sine of 1 V at `w`.
    model SineButterworth {
        param w = 1.0 in "rad/s";
        Se source = (w * t).sin();
        1 loop1; R rs = 1.0; I inductor1 = 1.0; 0 node; C capacitor = 0.5;
        1 loop2; I inductor3 = 1.0; R load = 1.0;
        source -> loop1 -> { rs, inductor1 };
        loop1 -> node -> capacitor;
        node -> loop2 -> { inductor3, load };
        output load_voltage = load.e in "V";
    }
}

/// At ω = 1 rad/s the steady response to sin(t) is |H(j)| sin(t + arg H(j)) with
/// |H(j)| = 1/(2√2) and arg H(j) = −135°: measured on periods 10 to 15 of a run (the
/// slowest transient decays as e^{−t/2}: below 1e−13 after 10 periods), by projection
/// on sin and cos, to 1e−4 of |H| (Radau5 at rtol 1e−10).
#[test]
fn one_frequency_matches_the_time_domain_sine_response() {
    let lin = butterworth_linear();
    let output = lin.output_index("load_voltage").unwrap();
    let h = frequency_response(&lin, 0, output, &[1.0]).h[0];
    let model = SineButterworth::default();
    let period = 2.0 * std::f64::consts::PI;
    let per = 1000;
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    });
    let run = simulate(&model, solver, 0.0, 15.0 * period, 15 * per + 1).unwrap();
    let times = run.times();
    assert!((times[10 * per] - 10.0 * period).abs() < 1e-9);
    let y = run.column("load_voltage").unwrap();
    let (mut a, mut b, mut count) = (0.0, 0.0, 0);
    // The rectangle rule over whole periods integrates sin² and sin·cos exactly.
    for k in 10 * per..15 * per {
        a += y[k] * times[k].sin();
        b += y[k] * times[k].cos();
        count += 1;
    }
    let (a, b) = (2.0 * a / count as f64, 2.0 * b / count as f64);
    let measured = Complex::new(a, b);
    assert!(
        (measured - h).norm() <= 1e-4 * h.norm(),
        "measured {measured}, H(j) = {h}"
    );
    assert!((h.norm() - 1.0 / (2.0 * 2f64.sqrt())).abs() < 1e-14);
    assert!((h.arg().to_degrees() + 135.0).abs() < 1e-12);
}

#[test]
fn the_inputs_of_a_generated_model_are_named_and_unknown_names_listed() {
    assert_eq!(Butterworth::INPUTS.len(), 1);
    let error = Channel::named::<Butterworth>("volts").unwrap_err();
    assert!(error.to_string().contains("`voltage`"), "{error}");
    assert_eq!(
        Channel::named::<QuickReturn>("l1[1]").unwrap(),
        Channel::Parameter(6)
    );
}
