//! Large generated models, whose evaluation the macro splits into chunk functions
//! (`bgdsl-macros/src/chunks.rs`): the chains of `models/benches/sizing/generate.sh`
//! (`large_chain/*.rs`, regenerate with `generate.sh scalar 300`, `LOSSLESS=1
//! generate.sh scalar 300` and `generate.sh rigid 420`). A hand-written chain is the
//! reference for the derivatives, the Jacobian and the energy account; the lossless
//! chain conserves its energy; the rigid-body chain's account balances.

use bgdsl_runtime::{
    simulate, DormandPrinceOptions, Dual, JacobianEvaluator, Model, Scalar, Solver,
};

mod damped {
    include!("large_chain/damped.rs");
}
mod lossless {
    include!("large_chain/lossless.rs");
}
mod bodies {
    include!("large_chain/bodies.rs");
}

/// The generator's weight of cell `i` (1-based): masses m w, springs k / w, dampers c w.
fn weight(i: usize) -> f64 {
    1.0 + (i % 7) as f64 * 0.125
}

/// The chain by hand, for `cells` cells with momenta `p` and spring deflections `q`:
/// cell i's force F_i = K_i q_i + c_i (v_i − v_{i+1}) (no damper and no force when
/// lossless); dp_1 = force sin 3t − c v_1 − F_1, dp_i = F_{i−1} − F_i, dq_i = v_i − v_{i+1}.
struct Hand {
    cells: usize,
    lossless: bool,
    m: f64,
    k: f64,
    c: f64,
    force: f64,
}

impl Hand {
    fn velocities(&self, p: &[f64]) -> Vec<f64> {
        (0..self.cells)
            .map(|i| p[i] / (self.m * weight(i + 1)))
            .collect()
    }

    fn forces(&self, p: &[f64], q: &[f64]) -> Vec<f64> {
        let v = self.velocities(p);
        (0..self.cells)
            .map(|i| {
                let next = v.get(i + 1).copied().unwrap_or(0.0);
                let damper = if self.lossless {
                    0.0
                } else {
                    self.c * weight(i + 1) * (v[i] - next)
                };
                self.k / weight(i + 1) * q[i] + damper
            })
            .collect()
    }

    /// (dp, dq).
    fn derivatives(&self, t: f64, p: &[f64], q: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let v = self.velocities(p);
        let f = self.forces(p, q);
        let dp = (0..self.cells)
            .map(|i| {
                let before = if i > 0 {
                    f[i - 1]
                } else if self.lossless {
                    0.0
                } else {
                    self.force * (3.0 * t).sin() - self.c * v[0]
                };
                before - f[i]
            })
            .collect();
        let dq = (0..self.cells)
            .map(|i| v[i] - v.get(i + 1).copied().unwrap_or(0.0))
            .collect();
        (dp, dq)
    }

    /// (stored, input, dissipated).
    fn power(&self, t: f64, p: &[f64], q: &[f64]) -> (f64, f64, f64) {
        let v = self.velocities(p);
        let stored = (0..self.cells)
            .map(|i| 0.5 * p[i] * v[i] + 0.5 * self.k / weight(i + 1) * q[i] * q[i])
            .sum();
        if self.lossless {
            return (stored, 0.0, 0.0);
        }
        let input = self.force * (3.0 * t).sin() * v[0];
        let dissipated = self.c * v[0] * v[0]
            + (0..self.cells)
                .map(|i| {
                    let rel = v[i] - v.get(i + 1).copied().unwrap_or(0.0);
                    self.c * weight(i + 1) * rel * rel
                })
                .sum::<f64>();
        (stored, input, dissipated)
    }
}

/// Where each cell's momentum and deflection lie in the model's state vector.
fn layout(names: &[&str], cells: usize) -> (Vec<usize>, Vec<usize>) {
    let at = |name: String| names.iter().position(|n| *n == name).expect(&name);
    (
        (1..=cells).map(|i| at(format!("m{i}.p"))).collect(),
        (1..=cells).map(|i| at(format!("k{i}.q"))).collect(),
    )
}

/// A state away from rest, the same every run.
fn state(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 0.01 * ((i * 7919) % 23) as f64 - 0.1)
        .collect()
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-12 * scale
}

