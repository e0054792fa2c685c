//! The standard library's switching elements one by one, each in a small model
//! against its closed form: Coulomb friction with and without stiction on a mass on a
//! spring, a one-sided spring-damper contact, and a switch driven by a clock.

use bgdsl_runtime::{
    bond_graph, event_energy, DormandPrinceOptions, Model, Simulation, Solver, SolverError,
    Trajectory,
};
use std::f64::consts::PI;

bond_graph! {
    /// A mass on a spring, released at rest at `x0`, sliding on a fixed floor with
    /// kinetic Coulomb friction only.
    pub model KineticFriction {
        param m = 1.0; param k = 100.0; param fc = 3.0; param x0 = 1.0;
        Sf ground = 0.0;
        1 floor;
        ground -> floor;
        I mass = m;
        C spring = k;
        1 v;
        v -> { mass, spring };
        // The mass starts moving towards x < 0: slip floor − mass > 0.
        CoulombFriction dry(a = floor, b = v, fc = fc, forward0 = true);
        init spring.q = x0;
        output x = spring.q;
    }
}

bond_graph! {
    /// The same with stiction: stuck, the friction force on the mass is what the
    /// spring needs, `k x`.
    pub model StictionFriction {
        param m = 1.0; param k = 100.0; param fc = 3.0; param x0 = 1.0;
        Sf ground = 0.0;
        1 floor;
        ground -> floor;
        I mass = m;
        C spring = k;
        1 v;
        v -> { mass, spring };
        StickSlip dry(a = floor, b = v, fc = fc, fs = fc, held = k * spring.q);
        init spring.q = x0;
        output x = spring.q;
    }
}

bond_graph! {
    /// A mass moving at `v0` towards a spring-damper stop at x = 0.
    pub model ContactStop {
        param m = 1.0; param k = 1.0e4; param c = 20.0; param v0 = 1.0; param x0 = 0.01;
        I mass = m;
        1 v;
        v -> mass;
        /// position of the mass
        state x: f64 = x0;
        der x = v.f;
        Contact stop(at = v, gap = x, dir = 1.0, k = k, c = c);
        init mass.p = -m * v0;
        output velocity = v.f;
    }
}

bond_graph! {
    /// A source `voltage` charging a capacitor with a load through a switch closed
    /// between `t_on` and `t_off`.
    pub model SwitchedRc {
        param voltage = 5.0; param r_on = 100.0; param r_load = 300.0; param cap = 1.0e-5;
        param t_on = 1.0e-3; param t_off = 4.0e-3;
        Se source = voltage;
        0 supply;
        0 out;
        R load = r_load;
        C capacitor = 1.0 / cap;
        source -> supply;
        Switch s(a = supply, b = out, control = (t - t_on) * (t_off - t), r_on = r_on,
            g_off = 0.0);
        out -> { load, capacitor };
        output v_out = out.e;
    }
}

fn dopri5(rtol: f64) -> Solver {
    Solver::DormandPrince(DormandPrinceOptions {
        rtol,
        atol: rtol * 1e-2,
        ..Default::default()
    })
}

fn initial_state<M: Model>(model: &M) -> Vec<f64> {
    let mut x = vec![0.0; M::STATE_NAMES.len()];
    model.initial_state(&mut x);
    x
}

/// Coulomb's oscillator (Den Hartog, 1930): from rest at `x₀` each half period `π/ω`
/// ends at rest at `x_{n+1} = −(x_n − 2 fc/k · sign x_n)`, while `k |x_n| > fc`. With
/// the defaults (ω = 10 rad/s, fc/k = 0.03, x₀ = 1) the turning points are
/// `±(1 − 0.06 n)` for n ≤ 16 and the 17th, at 0.02, is inside the stiction band.
fn turning_points() -> Vec<(f64, f64)> {
    let (omega, band) = (10.0, 0.03);
    let mut x: f64 = 1.0;
    let mut out = Vec::new();
    for n in 1.. {
        let stop = x.abs() <= band;
        if stop {
            break;
        }
        x = -(x - 2.0 * band * x.signum());
        out.push((n as f64 * PI / omega, x));
    }
    out
}

