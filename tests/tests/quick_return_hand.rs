//! Checks of the hand-written quick return mechanism (`models/benches/quick_return_hand/
//! model.rs`), the reference the bond-graph model will be validated against: its
//! initial state, its exact power balance, its rotation kinematics, a short run, and —
//! in the near-rigid limit — agreement with the rigid-body reference
//! `models::quick_return_rigid`. Every tolerance says where it comes from.

mod common;

#[path = "../../models/benches/quick_return_hand/model.rs"]
#[allow(dead_code)]
mod quick_return_hand;

use bgdsl_runtime::{
    DormandPrinceOptions, Dual, Model, Radau5Options, Scalar, Simulation, Solver, Trajectory,
};
use common::{initial_state, Rng};
use models::quick_return_rigid::{quick_return_cycle, rigid_state, RigidParams};
use quick_return_hand::{
    coupling_at, link_at, QuickReturnHand, QuickReturnHandParams, H_AT, K23R, K3C, K5C, KC,
    N_COUPLINGS, N_LINKS, N_OUTPUTS, N_STATES, OUTPUT_NAMES, POS_AT, P_AT, R_AT, STATE_NAMES,
};

type Vec3 = [f64; 3];
type Mat3 = [[f64; 3]; 3];

fn output(name: &str) -> usize {
    OUTPUT_NAMES
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("no output {name}"))
}

fn outputs(model: &QuickReturnHand, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; N_OUTPUTS];
    model.outputs(0.0, x, &mut y);
    y
}

fn derivatives(model: &QuickReturnHand, x: &[f64]) -> Vec<f64> {
    let mut dx = vec![0.0; N_STATES];
    model.derivatives(0.0, x, &mut dx);
    dx
}

fn vec_at(x: &[f64], at: usize) -> Vec3 {
    [x[at], x[at + 1], x[at + 2]]
}

/// Link `i`'s orientation (1-based), from the row-major state.
fn rot_at(x: &[f64], i: usize) -> Mat3 {
    let at = link_at(i) + R_AT;
    [vec_at(x, at), vec_at(x, at + 3), vec_at(x, at + 6)]
}

fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn transpose(a: &Mat3) -> Mat3 {
    let mut t = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            t[i][j] = a[j][i];
        }
    }
    t
}

fn norm(m: &Mat3) -> f64 {
    m.iter().flatten().map(|v| v * v).sum::<f64>().sqrt()
}

/// A point of link `i` (1-based) at body x-coordinate `bx`, in frame 0.
fn point(x: &[f64], i: usize, bx: f64) -> Vec3 {
    let r = vec_at(x, link_at(i) + POS_AT);
    let rot = rot_at(x, i);
    [0, 1, 2].map(|k| r[k] + bx * rot[k][0])
}

fn rotation(axis: Vec3, angle: f64) -> Mat3 {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = axis.map(|a| a / n);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
        [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
        [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
    ]
}

/// A state far from the mechanism's motion, to exercise every term in 3-D: random
/// momenta (speeds up to 2 m/s, rates up to ~10 rad/s about the weakest axis), random
/// orientations (rotations about random axes, optionally made non-orthogonal by up to
/// 5 % per entry), positions near the initial ones, spring deflections of ~0.1 mm
/// (joint forces ~10 N), sliding offsets of ~0.1 m and rotational deflections ~0.05 rad.
fn random_state(rng: &mut Rng, params: &QuickReturnHandParams, orthogonal: bool) -> Vec<f64> {
    let model = QuickReturnHand::new(params.clone());
    let mut x = initial_state(&model);
    let masses = params.masses();
    for i in 1..=N_LINKS {
        let at = link_at(i);
        let j_max = params.inertia(i - 1).into_iter().fold(0.0, f64::max);
        for k in 0..3 {
            x[at + P_AT + k] = masses[i - 1] * rng.symmetric(2.0);
            x[at + H_AT + k] = j_max * rng.symmetric(10.0);
            x[at + POS_AT + k] += rng.symmetric(0.05);
        }
        let axis = [rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)];
        let mut rot = rotation(axis, rng.symmetric(3.0));
        if !orthogonal {
            rot.iter_mut()
                .flatten()
                .for_each(|v| *v += rng.symmetric(0.05));
        }
        for row in 0..3 {
            for col in 0..3 {
                x[at + R_AT + 3 * row + col] = rot[row][col];
            }
        }
    }
    for k in 0..N_COUPLINGS {
        let scale = match k {
            K23R | KC => 0.05,
            _ => 1e-4,
        };
        for axis in 0..3 {
            x[coupling_at(k) + axis] = rng.symmetric(scale);
        }
    }
    x[coupling_at(K3C)] = rng.symmetric(0.1);
    x[coupling_at(K5C)] = rng.symmetric(0.1);
    x
}

