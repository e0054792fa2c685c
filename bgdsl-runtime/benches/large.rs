//! The stiff path on large models: Jacobian evaluation, set-up, one Radau5 step and
//! one Rodas4 step, each as a ratio to one `f64` evaluation of the right-hand side at
//! the same size (the anchor), for hand-written chain models of 100 to 10,000 states
//! (`tests/support/large_chains.rs`):
//!
//! - `mass`: a mass-spring-damper chain, states interleaved (banded LU);
//! - `mass split`: the same chain, positions first, then velocities (the band is the
//!   whole matrix: the sparse LU, its fallback band allocated only if needed);
//! - `blocks`: dense 20-state blocks coupled to their neighbours (rigid bodies).
//!
//! `cargo bench -p bgdsl-runtime --bench large` prints the table (median of 5 timings
//! of at least 20 ms each; a step is the mean over a run: wall time over steps, with
//! its Jacobians and LU factorizations amortized), the least-squares growth exponents
//! over 1,000–10,000 and 2,000–10,000 states, and the peak heap memory of `Simulation::new` (a counting
//! allocator), then times the same operations with criterion at 1,000 and 10,000
//! states. `LARGE_TABLE_ONLY=1` skips criterion.

#[path = "../tests/support/large_chains.rs"]
mod large_chains;

use std::alloc::{GlobalAlloc, Layout, System};
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use bgdsl_runtime::{
    Jacobian, JacobianEvaluator, Model, Radau5Options, Rodas4Options, Simulation, Solver,
    SparsityPattern,
};
use criterion::Criterion;
use large_chains::{BlockChain, Interleaved, MassChain};

