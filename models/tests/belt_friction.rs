//! The stick-slip oscillator (a mass on a spring riding a moving belt, Coulomb friction
//! with stiction) against an independent event-driven closed-form solution
//! (`belt_friction/reference.rs`).

#[path = "belt_friction/reference.rs"]
mod reference;

use reference::{Belt, Phase};

/// The catalogue's default belt: m = 1 kg, k = 10 N/m, v_b = 0.1 m/s, μs = 0.6,
/// μk = 0.4, g = 9.81 m/s².
fn belt() -> Belt {
    Belt {
        m: 1.0,
        k: 10.0,
        v_b: 0.1,
        fs: 0.6 * 9.81,
        fc: 0.4 * 9.81,
    }
}

/// The reference itself: energy closes phase by phase (the closed forms of the loss and
/// the belt's work against the state's energy), and the limit cycle has the textbook
/// durations: stick 2 (fs − fc) / (k v_b), slip (π + 2 atan(v_b / (ω d))) / ω with
/// d = (fs − fc) / k.
#[test]
fn the_reference_closes_its_energy_and_reaches_the_textbook_limit_cycle() {
    let b = belt();
    let segments = b.solve(-1.0, 0.0, 40.0);
    let phases: Vec<Phase> = segments.iter().take(4).map(|s| s.phase).collect();
    assert_eq!(
        phases,
        [
            Phase::SlipSlower,
            Phase::SlipFaster,
            Phase::Stick,
            Phase::SlipSlower
        ]
    );
    for s in &segments {
        let (x1, v1) = b.state(s.phase, s.x0, s.v0, s.t1 - s.t0);
        let change = b.energy(x1, v1) - b.energy(s.x0, s.v0);
        let account = b.belt_work(s) - b.friction_loss(s);
        assert!(
            (change - account).abs() < 1e-12,
            "{s:?}: ΔE {change} vs {account}"
        );
    }
    let w = (b.k / b.m).sqrt();
    let d = (b.fs - b.fc) / b.k;
    let stick = 2.0 * (b.fs - b.fc) / (b.k * b.v_b);
    let slip = (core::f64::consts::PI + 2.0 * (b.v_b / (w * d)).atan()) / w;
    let full: Vec<_> = segments[2..segments.len() - 1].to_vec();
    assert!(full.len() >= 10, "{} phases", full.len());
    for s in &full[1..] {
        let expected = if s.phase == Phase::Stick { stick } else { slip };
        assert!(
            (s.t1 - s.t0 - expected).abs() < 1e-12,
            "{s:?}: {} vs {expected}",
            s.t1 - s.t0
        );
    }
}

use bgdsl_runtime::{
    event_energy, DormandPrinceOptions, EventRecord, Model, Recorder, Simulation, Solver,
    Trajectory,
};
use models::hybrid::{BeltFriction, BeltFrictionParams};

/// The model with the reference's data.
fn model() -> BeltFriction {
    let b = belt();
    BeltFriction::new(BeltFrictionParams {
        m: b.m,
        k: b.k,
        v_belt: b.v_b,
        mu_s: 0.6,
        mu_k: 0.4,
        g: 9.81,
        x0: -1.0,
    })
}

/// DOPRI5 at rtol 1e-10: the slips are harmonic, nothing is stiff.
fn solver() -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    })
}

const T_END: f64 = 20.0;

fn state_index(name: &str) -> usize {
    BeltFriction::STATE_NAMES
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("no state {name}"))
}

/// The contact's phase in a state of the model, from its modes.
fn phase_of(x: &[f64]) -> Phase {
    let stuck = x[state_index("friction.stuck")] != 0.0;
    // `forward`: slip = belt − mass > 0, the mass slower than the belt.
    let forward = x[state_index("friction.forward")] != 0.0;
    match (stuck, forward) {
        (true, _) => Phase::Stick,
        (false, true) => Phase::SlipSlower,
        (false, false) => Phase::SlipFaster,
    }
}

/// The model's phases: (phase, start time), a new one at every event that changes it.
fn model_phases(run: &Trajectory) -> Vec<(Phase, f64)> {
    let x0: Vec<f64> = (0..BeltFriction::N_STATES)
        .map(|i| run.state(0, i).unwrap())
        .collect();
    let mut phases = vec![(phase_of(&x0), 0.0)];
    for e in run.events().iter() {
        let after = phase_of(e.after);
        if after != phases.last().unwrap().0 {
            phases.push((after, e.t));
        }
    }
    phases
}