/// The default parameters with each choice of K3C's rocker point.
fn both_k3c_choices() -> [QuickReturnHandParams; 2] {
    [
        QuickReturnHandParams::default(),
        QuickReturnHandParams {
            k3c_point_under_slider: 1.0,
            ..Default::default()
        },
    ]
}

mod should {
    use super::*;

    /// (a) The initial state is the spec's geometry (typed in here from the spec:
    /// pin A at (0, 0.2), rocker tip at (0, 0.3), O5 at (√0.07, 0), the rod at
    /// −asin 0.75, the crank, slider and rocker turned +90°) with every pair of coupled
    /// points coinciding (1e-15: rounding of sin/cos of the computed angles); every
    /// joint force is exactly zero (each is `K·0 + R·0`); and the derivative is exactly
    /// gravity on every momentum plus the drive damper's torque `R_C w_drive` on the
    /// crank, with the drive coupling's deflection growing at `w_drive`; nothing else
    /// moves. With g = 0 as well, and for both choices of K3C's rocker point.
    #[test]
    fn start_at_rest_unstretched_with_only_gravity_and_the_drive() {
        for base in both_k3c_choices() {
            for g in [9.81, 0.0] {
                let params = QuickReturnHandParams { g, ..base.clone() };
                let model = QuickReturnHand::new(params.clone());
                let x = initial_state(&model);
                let close = |a: Vec3, b: Vec3, what: &str| {
                    for k in 0..3 {
                        assert!((a[k] - b[k]).abs() <= 1e-15, "{what}: {a:?} vs {b:?}");
                    }
                };
                let x5 = 0.07f64.sqrt();
                close(point(&x, 1, -0.1), [0.0, 0.0, 0.0], "O1");
                close(point(&x, 1, 0.1), [0.0, 0.2, 0.0], "A1");
                close(point(&x, 2, 0.0), [0.0, 0.2, 0.0], "A2");
                close(point(&x, 3, -0.35), [0.0, -0.4, 0.0], "O3");
                close(point(&x, 3, 0.35), [0.0, 0.3, 0.0], "A33");
                close(point(&x, 4, -0.2), [0.0, 0.3, 0.0], "rod top");
                close(point(&x, 4, 0.2), [x5, 0.0, 0.0], "rod bottom");
                close(point(&x, 5, 0.0), [x5, 0.0, 0.0], "O5");
                close(vec_at(&x, link_at(3) + POS_AT), [0.0, -0.05, 0.0], "C3");
                let quarter = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
                for i in 1..=3 {
                    assert!(norm(&sub_m(&rot_at(&x, i), &quarter)) <= 1e-15, "R{i}");
                }
                let psi = -(0.75f64).asin();
                assert!((psi.to_degrees() + 48.59).abs() < 0.005);
                let rod = rotation([0.0, 0.0, 1.0], psi);
                assert!(norm(&sub_m(&rot_at(&x, 4), &rod)) <= 1e-15, "R4");
                assert_eq!(
                    rot_at(&x, 5),
                    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
                );
                for k in 0..N_COUPLINGS {
                    assert_eq!(vec_at(&x, coupling_at(k)), [0.0; 3], "coupling {k}");
                }

                let y = outputs(&model, &x);
                for force in ["F_O1", "F_A2", "F_O3", "F_O5", "F_5C"] {
                    for axis in ["x", "y", "z"] {
                        assert_eq!(y[output(&format!("{force}_{axis}"))], 0.0, "{force}_{axis}");
                    }
                }
                let drive = params.R_C * params.w_drive;
                assert_eq!(
                    [y[output("Tc_x")], y[output("Tc_y")], y[output("Tc_z")]],
                    [0.0, 0.0, drive]
                );
                assert_eq!(y[output("P_in")], drive * params.w_drive);
                assert_eq!(
                    y[output("P_diss")],
                    params.R_C * params.w_drive * params.w_drive
                );
                assert_eq!(y[output("crank_angle")], core::f64::consts::FRAC_PI_2);

                let dx = derivatives(&model, &x);
                let mut expected = vec![0.0; N_STATES];
                for (i, m) in params.masses().into_iter().enumerate() {
                    expected[link_at(i + 1) + P_AT + 1] = -m * g;
                }
                expected[link_at(1) + H_AT + 2] = drive;
                expected[coupling_at(KC) + 2] = params.w_drive;
                for (k, name) in STATE_NAMES.iter().enumerate() {
                    assert_eq!(dx[k], expected[k], "d/dt {name}");
                }
            }
        }
    }

