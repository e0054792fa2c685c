//! The flagship's cost in CPU time (this thread's, so a busy shared machine inflates it
//! far less than wall time): the 0–5 s Radau5 run, its achieved error against rtol
//! 1e-10, the results file's formatting and writing, and one f64 derivative as the
//! anchor. The solver is the flagship's (`models::catalog::flagship_solver`), with
//! `rtol` and the reuse settings overridable (`NEWTON_TOL=x` sets the Newton
//! tolerance). For profiling (`perf record` on the release binary) and for comparing
//! Radau5's reuse settings:
//!
//! `cargo run --release -p models --example flagship_profile -- [reps] [rtol]
//! [reuse_jacobian_below] [hold_step_min] [hold_step_max]`
//!
//! (`NOERR=1` skips the error, `RUNONLY=1` stops after the timed runs (for `perf`),
//! `CSVONLY=1` only formats the file, 100 times.)

/// A point in this thread's CPU time.
struct Instant(f64);
impl Instant {
    fn now() -> Self {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        }; // SAFETY: `ts` is a valid timespec for the call to fill.
        unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        Instant(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
    }
    fn elapsed(&self) -> Dur {
        Dur(Instant::now().0 - self.0)
    }
}
struct Dur(f64);
impl Dur {
    fn as_secs_f64(&self) -> f64 {
        self.0
    }
}
use bgdsl_runtime::{Model, Radau5Options, Solver};
use models::catalog::flagship_solver;
use models::quick_return::results::{sample_times, COLUMNS};
use models::quick_return::run::{record, Recorded};
use models::quick_return::QuickReturn;

fn achieved_error(run: &Recorded, reference: &Recorded) -> f64 {
    let mut worst = 0.0f64;
    for i in 1..COLUMNS.len() {
        let (a, b) = (run.results.column_at(i), reference.results.column_at(i));
        let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let dev = a
            .iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        if peak > 0.0 {
            worst = worst.max(dev / peak);
        }
    }
    worst
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let get = |i: usize, d: f64| args.get(i).map(|s| s.parse().unwrap()).unwrap_or(d);
    let reps = get(1, 30.0) as usize;
    let rtol = get(2, 1e-6);
    let Solver::Radau5(d) = flagship_solver() else {
        unreachable!("the flagship's solver is Radau5")
    };
    let reuse = get(3, d.reuse_jacobian_below);
    let hmin = get(4, d.hold_step_min);
    let hmax = get(5, d.hold_step_max);
    let m = QuickReturn::default();
    let times = sample_times();
    let solver = Solver::Radau5(Radau5Options {
        rtol,
        reuse_jacobian_below: reuse,
        hold_step_min: hmin,
        hold_step_max: hmax,
        newton_tol: std::env::var("NEWTON_TOL")
            .ok()
            .map(|v| v.parse().unwrap())
            .or(d.newton_tol),
        ..d
    });
    let err = if std::env::var("NOERR").is_err() {
        let reference = record(
            &m,
            Solver::Radau5(Radau5Options {
                rtol: 1e-10,
                atol: 1e-14,
                ..Default::default()
            }),
            &times,
        )
        .unwrap();
        achieved_error(&record(&m, solver, &times).unwrap(), &reference)
    } else {
        f64::NAN
    };
    let mut walls = Vec::new();
    let mut stats = None;
    for _ in 0..reps {
        let s = Instant::now();
        let r = record(&m, solver, &times).unwrap();
        walls.push(s.elapsed().as_secs_f64() * 1e3);
        stats = Some(r.stats);
    }
    if std::env::var("RUNONLY").is_ok() {
        return;
    }
    let rec = record(&m, solver, &times).unwrap();
    if std::env::var("CSVONLY").is_ok() {
        for _ in 0..100 {
            let mut buf = Vec::with_capacity(1 << 23);
            rec.results.write_csv_to(&mut buf).unwrap();
            std::hint::black_box(&buf);
        }
        return;
    }
    let mut fmt = Vec::new();
    let mut file = Vec::new();
    let mut fw = Vec::new();
    let path = std::env::temp_dir().join("flagship_profile.csv");
    for _ in 0..10 {
        let mut buf = Vec::with_capacity(1 << 23);
        let s = Instant::now();
        rec.results.write_csv_to(&mut buf).unwrap();
        fmt.push(s.elapsed().as_secs_f64() * 1e3);
        let s = Instant::now();
        rec.results.write_csv(&path).unwrap();
        file.push(s.elapsed().as_secs_f64() * 1e3);
        let s = std::time::Instant::now();
        rec.results.write_csv(&path).unwrap();
        fw.push(s.elapsed().as_secs_f64() * 1e3);
    }
    fmt.sort_by(f64::total_cmp);
    file.sort_by(f64::total_cmp);
    fw.sort_by(f64::total_cmp);
    println!("csv: format only {:.2} ms cpu; write_csv {:.2} ms cpu, {:.2} ms wall (min), {:.2} wall (median)", fmt[0], file[0], fw[0], fw[5]);
    let mut x = vec![0.0; QuickReturn::N_STATES];
    m.initial_state(&mut x);
    let mut dx = vec![0.0; QuickReturn::N_STATES];
    let mut an = Vec::new();
    for _ in 0..reps {
        let s = Instant::now();
        for _ in 0..10000 {
            m.derivatives::<f64>(0.0, std::hint::black_box(&x), &mut dx);
            std::hint::black_box(&mut dx);
        }
        an.push(s.elapsed().as_secs_f64() * 1e6 / 10000.0);
    }
    walls.sort_by(f64::total_cmp);
    an.sort_by(f64::total_cmp);
    let s = stats.unwrap();
    println!("rtol {rtol:e} reuse {reuse} hold [{hmin},{hmax}]: err {err:.2e}; min {:.2} ms med {:.2} ms; rhs {:.3} us; ratio {:.0}; steps {} rej {} rhs {} jac {} dirs {} lu {}", walls[0], walls[reps/2], an[0], walls[0]*1e3/an[0], s.accepted + s.rejected, s.rejected, s.n_rhs, s.n_jac, s.n_jac_rhs, s.n_lu);
}
