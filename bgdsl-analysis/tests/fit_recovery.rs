//! Parameter estimation recovers known parameters from simulated measurements with
//! seeded Gaussian noise: the truth lies within the reported 95 % interval, and the
//! residual RMS equals the noise's standard deviation (to 15 %: the sample standard
//! deviation of a few hundred normal draws).

use bgdsl_analysis::fit::{
    chi_square_upper_tail, fit, FitOptions, FitParameter, Measurements, NoiseModel,
};
use bgdsl_analysis::sensitivity::parameter_index;
use bgdsl_runtime::{bond_graph, FromParams, Model, Radau5Options, Simulation, Solver};
use models::quick_return::QuickReturn;
use models::DcMotor;

/// Standard normal draws from a seeded xorshift64* generator (Vigna 2016) and the
/// Box–Muller transform: reproducible noise without a dependency.
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        (bits as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (core::f64::consts::TAU * v).cos()
    }
}

/// `columns` of `model`'s run at `times`, each with noise of standard deviation
/// `sigma[k]`, as measurements CSV text.
fn measured<M: Model>(
    model: &M,
    solver: Solver,
    times: &[f64],
    columns: &[&str],
    sigma: &[f64],
    seed: u64,
) -> String {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, solver).unwrap();
    let mut rows = Vec::new();
    sim.run(
        times[0],
        &x0,
        times,
        &mut |t: f64, _x: &[f64], y: &[f64]| rows.push((t, y.to_vec())),
    )
    .unwrap();
    let mut noise = Noise(seed);
    let mut text = format!("t,{}\n", columns.join(","));
    for (t, y) in rows {
        text.push_str(&format!("{t}"));
        for (c, s) in columns.iter().zip(sigma) {
            let o = M::OUTPUT_NAMES.iter().position(|n| n == c).unwrap();
            text.push_str(&format!(",{}", y[o] + s * noise.normal()));
        }
        text.push('\n');
    }
    text
}

#[test]
fn dc_motor_resistance_and_friction_from_a_noisy_step_response() {
    let truth = DcMotor::default();
    let times: Vec<f64> = (0..301).map(|k| 0.3 * k as f64 / 300.0).collect();
    let sigma = [0.05, 0.5];
    let csv = measured(
        &truth,
        truth.default_solver(),
        &times,
        &["current", "motor_speed"],
        &sigma,
        16,
    );
    let data = Measurements::parse_csv(&csv).unwrap();

    let names = ["resistance", "rotor_friction"];
    let mut start = truth.params().clone();
    start.resistance *= 1.5;
    start.rotor_friction *= 3.0;
    let guess = DcMotor::from_params(start);
    let parameters: Vec<FitParameter> = names
        .iter()
        .map(|n| FitParameter {
            index: parameter_index::<DcMotor>(n).unwrap(),
            lower: 0.0,
            upper: f64::INFINITY,
        })
        .collect();
    let (report, _fitted) = fit(&guess, None, &data, &parameters, &FitOptions::default()).unwrap();
    eprintln!("{report:#?}");
    assert!(report.converged);
    let true_values = [truth.params().resistance, truth.params().rotor_friction];
    for (p, truth) in report.parameters.iter().zip(true_values) {
        assert!(
            p.interval.0 <= truth && truth <= p.interval.1,
            "{}: {} not in {:?}",
            p.name,
            truth,
            p.interval
        );
        // The interval is informative: narrower than the start's distance to the truth.
        assert!(
            p.interval.1 - p.interval.0 < (p.initial - truth).abs(),
            "{p:?}"
        );
    }
    // Each column's σ is estimated: its residual RMS and its σ both equal the noise's
    // standard deviation to 15 %.
    for (column, s) in report.columns.iter().zip(sigma) {
        assert!(!column.sigma_given);
        for estimate in [column.residual_rms, column.sigma] {
            assert!(
                (estimate / s - 1.0).abs() < 0.15,
                "{}: {estimate} vs noise {s}",
                column.name
            );
        }
    }
    assert!(report.weights_settled && report.chi_square.is_none());
}

