//! Forward sensitivities `dy/dp` against central finite differences of whole runs
//! (`(y(p + h) − y(p − h)) / 2h`, `h = 1e-3 |p|`, each run at `rtol` 1e-11 so that the
//! difference quotient is good to about 1e-6 of the sensitivity's scale) on three models
//! of the catalogue: the DC motor (stiff: an electrical time constant of 0.5 ms under a
//! mechanical one of 0.1 s), the quarter car over its bump, and the Duffing oscillator
//! (whose initial state is a parameter: `∂x₀/∂p` enters). Held to 3e-4 of the largest
//! `|dy/dp|` of each output over the run. The finite differences are the limit: where
//! the exact sensitivity has settled to a constant (the DC motor after 0.3 s) they
//! wiggle by about 1e-5 of it from run to run (the solver's step sequences differ),
//! and most of the measured differences (printed; 2e-7 to 1e-4) are theirs. The
//! sensitivities use 10 SDIRK3 steps per sample interval, 50 on the DC motor, whose
//! 0.5 ms electrical transient needs steps below it.

use bgdsl_analysis::sensitivity::{forward_sensitivities, parameter_index, SensitivityOptions};
use bgdsl_runtime::{FromParams, Model, Radau5Options, Simulation, Solver};
use models::{DcMotor, Duffing, QuarterCar};

fn tight() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-11,
        atol: 1e-13,
        // The quarter car's bump (0.5 to 0.7 s) comes after half a second of rest: a
        // solver free to step over it would miss it.
        max_step: 0.01,
        ..Default::default()
    })
}

/// The outputs at `times` of `model` with parameter value `index` set to `value`.
fn outputs_with<M: Model + FromParams + Clone>(
    model: &M,
    index: usize,
    value: f64,
    times: &[f64],
) -> Vec<Vec<f64>> {
    let mut values = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    values[index] = value;
    let mut moved = M::from_params(model.params().clone());
    moved.set_parameter_values(&values);
    let mut x0 = vec![0.0; M::N_STATES];
    moved.initial_state(&mut x0);
    let mut sim = Simulation::new(&moved, tight()).unwrap();
    let mut out = Vec::new();
    sim.run(
        times[0],
        &x0,
        times,
        &mut |_t: f64, _x: &[f64], y: &[f64]| out.push(y.to_vec()),
    )
    .unwrap();
    out
}

fn check<M: Model + FromParams + Clone>(
    model: &M,
    parameters: &[&str],
    outputs: &[&str],
    t_end: f64,
    samples: usize,
    substeps: usize,
) {
    let times: Vec<f64> = (0..samples)
        .map(|k| t_end * k as f64 / (samples - 1) as f64)
        .collect();
    let which: Vec<usize> = parameters
        .iter()
        .map(|p| parameter_index::<M>(p).unwrap())
        .collect();
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-8,
        atol: 1e-10,
        max_step: 0.01,
        ..Default::default()
    });
    let options = SensitivityOptions { substeps, solver };
    let s = forward_sensitivities(model, None, &which, &times, &options).unwrap();
    // Generated models keep parameter tangents: ∂f/∂p is exact (h5's partials).
    assert!(s.exact_parameter_derivatives);
    let mut values = vec![0.0; M::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    for (j, &index) in which.iter().enumerate() {
        let h = 1e-3 * values[index].abs();
        let up = outputs_with(model, index, values[index] + h, &times);
        let down = outputs_with(model, index, values[index] - h, &times);
        for name in outputs {
            let o = M::OUTPUT_NAMES.iter().position(|n| n == name).unwrap();
            let fd: Vec<f64> = up
                .iter()
                .zip(&down)
                .map(|(a, b)| (a[o] - b[o]) / (2.0 * h))
                .collect();
            let scale = fd.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let worst = fd
                .iter()
                .zip(s.output_column(o, j))
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            if std::env::var_os("SHOW").is_some() {
                for (k, (a, b)) in fd.iter().zip(s.output_column(o, j)).enumerate().step_by(10) {
                    eprintln!("  t {} fd {a} s {b}", times[k]);
                }
            }
            eprintln!(
                "{}: d{name}/d{}: {:.2e} of {scale:.3e}",
                M::NAME,
                parameters[j],
                worst / scale
            );
            assert!(
                scale > 0.0 && worst <= 3e-4 * scale,
                "d{name}/d{}: {worst:e} vs {scale:e}",
                parameters[j]
            );
        }
    }
}

#[test]
fn dc_motor_sensitivities_match_finite_differences() {
    check(
        &DcMotor::default(),
        &["resistance", "rotor_friction", "load_inertia"],
        &["current", "load_speed"],
        0.5,
        101,
        50,
    );
}

#[test]
fn quarter_car_sensitivities_match_finite_differences() {
    check(
        &QuarterCar::default(),
        &["suspension_damping", "suspension_stiffness"],
        &["body_height", "tyre_force"],
        1.5,
        151,
        10,
    );
}

#[test]
fn duffing_sensitivities_match_finite_differences() {
    check(
        &Duffing::default(),
        &["k3", "c", "x0"],
        &["x", "velocity"],
        10.0,
        201,
        10,
    );
}

/// Setting parameter values on a model made from other parameters gives the model made
/// from those values (what finite differences and fitting rely on).
#[test]
fn set_parameter_values_equals_from_params() {
    let base = QuarterCar::default();
    let mut params = base.params().clone();
    params.sprung_mass = 330.0;
    let direct = QuarterCar::from_params(params);
    let mut values = vec![0.0; QuarterCar::N_PARAMETER_VALUES];
    direct.parameter_values(&mut values);
    let mut set = QuarterCar::from_params(base.params().clone());
    set.set_parameter_values(&values);
    let (mut a, mut b) = (
        vec![0.0; QuarterCar::N_STATES],
        vec![0.0; QuarterCar::N_STATES],
    );
    direct.initial_state(&mut a);
    set.initial_state(&mut b);
    assert_eq!(a, b);
    let (mut ya, mut yb) = (
        vec![0.0; QuarterCar::N_OUTPUTS],
        vec![0.0; QuarterCar::N_OUTPUTS],
    );
    direct.outputs::<f64>(0.7, &a, &mut ya);
    set.outputs::<f64>(0.7, &a, &mut yb);
    assert_eq!(ya, yb);
}
