//! Observed order of convergence of the fixed-step methods under step halving.
//!
//! For a method of order `p` the global error at a fixed time behaves like
//! `C h^p (1 + O(h))`, so `log2(e(h) / e(h/2))` tends to `p`. The steps below are small
//! enough that the `O(h)` correction moves the observed order by less than 0.25 (the
//! orders observed are noted at each test), and large enough that the errors
//! (>= 1e-13) stay well above rounding (~1e-16 per step, a few hundred steps). A
//! tolerance of ±0.3 therefore passes a correct method, while an order-(p-1) method, or
//! a tableau with one wrong coefficient, misses it by about 1.
//!
//! The end times avoid zeros of the global error's leading term: for the logistic
//! equation that term changes sign near t = 5, and at t = 4 Dormand–Prince's observed
//! order is still 5.6 at h = 0.4 / 8.

use bgdsl_runtime::{FixedStep, Model, Scalar, Simulation, Solver};

/// `y' = -y + sin t`, `y(0) = 1`: linear, non-autonomous;
/// `y(t) = (sin t - cos t) / 2 + 3/2 e^-t`.
struct Forced;

impl Model for Forced {
    type Params = ();
    const NAME: &'static str = "forced";
    const STATE_NAMES: &'static [&'static str] = &["y"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 1.0;
    }
    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = -x[0] + T::from_f64(t.sin());
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

fn forced_exact(t: f64) -> f64 {
    0.5 * (t.sin() - t.cos()) + 1.5 * (-t).exp()
}

/// The logistic equation `y' = y (1 - y)`, `y(0) = 0.1`: nonlinear, autonomous;
/// `y(t) = 1 / (1 + 9 e^-t)`.
struct Logistic;

impl Model for Logistic {
    type Params = ();
    const NAME: &'static str = "logistic";
    const STATE_NAMES: &'static [&'static str] = &["y"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    fn params(&self) -> &() {
        &()
    }
    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 0.1;
    }
    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        dx[0] = x[0] * (T::from_f64(1.0) - x[0]);
    }
    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

fn logistic_exact(t: f64) -> f64 {
    1.0 / (1.0 + 9.0 * (-t).exp())
}

/// The error at `t_end` of a fixed-step run with step `t_end / n`, and the number of
/// derivative evaluations.
fn error_at_end<M: Model>(
    model: &M,
    method: fn(FixedStep) -> Solver,
    t_end: f64,
    n: usize,
    exact: fn(f64) -> f64,
) -> (f64, usize) {
    let solver = method(FixedStep::new(t_end / n as f64));
    let mut sim = Simulation::new(model, solver).unwrap();
    let mut x0 = [0.0];
    model.initial_state(&mut x0);
    let stats = sim.run(0.0, &x0, &[t_end], &mut ()).unwrap();
    assert_eq!(stats.accepted, n, "the grid lands on t_end in n steps");
    ((sim.state()[0] - exact(t_end)).abs(), stats.n_rhs)
}

/// Observed orders `log2(e(h_i) / e(h_i / 2))` for `n = n0, 2 n0, 4 n0, 8 n0` steps
/// to `t_end`.
fn observed_orders<M: Model>(
    model: &M,
    method: fn(FixedStep) -> Solver,
    t_end: f64,
    n0: usize,
    exact: fn(f64) -> f64,
) -> Vec<f64> {
    let errors: Vec<f64> = (0..4)
        .map(|i| error_at_end(model, method, t_end, n0 << i, exact).0)
        .collect();
    assert!(
        errors.iter().all(|e| *e > 1e-13),
        "errors must stay above rounding: {errors:?}"
    );
    let orders = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    eprintln!("{} errors {errors:?} orders {orders:?}", M::NAME);
    orders
}

fn assert_order(orders: &[f64], p: f64) {
    for o in orders {
        assert!(
            (o - p).abs() <= 0.3,
            "observed orders {orders:?}, expected {p}"
        );
    }
}

#[test]
fn rk4_converges_with_order_4() {
    // Observed: 4.14, 4.07, 4.04 and 3.97, 3.98, 3.99.
    assert_order(
        &observed_orders(&Forced, Solver::Rk4, 4.0, 40, forced_exact),
        4.0,
    );
    assert_order(
        &observed_orders(&Logistic, Solver::Rk4, 2.0, 20, logistic_exact),
        4.0,
    );
}

#[test]
fn rk4_costs_four_evaluations_per_step() {
    let (_, n_rhs) = error_at_end(&Forced, Solver::Rk4, 1.0, 10, forced_exact);
    assert_eq!(n_rhs, 40);
}

#[test]
fn dormand_prince_fifth_order_formula_converges_with_order_5() {
    // Observed: 5.19, 5.10, 5.05 and 5.22, 5.13, 5.07.
    assert_order(
        &observed_orders(&Forced, Solver::DormandPrinceFixed, 4.0, 20, forced_exact),
        5.0,
    );
    assert_order(
        &observed_orders(
            &Logistic,
            Solver::DormandPrinceFixed,
            2.0,
            10,
            logistic_exact,
        ),
        5.0,
    );
}

#[test]
fn dormand_prince_fixed_step_reuses_the_last_stage() {
    // FSAL: 7 stages, but the first of every step after the first is the last of the one
    // before, so n steps cost 6 n + 1 evaluations.
    let (_, n_rhs) = error_at_end(&Forced, Solver::DormandPrinceFixed, 1.0, 10, forced_exact);
    assert_eq!(n_rhs, 61);
}