/// The quick return's output-slider guide damping (joint `j5C`, `R5C[0]`, 20 N·s/m)
/// from the output slider's position `r_C5_x` over the first turn (2 ms samples,
/// noise 10 µm: the damper's force shows through the joints' deflections), started at
/// 30 N·s/m.
#[test]
fn quick_return_guide_damping_from_the_output_slider_position() {
    let truth = QuickReturn::default();
    let times: Vec<f64> = (0..=629).map(|k| 2e-3 * k as f64).collect();
    let sigma = [1e-5];
    // The data from a run ten times more accurate than the fit's (rtol 1e-10 against
    // 1e-8): the intervals account for the noise, not for a solver's error in the data.
    let tight = Solver::Radau5(Radau5Options {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    });
    let csv = measured(&truth, tight, &times, &["r_C5_x"], &sigma, 5);
    let data = Measurements::parse_csv(&csv).unwrap();
    let index = parameter_index::<QuickReturn>("R5C[0]").unwrap();
    let mut values = vec![0.0; QuickReturn::N_PARAMETER_VALUES];
    truth.parameter_values(&mut values);
    let true_value = values[index];
    values[index] = 30.0;
    let mut guess = QuickReturn::from_params(truth.params().clone());
    guess.set_parameter_values(&values);
    let parameters = [FitParameter {
        index,
        lower: 0.0,
        upper: f64::INFINITY,
    }];
    let mut options = FitOptions::default();
    options.sensitivity.substeps = 2;
    let (report, _) = fit(&guess, None, &data, &parameters, &options).unwrap();
    eprintln!("{report:#?}");
    assert!(report.converged);
    let p = &report.parameters[0];
    // Within three standard errors (99.7 %), not the 95 % interval: with this seed (the
    // first tried) the estimate is 19.99925 ± 0.00033, 2.2 standard errors from the
    // truth, which a 95 % interval misses about once in 36 draws. The same noise scaled
    // by 1/5 gave the same 2.2: the estimate's error is the noise's, not a bias.
    assert!(
        (p.value - true_value).abs() <= 3.0 * p.standard_error,
        "{p:?}"
    );
    assert!(p.interval.1 - p.interval.0 < 1.0, "{p:?}");
    let rms = report.columns[0].residual_rms;
    assert!((rms / sigma[0] - 1.0).abs() < 0.15, "residual RMS {rms}");
}

bond_graph! {
    /// A permanent-magnet DC motor with an inertial, viscously damped rotor on a 12 V
    /// step (two states: cheap enough to fit many times in a debug build).
    pub model Motor {
        /// supply voltage
        param voltage = 12.0 in "V";
        /// armature resistance
        param resistance = 1.0 in "Ω";
        /// armature inductance
        param inductance = 0.5e-3 in "H";
        /// torque constant
        param torque_constant = 0.05 in "N·m/A";
        /// rotor inertia
        param inertia = 1.0e-4 in "kg·m²";
        /// rotor viscous friction
        param friction = 1.0e-4 in "N·m·s/rad";
        Se supply = voltage;
        1 armature;
        R winding = resistance;
        I coil = inductance, p in "Wb";
        GY motor = torque_constant;
        1 shaft;
        I rotor = inertia, p in "N·m·s";
        R bearing = friction;
        supply -> armature -> { winding, coil };
        armature -> motor -> shaft -> { rotor, bearing };
        /// Armature current, A.
        output current = armature.f in "A";
        /// Rotor speed, rad/s.
        output speed = shaft.f in "rad/s";
    }
}

/// The seeds of the coverage study.
const SEEDS: u64 = 200;

/// The fewest of `SEEDS` intervals that must cover the truth: with a true coverage of
/// 95 %, `P(X ≤ 181) = 0.0058` for `X ~ Binomial(200, 0.95)`, so 182 or more covered
/// is the acceptance region of a test at the 1 % level (`P(X ≤ 182) = 0.012` would
/// exceed it).
const MIN_COVERED: usize = 182;

