//! A generated model evaluates and integrates without touching the heap. Its own test
//! binary, because it installs a counting global allocator.
//!
//! The counter is per thread, so the test harness's own threads (and other tests, were
//! there any) cannot disturb the count.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use bgdsl_runtime::{Model, Simulation, Solver, Trajectory};
use models::{QuarterCar, QuarterCarParams};

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the allocator may be called while the thread's locals are torn down.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Heap allocations made by this thread while running `f`.
fn allocations_in<R>(f: impl FnOnce() -> R) -> (u64, R) {
    let before = ALLOCATIONS.with(Cell::get);
    let result = f();
    (ALLOCATIONS.with(Cell::get) - before, result)
}

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
}
