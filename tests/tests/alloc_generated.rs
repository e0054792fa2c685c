//! A generated model evaluates and integrates without touching the heap. Its own test
//! binary, because it installs a counting global allocator.
//!
//! The counter is per thread, so the test harness's own threads (and other tests, were
//! there any) cannot disturb the count.

mod common;
#[path = "common/textbook.rs"]
mod textbook;

use bgdsl_runtime::{Model, Simulation, Solver, Trajectory};
use common::counting::{allocations_in, Counting};
use models::{QuarterCar, QuarterCarParams};
use textbook::{DiodeRc, Gear, GearParams, SliderCrank, SliderCrankParams};

#[global_allocator]
static GLOBAL: Counting = Counting;

mod should {
    use super::*;

    #[test]
    fn count_allocations_at_all() {
        let (n, v) = allocations_in(|| vec![1.0f64; 8]);
        assert_eq!((n, v.len()), (1, 8), "the counter sees a Vec");
    }

    /// 10,000 evaluations of the quarter car's derivative and outputs, over the bump
    /// (the `if` in the road law) and the flat road.
    #[test]
    fn evaluate_the_generated_quarter_car_without_allocating() {
        let model = QuarterCar::new(QuarterCarParams {
            wave_amplitude: 0.01,
            ..Default::default()
        });
        let mut x = [0.0; 4];
        model.initial_state(&mut x);
        let mut dx = [0.0; 4];
        let mut y = [0.0; QuarterCar::N_OUTPUTS];
        let (n, checksum) = allocations_in(|| {
            let mut checksum = 0.0;
            for i in 0..10_000 {
                let t = i as f64 * 1e-4;
                model.derivatives::<f64>(t, &x, &mut dx);
                model.outputs::<f64>(t, &x, &mut y);
                checksum += dx[3] + y[0];
                x[1] += 1e-6 * dx[1];
            }
            checksum
        });
        assert!(checksum.is_finite());
        assert_eq!(
            n, 0,
            "heap allocations in 10,000 derivative and output evaluations"
        );
    }

    /// After `Simulation::new` (which allocates the workspace) and with a trajectory
    /// created with room for every sample, whole runs allocate nothing: adaptive DP5 and
    /// fixed-step RK4, recording into the trajectory or into a closure, run twice.
    #[test]
    fn integrate_the_generated_quarter_car_without_allocating() {
        let model = QuarterCar::default();
        let mut x0 = [0.0; 4];
        model.initial_state(&mut x0);
        for solver in [Solver::dopri5(), Solver::rk4(1e-3)] {
            let mut sim = Simulation::new(&model, solver).unwrap();
            let mut traj = Trajectory::for_model::<QuarterCar>(1001);
            let (n, result) = allocations_in(|| {
                let first = sim.run_uniform(0.0, &x0, 2.0, 1001, &mut traj);
                traj.clear();
                let second = sim.run_uniform(0.0, &x0, 2.0, 1001, &mut traj);
                let mut peak: f64 = 0.0;
                let third = sim.run_uniform(
                    0.0,
                    &x0,
                    2.0,
                    1001,
                    &mut |_t: f64, _x: &[f64], y: &[f64]| {
                        peak = peak.max(y[5].abs());
                    },
                );
                (first, second, third, peak)
            });
            let (first, second, third, peak) = result;
            let stats = first.unwrap();
            assert_eq!(second.unwrap(), stats, "a rerun does the same work");
            assert_eq!(third.unwrap(), stats);
            assert!(stats.accepted > 100 && peak > 0.0);
            assert_eq!(traj.len(), 1001);
            assert_eq!(n, 0, "heap allocations in three {} runs", solver.name());
        }
    }

    /// 10,000 evaluations of `derivatives`, `outputs` and `power_balance` of `model` in
    /// `f64`, walking the state by `step · dx`: the count of heap allocations.
    fn evaluations<M: Model>(model: &M, x: &mut [f64], step: f64) -> usize {
        let mut dx = [0.0; 8];
        let mut y = [0.0; 8];
        let (n, checksum) = allocations_in(|| {
            let mut checksum = 0.0;
            for i in 0..10_000 {
                let t = i as f64 * 1e-4;
                model.derivatives::<f64>(t, x, &mut dx[..M::N_STATES]);
                model.outputs::<f64>(t, x, &mut y[..M::N_OUTPUTS]);
                checksum += model.power_balance::<f64>(t, x).unwrap().stored + y[0];
                for (xi, di) in x.iter_mut().zip(&dx) {
                    *xi += step * di;
                }
            }
            checksum
        });
        assert!(checksum.is_finite(), "{}: evaluations stay finite", M::NAME);
        n
    }

    /// Whole runs after `Simulation::new`, twice each, with DP5 and the stiff default
    /// (whose Jacobians differentiate through the per-evaluation solve): the count of
    /// heap allocations.
    fn runs<M: Model>(model: &M, t_end: f64) -> usize {
        let mut x0 = vec![0.0; M::N_STATES];
        model.initial_state(&mut x0);
        let mut total = 0;
        for solver in [Solver::dopri5(), Solver::stiff()] {
            let mut sim = Simulation::new(model, solver).unwrap();
            let mut traj = Trajectory::for_model::<M>(201);
            let (n, (first, second)) = allocations_in(|| {
                let first = sim.run_uniform(0.0, &x0, t_end, 201, &mut traj);
                traj.clear();
                let second = sim.run_uniform(0.0, &x0, t_end, 201, &mut traj);
                (first, second)
            });
            let stats = first.unwrap();
            assert_eq!(second.unwrap(), stats, "a rerun does the same work");
            assert!(
                stats.accepted > 0,
                "{}: {} integrates",
                M::NAME,
                solver.name()
            );
            total += n;
        }
        total
    }

    /// Dependent storage (the gear's output shaft: a constraint solved at each
    /// evaluation) and a mechanism with four dependent inertias behind
    /// configuration-dependent transformers: no heap allocation, evaluating or
    /// integrating.
    #[test]
    fn evaluate_and_integrate_dependent_storage_without_allocating() {
        let gear = Gear::new(GearParams {
            amplitude: 1.0,
            ..Default::default()
        });
        assert_eq!(evaluations(&gear, &mut [0.1], 1e-4), 0, "gear evaluations");
        assert_eq!(runs(&gear, 1.0), 0, "gear runs");
        let crank = SliderCrank::new(SliderCrankParams {
            tau: 0.2,
            ..Default::default()
        });
        let mut x = vec![0.0; SliderCrank::N_STATES];
        crank.initial_state(&mut x);
        assert_eq!(
            evaluations(&crank, &mut x, 1e-5),
            0,
            "slider-crank evaluations"
        );
        assert_eq!(runs(&crank, 0.5), 0, "slider-crank runs");
    }

    /// A non-linear loop (the diode's, solved by Newton at each evaluation): no heap
    /// allocation, evaluating or integrating.
    #[test]
    fn evaluate_and_integrate_a_nonlinear_loop_without_allocating() {
        let diode = DiodeRc::default();
        assert_eq!(
            evaluations(&diode, &mut [0.0], 1e-7),
            0,
            "diode evaluations"
        );
        assert_eq!(runs(&diode, 2e-3), 0, "diode runs");
    }
}
