//! The per-evaluation solve of implicit unknowns (`bgdsl_runtime::implicit`): exact in
//! one step for a linear system, quadratic convergence on a non-linear one, the
//! implicit-function derivatives of `refine`, and every failure.

use std::cell::{Cell, RefCell};

use bgdsl_runtime::implicit::{
    solve, Failure, FailureKind, ImplicitMemory, MAX_ITERATIONS, TOLERANCE,
};
use bgdsl_runtime::{Dual, DualN, ModelError, Scalar};

/// `A z = b` with a 3×3 `A` that needs pivoting (a zero in the top-left corner).
const A: [[f64; 3]; 3] = [[0.0, 2.0, 1.0], [3.0, -1.0, 0.5], [1.0, 1.0, 4.0]];
const B: [f64; 3] = [1.0, -2.0, 3.5];

fn linear_residual<T: Scalar>(z: &[T; 3], r: &mut [T; 3]) {
    for i in 0..3 {
        let mut sum = T::from_f64(-B[i]);
        for j in 0..3 {
            sum += T::from_f64(A[i][j]) * z[j];
        }
        r[i] = sum;
    }
}

#[test]
fn a_linear_system_is_solved_exactly_in_one_evaluation() {
    let calls = Cell::new(0);
    let solution = solve([10.0, -3.0, 7.0], true, |z, r| {
        calls.set(calls.get() + 1);
        linear_residual(z, r);
    })
    .unwrap();
    assert_eq!(calls.get(), 1, "one evaluation, no verification");
    let mut r = [0.0; 3];
    linear_residual(&solution.z, &mut r);
    for (j, rj) in r.iter().enumerate() {
        assert!(rj.abs() < 1e-14, "residual {j}: {rj:e}");
    }
    // The same system solved as non-linear converges to the same z (to round-off),
    // verifying once: the step, then the check.
    let iterated = solve([10.0, -3.0, 7.0], false, linear_residual).unwrap();
    for j in 0..3 {
        assert!((iterated.z[j] - solution.z[j]).abs() < 1e-14);
    }
}

/// A diode `i = Is (exp(v / Vt) − 1)` fed from a source `V` through a resistor `R`:
/// the diode voltage `v` solves `(V − v) / R − Is (exp(v / Vt) − 1) = 0`.
struct Diode {
    source: f64,
    resistance: f64,
    saturation: f64,
    thermal: f64,
}

const DIODE: Diode = Diode {
    source: 5.0,
    resistance: 1e3,
    saturation: 1e-12,
    thermal: 0.025852,
};

impl Diode {
    fn residual<T: Scalar>(&self, source: T, v: T) -> T {
        let current = (source - v) / T::from_f64(self.resistance);
        let diode =
            T::from_f64(self.saturation) * ((v / T::from_f64(self.thermal)).exp() - T::one());
        current - diode
    }

    /// The root by bisection on `[0, V]` (the residual falls monotonically), to the
    /// last bit: the reference the Lambert-W closed form would give.
    fn reference(&self) -> f64 {
        let (mut low, mut high) = (0.0, self.source);
        while high - low > 0.0 {
            let mid = 0.5 * (low + high);
            if mid <= low || mid >= high {
                break;
            }
            if self.residual(self.source, mid) > 0.0 {
                low = mid;
            } else {
                high = mid;
            }
        }
        0.5 * (low + high)
    }
}

