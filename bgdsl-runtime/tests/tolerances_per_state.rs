//! Per-state absolute tolerances ([`Simulation::set_atol`]): they reach every adaptive
//! method's error norm, and bad ones are refused naming the state.

mod stiff_common;

use bgdsl_runtime::{
    DormandPrinceOptions, FixedStep, Radau5Options, Rodas4Options, Simulation, Solver, SolverError,
};
use stiff_common::{Robertson, ROBERTSON_REF};

/// Robertson to `t = 1e11` with Radau5 (rtol 1e-6). `y2` ends near 8.3e-14 (reference:
/// Bari test set, ROBER), so a scalar `atol = 1e-4` leaves it unresolved (it ends with
/// the wrong sign), while `atol = 1e-14` for `y2` alone resolves it to 1e-3 relative,
/// with fewer steps than the scalar 1e-14 that the other states do not need.
#[test]
fn a_tight_atol_for_one_state_resolves_it() {
    let solver = Solver::Radau5(Radau5Options {
        atol: 1e-4,
        ..Default::default()
    });
    let x0 = [1.0, 0.0, 0.0];
    let mut sim = Simulation::new(&Robertson, solver).unwrap();
    sim.run(0.0, &x0, &[1e11], &mut ()).unwrap();
    let loose = sim.state()[1];
    assert!(
        (loose - ROBERTSON_REF[1]).abs() > 0.5 * ROBERTSON_REF[1],
        "y2 = {loose:e}"
    );

    sim.set_atol(&[1e-4, 1e-14, 1e-4]).unwrap();
    assert_eq!(sim.atol(), Some(&[1e-4, 1e-14, 1e-4][..]));
    let per_state = sim.run(0.0, &x0, &[1e11], &mut ()).unwrap();
    let x = sim.state().to_vec();
    let rel = (x[1] - ROBERTSON_REF[1]).abs() / ROBERTSON_REF[1];
    assert!(rel < 1e-3, "y2 = {:e}, relative error {rel:e}", x[1]);
    for i in [0, 2] {
        assert!((x[i] - ROBERTSON_REF[i]).abs() < 1e-6, "{x:?}");
    }

    let tight = Solver::Radau5(Radau5Options {
        atol: 1e-14,
        ..Default::default()
    });
    let mut sim = Simulation::new(&Robertson, tight).unwrap();
    let all_tight = sim.run(0.0, &x0, &[1e11], &mut ()).unwrap();
    assert!(
        per_state.steps() < all_tight.steps(),
        "{per_state:?} vs {all_tight:?}"
    );
}

/// Per-state tolerances equal to the scalar one change nothing: the same steps, the
/// same result, bit for bit (Radau5, Rodas4, Dormand–Prince).
#[test]
fn per_state_atol_equal_to_the_scalar_one_changes_nothing() {
    let solvers = [
        Solver::Radau5(Radau5Options {
            atol: 1e-10,
            ..Default::default()
        }),
        Solver::Rodas4(Rodas4Options {
            atol: 1e-10,
            ..Default::default()
        }),
    ];
    let x0 = [1.0, 0.0, 0.0];
    for solver in solvers {
        let mut sim = Simulation::new(&Robertson, solver).unwrap();
        let a = sim.run(0.0, &x0, &[1e5], &mut ()).unwrap();
        let xa = sim.state().to_vec();
        sim.set_atol(&[1e-10; 3]).unwrap();
        let b = sim.run(0.0, &x0, &[1e5], &mut ()).unwrap();
        assert_eq!(a, b, "{}", solver.name());
        assert_eq!(xa, sim.state(), "{}", solver.name());
    }
    let dopri = Solver::DormandPrince(DormandPrinceOptions {
        atol: 1e-10,
        ..Default::default()
    });
    let mut sim = Simulation::new(&Robertson, dopri).unwrap();
    let a = sim.run(0.0, &x0, &[0.01], &mut ()).unwrap();
    let xa = sim.state().to_vec();
    sim.set_atol(&[1e-10; 3]).unwrap();
    let b = sim.run(0.0, &x0, &[0.01], &mut ()).unwrap();
    assert_eq!((a, xa.as_slice()), (b, sim.state()));
    // A looser atol for y2 alone takes fewer steps.
    sim.set_atol(&[1e-10, 1e-4, 1e-10]).unwrap();
    let c = sim.run(0.0, &x0, &[0.01], &mut ()).unwrap();
    assert!(c.steps() < b.steps(), "{c:?} vs {b:?}");
}

