//! Parameter estimation recovers known parameters from simulated measurements with
//! seeded Gaussian noise: the truth lies within the reported 95 % interval, and the
//! residual RMS equals the noise's standard deviation (to 15 %: the sample standard
//! deviation of a few hundred normal draws).

use bgdsl_analysis::fit::{fit, FitOptions, FitParameter, Measurements};
use bgdsl_analysis::sensitivity::parameter_index;
use bgdsl_runtime::{FromParams, Model, Radau5Options, Simulation, Solver};
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
    for ((name, rms), s) in report.residual_rms.iter().zip(sigma) {
        assert!(
            (rms / s - 1.0).abs() < 0.15,
            "{name}: residual RMS {rms} vs noise {s}"
        );
    }
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
    let rms = report.residual_rms[0].1;
    assert!((rms / sigma[0] - 1.0).abs() < 0.15, "residual RMS {rms}");
}