#[test]
fn a_diode_with_a_series_resistor_converges_quadratically() {
    let reference = DIODE.reference();
    assert!((0.5..0.8).contains(&reference), "{reference}");
    // From a cold start (v = 0, where the exponential overshoots wildly): it must get
    // there within the iteration limit.
    let cold = solve([0.0], false, |z, r| {
        r[0] = DIODE.residual(DualN::constant(DIODE.source), z[0])
    })
    .unwrap();
    assert!(
        (cold.z[0] - reference).abs() <= 1e-12 * reference,
        "{} against {reference}",
        cold.z[0]
    );
    // From the previous solution of a nearby state (the source 2 % lower), the errors
    // of the iterates square at each step.
    let iterates = RefCell::new(Vec::new());
    let nearby = Diode {
        source: 4.9,
        ..DIODE
    }
    .reference();
    let warm = solve([nearby], false, |z, r| {
        iterates.borrow_mut().push(z[0].value());
        r[0] = DIODE.residual(DualN::constant(DIODE.source), z[0]);
    })
    .unwrap();
    // Converged means a scaled residual of at most 1e-10 A: with ∂r/∂v ≈ i/Vt ≈ 0.17
    // S that is an error of at most ~1e-9 V. The refinement step (what the generated
    // code evaluates with) squares it: exact to round-off.
    assert!((warm.z[0] - reference).abs() <= 2e-9, "{}", warm.z[0]);
    let refined = warm.refine(&[DIODE.residual(DIODE.source, warm.z[0])])[0];
    assert!(
        (refined - reference).abs() <= 4.0 * f64::EPSILON * reference,
        "{refined}"
    );
    let errors: Vec<f64> = iterates
        .borrow()
        .iter()
        .map(|v| (v - reference).abs())
        .collect();
    assert!(
        errors.len() <= 5,
        "{} evaluations: {errors:?}",
        errors.len()
    );
    // e_{k+1} ≤ C e_k² with C = |r''/(2 r')| at the root, about 1/(2 Vt) (≈ 19/V);
    // checked while the error is above round-off.
    let c = 1.0 / (2.0 * DIODE.thermal);
    for pair in errors.windows(2) {
        if pair[1] > 1e-15 {
            assert!(
                pair[1] <= 2.0 * c * pair[0] * pair[0],
                "not quadratic: {errors:?}"
            );
        }
    }
    // The check is not vacuous: at least two steps above round-off.
    assert!(errors[1] > 1e-15 && errors[0] > 1e-6, "{errors:?}");
}

/// `refine` with a residual on `Dual` (the source voltage seeded) gives `dv/dV` of the
/// implicit function: `−(∂r/∂v)⁻¹ ∂r/∂V = (1/R) / (1/R + Is/Vt exp(v/Vt))`.
#[test]
fn refine_gives_the_implicit_function_derivative() {
    let solution = solve([0.6], false, |z, r| {
        r[0] = DIODE.residual(DualN::constant(DIODE.source), z[0])
    })
    .unwrap();
    let v = solution.z[0];
    let r_dual = [DIODE.residual(Dual::variable(DIODE.source), Dual::constant(v))];
    let refined = solution.refine(&r_dual);
    let g = 1.0 / DIODE.resistance;
    let exact = g / (g + DIODE.saturation / DIODE.thermal * (v / DIODE.thermal).exp());
    assert!(
        (refined[0].eps - exact).abs() <= 1e-12 * exact,
        "{} against {exact}",
        refined[0].eps
    );
    // Its value is a (harmless) Newton step from the solution: the root to round-off,
    // on Dual as on f64.
    let reference = DIODE.reference();
    assert!((refined[0].re - reference).abs() <= 4.0 * f64::EPSILON * reference);
    let r64 = [DIODE.residual(DIODE.source, v)];
    assert_eq!(solution.refine(&r64)[0], refined[0].re);
}