/// With stiction the mass reverses at each closed-form turning point (events to
/// 1e-9 s, positions to 1e-9 m; DOPRI5 at rtol 1e-12, whose global error over 5 s of
/// this oscillation is of order 1e-11) and sticks at the last one for good: 17
/// events, the last one switching `dry.stuck` on, and the mass still there 1 s later.
#[test]
fn stick_slip_stops_at_the_closed_form_turning_point() {
    let model = StictionFriction::default();
    let turns = turning_points();
    assert_eq!(turns.len(), 17);
    let t_end = turns.last().unwrap().0 + 1.0;
    let mut traj = Trajectory::for_model::<StictionFriction>(2).with_event_capacity(32);
    Simulation::new(&model, dopri5(1e-12))
        .unwrap()
        .run(0.0, &initial_state(&model), &[0.0, t_end], &mut traj)
        .unwrap();
    let q = StictionFriction::STATE_NAMES.iter().position(|n| *n == "spring.q").unwrap();
    let stuck = StictionFriction::STATE_NAMES.iter().position(|n| *n == "dry.stuck").unwrap();
    assert_eq!(traj.events().len(), turns.len());
    for (event, &(t, x)) in traj.events().iter().zip(&turns) {
        assert!((event.t - t).abs() < 1e-9, "{} at {} vs {t}", event.name, event.t);
        assert!((event.after[q] - x).abs() < 1e-9, "at {x}: {}", event.after[q]);
    }
    let last = traj.events().get(turns.len() - 1).unwrap();
    assert_eq!((last.before[stuck], last.after[stuck]), (0.0, 1.0));
    assert!((traj.value(1, "x").unwrap() - turns.last().unwrap().1).abs() < 1e-9);
}

/// Kinetic friction alone reverses at the same turning points, but where the mass
/// should stick it cannot: the force flips with every crossing of zero slip, and the
/// run ends with the chattering error at the 17th turning point (to 1e-6 s), after
/// the 16 reversals it shares with the stiction model.
#[test]
fn kinetic_friction_alone_chatters_where_it_should_stick() {
    let model = KineticFriction::default();
    let turns = turning_points();
    let mut traj = Trajectory::for_model::<KineticFriction>(2).with_event_capacity(256);
    let result = Simulation::new(&model, dopri5(1e-12)).unwrap().run(
        0.0,
        &initial_state(&model),
        &[0.0, 10.0],
        &mut traj,
    );
    let t_stick = turns.last().unwrap().0;
    match result {
        Err(SolverError::Chattering { t, event, .. }) => {
            assert!(event.starts_with("dry."), "{event}");
            assert!((t - t_stick).abs() < 1e-6, "chattering at {t}, not {t_stick}");
        }
        other => panic!("expected the chattering error, got {other:?}"),
    }
    for (event, &(t, _)) in traj.events().iter().zip(&turns[..16]) {
        assert!((event.t - t).abs() < 1e-9, "{} at {} vs {t}", event.name, event.t);
    }
}