    /// (b) `dE_stored/dt = P_in − P_diss` exactly, at 100 random 3-D states (50 with
    /// orthogonal orientations, 50 without: the identity holds for any R, see the
    /// model's documentation), for both choices of K3C's point. `dE/dt` is the exact
    /// directional derivative of the `E_stored` output along the state derivative
    /// (dual numbers seeded with `dx/dt`), so the residual is rounding: 1e-9 of
    /// `|P_in| + P_diss`. Also the total momentum balance: `Σ dp/dt` equals the ground
    /// forces (F_O1, F_O3, F_5C) plus the weight, to rounding (1e-12 of the forces),
    /// which shows that every internal coupling acts equally and oppositely.
    #[test]
    fn balance_power_exactly_at_random_states() {
        let mut rng = Rng::new(0x5EED_0001);
        let mut worst: f64 = 0.0;
        for n in 0..100 {
            let params = QuickReturnHandParams {
                g: rng.uniform(0.0, 20.0),
                ..both_k3c_choices()[n % 2].clone()
            };
            let model = QuickReturnHand::new(params.clone());
            let x = random_state(&mut rng, &params, n < 50);
            let dx = derivatives(&model, &x);
            let xd: Vec<Dual> = x.iter().zip(&dx).map(|(&v, &d)| Dual::new(v, d)).collect();
            let mut yd = vec![Dual::constant(0.0); N_OUTPUTS];
            model.outputs(0.0, &xd, &mut yd);
            let de_dt = yd[output("E_stored")].eps;
            let p_in = yd[output("P_in")].to_f64();
            let p_diss = yd[output("P_diss")].to_f64();
            let residual = (de_dt - (p_in - p_diss)).abs() / (p_in.abs() + p_diss);
            worst = worst.max(residual);
            assert!(
                residual < 1e-9,
                "state {n}: dE/dt = {de_dt}, P_in − P_diss = {}",
                p_in - p_diss
            );

            let y = outputs(&model, &x);
            let total_mass: f64 = params.masses().iter().sum();
            let mut scale = 0.0;
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                let momentum_rate: f64 = (1..=N_LINKS).map(|i| dx[link_at(i) + P_AT + k]).sum();
                let ground: f64 = ["F_O1", "F_O3", "F_5C"]
                    .iter()
                    .map(|f| y[output(&format!("{f}_{axis}"))])
                    .sum();
                let weight = if k == 1 { -total_mass * params.g } else { 0.0 };
                for i in 1..=N_LINKS {
                    scale += dx[link_at(i) + P_AT + k].abs();
                }
                assert!(
                    (momentum_rate - ground - weight).abs() <= 1e-12 * (1.0 + scale),
                    "state {n}: Σ dp/dt_{axis} = {momentum_rate}, external {}",
                    ground + weight
                );
            }
        }
        eprintln!("largest relative power residual: {worst:e}");
    }

    /// (c) `dR/dt = skew(w) R` keeps `RᵀR` constant: `d/dt(RᵀR) = ṘᵀR + RᵀṘ` vanishes
    /// for every link at 100 random states, with orthogonal and with non-orthogonal
    /// orientations (it vanishes for any R), to rounding: 1e-13 of `|Ṙ||R|`. And the
    /// angular velocity in `Ṙ Rᵀ = skew(w)` (orthogonal R) is the paper's
    /// `w = (R J Rᵀ)⁻¹ h`, solved here independently (Cramer's rule on the world-frame
    /// inertia tensor), to 1e-10 relative (the tensor's condition number is ~200).
    #[test]
    fn keep_rotation_matrices_orthogonal() {
        let mut rng = Rng::new(0x5EED_0002);
        let params = QuickReturnHandParams::default();
        let model = QuickReturnHand::new(params.clone());
        for n in 0..100 {
            let orthogonal = n % 2 == 0;
            let x = random_state(&mut rng, &params, orthogonal);
            let dx = derivatives(&model, &x);
            for i in 1..=N_LINKS {
                let rot = rot_at(&x, i);
                let rate = rot_at(&dx, i);
                let d = add_m(
                    &mat_mul(&transpose(&rate), &rot),
                    &mat_mul(&transpose(&rot), &rate),
                );
                assert!(
                    norm(&d) <= 1e-13 * (1e-300 + norm(&rate) * norm(&rot)),
                    "state {n}, link {i}: d/dt(RᵀR) = {d:?}"
                );
                if orthogonal {
                    let s = mat_mul(&rate, &transpose(&rot));
                    let w = [s[2][1], s[0][2], s[1][0]];
                    let j_body = params.inertia(i - 1);
                    let mut j_world = [[0.0; 3]; 3];
                    for a in 0..3 {
                        for b in 0..3 {
                            j_world[a][b] = (0..3).map(|k| rot[a][k] * j_body[k] * rot[b][k]).sum();
                        }
                    }
                    let h = vec_at(&x, link_at(i) + H_AT);
                    let expected = cramer(&j_world, h);
                    let scale = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    for k in 0..3 {
                        assert!(
                            (w[k] - expected[k]).abs() <= 1e-10 * scale,
                            "state {n}, link {i}: w = {w:?}, (R J Rᵀ)⁻¹ h = {expected:?}"
                        );
                        assert!((s[k][k]).abs() <= 1e-12 * scale, "skew(w) diagonal");
                    }
                    assert!((s[0][1] + s[1][0]).abs() <= 1e-12 * scale, "skew(w)");
                    assert!((s[0][2] + s[2][0]).abs() <= 1e-12 * scale, "skew(w)");
                    assert!((s[1][2] + s[2][1]).abs() <= 1e-12 * scale, "skew(w)");
                }
            }
        }
    }

    /// (d) 0 to 0.2 s of the default model (the sudden start) with Dormand–Prince at
    /// rtol 1e-10: the motion stays in the plane — the z-components of every force and
    /// momentum output, of every link's momentum and the in-plane components of its
    /// angular momentum stay zero to 1e-12 (they are exactly zero: no term feeds them);
    /// and the energy balance `E(t) − E(0) = ∫P_in − ∫P_diss` holds along the run, the
    /// integrals being integrated with the model as two extra states. Both sides carry
    /// only the solver's error: the tolerance is 1e-8 of the energy put in, 100× the
    /// relative tolerance (about 5e-13 is seen).
    #[test]
    fn stay_planar_and_conserve_energy_over_a_short_run() {
        for params in both_k3c_choices() {
            let model = WithWork(QuickReturnHand::new(params));
            let mut x0 = vec![0.0; N_STATES + 2];
            model.initial_state(&mut x0);
            let solver = Solver::DormandPrince(DormandPrinceOptions {
                rtol: 1e-10,
                atol: 1e-13,
                ..Default::default()
            });
            let mut sim = Simulation::new(&model, solver).unwrap();
            let mut traj = Trajectory::for_model::<WithWork>(201);
            let stats = sim.run_uniform(0.0, &x0, 0.2, 201, &mut traj).unwrap();
            eprintln!("dopri5 0-0.2 s: {stats:?}");

            let planar: Vec<String> = [
                "F_O1", "F_A2", "F_O3", "F_O5", "F_5C", "p3", "p5", "r_C3", "r_C5",
            ]
            .iter()
            .map(|s| format!("{s}_z"))
            .chain(
                [
                    "h1_x", "h1_y", "Tc_x", "Tc_y", "R1_13", "R1_23", "R4_31", "R4_32",
                ]
                .map(String::from),
            )
            .chain((1..=N_LINKS).flat_map(|i| {
                [
                    format!("link{i}.p_z"),
                    format!("link{i}.h_x"),
                    format!("link{i}.h_y"),
                    format!("link{i}.r_z"),
                ]
            }))
            .collect();
            for name in &planar {
                let worst = traj
                    .column(name)
                    .unwrap()
                    .iter()
                    .fold(0.0f64, |m, v| m.max(v.abs()));
                assert!(worst <= 1e-12, "{name} leaves the plane: {worst:e}");
            }

            let e = traj.column("E_stored").unwrap();
            let w_in = traj.column("W_in").unwrap();
            let w_diss = traj.column("W_diss").unwrap();
            let scale = w_in.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let mut worst: f64 = 0.0;
            for k in 0..traj.len() {
                let residual = (e[k] - e[0] - (w_in[k] - w_diss[k])).abs();
                worst = worst.max(residual / scale);
                assert!(
                    residual <= 1e-8 * scale,
                    "t = {}: E − E0 = {}, ∫P_in − ∫P_diss = {}",
                    traj.times()[k],
                    e[k] - e[0],
                    w_in[k] - w_diss[k]
                );
            }
            eprintln!("energy put in {scale:.4} J, largest relative energy residual {worst:e}");
        }
    }

    /// (e) The near-rigid limit (`QuickReturnHandParams::stiff_limit`: translational
    /// couplings and the drive coupling 100× stiffer and more damped, slide frictions
    /// and the slider's rotational coupling unchanged) over 0–5 s with Radau5 (rtol
    /// 1e-7, atol 1e-11: the joint deflections are ~1e-5 m), for both choices of K3C's
    /// rocker point, against the rigid-body reference at the simulated crank angle,
    /// speed and acceleration, after the start-up transient (t ≥ 2.5 s): drive torque
    /// and the forces at O1, A2, O3 and O5 within 1 % of each signal's peak (0.35 % is
    /// seen: what remains is the joints' compliance and damping); the output slider
    /// within 1 mm (0.42 mm is seen, in the quick return, where the slider is 0.2 m
    /// from O3 and the rocker multiplies the joint deflections by 0.7/0.2); the
    /// quick-return time ratio 2.00 ± 0.01 (the rigid kinematics gives exactly 2;
    /// 1.9994 is seen) and the period 2π/5 s ± 0.2 % (from the output slider's turning
    /// points, located to ~1e-5 s by interpolating its momentum's zero crossings
    /// between 1 ms samples).
    #[test]
    fn agree_with_the_rigid_reference_in_the_stiff_limit() {
        for k3c_point_under_slider in [0.0, 1.0] {
            check_stiff_limit_against_rigid(QuickReturnHandParams {
                k3c_point_under_slider,
                ..QuickReturnHandParams::stiff_limit()
            });
        }
    }
}

