//! Exact Jacobians of the generated models: for every model in the `models` crate (and
//! a sparse chain generated here), at 24 seeded random states,
//!
//! - the automatically differentiated Jacobian equals a central-difference Jacobian to
//!   1e-6 relative to the largest entry of its row;
//! - the compressed Jacobian (one evaluation per colour) equals the dense one (one per
//!   column) bit for bit inside the pattern, and is +0.0 outside it;
//! - every non-zero of the (dense) AD Jacobian lies inside the sparsity pattern the
//!   macro declares, and every declared entry is non-zero at some state (the pattern is
//!   exact, neither too small nor too large);
//! - the Jacobian-vector product equals `J v`;
//! - the number of colours is the one worked out by hand below.
//!
//! When a model is added to `models`, add it to the list at the bottom.

use bgdsl_runtime::{bond_graph, JacobianEvaluator, Model, SparsityPattern};
use models::{DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

/// SplitMix64: a small seeded generator, so every run tests the same states.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
}

/// The finite-difference step for state `j` at value `x` with typical magnitude
/// `scale`: `ε^(1/3) · max(|x|, scale)`. A central difference errs by `h² |f'''| / 6`
/// (truncation) plus about `ε |f| / h` (round-off); `h ∝ ε^(1/3)` of the state's scale
/// balances the two at `~ε^(2/3) ≈ 4e-11` of the function's scale, four orders of
/// magnitude inside the 1e-6 tolerance. (For the linear models the truncation error is
/// zero and only round-off remains.)
fn step(x: f64, scale: f64) -> f64 {
    f64::EPSILON.cbrt() * x.abs().max(scale)
}

/// The central-difference Jacobian (row-major), dividing by the step actually taken.
fn finite_difference_jacobian<M: Model>(model: &M, t: f64, x: &[f64], scales: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut jac = vec![0.0; n * n];
    let (mut above, mut below) = (vec![0.0; n], vec![0.0; n]);
    let mut xs = x.to_vec();
    for j in 0..n {
        let h = step(x[j], scales[j]);
        xs[j] = x[j] + h;
        let up = xs[j];
        model.derivatives(t, &xs, &mut above);
        xs[j] = x[j] - h;
        let down = xs[j];
        model.derivatives(t, &xs, &mut below);
        xs[j] = x[j];
        for i in 0..n {
            jac[i * n + j] = (above[i] - below[i]) / (up - down);
        }
    }
    jac
}