/// Bad per-state tolerances are refused, naming the state; the previous ones stay.
#[test]
fn bad_per_state_atol_is_refused_naming_the_state() {
    let mut sim = Simulation::new(&Robertson, Solver::stiff()).unwrap();
    sim.set_atol(&[1e-8, 1e-12, 1e-8]).unwrap();
    let err = sim.set_atol(&[1e-8, -1e-12, 1e-8]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "invalid absolute tolerance -1e-12 for state `y2`: expected a finite number >= 0"
    );
    let err = sim.set_atol(&[1e-8, 1e-12, f64::NAN]).unwrap_err();
    assert!(matches!(err, SolverError::InvalidAtol { state: "y3", .. }));
    let err = sim.set_atol(&[1e-8, 1e-12]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "`atol` has 2 values but the model has 3 states: give one per state, in the order \
         of Model::STATE_NAMES"
    );
    assert_eq!(sim.atol(), Some(&[1e-8, 1e-12, 1e-8][..]));
    // A zero atol is allowed with rtol > 0, refused with rtol = 0.
    sim.set_atol(&[0.0, 1e-12, 1e-8]).unwrap();
    let pure_absolute = Solver::Rodas4(Rodas4Options {
        rtol: 0.0,
        ..Default::default()
    });
    let mut sim = Simulation::new(&Robertson, pure_absolute).unwrap();
    let err = sim.set_atol(&[1e-8, 0.0, 1e-8]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "invalid absolute tolerance 0 for state `y2`: expected a number > 0 (rtol is 0)"
    );
    // A fixed-step method controls no error.
    let mut sim = Simulation::new(&Robertson, Solver::Rk4(FixedStep::new(1e-3))).unwrap();
    let err = sim.set_atol(&[1e-8; 3]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "`set_atol` is not available with rk4: a fixed-step method controls no error"
    );
}

/// The allocation-free Dormand–Prince of `rk` (the `no_std` integrator) with per-state
/// atol takes the driver's steps with the same atol, bit for bit: HIRES (8 states,
/// mildly stiff, to t = 5) with a tight atol on the two smallest species and a loose
/// one elsewhere. The per-state tolerances matter (the run differs from the scalar
/// one), and a bad entry is refused naming the state.
#[test]
fn the_no_std_dormand_prince_takes_the_drivers_steps() {
    use bgdsl_runtime::rk::DormandPrince;
    use bgdsl_runtime::Model;
    use stiff_common::Hires;

    let options = DormandPrinceOptions {
        rtol: 1e-6,
        atol: 1e-4,
        ..Default::default()
    };
    let atol = [1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-10, 1e-10];
    let t_end = 5.0;
    let mut x0 = [0.0; 8];
    Hires.initial_state(&mut x0);

    let mut sim = Simulation::new(&Hires, Solver::DormandPrince(options)).unwrap();
    sim.set_atol(&atol).unwrap();
    let driver = sim.run(0.0, &x0, &[t_end], &mut ()).unwrap();

    let mut dopri = DormandPrince::<8>::new(options).unwrap();
    dopri.set_atol::<Hires>(Some(atol)).unwrap();
    assert_eq!(dopri.atol(), Some(&atol));
    let (mut t, mut x) = (0.0, x0);
    dopri.advance_to(&Hires, &mut t, &mut x, t_end).unwrap();
    assert_eq!(t, t_end);
    assert_eq!(x, sim.state(), "the same end state, bit for bit");
    let embedded = dopri.stats();
    assert_eq!(
        (embedded.accepted, embedded.rejected),
        (driver.accepted, driver.rejected)
    );

    let mut scalar = DormandPrince::<8>::new(options).unwrap();
    let (mut t, mut y) = (0.0, x0);
    scalar.advance_to(&Hires, &mut t, &mut y, t_end).unwrap();
    assert_ne!(y, x, "the per-state atol changes the run");

    let bad = [1e-4, 1e-4, 1e-4, -1.0, 1e-4, 1e-4, 1e-10, 1e-10];
    let err = dopri.set_atol::<Hires>(Some(bad)).unwrap_err();
    assert!(
        matches!(err, SolverError::InvalidAtol { state, value: -1.0, .. } if state == Hires::STATE_NAMES[3]),
        "{err}"
    );
    assert_eq!(dopri.atol(), Some(&atol), "unchanged after a refusal");
    dopri.set_atol::<Hires>(None).unwrap();
    assert_eq!(dopri.atol(), None);
}