/// The chunked derivatives, the Jacobian (automatic differentiation through the
/// chunks, on `DualN`) and the power account of the 300-state damped chain equal the
/// hand-written chain's to 1e-12 of the largest entry (the same operations, summed in
/// possibly another order).
#[test]
fn chunked_chain_equals_the_hand_written_one() {
    let model = damped::Chain::default();
    let n = damped::Chain::N_STATES;
    assert_eq!(n, 300);
    let cells = n / 2;
    let hand = Hand {
        cells,
        lossless: false,
        m: 1.0,
        k: 100.0,
        c: 0.5,
        force: 1.0,
    };
    let (ip, iq) = layout(damped::Chain::STATE_NAMES, cells);
    let x = state(n);
    let p: Vec<f64> = ip.iter().map(|&i| x[i]).collect();
    let q: Vec<f64> = iq.iter().map(|&i| x[i]).collect();
    let t = 0.4;
    let mut dx = vec![0.0; n];
    model.derivatives(t, &x, &mut dx);
    let (dp, dq) = hand.derivatives(t, &p, &q);
    let scale = dx.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for i in 0..cells {
        assert!(
            close(dx[ip[i]], dp[i], scale),
            "dp_{}: {} vs {}",
            i + 1,
            dx[ip[i]],
            dp[i]
        );
        assert!(
            close(dx[iq[i]], dq[i], scale),
            "dq_{}: {} vs {}",
            i + 1,
            dx[iq[i]],
            dq[i]
        );
    }
    // The Jacobian by central differences of the hand-written chain (exact: it is
    // linear in the state), against the model's by automatic differentiation.
    let mut jac = vec![0.0; n * n];
    JacobianEvaluator::new(&model).evaluate(&model, t, &x, &mut jac);
    let flat = |p: &[f64], q: &[f64]| {
        let (dp, dq) = hand.derivatives(t, p, q);
        let mut out = vec![0.0; n];
        for i in 0..cells {
            out[ip[i]] = dp[i];
            out[iq[i]] = dq[i];
        }
        out
    };
    for j in 0..n {
        let (mut plus, mut minus) = (x.clone(), x.clone());
        plus[j] += 0.5;
        minus[j] -= 0.5;
        let split = |x: &[f64]| -> (Vec<f64>, Vec<f64>) {
            (
                ip.iter().map(|&i| x[i]).collect(),
                iq.iter().map(|&i| x[i]).collect(),
            )
        };
        let (pp, qp) = split(&plus);
        let (pm, qm) = split(&minus);
        let (fp, fm) = (flat(&pp, &qp), flat(&pm, &qm));
        for i in 0..n {
            let expected = fp[i] - fm[i];
            let scale = 1.0 + expected.abs();
            assert!(
                (jac[i * n + j] - expected).abs() <= 1e-9 * scale,
                "J[{i}][{j}]: {} vs {expected}",
                jac[i * n + j]
            );
        }
    }
    let balance = model.power_balance(t, &x).expect("an account");
    let (stored, input, dissipated) = hand.power(t, &p, &q);
    assert!(
        close(balance.stored, stored, stored),
        "{} vs {stored}",
        balance.stored
    );
    assert!(
        close(balance.input, input, input.abs() + 1.0),
        "{} vs {input}",
        balance.input
    );
    assert!(
        close(balance.dissipated, dissipated, dissipated),
        "{} vs {dissipated}",
        balance.dissipated
    );
    let mut y = vec![0.0; damped::Chain::N_OUTPUTS];
    model.outputs(t, &x, &mut y);
    assert_eq!(y[0], q[0], "output x1 = k1.q");
}