/// Runs every check of the module documentation on `model`, with states drawn
/// uniformly within `±scales` of the declared initial state and times in `[0, 1)`.
fn check_model<M: Model>(model: &M, scales: &[f64], expected_colours: usize) {
    let n = M::N_STATES;
    assert_eq!(scales.len(), n, "{}: one scale per state", M::NAME);
    assert!(
        M::JACOBIAN_SPARSITY.is_some(),
        "{}: generated models declare a pattern",
        M::NAME
    );
    let mut compressed = JacobianEvaluator::new(model);
    let mut dense = JacobianEvaluator::with_pattern(SparsityPattern::dense(n));
    let pattern = compressed.pattern().clone();

    let mut x0 = vec![0.0; n];
    model.initial_state(&mut x0);
    let (mut jc, mut jd) = (vec![f64::NAN; n * n], vec![f64::NAN; n * n]);
    let mut jv = vec![f64::NAN; n];
    let mut ever_non_zero = vec![false; n * n];
    let mut rng = Rng(0x5EED ^ n as u64);
    for sample in 0..24 {
        let x: Vec<f64> = x0
            .iter()
            .zip(scales)
            .map(|(&c, &s)| c + rng.uniform(-s, s))
            .collect();
        let t = rng.uniform(0.0, 1.0);
        let at = format!("{} at sample {sample} (t = {t}, x = {x:?})", M::NAME);

        let colours = compressed.n_colours();
        assert_eq!(compressed.evaluate(model, t, &x, &mut jc), colours, "{at}");
        assert_eq!(dense.evaluate(model, t, &x, &mut jd), n, "{at}");
        for i in 0..n {
            for j in 0..n {
                if jd[i * n + j] != 0.0 {
                    assert!(
                        pattern.contains(i, j),
                        "{at}: ∂({})'/∂{} = {} but the declared pattern leaves it out",
                        M::STATE_NAMES[i],
                        M::STATE_NAMES[j],
                        jd[i * n + j]
                    );
                    ever_non_zero[i * n + j] = true;
                }
            }
        }

        // Inside the pattern the compressed and dense evaluations do the very same
        // arithmetic on each row: identical bits. Outside it the compressed Jacobian
        // holds +0.0 and the dense one a zero of either sign (checked above).
        for k in 0..n * n {
            let (i, j) = (k / n, k % n);
            if pattern.contains(i, j) {
                assert_eq!(
                    jc[k].to_bits(),
                    jd[k].to_bits(),
                    "{at}: compressed {} vs dense {} at ({i}, {j})",
                    jc[k],
                    jd[k]
                );
            } else {
                assert_eq!(
                    jc[k].to_bits(),
                    0.0f64.to_bits(),
                    "{at}: ({i}, {j}) outside the pattern"
                );
            }
        }

        let fd = finite_difference_jacobian(model, t, &x, scales);
        for i in 0..n {
            let row = &jd[i * n..(i + 1) * n];
            let scale = row
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()))
                .max(f64::MIN_POSITIVE);
            for j in 0..n {
                assert!(
                    (jd[i * n + j] - fd[i * n + j]).abs() <= 1e-6 * scale,
                    "{at}: ∂({})'/∂{}: AD {} vs central difference {} (row scale {scale})",
                    M::STATE_NAMES[i],
                    M::STATE_NAMES[j],
                    jd[i * n + j],
                    fd[i * n + j]
                );
            }
        }

        let v: Vec<f64> = (0..n).map(|_| rng.uniform(-1.0, 1.0)).collect();
        compressed.jvp(model, t, &x, &v, &mut jv);
        for i in 0..n {
            let row = &jd[i * n..(i + 1) * n];
            let product: f64 = row.iter().zip(&v).map(|(a, b)| a * b).sum();
            let size: f64 = row.iter().zip(&v).map(|(a, b)| (a * b).abs()).sum();
            assert!(
                (jv[i] - product).abs() <= 1e-14 * size,
                "{at}: row {i}: jvp {} vs J·v {product}",
                jv[i]
            );
        }
    }
    for i in 0..n {
        for &j in pattern.row(i) {
            assert!(
                ever_non_zero[i * n + j],
                "{}: the pattern declares ∂({})'/∂{} but it was zero at every sample",
                M::NAME,
                M::STATE_NAMES[i],
                M::STATE_NAMES[j]
            );
        }
    } // Last, so that a wrong pattern is reported by the checks above, which say where.
    assert_eq!(
        compressed.n_colours(),
        expected_colours,
        "{}: colours",
        M::NAME
    );
}

bond_graph! {
    /// Five masses in a row joined by four stiff, hardening spring-dampers, the first
    /// mass pushed by a sinusoidal force: a generated model with a sparse Jacobian.
    ///
    /// States in declaration order: `p₀, q₀, p₁, q₁, p₂, q₂, p₃, q₃, p₄` (`qᵢ` the
    /// compression of the spring between masses `i` and `i + 1`). With `eᵢ = k qᵢ +
    /// k₃ qᵢ³ + c (vᵢ − vᵢ₊₁)`: `ṗ₀ = F − e₀`, `ṗᵢ = eᵢ₋₁ − eᵢ`, `ṗ₄ = e₃`,
    /// `q̇ᵢ = vᵢ − vᵢ₊₁`.
    pub model MassChain {
        param m = 0.1;
        param k = 1.0e5;
        param k3 = 1.0e9;
        param c = 20.0;
        param force = 10.0;
        param omega = 50.0;

        Se push = force * (omega * t).sin();
        1 v0;
        I mass0 = m;
        0 f0;
        1 r0;
        C spring0 { e = k * q + k3 * q.powi(3) };
        R damper0 = c;
        1 v1;
        I mass1 = m;
        0 f1;
        1 r1;
        C spring1 { e = k * q + k3 * q.powi(3) };
        R damper1 = c;
        1 v2;
        I mass2 = m;
        0 f2;
        1 r2;
        C spring2 { e = k * q + k3 * q.powi(3) };
        R damper2 = c;
        1 v3;
        I mass3 = m;
        0 f3;
        1 r3;
        C spring3 { e = k * q + k3 * q.powi(3) };
        R damper3 = c;
        1 v4;
        I mass4 = m;

        push -> v0 -> mass0;
        v0 -> f0 -> v1 -> mass1;
        f0 -> r0 -> { spring0, damper0 };
        v1 -> f1 -> v2 -> mass2;
        f1 -> r1 -> { spring1, damper1 };
        v2 -> f2 -> v3 -> mass3;
        f2 -> r2 -> { spring2, damper2 };
        v3 -> f3 -> v4 -> mass4;
        f3 -> r3 -> { spring3, damper3 };

        output x = spring0.q;
    }
}

