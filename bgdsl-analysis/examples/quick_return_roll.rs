//! The quick return's out-of-plane Floquet multiplier (`docs/quick-return-floquet.md`):
//! the periodic variant's orbit and the multipliers of its out-of-plane motion, for the
//! flagship's joints and parameter changes (`sweep`), for the model with configuration
//! springs in its rotational joints (`variant`), and the energy account of a run
//! perturbed along the growing mode (`energy`).
//!
//! `cargo run --release -p bgdsl-analysis --example quick_return_roll -- sweep 1600`
//! (the second argument: SDIRK steps per period of the monodromy matrix).

use bgdsl_analysis::periodic::{eigenvalues, periodic_orbit, PeriodicOptions, PeriodicOrbit};
use bgdsl_runtime::multibond::{rot_z, skew, Matrix3, Vector3};
use bgdsl_runtime::{FromParams, Model, Radau5Options, Simulation, Solver};
use models::quick_return::configuration_springs::{
    rotation_energy, QuickReturnRotationSprings, QuickReturnRotationSpringsParams,
};
use models::quick_return::{QuickReturn, QuickReturnParams};
use nalgebra::{Complex, DMatrix, DVector};

/// Whether a state changes sign under the reflection z → −z, which maps the planar
/// orbit onto itself: the out-of-plane states (positions and momenta along z, angular
/// momenta and rotational deflections about x and y, the entries of a rotation matrix
/// that couple z to x or y). The monodromy matrix of a planar orbit does not mix them
/// with the others.
fn odd(name: &str) -> bool {
    let angular =
        name.contains("rotation.p") || name.starts_with("j23r.") || name.starts_with("jC.");
    if ["R_13", "R_23", "R_31", "R_32"]
        .iter()
        .any(|r| name.ends_with(r))
    {
        return true;
    }
    if name.contains(".R_") {
        return false;
    }
    if angular {
        name.ends_with("_x") || name.ends_with("_y")
    } else {
        name.ends_with("_z")
    }
}

/// The out-of-plane states of `names`, but for the orbit's free states.
fn odd_states(names: &[&str], orbit: &PeriodicOrbit) -> Vec<usize> {
    (0..names.len())
        .filter(|&i| odd(names[i]) && !orbit.free_states.iter().any(|f| f.index == i))
        .collect()
}

/// The out-of-plane block of Φ in tangent coordinates: `T` embeds the out-of-plane
/// unknowns (the states of `keep` outside rotation matrices, and each body's angles
/// about X0 and Y0, `δR = skew(δθ) R`) into the states, `P` reads them back (`δθ =
/// vee(asym(δR Rᵀ))`, `P T = I`), and the block is `P Φ T`. The directions off the
/// rotation matrices (symmetric `δR Rᵀ`) are left out: they are not motions.
fn tangent_block(
    names: &[&str],
    orbit: &PeriodicOrbit,
    keep: &[usize],
) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = names.len();
    let plain: Vec<usize> = keep
        .iter()
        .copied()
        .filter(|&i| !names[i].contains(".R_"))
        .collect();
    let bodies: Vec<String> = names
        .iter()
        .filter_map(|s| s.strip_suffix(".R_11").map(str::to_string))
        .collect();
    let m = plain.len() + 2 * bodies.len();
    let mut t = DMatrix::zeros(n, m);
    let mut p = DMatrix::zeros(m, n);
    for (k, &i) in plain.iter().enumerate() {
        t[(i, k)] = 1.0;
        p[(k, i)] = 1.0;
    }
    let index = |body: &str, i: usize, j: usize| {
        names
            .iter()
            .position(|s| *s == format!("{body}.R_{}{}", i + 1, j + 1))
            .unwrap()
    };
    for (b, body) in bodies.iter().enumerate() {
        let r = Matrix3::from_fn(|i, j| orbit.x0[index(body, i, j)]);
        for (a, axis) in [Vector3::<f64>::x(), Vector3::<f64>::y()]
            .iter()
            .enumerate()
        {
            let col = plain.len() + 2 * b + a;
            let d: Matrix3<f64> = skew(*axis) * r;
            for i in 0..3 {
                for j in 0..3 {
                    t[(index(body, i, j), col)] = d[(i, j)];
                }
            }
            // δθ_x = (A32 − A23)/2, δθ_y = (A13 − A31)/2 with A = δR Rᵀ: A_ij = Σ_k δR_ik R_jk.
            let (u, v) = if a == 0 {
                ((2, 1), (1, 2))
            } else {
                ((0, 2), (2, 0))
            };
            for k in 0..3 {
                p[(col, index(body, u.0, k))] += 0.5 * r[(u.1, k)];
                p[(col, index(body, v.0, k))] -= 0.5 * r[(v.1, k)];
            }
        }
    }
    (t, p)
}