/// Two unknowns, a rotation-like coupling, refined on `DualN<2>`: both parameters'
/// derivatives at once, against `−J⁻¹ ∂r/∂θ` computed by hand.
#[test]
fn refine_with_two_unknowns_and_two_parameters() {
    // r(z; a, b) = [z0 + 0.5 sin z1 − a, z1 − 0.3 z0² − b].
    fn residual<T: Scalar>(z: &[T; 2], a: T, b: T) -> [T; 2] {
        [
            z[0] + T::from_f64(0.5) * z[1].sin() - a,
            z[1] - T::from_f64(0.3) * z[0] * z[0] - b,
        ]
    }
    let (a, b) = (0.8, -0.2);
    let solution = solve([0.0, 0.0], false, |z, r| {
        *r = residual(z, DualN::constant(a), DualN::constant(b))
    })
    .unwrap();
    let z = solution.z;
    let constant = z.map(DualN::<2>::constant);
    let refined = solution.refine(&residual(
        &constant,
        DualN::new(a, [1.0, 0.0]),
        DualN::new(b, [0.0, 1.0]),
    ));
    // J = [[1, 0.5 cos z1], [−0.6 z0, 1]], ∂r/∂(a, b) = −I, so dz/d(a, b) = J⁻¹.
    let j = [[1.0, 0.5 * z[1].cos()], [-0.6 * z[0], 1.0]];
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let inverse = [
        [j[1][1] / det, -j[0][1] / det],
        [-j[1][0] / det, j[0][0] / det],
    ];
    for (row, (z_row, want_row)) in refined.iter().zip(&inverse).enumerate() {
        for (col, (got, want)) in z_row.tangents().iter().zip(want_row).enumerate() {
            assert!(
                (got - want).abs() <= 1e-14,
                "dz{row}/dθ{col}: {got} against {want}"
            );
        }
    }
}

#[test]
fn a_singular_jacobian_names_the_unknown_whose_pivot_failed() {
    // The second equation is twice the first: a redundant constraint.
    let failure = solve([0.0, 0.0], true, |z, r| {
        r[0] = z[0] + z[1] - DualN::constant(1.0);
        r[1] = DualN::constant(2.0) * z[0] + DualN::constant(2.0) * z[1] - DualN::constant(2.0);
    })
    .unwrap_err();
    assert_eq!(failure.kind, FailureKind::Singular);
    assert_eq!(failure.unknown, 1);
    assert!(failure.t.is_nan(), "the caller fills the time in");
    // Nearly singular (a pivot of 1e-15 next to entries of 1) is singular too.
    let failure = solve([0.0, 0.0], false, |z, r| {
        r[0] = z[0] + z[1];
        r[1] = z[0] + z[1] * DualN::constant(1.0 + 1e-15);
    })
    .unwrap_err();
    assert_eq!(failure.kind, FailureKind::Singular);
    // A Jacobian column that is all zero (an unknown nothing reads).
    let failure = solve([0.0, 0.0], true, |z, r| {
        r[0] = z[0];
        r[1] = z[0] * DualN::constant(3.0) - DualN::constant(1.0);
    })
    .unwrap_err();
    assert_eq!((failure.kind, failure.unknown), (FailureKind::Singular, 1));
}

#[test]
fn a_non_finite_residual_is_reported() {
    let failure = solve([1.0, 2.0], false, |z, r| {
        r[0] = z[0] - DualN::constant(1.0);
        r[1] = (z[1] - DualN::constant(5.0)).ln();
    })
    .unwrap_err();
    assert_eq!((failure.kind, failure.unknown), (FailureKind::NonFinite, 1));
    assert!(failure.residual.is_nan());
    // Also in the one-step (linear) mode.
    let failure = solve([0.0], true, |z, r| {
        r[0] = z[0] * DualN::constant(f64::INFINITY)
    })
    .unwrap_err();
    assert_eq!(failure.kind, FailureKind::NonFinite);
}

#[test]
fn no_convergence_names_the_worst_unknown_and_its_residual() {
    // z1² + 1 has no real root; z0 is easy.
    let calls = Cell::new(0);
    let failure = solve([0.0, 0.5], false, |z, r| {
        calls.set(calls.get() + 1);
        r[0] = z[0] - DualN::constant(2.0);
        r[1] = z[1] * z[1] + DualN::constant(1.0);
    })
    .unwrap_err();
    assert_eq!(
        (failure.kind, failure.unknown),
        (FailureKind::NotConverged, 1)
    );
    assert!(failure.residual >= 1.0, "{}", failure.residual);
    // Bounded work: every iteration evaluates at most once per halving, plus one.
    assert!(calls.get() <= 1 + MAX_ITERATIONS * 11, "{}", calls.get());
}