/// The pattern of the generated chain, derived by hand from the equations in its
/// documentation: the macro must emit exactly this.
#[test]
fn the_macro_emits_the_chain_pattern_derived_by_hand() {
    let expected: [&[usize]; 9] = [
        &[0, 1, 2],       // ṗ₀: F − e₀(q₀, p₀, p₁)
        &[0, 2],          // q̇₀: v₀ − v₁
        &[0, 1, 2, 3, 4], // ṗ₁: e₀ − e₁(q₁, p₁, p₂)
        &[2, 4],
        &[2, 3, 4, 5, 6],
        &[4, 6],
        &[4, 5, 6, 7, 8],
        &[6, 8],
        &[6, 7, 8], // ṗ₄: e₃
    ];
    assert_eq!(
        MassChain::STATE_NAMES,
        [
            "mass0.p",
            "spring0.q",
            "mass1.p",
            "spring1.q",
            "mass2.p",
            "spring2.q",
            "mass3.p",
            "spring3.q",
            "mass4.p"
        ]
    );
    assert_eq!(MassChain::JACOBIAN_SPARSITY, Some(&expected[..]));
}

/// First fit over the columns of the chain pattern above: columns 0–4 all share row 2
/// (colours 0–4); column 5 (rows 4, 6) meets only columns 2–4 earlier, so colour 0;
/// column 6 meets 2–5 (colours 2, 3, 4, 0), so 1; column 7 meets 4–6, so 2; column 8
/// meets 4–7, so 3. Five colours for nine states: at least five are needed, as rows
/// have five entries.
#[test]
fn mass_chain() {
    let scales: Vec<f64> = (0..9)
        .map(|j: usize| if j.is_multiple_of(2) { 1.0e-2 } else { 1.0e-3 })
        .collect();
    check_model(&MassChain::default(), &scales, 5);
    let evaluator = JacobianEvaluator::new(&MassChain::default());
    let colours: Vec<usize> = (0..9).map(|j| evaluator.colouring().colour_of(j)).collect();
    assert_eq!(colours, [0, 1, 2, 3, 4, 0, 1, 2, 3]);
}

// The models of the `models` crate. Each has a row that reads every state (the
// momentum balance of a mass or inertia coupled to everything else, or the flux of an
// inductor in a loop with a capacitor), so no two columns share a colour: as many
// colours as states. Their states are sampled within ±1 (in SI units) of the declared
// initial state; the Jacobians of these models do not care about physical plausibility.

/// `ṗ = F − k q − c p/m` reads `p` and `q`.
#[test]
fn oscillator() {
    check_model(&Oscillator::default(), &[1.0; 2], 2);
}

/// `λ̇ = V − R λ/L − q/C` reads `λ` and `q`.
#[test]
fn series_rlc() {
    check_model(&SeriesRlc::default(), &[1.0; 2], 2);
}

/// The rotor's momentum balance reads the current, the rotor speed, the shaft twist
/// and the load speed.
#[test]
fn dc_motor() {
    check_model(&DcMotor::default(), &[1.0; 4], 4);
}

/// The wheel's momentum balance reads the tyre compression, both velocities and the
/// suspension compression.
#[test]
fn quarter_car() {
    check_model(&QuarterCar::default(), &[1.0; 4], 4);
}

/// `ṗ = F(t) − k q − k₃ q³ − c p/m` reads `p` and `q`; the cubic term makes the
/// Jacobian depend on the state.
#[test]
fn duffing() {
    check_model(&Duffing::default(), &[1.0; 2], 2);
}
