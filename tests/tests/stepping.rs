//! A host drives a generated model: inputs set between steps, `advance_to` at a fixed
//! rate, snapshots saved and restored, and not one heap allocation per call once the
//! stepper exists.
//!
//! The model is a cart of mass m on a viscous guide (c), pushed by a force the host
//! sets: `m v' = F − c v`, so after a jump of F at t₁ the speed relaxes exponentially
//! towards F / c with time constant m / c. That closed form is what every run is checked
//! against.

mod common;

use bgdsl_runtime::{bond_graph, Model, Snapshot, Solver, Stepper, WithInputs};
use common::counting::{allocations_in, Counting};

bond_graph! {
    /// A cart on a viscous guide, pushed by a force the host sets.
    pub model Cart {
        /// cart mass
        param m = 2.0 in "kg";
        /// guide friction
        param c = 4.0 in "N·s/m";
        /// the push
        input force = 0.0 in "N";
        /// a second input, to check the layout
        input unused = 7.5;

        I cart = m;
        R guide = c;
        MSe push = force;
        1 v;
        push -> v -> { cart, guide };

        output speed = v.f;
        output power_in = push.e * push.f;
    }
}

/// The speed at `t` when the force is `f1` until `t1`, then `f2`, from rest.
fn speed(p: &CartParams, f1: f64, t1: f64, f2: f64, t: f64) -> f64 {
    let tau = p.m / p.c;
    let relax = |v0: f64, target: f64, dt: f64| target + (v0 - target) * (-dt / tau).exp();
    if t <= t1 {
        relax(0.0, f1 / p.c, t)
    } else {
        relax(relax(0.0, f1 / p.c, t1), f2 / p.c, t - t1)
    }
}

#[test]
fn inputs_are_plain_data_with_names_units_and_defaults() {
    assert_eq!(
        Cart::INPUTS
            .iter()
            .map(|i| (i.name, i.unit, i.doc))
            .collect::<Vec<_>>(),
        [
            ("force", "N", "the push"),
            ("unused", "", "a second input, to check the layout")
        ]
    );
    let cart = Cart::default();
    assert_eq!(
        cart.inputs(),
        CartInputs {
            force: 0.0,
            unused: 7.5
        }
    );
    let mut values = [0.0; 2];
    cart.input_values(&mut values);
    assert_eq!(values, [0.0, 7.5]);
    let mut cart = cart;
    cart.set_input_values(&[3.0, -1.0]);
    assert_eq!(
        cart.inputs,
        CartInputs {
            force: 3.0,
            unused: -1.0
        }
    );
    // Parameters and inputs are separate: a scenario sets the first, a host the second.
    let names: Vec<&str> = Cart::PARAMETERS.iter().map(|p| p.name).collect();
    assert_eq!(names, ["m", "c"]);
    let text = serde_yaml::to_string(&CartInputs {
        force: 1.5,
        unused: 0.0,
    })
    .expect("serialises");
    let back: CartInputs = serde_yaml::from_str(&text).expect("deserialises");
    assert_eq!(back.force, 1.5);
}

#[test]
fn flat_parameter_access_follows_the_declared_order() {
    let mut model = models::quick_return::QuickReturn::default();
    let n = models::quick_return::QuickReturn::N_PARAMETER_VALUES;
    let declared: usize = models::quick_return::QuickReturn::PARAMETERS
        .iter()
        .map(|p| p.len)
        .sum();
    assert_eq!(n, declared);
    let mut values = vec![0.0; n];
    model.parameter_values(&mut values);
    // m1 comes first, then m2..m5, then l1 component by component.
    assert_eq!(&values[..8], &[0.5, 0.1, 0.7, 0.3, 0.1, 0.2, 0.01, 0.01]);
    values[5] = 0.25;
    values[0] = 0.6;
    model.set_parameter_values(&values);
    assert_eq!(model.params.l1, [0.25, 0.01, 0.01]);
    assert_eq!(model.params.m1, 0.6);
}