/// Intervals that hold at their stated rate with noise ten times larger, relative to
/// its column's RMS, on one column than on the other: the motor's current with noise of
/// 5 % of its RMS, its speed with 0.5 %, both measured at 151 times over 0.3 s.
///
/// Over 200 seeds, the resistance's and the friction's 95 % intervals each cover the
/// truth in at least 182 (the 1 % binomial bound above), and `Σ z²` of the
/// standardised errors `z = (estimate − truth) / standard error` over the seeds lies in
/// the central 99 % of χ²(200), [152.2, 255.3] (a check of the standard errors' size,
/// which intervals too wide fail as well as too narrow ones).
///
/// The same data fitted with one pooled variance ([`NoiseModel::Pooled`], the method
/// of session 24) must fail that check: the pooled σ is about √((5² + 0.5²)/2) = 3.6 %
/// of either column's RMS, 0.71 times the current's noise and 7 times the speed's, and
/// both parameters lean on the current enough that their intervals come out too
/// narrow (measured: 162 and 169 of 200 covered, `Σ z²` 386 and 376; per column: 192
/// and 190, `Σ z²` 201 and 180).
///
/// 400 fits started at the truth: about 5 s of CPU time in a debug build.
#[test]
fn intervals_cover_the_truth_at_their_rate_with_unequal_noise_per_column() {
    let truth = Motor::default();
    let times: Vec<f64> = (0..=150).map(|k| 2e-3 * k as f64).collect();
    let tight = Solver::Radau5(Radau5Options {
        rtol: 1e-11,
        atol: 1e-13,
        ..Default::default()
    });
    let clean = Measurements::parse_csv(&measured(
        &truth,
        tight,
        &times,
        &["current", "speed"],
        &[0.0, 0.0],
        1,
    ))
    .unwrap();
    let rms = |c: usize| {
        let v = &clean.values[c];
        (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
    };
    let sigma = [0.05 * rms(0), 0.005 * rms(1)];
    let true_values = [truth.params().resistance, truth.params().friction];
    let parameters: Vec<FitParameter> = ["resistance", "friction"]
        .iter()
        .map(|n| FitParameter {
            index: parameter_index::<Motor>(n).unwrap(),
            lower: 0.0,
            upper: f64::INFINITY,
        })
        .collect();

    let study = |noise: NoiseModel| {
        let mut covered = [0usize; 2];
        let mut z2 = [0.0f64; 2];
        for seed in 1..=SEEDS {
            let csv = measured(&truth, tight, &times, &["current", "speed"], &sigma, seed);
            let data = Measurements::parse_csv(&csv).unwrap();
            let options = FitOptions {
                noise,
                ..FitOptions::default()
            };
            let (report, _) = fit(&truth, None, &data, &parameters, &options).unwrap();
            assert!(report.converged && report.weights_settled, "{report:#?}");
            for (j, p) in report.parameters.iter().enumerate() {
                let truth = true_values[j];
                covered[j] += usize::from(p.interval.0 <= truth && truth <= p.interval.1);
                z2[j] += ((p.value - truth) / p.standard_error).powi(2);
            }
        }
        (covered, z2)
    };
    let holds = |(covered, z2): ([usize; 2], [f64; 2])| {
        (0..2).all(|j| {
            let tail = chi_square_upper_tail(z2[j], SEEDS as f64);
            covered[j] >= MIN_COVERED && (0.005..=0.995).contains(&tail)
        })
    };
    let per_column = study(NoiseModel::PerColumn);
    let pooled = study(NoiseModel::Pooled);
    eprintln!(
        "per column: covered {:?}, Σz² {:?}",
        per_column.0, per_column.1
    );
    eprintln!("pooled:     covered {:?}, Σz² {:?}", pooled.0, pooled.1);
    assert!(holds(per_column), "per column: {per_column:?}");
    assert!(!holds(pooled), "pooled: {pooled:?}");
}

/// A model linear in its parameters, `a` and `b`: a flow source of `a + b·t` fills a
/// capacitor, so the measured level is `q = a·t + b·t²/2` and the measured flow
/// `f = a + b·t`. With each column's σ given, the estimate is the weighted linear
/// least-squares solution and its covariance the closed form `(AᵀWA)⁻¹`, `A` the
/// sensitivities `[t, t²/2]` and `[1, t]`, `W = diag(1/σₖ²)`; both to 1e-10. The
/// intervals use the normal quantile (no variance estimated) and `χ²` is the weighted
/// residual sum of squares.
mod linear {
    use super::*;

    bond_graph! {
        /// A flow source ramping from `a` at slope `b` into a unit capacitor.
        pub model Ramp {
            /// the flow at t = 0
            param a = 1.0 in "m³/s";
            /// the flow's slope
            param b = -0.5 in "m³/s²";
            Sf source = a + b * t;
            C tank = 1.0, q in "m³";
            source -> tank;
            /// The stored volume.
            output level = tank.q in "m³";
            /// The inflow.
            output flow = source.f in "m³/s";
        }
    }

    /// The sensitivities of (level, flow) to (a, b) at time `t`.
    fn rows(t: f64) -> [[f64; 2]; 2] {
        [[t, 0.5 * t * t], [1.0, t]]
    }

    #[test]
    fn covariance_with_given_sigma_is_the_weighted_closed_form() {
        let truth = Ramp::default();
        let times: Vec<f64> = (0..=40).map(|k| 0.05 * k as f64).collect();
        let sigma = [0.02, 0.2];
        let csv = measured(
            &truth,
            Solver::dopri5(),
            &times,
            &["level", "flow"],
            &sigma,
            9,
        );
        let mut data = Measurements::parse_csv(&csv).unwrap();
        data.set_sigma("level", sigma[0]).unwrap();
        data.set_sigma("flow", sigma[1]).unwrap();
        let parameters: Vec<FitParameter> = ["a", "b"]
            .iter()
            .map(|n| FitParameter {
                index: parameter_index::<Ramp>(n).unwrap(),
                lower: f64::NEG_INFINITY,
                upper: f64::INFINITY,
            })
            .collect();
        let start = Ramp::from_params(RampParams { a: 3.0, b: 2.0 });
        // Iterated until no step lowers the cost, so the estimate is the minimum to
        // rounding, not to the default tolerance's 1e-8 of the cost.
        let options = FitOptions {
            tolerance: 1e-15,
            ..FitOptions::default()
        };
        let (report, _) = fit(&start, None, &data, &parameters, &options).unwrap();

        // The weighted normal equations by hand.
        let mut ata = nalgebra::Matrix2::<f64>::zeros();
        let mut aty = nalgebra::Vector2::<f64>::zeros();
        for (k, &t) in times.iter().enumerate() {
            for (c, row) in rows(t).iter().enumerate() {
                let a = nalgebra::Vector2::new(row[0], row[1]);
                let w = sigma[c].powi(-2);
                ata += w * a * a.transpose();
                aty += w * a * data.values[c][k];
            }
        }
        let covariance = ata.try_inverse().unwrap();
        let estimate = covariance * aty;
        for i in 0..2 {
            let p = &report.parameters[i];
            assert!(
                (p.value - estimate[i]).abs() <= 1e-10 * estimate[i].abs(),
                "{}: {} vs {}",
                p.name,
                p.value,
                estimate[i]
            );
            assert_eq!(p.t_quantile, 1.959_963_984_540_054);
            assert!(p.degrees_of_freedom.is_infinite());
            for j in 0..2 {
                let scale = (covariance[(i, i)] * covariance[(j, j)]).sqrt();
                assert!(
                    (report.covariance[(i, j)] - covariance[(i, j)]).abs() <= 1e-10 * scale,
                    "covariance ({i}, {j}): {} vs {}",
                    report.covariance[(i, j)],
                    covariance[(i, j)]
                );
            }
        }
        let mut chi_square = 0.0;
        for (k, &t) in times.iter().enumerate() {
            for (c, row) in rows(t).iter().enumerate() {
                let model = row[0] * estimate[0] + row[1] * estimate[1];
                chi_square += ((data.values[c][k] - model) / sigma[c]).powi(2);
            }
        }
        let check = report.chi_square.unwrap();
        assert!((check.chi_square - chi_square).abs() <= 1e-8 * chi_square);
        assert_eq!(check.degrees_of_freedom, (2 * times.len() - 2) as f64);
        assert!(report.columns.iter().all(|c| c.sigma_given));
    }
}