/// The body of test (e), for one choice of K3C's rocker point.
fn check_stiff_limit_against_rigid(params: QuickReturnHandParams) {
    eprintln!("k3c_point_under_slider = {}", params.k3c_point_under_slider);
    let rigid = RigidParams {
        m1: params.m1,
        m2: params.m2,
        m3: params.m3,
        m4: params.m4,
        m5: params.m5,
        l1: params.l1,
        l2: params.l2,
        l3: params.l3,
        l4: params.l4,
        l5: params.l5,
        d: params.d,
        g: params.g,
        R3C: params.R3C[0],
        R5C: params.R5C[0],
    };
    assert!((quick_return_cycle(&rigid).time_ratio - 2.0).abs() < 1e-12);
    let model = QuickReturnHand::new(params);
    let x0 = initial_state(&model);
    let solver = Solver::Radau5(Radau5Options {
        rtol: 1e-7,
        atol: 1e-11,
        ..Default::default()
    });
    let mut sim = Simulation::new(&model, solver).unwrap();
    let n = 5001;
    let mut traj = Trajectory::for_model::<QuickReturnHand>(n);
    let started = std::time::Instant::now();
    let stats = sim.run_uniform(0.0, &x0, 5.0, n, &mut traj).unwrap();
    eprintln!(
        "radau5 stiff limit 0-5 s: {stats:?} in {:?}",
        started.elapsed()
    );

    let col = |name: &str| traj.column(name).unwrap();
    let t = traj.times();
    let first = t.iter().position(|&t| t >= 2.5).unwrap();
    let (angle, speed, accel) = (col("crank_angle"), col("w1_z"), col("dw1_z"));
    let solutions: Vec<_> = (first..n)
        .map(|k| rigid_state(angle[k], speed[k], accel[k], &rigid))
        .collect();
    type Pick = fn(&models::quick_return_rigid::RigidSolution) -> f64;
    let signals: [(&str, Pick); 9] = [
        ("Tc_z", |s| s.tc[2]),
        ("F_O1_x", |s| s.f_o1[0]),
        ("F_O1_y", |s| s.f_o1[1]),
        ("F_A2_x", |s| s.f_a2[0]),
        ("F_A2_y", |s| s.f_a2[1]),
        ("F_O3_x", |s| s.f_o3[0]),
        ("F_O3_y", |s| s.f_o3[1]),
        ("F_O5_x", |s| s.f_o5[0]),
        ("F_O5_y", |s| s.f_o5[1]),
    ];
    for (name, pick) in signals {
        let simulated = &col(name)[first..];
        let reference: Vec<f64> = solutions.iter().map(pick).collect();
        let peak = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let error = simulated
            .iter()
            .zip(&reference)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        eprintln!(
            "{name}: peak {peak:.4}, largest difference {:.3e} of the peak",
            error / peak
        );
        assert!(
            error <= 0.01 * peak,
            "{name}: difference {error} > 1 % of peak {peak}"
        );
    }
    let x5 = &col("r_C5_x")[first..];
    let error = x5
        .iter()
        .zip(&solutions)
        .fold(0.0f64, |m, (a, s)| m.max((a - s.output_x.value).abs()));
    eprintln!("output slider: largest difference {error:.3e} m");
    assert!(error <= 1e-3, "output slider off by {error} m");

    // Turning points of the output slider: zero crossings of its momentum.
    let p5 = &col("p5_x")[first..];
    let times = &t[first..];
    let mut turns = Vec::new(); // (time, true at a right extreme)
    for k in 1..p5.len() {
        if p5[k - 1] != 0.0 && p5[k - 1].signum() != p5[k].signum() {
            let frac = p5[k - 1] / (p5[k - 1] - p5[k]);
            turns.push((
                times[k - 1] + frac * (times[k] - times[k - 1]),
                p5[k - 1] > 0.0,
            ));
        }
    }
    assert!(turns.len() >= 4, "turning points {turns:?}");
    let (mut forward, mut back) = (Vec::new(), Vec::new());
    for pair in turns.windows(2) {
        let duration = pair[1].0 - pair[0].0;
        if pair[0].1 {
            forward.push(duration);
        } else {
            back.push(duration);
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let ratio = mean(&forward) / mean(&back);
    eprintln!("turning points {turns:?}, time ratio {ratio:.5}");
    assert!((ratio - 2.0).abs() <= 0.01, "time ratio {ratio}");
    let period = 2.0 * core::f64::consts::PI / 5.0;
    for same in [true, false] {
        let at: Vec<f64> = turns.iter().filter(|t| t.1 == same).map(|t| t.0).collect();
        for pair in at.windows(2) {
            let measured = pair[1] - pair[0];
            assert!(
                (measured / period - 1.0).abs() <= 2e-3,
                "period {measured} vs {period}"
            );
        }
    }
}

fn sub_m(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = *a;
    c.iter_mut()
        .flatten()
        .zip(b.iter().flatten())
        .for_each(|(x, y)| *x -= y);
    c
}

fn add_m(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = *a;
    c.iter_mut()
        .flatten()
        .zip(b.iter().flatten())
        .for_each(|(x, y)| *x += y);
    c
}

/// `a⁻¹ b` by Cramer's rule.
fn cramer(a: &Mat3, b: Vec3) -> Vec3 {
    let det = |m: &Mat3| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    [0, 1, 2].map(|col| {
        let mut m = *a;
        for row in 0..3 {
            m[row][col] = b[row];
        }
        det(&m) / d
    })
}

/// The hand model with two more states, the drive's work `W_in = ∫P_in` and the
/// dissipated energy `W_diss = ∫P_diss`, so that the solver integrates them with the
/// same accuracy as the motion.
struct WithWork(QuickReturnHand);

const fn with_work_names() -> [&'static str; N_STATES + 2] {
    let mut names = [""; N_STATES + 2];
    let mut i = 0;
    while i < N_STATES {
        names[i] = STATE_NAMES[i];
        i += 1;
    }
    names[N_STATES] = "W_in";
    names[N_STATES + 1] = "W_diss";
    names
}

const WITH_WORK_NAMES: [&str; N_STATES + 2] = with_work_names();

impl Model for WithWork {
    type Params = QuickReturnHandParams;
    const NAME: &'static str = "QuickReturnHandWithWork";
    const STATE_NAMES: &'static [&'static str] = &WITH_WORK_NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = OUTPUT_NAMES;

    fn params(&self) -> &QuickReturnHandParams {
        &self.0.params
    }

    fn initial_state(&self, x0: &mut [f64]) {
        self.0.initial_state(&mut x0[..N_STATES]);
        x0[N_STATES] = 0.0;
        x0[N_STATES + 1] = 0.0;
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        self.0.derivatives(t, &x[..N_STATES], &mut dx[..N_STATES]);
        let mut y = [T::from_f64(0.0); N_OUTPUTS];
        self.0.outputs(t, &x[..N_STATES], &mut y);
        dx[N_STATES] = y[output("P_in")];
        dx[N_STATES + 1] = y[output("P_diss")];
    }

    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        self.0.outputs(t, &x[..N_STATES], y);
    }
}