#[test]
fn a_1_khz_host_loop_with_a_force_step_matches_the_closed_form() {
    for solver in ["dopri5", "radau5", "rodas4"] {
        let mut stepper = Stepper::new(Cart::default(), Solver::from_name(solver).expect("known"))
            .expect("valid");
        let p = stepper.model().params.clone();
        let mut worst: f64 = 0.0;
        for k in 1..=2000 {
            let t = k as f64 * 1e-3;
            // The host applies 2 N for the first second, then 6 N (a jump).
            let force = if t <= 1.0 + 1e-12 { 2.0 } else { 6.0 };
            let outputs = stepper
                .advance_with(t, CartInputs { force, unused: 0.0 })
                .expect("advances");
            let expected = speed(&p, 2.0, 1.0, 6.0, t);
            worst = worst.max((outputs[0] - expected).abs());
        }
        // Default tolerances (rtol 1e-6): the speed (≤ 1.5 m/s) within 1e-5.
        assert!(worst < 1e-5, "{solver}: worst speed error {worst:e}");
        assert_eq!(stepper.time(), 2.0);
    }
}

#[test]
fn a_snapshot_restores_the_run_exactly_and_survives_serialisation() {
    let mut stepper = Stepper::new(Cart::default(), Solver::stiff()).expect("valid");
    stepper.set_inputs(CartInputs {
        force: 3.0,
        unused: 0.0,
    });
    stepper.advance_to(0.5).expect("advances");
    let saved = stepper.snapshot();
    let first = stepper.advance_to(1.0).expect("advances")[0];
    let text = serde_yaml::to_string(&saved).expect("serialises");
    let loaded: Snapshot = serde_yaml::from_str(&text).expect("deserialises");
    assert_eq!(loaded, saved);
    stepper.restore(&loaded).expect("same model");
    assert_eq!(stepper.time(), 0.5);
    let again = stepper.advance_to(1.0).expect("advances")[0];
    assert_eq!(first.to_bits(), again.to_bits(), "{first} vs {again}");

    let wrong = Snapshot {
        model: "Other".into(),
        ..saved.clone()
    };
    let error = stepper.restore(&wrong).expect_err("another model");
    assert_eq!(
        error.to_string(),
        "the snapshot is of model `Other`, but this stepper runs `Cart`"
    );
    let short = Snapshot {
        state: vec![0.0; 3],
        ..saved
    };
    let error = stepper.restore(&short).expect_err("wrong length");
    assert_eq!(
        error.to_string(),
        "the snapshot's state has 3 values, but the model has 1 states"
    );
    assert_eq!(
        stepper.time(),
        1.0,
        "a failed restore leaves the stepper alone"
    );
}

#[test]
fn going_back_in_time_is_refused() {
    let mut stepper = Stepper::new(Cart::default(), Solver::stiff()).expect("valid");
    stepper.advance_to(1.0).expect("advances");
    assert!(stepper.advance_to(0.5).is_err());
    assert!(stepper.advance_to(f64::NAN).is_err());
    assert_eq!(stepper.time(), 1.0);
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn advancing_allocates_nothing_after_set_up() {
    let (seen, _) = allocations_in(|| vec![0u8; 16]);
    assert_eq!(seen, 1, "the counter sees a Vec");
    for solver in ["dopri5", "radau5", "rodas4", "rk4"] {
        let mut stepper = Stepper::new(Cart::default(), Solver::from_name(solver).expect("known"))
            .expect("valid");
        // One call first: anything lazily set up on first use is not per-call cost.
        stepper.advance_to(1e-3).expect("advances");
        let (allocations, sum) = allocations_in(|| {
            let mut sum = 0.0;
            for k in 2..=1000 {
                let force = if k % 200 < 100 { 1.0 } else { -1.0 };
                let outputs = stepper
                    .advance_with(k as f64 * 1e-3, CartInputs { force, unused: 0.0 })
                    .expect("advances");
                sum += outputs[0];
            }
            sum
        });
        assert!(sum.is_finite());
        assert_eq!(allocations, 0, "{solver}");
    }
}
