//! The sensitivity of the quick return's peak drive torque (`Tc[2]`, its largest
//! magnitude over the second turn, 1.26–2.51 s) to each link mass and joint stiffness,
//! from one sensitivity run (the envelope theorem: the derivative of a smooth maximum
//! is the derivative at the time it is reached), checked against central differences
//! of whole runs for two of them, to 1 % (the peak is read on a 2 ms grid, whose
//! sampling moves the maximum between the runs; measured: 5e-4 for `m1`, 1e-5 for
//! `K_C`). A 117-state, 14-parameter sensitivity run: 12 s in a debug build. The
//! values are printed with `--nocapture` (and quoted in `docs/periodic-and-fitting.md`).

use bgdsl_analysis::sensitivity::{forward_sensitivities, parameter_index, SensitivityOptions};
use bgdsl_runtime::{FromParams, Model, Radau5Options, Simulation, Solver};
use models::quick_return::QuickReturn;

const PARAMETERS: [&str; 14] = [
    "m1", "m2", "m3", "m4", "m5", "K01", "K12", "K03", "K3C[1]", "K23r", "K_C", "K34", "K45",
    "K5C[1]",
];

fn solver() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-9,
        atol: 1e-11,
        ..Default::default()
    })
}

fn times() -> Vec<f64> {
    (0..=1257).map(|k| 2e-3 * k as f64).collect()
}

/// The peak `|Tc_z|` over the second turn, and the sample where it is reached.
fn peak(torque: &[f64]) -> (f64, usize) {
    let start = 629;
    let (k, v) = torque[start..]
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .unwrap();
    (v.abs(), start + k)
}

fn peak_with(index: usize, value: f64) -> f64 {
    let base = QuickReturn::default();
    let mut values = vec![0.0; QuickReturn::N_PARAMETER_VALUES];
    base.parameter_values(&mut values);
    values[index] = value;
    let mut model = QuickReturn::from_params(base.params().clone());
    model.set_parameter_values(&values);
    let mut x0 = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x0);
    let tc = QuickReturn::OUTPUT_NAMES
        .iter()
        .position(|n| *n == "Tc_z")
        .unwrap();
    let mut torque = Vec::new();
    let mut sim = Simulation::new(&model, solver()).unwrap();
    sim.run(0.0, &x0, &times(), &mut |_t: f64, _x: &[f64], y: &[f64]| {
        torque.push(y[tc])
    })
    .unwrap();
    peak(&torque).0
}

#[test]
fn peak_drive_torque_sensitivities() {
    let model = QuickReturn::default();
    let which: Vec<usize> = PARAMETERS
        .iter()
        .map(|p| parameter_index::<QuickReturn>(p).unwrap())
        .collect();
    let options = SensitivityOptions {
        solver: solver(),
        substeps: 2,
    };
    let s = forward_sensitivities(&model, None, &which, &times(), &options).unwrap();
    let tc = QuickReturn::OUTPUT_NAMES
        .iter()
        .position(|n| *n == "Tc_z")
        .unwrap();
    let torque: Vec<f64> = s.outputs.iter().map(|y| y[tc]).collect();
    let (value, at) = peak(&torque);
    let sign = torque[at].signum();
    eprintln!("peak |Tc_z| = {value:.6} N·m at t = {:.3} s", s.times[at]);
    let mut values = vec![0.0; QuickReturn::N_PARAMETER_VALUES];
    model.parameter_values(&mut values);
    let mut derivative = Vec::new();
    for (j, name) in PARAMETERS.iter().enumerate() {
        let d = sign * s.output_sensitivities[at][(tc, j)];
        let p = values[which[j]];
        eprintln!(
            "  d peak / d {name} = {d:.4e} (relative: {:.4e})",
            d * p / value
        );
        derivative.push(d);
    }
    for name in ["m1", "K_C"] {
        let j = PARAMETERS.iter().position(|n| *n == name).unwrap();
        let p = values[which[j]];
        let h = 1e-3 * p;
        let fd = (peak_with(which[j], p + h) - peak_with(which[j], p - h)) / (2.0 * h);
        eprintln!("  {name}: finite differences {fd:.4e}");
        assert!(
            (fd - derivative[j]).abs() <= 0.01 * fd.abs(),
            "{name}: {} vs {fd}",
            derivative[j]
        );
    }
}