/// Counts the bytes allocated now and at most since the last [`reset_peak`].
struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, layout, new_size) };
        if !q.is_null() {
            CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
            let now = CURRENT.fetch_add(new_size, Ordering::Relaxed) + new_size;
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        q
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The heap bytes `f` needs at most above what was allocated before it.
fn peak_bytes<R>(f: impl FnOnce() -> R) -> (usize, R) {
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let r = f();
    (PEAK.load(Ordering::Relaxed) - base, r)
}

/// Seconds per call of `f`: the median of 5 timings of at least 20 ms each.
fn seconds(mut f: impl FnMut()) -> f64 {
    let mut calls = 1;
    loop {
        let start = Instant::now();
        for _ in 0..calls {
            f();
        }
        if start.elapsed() >= Duration::from_millis(20) {
            break;
        }
        calls *= 2;
    }
    let mut times: Vec<f64> = (0..5)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..calls {
                f();
            }
            start.elapsed().as_secs_f64() / calls as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[2]
}

/// The interval of the runs timed per step, s.
const T_END: f64 = 0.02;

fn radau() -> Solver {
    Solver::Radau5(Radau5Options {
        rtol: 1e-6,
        atol: 1e-9,
        ..Default::default()
    })
}

fn rodas() -> Solver {
    Solver::Rodas4(Rodas4Options {
        rtol: 1e-6,
        atol: 1e-9,
        ..Default::default()
    })
}

/// Seconds per step of `solver` on `model` (a run over [`T_END`], wall time over
/// steps), and the steps, Jacobians and LUs of a run.
fn per_step<M: Model>(model: &M, solver: Solver) -> (f64, [usize; 3]) {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    let mut sim = Simulation::new(model, solver).unwrap();
    let stats = sim.run(0.0, &x0, &[T_END], &mut ()).unwrap();
    let steps = stats.steps();
    let t = seconds(|| {
        black_box(sim.run(0.0, &x0, &[T_END], &mut ()).unwrap());
    });
    (t / steps as f64, [steps, stats.n_jac, stats.n_lu])
}

/// One row of the table.
struct Row {
    model: &'static str,
    n: usize,
    rhs: f64,
    jacobian: f64,
    setup: f64,
    radau: f64,
    rodas: f64,
    setup_bytes: usize,
    counts: [[usize; 3]; 2],
}

fn measure<M: Model + Default>(name: &'static str) -> Row {
    let model = M::default();
    let n = M::N_STATES;
    let mut x = vec![0.0; n];
    model.initial_state(&mut x);
    let mut dx = vec![0.0; n];
    let rhs = seconds(|| model.derivatives(0.0, black_box(&x), &mut dx));
    let mut evaluator = JacobianEvaluator::new(&model);
    let mut jac = Jacobian::new(SparsityPattern::for_model::<M>().unwrap().into());
    let jacobian = seconds(|| {
        evaluator.evaluate_sparse(&model, 0.0, black_box(&x), &mut jac);
    });
    let setup = seconds(|| {
        black_box(Simulation::new(&model, radau()).unwrap());
    });
    let (setup_bytes, sim) = peak_bytes(|| Simulation::new(&model, radau()).unwrap());
    drop(sim);
    let (radau, radau_counts) = per_step(&model, radau());
    let (rodas, rodas_counts) = per_step(&model, rodas());
    Row {
        model: name,
        n,
        rhs,
        jacobian,
        setup,
        radau,
        rodas,
        setup_bytes,
        counts: [radau_counts, rodas_counts],
    }
}

/// The least-squares slope of `log y` against `log n`.
fn exponent(points: &[(usize, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .map(|&(n, y)| ((n as f64).ln(), y.ln()))
        .collect();
    let k = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / k,
        pts.iter().map(|p| p.1).sum::<f64>() / k,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

fn table() {
    // The split chain's pattern has 7 S / 2 - 4 entries.
    let rows = vec![
        measure::<Interleaved<100>>("mass"),
        measure::<Interleaved<1000>>("mass"),
        measure::<Interleaved<2000>>("mass"),
        measure::<Interleaved<5000>>("mass"),
        measure::<Interleaved<10000>>("mass"),
        measure::<MassChain<100, 346>>("mass split"),
        measure::<MassChain<1000, 3496>>("mass split"),
        measure::<MassChain<2000, 6996>>("mass split"),
        measure::<MassChain<5000, 17496>>("mass split"),
        measure::<MassChain<10000, 34996>>("mass split"),
        measure::<BlockChain<100>>("blocks"),
        measure::<BlockChain<1000>>("blocks"),
        measure::<BlockChain<2000>>("blocks"),
        measure::<BlockChain<5000>>("blocks"),
        measure::<BlockChain<10000>>("blocks"),
    ];
    println!(
        "\n| model | states | RHS (µs) | Jacobian / RHS | set-up / RHS | Radau5 step / RHS | Rodas4 step / RHS | set-up peak heap (MB) | Radau5 steps, Jacobians, LUs | Rodas4 steps, Jacobians, LUs |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---|---|");
    for r in &rows {
        println!(
            "| {} | {} | {:.2} | {:.1} | {:.0} | {:.0} | {:.0} | {:.2} | {:?} | {:?} |",
            r.model,
            r.n,
            r.rhs * 1e6,
            r.jacobian / r.rhs,
            r.setup / r.rhs,
            r.radau / r.rhs,
            r.rodas / r.rhs,
            r.setup_bytes as f64 / 1e6,
            r.counts[0],
            r.counts[1],
        );
    }
    println!(
        "\nGrowth exponents of the times and of the heap (least squares on log-log; 1 is linear):\n"
    );
    println!(
        "| model | states | RHS | Jacobian | set-up | Radau5 step | Rodas4 step | set-up heap |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    for (model, from) in [
        ("mass", 1000),
        ("mass", 2000),
        ("mass split", 1000),
        ("mass split", 2000),
        ("blocks", 1000),
        ("blocks", 2000),
    ] {
        let of = |f: &dyn Fn(&Row) -> f64| {
            let pts: Vec<(usize, f64)> = rows
                .iter()
                .filter(|r| r.model == model && r.n >= from)
                .map(|r| (r.n, f(r)))
                .collect();
            exponent(&pts)
        };
        println!(
            "| {model} | {from}-10000 | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
            of(&|r| r.rhs),
            of(&|r| r.jacobian),
            of(&|r| r.setup),
            of(&|r| r.radau),
            of(&|r| r.rodas),
            of(&|r| r.setup_bytes as f64),
        );
    }
    println!();
}

fn bench_model<M: Model + Default>(c: &mut Criterion, name: &str) {
    let model = M::default();
    let n = M::N_STATES;
    let mut x = vec![0.0; n];
    model.initial_state(&mut x);
    let mut dx = vec![0.0; n];
    let mut group = c.benchmark_group(format!("large/{name}/{n}"));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(2));
    group.bench_function("rhs", |b| {
        b.iter(|| model.derivatives(0.0, black_box(&x), &mut dx))
    });
    let mut evaluator = JacobianEvaluator::new(&model);
    let mut jac = Jacobian::new(SparsityPattern::for_model::<M>().unwrap().into());
    group.bench_function("jacobian", |b| {
        b.iter(|| evaluator.evaluate_sparse(&model, 0.0, black_box(&x), &mut jac))
    });
    group.bench_function("set-up", |b| {
        b.iter(|| black_box(Simulation::new(&model, radau()).unwrap()))
    });
    for (label, solver) in [("radau5 step", radau()), ("rodas4 step", rodas())] {
        let mut sim = Simulation::new(&model, solver).unwrap();
        group.bench_function(label, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let start = Instant::now();
                    let stats = sim.run(0.0, &x, &[T_END], &mut ()).unwrap();
                    total += start.elapsed() / stats.steps() as u32;
                }
                total
            })
        });
    }
    group.finish();
}

fn main() {
    table();
    if std::env::var_os("LARGE_TABLE_ONLY").is_some() {
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    bench_model::<Interleaved<1000>>(&mut c, "mass");
    bench_model::<Interleaved<10000>>(&mut c, "mass");
    bench_model::<BlockChain<1000>>(&mut c, "blocks");
    bench_model::<BlockChain<10000>>(&mut c, "blocks");
    c.final_summary();
}