/// Stick and slip intervals over 20 s (two start-up slips, then four stick-slip
/// cycles: 10 phases) against the closed-form reference: the same phases in the same order, every
/// switch within 1e-8 s of the reference's (DOPRI5 at rtol 1e-10 with events located
/// to 1e-12 s; the breakaway's time error is the position error times k / (k v_b),
/// ~1e-9 s; measured 3.8e-10 s, and 7.4e-10 in position and velocity at the samples).
#[test]
fn stick_and_slip_intervals_match_the_event_driven_reference() {
    let b = belt();
    let reference = b.solve(-1.0, 0.0, T_END);
    let model = model();
    let times: Vec<f64> = (0..=2000).map(|k| k as f64 * T_END / 2000.0).collect();
    let mut run = Trajectory::for_model::<BeltFriction>(times.len()).with_event_capacity(256);
    let mut x0 = vec![0.0; BeltFriction::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(&model, solver()).unwrap();
    sim.run(0.0, &x0, &times, &mut run).unwrap();

    let phases = model_phases(&run);
    let expected: Vec<(Phase, f64)> = reference.iter().map(|s| (s.phase, s.t0)).collect();
    assert_eq!(
        phases.iter().map(|p| p.0).collect::<Vec<_>>(),
        expected.iter().map(|p| p.0).collect::<Vec<_>>(),
        "phases {phases:?}"
    );
    assert!(phases.len() >= 10, "{} phases", phases.len());
    // Every event changes the phase: the slip's crossing just after a breakaway, in
    // the direction it breaks away to, is not watched.
    assert_eq!(
        run.events().len(),
        phases.len() - 1,
        "events that change nothing"
    );
    let worst = phases
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a.1 - b.1).abs())
        .fold(0.0, f64::max);
    eprintln!("worst switch time error {worst:e} s");
    assert!(worst < 1e-8, "switch times off by {worst:e} s");
    // And the states in between: every sample against the closed form.
    let (xs, vs) = (run.column("x").unwrap(), run.column("velocity").unwrap());
    let mut worst_state = 0.0f64;
    for (k, &t) in run.times().iter().enumerate() {
        let (x, v) = b.at(&reference, t);
        worst_state = worst_state.max((xs[k] - x).abs()).max((vs[k] - v).abs());
        assert!(
            (xs[k] - x).abs() < 1e-8 && (vs[k] - v).abs() < 1e-8,
            "t = {t}: ({}, {}) vs ({x}, {v})",
            xs[k],
            vs[k]
        );
    }
    eprintln!("worst state error {worst_state:e}");
}

/// Accumulates the model's energy account along a run: the trapezoid rule on the
/// samples for the supplied and dissipated powers, each interval cut at the events
/// (before an event the state before it, after it the state after), and the events'
/// energy changes.
struct Account<'m> {
    model: &'m BeltFriction,
    last: Option<(f64, f64, f64)>,
    supplied: f64,
    dissipated: f64,
    events: f64,
}

impl Account<'_> {
    fn advance(&mut self, t: f64, x: &[f64]) {
        let pb = self.model.power_balance::<f64>(t, x).unwrap();
        if let Some((t0, input, dissipated)) = self.last {
            self.supplied += 0.5 * (t - t0) * (input + pb.input);
            self.dissipated += 0.5 * (t - t0) * (dissipated + pb.dissipated);
        }
        self.last = Some((t, pb.input, pb.dissipated));
    }
}

impl Recorder for Account<'_> {
    fn record(&mut self, t: f64, x: &[f64], _y: &[f64]) {
        self.advance(t, x);
    }

    fn event(&mut self, e: &EventRecord<'_>) {
        self.advance(e.t, e.before);
        self.events += event_energy(self.model, e.t, e.before, e.after).unwrap();
        self.last = None;
        self.advance(e.t, e.after);
    }
}

/// The energy balance over 20 s: stored(T) − stored(0) = ∫ supplied − ∫ dissipated +
/// Σ event energy to 1e-6 J (the supplied power is constant or linear between events,
/// which the trapezoid rule integrates exactly; the dissipated one is a sine arc, its
/// trapezoid error at 1e-4 s samples below 3e-7 J), and the friction loss and the
/// belt's work each equal the reference's closed forms (fc times the distance slid
/// over the belt, summed over the slips; the friction force times the belt's travel)
/// to 1e-6 J. The mode switches change no stored energy.
#[test]
fn the_energy_balance_closes_with_the_friction_loss() {
    let b = belt();
    let reference = b.solve(-1.0, 0.0, T_END);
    let loss: f64 = reference.iter().map(|s| b.friction_loss(s)).sum();
    let work: f64 = reference.iter().map(|s| b.belt_work(s)).sum();
    let model = model();
    let times: Vec<f64> = (0..=200_000)
        .map(|k| k as f64 * T_END / 200_000.0)
        .collect();
    let mut x0 = vec![0.0; BeltFriction::N_STATES];
    model.initial_state(&mut x0);
    let mut account = Account {
        model: &model,
        last: None,
        supplied: 0.0,
        dissipated: 0.0,
        events: 0.0,
    };
    let mut sim = Simulation::new(&model, solver()).unwrap();
    sim.run(0.0, &x0, &times, &mut account).unwrap();
    let x_end = sim.state().to_vec();
    let stored = |x: &[f64]| model.power_balance::<f64>(0.0, x).unwrap().stored;
    let change = stored(&x_end) - stored(&x0);
    let residual = change - (account.supplied - account.dissipated + account.events);
    eprintln!(
        "residual {residual:e} J, loss {:e}, work {:e}",
        account.dissipated - loss,
        account.supplied - work
    );
    assert!(residual.abs() < 1e-6, "balance residual {residual:e} J");
    assert_eq!(account.events, 0.0, "mode switches store nothing");
    assert!(
        (account.dissipated - loss).abs() < 1e-6,
        "friction loss {} vs reference {loss}",
        account.dissipated
    );
    assert!(
        (account.supplied - work).abs() < 1e-6,
        "belt work {} vs reference {work}",
        account.supplied
    );
}