/// The lossless chain (no damper, no force) keeps its energy: Dormand–Prince at rtol
/// 1e-10 over 2 s, the stored energy of the end state equals the start's to 1e-7
/// relative (the integrator's error, not the model's; the hand-written energy agrees).
#[test]
fn lossless_chain_conserves_energy() {
    let model = lossless::Chain::default();
    let n = lossless::Chain::N_STATES;
    let cells = n / 2;
    let hand = Hand {
        cells,
        lossless: true,
        m: 1.0,
        k: 100.0,
        c: 0.0,
        force: 0.0,
    };
    let (ip, iq) = layout(lossless::Chain::STATE_NAMES, cells);
    let solver = Solver::DormandPrince(DormandPrinceOptions {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    });
    let run = simulate(&model, solver, 0.0, 2.0, 2).expect("the chain runs");
    let energy = |row: usize| {
        let x: Vec<f64> = (0..n).map(|i| run.state(row, i).unwrap()).collect();
        let balance = model.power_balance(0.0, &x).expect("an account");
        let p: Vec<f64> = ip.iter().map(|&i| x[i]).collect();
        let q: Vec<f64> = iq.iter().map(|&i| x[i]).collect();
        let (hand_stored, input, dissipated) = hand.power(0.0, &p, &q);
        assert!(close(balance.stored, hand_stored, hand_stored));
        assert_eq!((balance.input, balance.dissipated), (input, dissipated));
        balance.stored
    };
    let (start, end) = (energy(0), energy(1));
    assert!(start > 1.0, "the chain starts moving: {start}");
    assert!(
        (end - start).abs() <= 1e-7 * start,
        "energy {start} -> {end}"
    );
}

/// The chunked rigid-body chain (20 bodies, 420 states): d(stored)/dt = input −
/// dissipated along the model's own dx/dt, by a dual-number directional derivative
/// through the chunks, to 1e-9 of the powers' size (as `power_balance.rs` checks the
/// catalogue), at a state away from rest.
#[test]
fn rigid_body_chain_balances_power() {
    let model = bodies::Bodies::default();
    let n = bodies::Bodies::N_STATES;
    assert_eq!(n, 420);
    let mut x = vec![0.0; n];
    model.initial_state(&mut x);
    for (i, v) in x.iter_mut().enumerate() {
        *v += 1e-3 * ((i * 7919 % 23) as f64 - 11.0);
    }
    let mut dx = vec![0.0; n];
    model.derivatives(0.3, &x, &mut dx);
    let along: Vec<Dual> = x.iter().zip(&dx).map(|(&v, &d)| Dual::new(v, d)).collect();
    let balance = model.power_balance(0.3, &along).expect("an account");
    let rate = balance.stored.eps;
    let (input, dissipated) = (balance.input.to_f64(), balance.dissipated.to_f64());
    let scale = input.abs() + dissipated.abs() + rate.abs();
    assert!(scale > 1e-3, "the state is away from rest: {scale}");
    assert!(
        (rate - (input - dissipated)).abs() <= 1e-9 * scale,
        "dE/dt {rate} vs input {input} - dissipated {dissipated}"
    );
}

/// A state record of more than 64 fields compares field by field in flat statements
/// (the derived `a == b && ...` chain overflowed rustc's stack at 10,000 states): equal
/// records are equal, and a difference in the last field alone is seen.
#[test]
fn large_state_records_compare_field_by_field() {
    let n = damped::Chain::N_STATES;
    let x = state(n);
    let a = damped::ChainState::from_slice(&x);
    assert_eq!(a, damped::ChainState::from_slice(&x));
    let mut y = x.clone();
    y[n - 1] += 1e-12;
    assert_ne!(a, damped::ChainState::from_slice(&y));
    let mut z = x;
    z[0] = f64::NAN;
    let nan = damped::ChainState::from_slice(&z);
    assert_ne!(
        nan, nan,
        "NaN is unequal to itself, as derived PartialEq has it"
    );
}

include!("large_chain/in_function.rs");

/// A chunked model declared in a function body builds and evaluates as the same model
/// declared in a module, bit for bit: its chunks are trait methods on the runtime's
/// slot types (`bgdsl-macros/src/chunks.rs`), which need nothing from the enclosing
/// module (a module of chunks with `use super::*` would not see the function's items).
#[test]
fn a_chunked_model_in_a_function_body() {
    let n = bodies::Bodies::N_STATES;
    let x = state(n);
    let mut want = vec![0.0; n];
    bodies::Bodies::default().derivatives::<f64>(0.3, &x, &mut want);
    let got = derivatives_in_a_function(0.3, &x);
    assert!(
        want.iter().any(|&d| d != 0.0),
        "a state away from equilibrium"
    );
    assert!(
        got.iter()
            .zip(&want)
            .all(|(p, q)| p.to_bits() == q.to_bits()),
        "the same derivatives"
    );
}