/// The eigenvalues of Φ's out-of-plane block (`keep`, in tangent coordinates: see
/// [`tangent_block`]) or of its block `keep` as it is (`tangent` false), largest
/// modulus first.
fn block_multipliers_in(
    names: &[&str],
    orbit: &PeriodicOrbit,
    keep: &[usize],
    tangent: bool,
) -> Vec<Complex<f64>> {
    let phi = &orbit.monodromy;
    let block = if tangent {
        let (t, p) = tangent_block(names, orbit, keep);
        &p * phi * &t
    } else {
        DMatrix::from_fn(keep.len(), keep.len(), |i, j| phi[(keep[i], keep[j])])
    };
    let mut mu = eigenvalues(&block).expect("the QR iteration converges");
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    mu
}

fn block_multipliers(orbit: &PeriodicOrbit, keep: &[usize]) -> Vec<Complex<f64>> {
    block_multipliers_in(&[], orbit, keep, false)
}

/// The periodic variant's orbit from the assembled state.
fn orbit_of<M: Model>(model: &M, period: f64, steps: usize) -> PeriodicOrbit {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut options = PeriodicOptions::new(period);
    options.warmup_periods = 2;
    options.steps = steps;
    periodic_orbit(model, &x0, &[], &options).expect("an orbit")
}

/// The orbit, or `None` when Newton's method does not converge.
fn try_orbit<M: Model>(model: &M, period: f64, steps: usize) -> Option<PeriodicOrbit> {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut options = PeriodicOptions::new(period);
    options.warmup_periods = 2;
    options.steps = steps;
    periodic_orbit(model, &x0, &[], &options).ok()
}

