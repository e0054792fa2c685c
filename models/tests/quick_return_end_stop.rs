//! The quick return with an end stop on its output slider's guide
//! (`QuickReturnEndStop`): impacts recorded as events, with Newton's restitution and
//! their energy loss; beyond the stroke the stop is never reached.

use bgdsl_runtime::{event_energy, Model, Simulation, Trajectory};
use models::catalog::flagship_solver;
use models::quick_return::QuickReturn;
use models::quick_return_hybrid::{QuickReturnEndStop, QuickReturnEndStopParams};

fn state(name: &str) -> usize {
    QuickReturnEndStop::STATE_NAMES
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("no state {name}"))
}

fn run<M: Model>(model: &M) -> Trajectory {
    let times: Vec<f64> = (0..=5000).map(|k| k as f64 / 1000.0).collect();
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut run = Trajectory::for_model::<M>(times.len()).with_event_capacity(1024);
    let mut sim = Simulation::new(model, flagship_solver()).unwrap();
    sim.run(0.0, &x0, &times, &mut run).unwrap();
    run
}

/// With the stop 4 mm inside the stroke (x_stop = 0.69 m): every turn ends its quick
/// return on the stop. Each `stop.hit` happens with the slider at the stop (1e-9 m:
/// events located to 1e-12 s, the slider slower than 1 m/s) and turns its momentum
/// along X0 over with the restitution (or to 0 when it comes to rest), y and z
/// untouched, removing exactly (1 − e²) p²/2m (or p²/2m) of stored energy (to 1e-9
/// relative: `event_energy` against the closed form); no sample lies beyond the stop.
#[test]
fn impacts_on_the_stop_are_events_with_restitution() {
    let model = QuickReturnEndStop::default();
    let p = model.params.clone();
    let run = run(&model);
    let (x, px, py) = (
        state("output_slider.r_x"),
        state("output_slider.translation.p_x"),
        state("output_slider.translation.p_y"),
    );
    let resting = state("stop.resting");
    let mut hits = 0;
    for e in run.events().iter().filter(|e| e.name == "stop.hit") {
        hits += 1;
        assert!(
            (e.before[x] - p.x_stop).abs() < 1e-9,
            "t = {}: hit at x = {}",
            e.t,
            e.before[x]
        );
        assert!(e.before[px] > 0.0, "moving into the stop");
        let rests = e.after[resting] == 1.0;
        let expected = if rests {
            0.0
        } else {
            -p.restitution * e.before[px]
        };
        assert_eq!(e.after[px], expected, "t = {}", e.t);
        assert_eq!(e.after[py], e.before[py]);
        let kept = if rests { 0.0 } else { p.restitution.powi(2) };
        let loss = (1.0 - kept) * e.before[px].powi(2) / (2.0 * p.m5);
        let change = event_energy(&model, e.t, e.before, e.after).unwrap();
        assert!(
            (change + loss).abs() <= 1e-9 * loss,
            "t = {}: {change} vs {}",
            e.t,
            -loss
        );
    }
    assert!(hits >= 4, "{hits} impacts in 4 turns");
    let beyond = run
        .column("r_C5_x")
        .unwrap()
        .iter()
        .fold(f64::NEG_INFINITY, |m, &v| m.max(v))
        - p.x_stop;
    assert!(beyond < 1e-9, "a sample {beyond} m beyond the stop");
}

/// With the stop beyond the stroke (x_stop = 1 m) nothing fires and every column of
/// the spec's results equals the flagship's within 3e-5 of its peak (the mode only
/// changes the solver's error norm; see the friction variant's test).
#[test]
fn a_stop_beyond_the_stroke_is_never_reached() {
    let model = QuickReturnEndStop::new(QuickReturnEndStopParams {
        x_stop: 1.0,
        ..QuickReturnEndStopParams::default()
    });
    let with = run(&model);
    assert!(with.events().is_empty());
    let flagship = run(&QuickReturn::default());
    for name in &models::quick_return::results::COLUMNS[1..] {
        let (a, b) = (flagship.column(name).unwrap(), with.column(name).unwrap());
        let peak = a.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
        let diff = a
            .iter()
            .zip(b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(diff < 3e-5 * peak, "{name}: {diff} of peak {peak}");
    }
}
