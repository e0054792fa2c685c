//! Tests of your model, as `cargo test` runs them: here the scale against the step
//! response of a damped oscillator (any control textbook, e.g. Ogata, Modern Control
//! Engineering, section 5-3), and its rules.

use bgdsl_cli::catalog::Checks;
use bgdsl_runtime::{simulate, Model, Solver};
use starter::{check, Scale, ScaleParams};

/// The tared reading at `t`: with `m = pan + load`, `w = sqrt(k / m)`,
/// `z = c / (2 sqrt(k m)) < 1` and `wd = w sqrt(1 - z^2)`,
/// `load (1 - exp(-z w t) (cos(wd t) + z / sqrt(1 - z^2) sin(wd t)))`.
fn reading(p: &ScaleParams, t: f64) -> f64 {
    let m = p.pan + p.load;
    let w = (p.stiffness / m).sqrt();
    let z = p.damping / (2.0 * (p.stiffness * m).sqrt());
    let s = (1.0 - z * z).sqrt();
    let wd = w * s;
    p.load * (1.0 - (-z * w * t).exp() * ((wd * t).cos() + z / s * (wd * t).sin()))
}

#[test]
fn the_reading_is_the_step_response_of_a_damped_oscillator() {
    for damping in [20.0, 40.0, 160.0] {
        let p = ScaleParams {
            damping,
            ..ScaleParams::default()
        };
        let run = simulate(&Scale::new(p.clone()), Solver::stiff(), 0.0, 1.0, 1001).unwrap();
        for i in 0..1001 {
            let t = i as f64 * 1e-3;
            let found = run.value(i, "reading").unwrap();
            // The stiff solver's default tolerances: 6e-6 kg seen.
            assert!(
                (found - reading(&p, t)).abs() < 1e-4,
                "damping {damping}, t = {t}: {found} against {}",
                reading(&p, t)
            );
        }
    }
}

#[test]
fn the_empty_pan_reads_zero_and_stays_put() {
    let p = ScaleParams {
        load: 0.0,
        ..ScaleParams::default()
    };
    let run = simulate(&Scale::new(p), Solver::stiff(), 0.0, 1.0, 101).unwrap();
    for i in 0..101 {
        assert!(run.value(i, "reading").unwrap().abs() < 1e-12);
    }
}

#[test]
fn a_negative_damping_or_mass_breaks_the_rules() {
    let bad = ScaleParams {
        damping: -1.0,
        pan: 0.0,
        ..ScaleParams::default()
    };
    let mut checks = Checks::new(Scale::PARAMETERS);
    check(&bad, &mut checks);
    let problems: Vec<String> = checks.problems().iter().map(|p| p.to_string()).collect();
    assert_eq!(problems.len(), 2, "{problems:?}");
    assert!(problems[0].starts_with("parameter `pan`"), "{problems:?}");
    assert!(
        problems[1].starts_with("parameter `damping`"),
        "{problems:?}"
    );
    let mut checks = Checks::new(Scale::PARAMETERS);
    check(&ScaleParams::default(), &mut checks);
    assert!(checks.problems().is_empty());
}

#[test]
fn an_fmus_importer_meets_the_same_rules() {
    // In `Model::parameter_values` order: pan, load, stiffness, damping, g.
    let values = [0.5, 2.0, 5000.0, -40.0, 9.81];
    let refused = bgdsl_cli::fmi::check_values::<Scale>(&values, check).unwrap_err();
    assert!(refused.starts_with("parameter `damping`"), "{refused}");
    let values = [0.5, 2.0, 5000.0, 40.0, 9.81];
    assert_eq!(
        bgdsl_cli::fmi::check_values::<Scale>(&values, check),
        Ok(())
    );
}