#[test]
fn a_bad_guess_is_rescued_by_backtracking() {
    // atan: plain Newton diverges from |z| > 1.39; halving the step keeps it.
    let solution = solve([3.0], false, |z, r| r[0] = z[0].atan()).unwrap();
    assert!(solution.z[0].abs() <= TOLERANCE);
}

#[test]
fn zero_unknowns_is_a_no_op() {
    let solution = solve::<0>([], false, |_, _| panic!("nothing to evaluate")).unwrap();
    assert_eq!(solution.z, []);
    let refined: [Dual; 0] = solution.refine(&[]);
    assert!(refined.is_empty());
    assert!(solve::<0>([], true, |_, _| panic!("nothing to evaluate")).is_ok());
}

/// A memory in a `static`: `const fn new`, `Sync`.
static MEMORY: ImplicitMemory<2> = ImplicitMemory::new();

#[test]
fn the_memory_keeps_the_guess_and_the_last_failure() {
    fn sync<T: Sync + Send>(_: &T) {}
    sync(&MEMORY);
    assert_eq!(MEMORY.guess(), [0.0, 0.0]);
    let memory = ImplicitMemory::<2>::default();
    memory.remember(&[1.5, -2.25]);
    assert_eq!(memory.guess(), [1.5, -2.25]);
    assert_eq!(memory.failure(), None);
    let failure = Failure {
        kind: FailureKind::NotConverged,
        unknown: 1,
        t: 0.125,
        residual: 3.2e-3,
    };
    memory.record(failure);
    assert_eq!(memory.failure(), Some(failure));
    let copy = memory.clone();
    assert_eq!(
        (copy.guess(), copy.failure()),
        (memory.guess(), Some(failure))
    );
    let shown = format!("{memory:?}");
    assert!(
        shown.contains("1.5") && shown.contains("NotConverged"),
        "{shown}"
    );
    memory.clear_failure();
    assert_eq!(memory.failure(), None);
    assert_eq!(copy.failure(), Some(failure), "the clone is its own");
    // A solve that succeeds (remembered) forgets the failure of an earlier one.
    copy.remember(&[0.5, 0.5]);
    assert_eq!(copy.failure(), None);
    // Equal whatever they hold: a memory is no part of a model's value.
    assert!(copy == memory);
}

#[test]
fn failures_become_model_errors_a_user_can_act_on() {
    let mut failure = Failure {
        kind: FailureKind::NotConverged,
        unknown: 0,
        t: 0.125,
        residual: 3.2e-3,
    };
    let error = failure.to_model_error("d1, d2, j");
    assert_eq!(
        error,
        ModelError::UnsolvedLoop {
            members: "d1, d2, j",
            t: 0.125,
            residual: 3.2e-3
        }
    );
    let text = error.to_string();
    assert!(
        text.starts_with("the algebraic loop through d1, d2, j did not converge at t = 0.125 s (residual 3.2e-3)"),
        "{text}"
    );
    failure.kind = FailureKind::NonFinite;
    failure.residual = f64::NAN;
    let text = failure.to_model_error("d1, d2, j").to_string();
    assert!(text.contains("d1, d2, j") && text.contains("NaN"), "{text}");
    failure.kind = FailureKind::Singular;
    let error = failure.to_model_error("mass2, rod");
    assert_eq!(
        error,
        ModelError::SingularConstraint {
            members: "mass2, rod",
            t: 0.125
        }
    );
    let text = error.to_string();
    assert!(
        text.starts_with("the constraints on mass2, rod are singular at t = 0.125 s: a redundant constraint or a dead-point configuration (the mass matrix is singular)"),
        "{text}"
    );
}