/// One line of the study: the largest out-of-plane and in-plane multipliers.
fn report<M: Model>(label: &str, model: &M, period: f64, steps: usize) -> Option<PeriodicOrbit> {
    let Some(orbit) = try_orbit(model, period, steps) else {
        println!("{label:<24} no orbit found");
        return None;
    };
    let out = odd_states(M::STATE_NAMES, &orbit);
    let inside: Vec<usize> = (0..M::N_STATES)
        .filter(|i| !out.contains(i) && !orbit.free_states.iter().any(|f| f.index == *i))
        .filter(|&i| !M::STATE_NAMES[i].contains(".R_"))
        .collect();
    let mu_out = block_multipliers_in(M::STATE_NAMES, &orbit, &out, true);
    let mu_raw = block_multipliers(&orbit, &out);
    let mu_in = block_multipliers(&orbit, &inside);
    let off_one = |m: &&Complex<f64>| (*m - 1.0).norm() > 1e-6;
    let show = |mu: &[Complex<f64>]| {
        mu.iter()
            .take(4)
            .map(|m| {
                if m.im.abs() > 1e-9 {
                    format!("{:.4}({:+.3}i)", m.norm(), m.im)
                } else {
                    format!("{:.4}", m.re)
                }
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    let in_largest = mu_in
        .iter()
        .filter(off_one)
        .map(|m| m.norm())
        .fold(0.0, f64::max);
    println!(
        "{label:<24} out (tangent): {:<40} raw R entries: {:<40} in (off 1): {in_largest:.4}  all (module): {}",
        show(&mu_out),
        show(&mu_raw),
        show(&orbit.multipliers)
    );
    Some(orbit)
}

fn flagship(change: impl FnOnce(&mut QuickReturnParams)) -> QuickReturn {
    let mut p = QuickReturnParams {
        k3c_point_under_slider: 1.0,
        ..Default::default()
    };
    change(&mut p);
    QuickReturn::from_params(p)
}

fn variant(
    change: impl FnOnce(&mut QuickReturnRotationSpringsParams),
) -> QuickReturnRotationSprings {
    let mut p = QuickReturnRotationSpringsParams::default();
    change(&mut p);
    QuickReturnRotationSprings::from_params(p)
}

fn sweep(steps: usize) {
    let t = core::f64::consts::TAU / 5.0;
    println!("flagship (periodic variant), {steps} SDIRK steps per period; out: four largest out-of-plane moduli");
    let cases: Vec<(&str, QuickReturn, f64)> = vec![
        ("as given", flagship(|_| {}), t),
        ("K23r x10", flagship(|p| p.K23r *= 10.0), t),
        ("R23r x10", flagship(|p| p.R23r *= 10.0), t),
        ("K_C x10", flagship(|p| p.K_C *= 10.0), t),
        ("R_C x0.1", flagship(|p| p.R_C *= 0.1), t),
        ("R_C x10", flagship(|p| p.R_C *= 10.0), t),
        (
            "rocker ly,lz x2 (Jx x4)",
            flagship(|p| {
                p.l3[1] *= 2.0;
                p.l3[2] *= 2.0
            }),
            t,
        ),
        ("w_drive 2.5", flagship(|p| p.w_drive = 2.5), 2.0 * t),
    ];
    for (label, model, period) in &cases {
        report(label, model, *period, steps);
    }
}

fn variants(steps: usize) {
    let t = core::f64::consts::TAU / 5.0;
    println!("configuration springs in j23r and jC, {steps} SDIRK steps per period");
    report("as given", &variant(|_| {}), t, steps);
    let cases: Vec<(&str, QuickReturnRotationSprings, f64)> = vec![
        ("K23r x10", variant(|p| p.K23r *= 10.0), t),
        ("K_C x10", variant(|p| p.K_C *= 10.0), t),
        ("R_C x0.1", variant(|p| p.R_C *= 0.1), t),
        ("R_C x10", variant(|p| p.R_C *= 10.0), t),
        (
            "rocker ly,lz x2 (Jx x4)",
            variant(|p| {
                p.l3[1] *= 2.0;
                p.l3[2] *= 2.0
            }),
            t,
        ),
        ("w_drive 4", variant(|p| p.w_drive = 4.0), 1.25 * t),
    ];
    for (label, model, period) in &cases {
        report(label, model, *period, steps);
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let what = args.next().unwrap_or_else(|| "all".into());
    let steps: usize = args
        .next()
        .map_or(1600, |a| a.parse().expect("a number of steps"));
    if what == "sweep" || what == "all" {
        sweep(steps);
    }
    if what == "variant" || what == "all" {
        variants(steps);
    }
    if what == "steps" {
        let t = core::f64::consts::TAU / 5.0;
        for steps in [800, 1600, 3200] {
            report(
                &format!("flagship, {steps} steps"),
                &flagship(|_| {}),
                t,
                steps,
            );
            report(
                &format!("configuration, {steps} steps"),
                &variant(|_| {}),
                t,
                steps,
            );
        }
    }
    if what == "energy" || what == "all" {
        energy(steps);
    }
}

/// The real eigenvector of Φ's out-of-plane block for the real multiplier nearest
/// `mu` (inverse iteration), as a full state vector of unit largest component.
fn eigenvector(orbit: &PeriodicOrbit, keep: &[usize], mu: f64) -> Vec<f64> {
    let phi = &orbit.monodromy;
    let n = keep.len();
    let shifted = DMatrix::from_fn(n, n, |i, j| {
        phi[(keep[i], keep[j])] - if i == j { mu * (1.0 + 1e-9) } else { 0.0 }
    });
    let lu = shifted.lu();
    let mut v = DVector::from_element(n, 1.0);
    for _ in 0..6 {
        v = lu.solve(&v).expect("not exactly an eigenvalue");
        v /= v.amax();
    }
    let mut full = vec![0.0; orbit.x0.len()];
    for (k, &i) in keep.iter().enumerate() {
        full[i] = v[k];
    }
    full
}

/// The heaviest components of the growing out-of-plane mode's eigenvector.
fn print_mode<M: Model>(orbit: &PeriodicOrbit, target: f64) {
    let out = odd_states(M::STATE_NAMES, orbit);
    let mu = block_multipliers(orbit, &out);
    let top = mu
        .iter()
        .filter(|m| m.im.abs() < 1e-12)
        .min_by(|a, b| (a.re - target).abs().total_cmp(&(b.re - target).abs()))
        .unwrap()
        .re;
    let v = eigenvector(orbit, &out, top);
    let mut order: Vec<usize> = (0..v.len()).filter(|&i| v[i] != 0.0).collect();
    order.sort_by(|&a, &b| v[b].abs().total_cmp(&v[a].abs()));
    println!("  mode of {top:.5}, largest components:");
    for &i in order.iter().take(14) {
        println!("    {:<28} {:+.3e}", M::STATE_NAMES[i], v[i]);
    }
}

/// A state's value by name.
fn get(names: &[&str], x: &[f64], name: &str) -> f64 {
    x[names
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("no state {name}"))]
}

fn rotation(names: &[&str], x: &[f64], body: &str) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| get(names, x, &format!("{body}.R_{}{}", i + 1, j + 1)))
}

/// The flagship's rotational couplings' phantom energies `½ K |q|² − K (3 − tr(R_aᵀ
/// R_b))/2` (j23r, jC): what their spring holds beyond the potential of the relative
/// orientation. Its decrease is the work the joint does on the mechanism beyond what a
/// configuration spring would.
fn phantoms(p: &QuickReturnParams, t: f64, x: &[f64]) -> [f64; 2] {
    let names = QuickReturn::STATE_NAMES;
    let q2 = |j: &str| {
        ["x", "y", "z"]
            .iter()
            .map(|c| get(names, x, &format!("{j}.spring.q_{c}")).powi(2))
            .sum::<f64>()
    };
    let drive = rot_z(p.theta0 + p.w_drive * t);
    [
        0.5 * p.K23r * q2("j23r")
            - rotation_energy(
                p.K23r,
                rotation(names, x, "slider"),
                rotation(names, x, "rocker"),
            ),
        0.5 * p.K_C * q2("jC") - rotation_energy(p.K_C, drive, rotation(names, x, "crank")),
    ]
}

/// Samples of a run: times, states, outputs.
type Samples = (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>);

fn sampled<M: Model>(model: &M, t0: f64, x0: &[f64], times: &[f64]) -> Samples {
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-12,
        atol: 1e-14,
        ..Default::default()
    });
    let mut sim = Simulation::new(model, solver).expect("a simulation");
    let (mut ts, mut xs, mut ys) = (Vec::new(), Vec::new(), Vec::new());
    sim.run(t0, x0, times, &mut |t: f64, x: &[f64], y: &[f64]| {
        ts.push(t);
        xs.push(x.to_vec());
        ys.push(y.to_vec());
    })
    .expect("a run");
    (ts, xs, ys)
}

