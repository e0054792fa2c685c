//! Proof that the partials' hot path is free of heap allocation once its buffers are
//! set up: [`PartialsWorkspace`]'s parameter and input partials, `parameter_jacobian_in`
//! and [`ParameterDerivatives`]' `∂f/∂p` and `∂g/∂p` (what the variational equations
//! evaluate at every SDIRK stage), on the flagship (117 states; more parameters than
//! one evaluation's lanes) and the DC servo (inputs). Each result is also compared with
//! the allocating functions' at the same point, so a workspace that reused stale values
//! would fail.
//!
//! A global allocator is per binary, so this test has a binary of its own; it counts the
//! allocations made on the current thread (the runtime's `support/counting.rs`).

#[path = "../../bgdsl-runtime/tests/support/counting.rs"]
mod counting;

use bgdsl_analysis::partials::{
    input_partials, parameter_jacobian, parameter_jacobian_in, parameter_partials,
    PartialsWorkspace, LANES,
};
use bgdsl_analysis::sensitivity::{parameter_index, ParameterDerivatives};
use bgdsl_runtime::{Model, WithInputs};
use counting::{allocations_in, Counting};
use models::dc_servo::DcServo;
use models::quick_return::QuickReturn;
use nalgebra::DMatrix;

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Ten of the flagship's parameter values: two evaluations of [`LANES`] lanes.
fn flagship_parameters() -> Vec<usize> {
    let names = [
        "w_drive", "m1", "m2", "m3", "K01", "K12", "K03", "K3C[1]", "K34", "K45",
    ];
    names
        .iter()
        .map(|n| parameter_index::<QuickReturn>(n).expect("a flagship parameter"))
        .collect()
}

/// `count` states near the initial one of `M`, each a little further along.
fn states<M: Model + Default>(count: usize) -> Vec<Vec<f64>> {
    let mut x0 = vec![0.0; M::N_STATES];
    M::default().initial_state(&mut x0);
    (0..count)
        .map(|k| {
            x0.iter()
                .enumerate()
                .map(|(i, v)| v + 1e-3 * (k * (i % 7)) as f64)
                .collect()
        })
        .collect()
}

#[test]
fn parameter_partials_allocate_nothing_after_set_up() {
    const { assert!(QuickReturn::EXACT_PARAMETER_DERIVATIVES) };
    let model = QuickReturn::default();
    let which = flagship_parameters();
    assert!(which.len() > LANES);
    let xs = states::<QuickReturn>(4);
    let mut work = PartialsWorkspace::new(&model);
    let mut df = DMatrix::zeros(QuickReturn::N_STATES, which.len());
    let mut dg = DMatrix::zeros(QuickReturn::N_OUTPUTS, which.len());
    work.parameter_partials(&model, 0.0, &xs[0], &which)
        .unwrap();
    for (k, x) in xs.iter().enumerate() {
        let t = 0.1 * k as f64;
        let n = allocations_in(|| {
            let p = work.parameter_partials(&model, t, x, &which).unwrap();
            df.copy_from(&p.df);
            dg.copy_from(&p.dg);
        })
        .0;
        assert_eq!(n, 0, "allocations in parameter_partials at state {k}");
        // The counter counts in this binary: the allocating function is seen to allocate.
        let (fresh_allocations, fresh) =
            allocations_in(|| parameter_partials(&model, t, x, &which));
        let fresh = fresh.unwrap();
        assert!(fresh_allocations > 0);
        assert_eq!(df, fresh.df, "∂f/∂p at state {k}");
        assert_eq!(dg, fresh.dg, "∂g/∂p at state {k}");
        assert!(fresh.df.iter().any(|&v| v != 0.0));
    }
}

#[test]
fn parameter_jacobian_allocates_nothing_after_set_up() {
    let model = QuickReturn::default();
    let which = flagship_parameters();
    let xs = states::<QuickReturn>(3);
    let mut work = PartialsWorkspace::new(&model);
    let mut out = vec![0.0; QuickReturn::N_STATES * which.len()];
    parameter_jacobian_in(&mut work, &model, 0.0, &xs[0], &which, &mut out).unwrap();
    let mut expected = out.clone();
    for x in &xs {
        let (n, method) = allocations_in(|| {
            parameter_jacobian_in(&mut work, &model, 0.5, x, &which, &mut out).unwrap()
        });
        assert_eq!(n, 0, "allocations in parameter_jacobian_in");
        assert_eq!(
            method,
            parameter_jacobian(&model, 0.5, x, &which, &mut expected).unwrap()
        );
        assert_eq!(out, expected);
    }
}

#[test]
fn input_partials_allocate_nothing_after_set_up() {
    const { assert!(DcServo::EXACT_PARAMETER_DERIVATIVES) };
    let model = DcServo::default();
    let which: Vec<usize> = (0..DcServo::INPUTS.len()).collect();
    assert!(!which.is_empty());
    let xs = states::<DcServo>(4);
    let mut work = PartialsWorkspace::new(&model);
    let mut df = DMatrix::zeros(DcServo::N_STATES, which.len());
    let mut dg = DMatrix::zeros(DcServo::N_OUTPUTS, which.len());
    work.input_partials(&model, 0.0, &xs[0], &which).unwrap();
    for x in &xs {
        let n = allocations_in(|| {
            let p = work.input_partials(&model, 0.0, x, &which).unwrap();
            df.copy_from(&p.df);
            dg.copy_from(&p.dg);
        })
        .0;
        assert_eq!(n, 0, "allocations in input_partials");
        let fresh = input_partials(&model, 0.0, x, &which).unwrap();
        assert_eq!((&df, &dg), (&fresh.df, &fresh.dg));
        assert!(fresh.df.iter().any(|&v| v != 0.0));
    }
}

#[test]
fn sensitivity_forcing_allocates_nothing_after_set_up() {
    let model = QuickReturn::default();
    let which = flagship_parameters();
    let mut derivatives = ParameterDerivatives::new(&model, &which).unwrap();
    assert!(derivatives.exact());
    let mut df = DMatrix::zeros(QuickReturn::N_STATES, which.len());
    let mut dg = DMatrix::zeros(QuickReturn::N_OUTPUTS, which.len());
    let xs = states::<QuickReturn>(3);
    derivatives.df_dp(0.0, &xs[0], &mut df);
    derivatives.dg_dp(0.0, &xs[0], &mut dg);
    for x in &xs {
        let n = allocations_in(|| {
            derivatives.df_dp(0.2, x, &mut df);
            derivatives.dg_dp(0.2, x, &mut dg);
        })
        .0;
        assert_eq!(n, 0, "allocations in df_dp and dg_dp");
        let fresh = parameter_partials(&model, 0.2, x, &which).unwrap();
        assert_eq!((&df, &dg), (&fresh.df, &fresh.dg));
    }
}
