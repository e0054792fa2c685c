//! Proof that stepping across events allocates nothing once a [`Simulation`] (or a
//! [`Stepper`]) and its recorder are set up: detection, location, actions, the
//! restart (a new Jacobian and LU for the stiff methods), the event log, a stop and
//! the chattering error included, for every method.
//!
//! A global allocator is per binary, so this test has a binary of its own; it counts
//! the allocations made on the current thread (`support/counting.rs`).

#[path = "support/counting.rs"]
mod counting;
#[path = "support/hybrid.rs"]
mod hybrid;

use bgdsl_runtime::{
    FixedStep, Model, Radau5Options, Rodas4Options, Simulation, Solver, Stepper, Trajectory,
};
use counting::{allocations_in, Counting};
use hybrid::{Ball, Clock, Switched};

#[global_allocator]
static GLOBAL: Counting = Counting;

fn methods() -> [Solver; 5] {
    [
        Solver::Rk4(FixedStep::new(0.01)),
        Solver::dopri5(),
        Solver::DormandPrinceFixed(FixedStep::new(0.01)),
        Solver::Radau5(Radau5Options::default()),
        Solver::Rodas4(Rodas4Options::default()),
    ]
}

/// Runs `model` with `solver` through `samples` uniform sample times to `t_end`, twice,
/// into a trajectory with room for every sample and `events` events, counting the
/// allocations of both runs. Returns the events of one run.
fn count_runs<M: Model>(
    model: &M,
    solver: Solver,
    t_end: f64,
    samples: usize,
    events: usize,
) -> usize {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, solver).unwrap();
    let mut traj = Trajectory::for_model::<M>(2 * samples).with_event_capacity(2 * events);
    let (n, (first, second)) = allocations_in(|| {
        let first = sim.run_uniform(0.0, &x0, t_end, samples, &mut traj);
        let second = sim.run_uniform(0.0, &x0, t_end, samples, &mut traj);
        (first, second)
    });
    let (first, second) = (first.unwrap(), second.unwrap());
    assert_eq!(
        n,
        0,
        "{} on {}: allocations in runs with events",
        solver.name(),
        M::NAME
    );
    assert_eq!(first, second);
    assert_eq!(traj.events().len(), 2 * first.events);
    first.events
}

/// One test, so that nothing else runs on this thread while counting.
#[test]
fn stepping_across_events_allocates_nothing_after_set_up() {
    let ball = Ball::default();
    let t_end = ball.apex(20).0;
    for solver in methods() {
        assert_eq!(count_runs(&ball, solver, t_end, 500, 20), 20);
        assert_eq!(count_runs(&Switched::default(), solver, 1.5, 100, 1), 1);
        let clock = Clock {
            times: [0.5, 0.5, 0.7],
            scale: [2.0, 1.0, 1.0],
            shift: [0.0, 1.0, 1.0],
        };
        assert_eq!(count_runs(&clock, solver, 1.0, 10, 3), 3);

        // A stop, and the chattering error, are plain data too.
        let stopping = Ball {
            stop: true,
            ..Ball::default()
        };
        assert_eq!(count_runs(&stopping, solver, 2.0, 50, 1), 1);
        let zeno = Ball {
            e: 0.5,
            ..Ball::default()
        };
        let mut sim = Simulation::new(&zeno, solver).unwrap();
        let (n, result) = allocations_in(|| sim.run(0.0, &[1.0, 0.0], &[10.0], &mut ()));
        assert!(result.is_err());
        assert_eq!(n, 0, "{}: allocations in a chattering run", solver.name());

        // A stepper advancing over impacts, its event log within capacity.
        let mut stepper = Stepper::new(ball.clone(), solver).unwrap();
        let (n, found) = allocations_in(|| {
            let mut found = 0;
            for k in 1..=40 {
                stepper.advance_to(0.1 * k as f64).unwrap();
                found += stepper.events().len();
            }
            found
        });
        assert_eq!(n, 0, "{}: allocations in stepper advances", solver.name());
        assert!(found >= 5, "{}: {found} impacts in 4 s", solver.name());
    }

    // Setting up does allocate, so the counter does count.
    let (n, sim) = allocations_in(|| Simulation::new(&ball, Solver::dopri5()));
    drop(sim);
    assert!(n > 0, "the counting allocator saw nothing");
}