/// The energy account of a run from the orbit perturbed by `eps` along the growing
/// out-of-plane eigenvector, differenced against the orbit, period by period.
fn account<M: Model>(
    label: &str,
    model: &M,
    orbit: &PeriodicOrbit,
    eps: f64,
    periods: usize,
    target: f64,
    phantom: &dyn Fn(f64, &[f64]) -> [f64; 2],
) {
    let names = M::STATE_NAMES;
    let out = odd_states(names, orbit);
    let mu = block_multipliers(orbit, &out);
    let top = mu
        .iter()
        .filter(|m| m.im.abs() < 1e-12)
        .min_by(|a, b| (a.re - target).abs().total_cmp(&(b.re - target).abs()))
        .unwrap()
        .re;
    let v = eigenvector(orbit, &out, top);
    let per = 400;
    let times: Vec<f64> = (0..=per * periods)
        .map(|k| orbit.t0 + orbit.period * k as f64 / per as f64)
        .collect();
    let x1: Vec<f64> = orbit.x0.iter().zip(&v).map(|(a, b)| a + eps * b).collect();
    let (ts, xa, ya) = sampled(model, orbit.t0, &orbit.x0, &times);
    let (_, xb, yb) = sampled(model, orbit.t0, &x1, &times);
    let col = |n: &str| M::OUTPUT_NAMES.iter().position(|o| *o == n).unwrap();
    let (e, pin, pdiss) = (col("E_stored"), col("P_in"), col("P_diss"));
    println!(
        "{label}: multiplier {top:.5}, eps {eps:e}; per period, perturbed run less the orbit (J):"
    );
    println!("  period  growth   dE_stored     W_drive       W_diss        closure    -dPhantom j23r  -dPhantom jC");
    let (mut w_in, mut w_diss) = (0.0, 0.0);
    let mut start = 0;
    let size = |k: usize| {
        out.iter()
            .map(|&i| (xb[k][i] - xa[k][i]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    for k in 1..ts.len() {
        let h = ts[k] - ts[k - 1];
        w_in += 0.5 * h * ((yb[k][pin] - ya[k][pin]) + (yb[k - 1][pin] - ya[k - 1][pin]));
        w_diss += 0.5 * h * ((yb[k][pdiss] - ya[k][pdiss]) + (yb[k - 1][pdiss] - ya[k - 1][pdiss]));
        if k % per == 0 {
            let de = (yb[k][e] - ya[k][e]) - (yb[start][e] - ya[start][e]);
            let (pa0, pb0, pa1, pb1) = (
                phantom(ts[start], &xa[start]),
                phantom(ts[start], &xb[start]),
                phantom(ts[k], &xa[k]),
                phantom(ts[k], &xb[k]),
            );
            let dph = |j: usize| -((pb1[j] - pa1[j]) - (pb0[j] - pa0[j]));
            println!(
                "  {:>6}  {:.4}  {de:+.4e}  {w_in:+.4e}  {w_diss:+.4e}  {:+.2e}  {:+.4e}  {:+.4e}",
                k / per,
                size(k) / size(start),
                de - (w_in - w_diss),
                dph(0),
                dph(1)
            );
            start = k;
            w_in = 0.0;
            w_diss = 0.0;
        }
    }
}

fn energy(steps: usize) {
    let t = core::f64::consts::TAU / 5.0;
    let model = flagship(|_| {});
    let orbit = orbit_of(&model, t, steps);
    let p = model.params().clone();
    print_mode::<QuickReturn>(&orbit, 1.08);
    for eps in [1e-5, 1e-4, 1e-3] {
        account("flagship", &model, &orbit, eps, 3, 1.08, &|t, x| {
            phantoms(&p, t, x)
        });
    }
}