/// The Kelvin–Voigt contact: from touch-down at `t_c = x₀ / v₀` the deflection is the
/// damped oscillation `q(τ) = −(v₀/ω_d) e^{−ζωτ} sin ω_d τ`, and the contact lets go
/// where its force `−(k q + c q')` reaches 0 (before q does: the damper pulls first),
/// found here by bisection on the closed form. Release time to 1e-9 s, rebound speed
/// to 1e-8 m/s (DOPRI5 at rtol 1e-12), and the release's event energy is the spring
/// energy `k q² / 2` it drops, to 1e-9 J.
#[test]
fn contact_releases_where_its_force_vanishes() {
    let model = ContactStop::default();
    let p = &model.params;
    let omega = (p.k / p.m).sqrt();
    let zeta = p.c / (2.0 * (p.k * p.m).sqrt());
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let q = |s: f64| -(p.v0 / wd) * (-zeta * omega * s).exp() * (wd * s).sin();
    let dq = |s: f64| {
        -(p.v0 / wd) * (-zeta * omega * s).exp() * (wd * (wd * s).cos() - zeta * omega * (wd * s).sin())
    };
    let force = |s: f64| p.k * q(s) + p.c * dq(s);
    let (mut lo, mut hi) = (1e-9, PI / wd);
    assert!(force(lo) < 0.0 && force(hi) > 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if force(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let (t_touch, t_release) = (p.x0 / p.v0, p.x0 / p.v0 + hi);

    let mut traj = Trajectory::for_model::<ContactStop>(2).with_event_capacity(8);
    Simulation::new(&model, dopri5(1e-12))
        .unwrap()
        .run(0.0, &initial_state(&model), &[0.0, t_release + 0.01], &mut traj)
        .unwrap();
    let events = traj.events();
    assert_eq!(events.len(), 2, "touch and release");
    let (touch, release) = (events.get(0).unwrap(), events.get(1).unwrap());
    assert!(touch.name.ends_with("touch") && release.name.ends_with("release"));
    assert!((touch.t - t_touch).abs() < 1e-9, "touch at {} vs {t_touch}", touch.t);
    assert!((release.t - t_release).abs() < 1e-9, "release at {} vs {t_release}", release.t);
    let rebound = traj.value(1, "velocity").unwrap();
    assert!((rebound - dq(hi)).abs() < 1e-8, "rebound {rebound} vs {}", dq(hi));
    let dropped = event_energy(&model, release.t, release.before, release.after).unwrap();
    let spring = 0.5 * p.k * q(hi) * q(hi);
    assert!((dropped + spring).abs() < 1e-9, "{dropped} J vs −{spring} J");
}

/// The clock-driven switch: open until `t_on` (the capacitor stays empty), closed
/// until `t_off` (charging towards `V R_L / (r_on + R_L)` with `τ = C (r_on ∥ R_L)`),
/// then open (discharging through `R_L`). Both switching instants to 1e-12 s (the
/// control is a function of t alone, so only the location's tolerance counts) and
/// the voltage at 101 samples to 1e-8 V: a switch located up to 1e-12 s late shifts
/// the charging curve, whose slope reaches `v_inf / τ` = 5000 V/s, by up to 5e-9 V.
#[test]
fn switch_follows_its_control() {
    let model = SwitchedRc::default();
    let p = &model.params;
    let v_inf = p.voltage * p.r_load / (p.r_on + p.r_load);
    let tau = p.cap * p.r_on * p.r_load / (p.r_on + p.r_load);
    let v_off = v_inf * (1.0 - (-(p.t_off - p.t_on) / tau).exp());
    let v = |t: f64| {
        if t < p.t_on {
            0.0
        } else if t < p.t_off {
            v_inf * (1.0 - (-(t - p.t_on) / tau).exp())
        } else {
            v_off * (-(t - p.t_off) / (p.cap * p.r_load)).exp()
        }
    };
    let mut traj = Trajectory::for_model::<SwitchedRc>(101).with_event_capacity(8);
    Simulation::new(&model, dopri5(1e-12))
        .unwrap()
        .run_uniform(0.0, &initial_state(&model), 1e-2, 101, &mut traj)
        .unwrap();
    let events = traj.events();
    assert_eq!(events.len(), 2);
    assert!((events.get(0).unwrap().t - p.t_on).abs() < 1e-12);
    assert!((events.get(1).unwrap().t - p.t_off).abs() < 1e-12);
    let out = traj.column("v_out").unwrap();
    for (i, &t) in traj.times().iter().enumerate() {
        assert!((out[i] - v(t)).abs() < 1e-8, "t = {t}: {} vs {}", out[i], v(t));
    }
}
