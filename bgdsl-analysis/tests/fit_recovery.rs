//! Parameter estimation recovers known parameters from simulated measurements with
//! seeded Gaussian noise: the truth lies within the reported 95 % interval, and the
//! residual RMS equals the noise's standard deviation (to 15 %: the sample standard
//! deviation of a few hundred normal draws).

use bgdsl_analysis::fit::{fit, FitOptions, FitParameter, Measurements};
use bgdsl_analysis::sensitivity::parameter_index;
use bgdsl_runtime::{FromParams, Model, Simulation};
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
    times: &[f64],
    columns: &[&str],
    sigma: &[f64],
    seed: u64,
) -> String {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, model.default_solver()).unwrap();
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
    let csv = measured(&truth, &times, &["current", "motor_speed"], &sigma, 16);
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
    for ((name, rms), s) in report.residual_rms.iter().zip(sigma) {
        assert!(
            (rms / s - 1.0).abs() < 0.15,
            "{name}: residual RMS {rms} vs noise {s}"
        );
    }
}
