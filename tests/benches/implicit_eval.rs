//! What the per-evaluation solve costs: `derivatives` in `f64` of the textbook models
//! that solve something at each evaluation (a rigid gear's dependent inertia, two
//! dampers in series, a diode's non-linear loop, a slider-crank's and a four-bar's
//! configuration-dependent mass matrix), each against an anchor in the same run: the
//! same physics reduced by hand to an explicit model (the equivalent inertia or
//! damper as a plain bond graph, the diode's loop current by Lambert's W, Lagrange's
//! equation of the mechanism).
//!
//! `cargo bench -p bgdsl-tests --bench implicit_eval -- --warm-up-time 1 --measurement-time 3`
//!
//! Each function evaluates the same 256 deterministic (time, state) points around the
//! model's start; the ratio of the two times of a group is the price of solving at
//! run time what the anchor's author solved on paper.

use std::hint::black_box;

use bgdsl_runtime::{bond_graph, Model, Scalar};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

#[path = "../tests/common/lagrange.rs"]
mod lagrange;
#[path = "../tests/common/textbook.rs"]
mod textbook;

use lagrange::{four_bar_angles, FourBarLagrange, SliderCrankLagrange};
use textbook::{DiodeRc, DiodeRcParams, FourBar, Gear, SeriesDampers, SliderCrank};

const POINTS: usize = 256;

bond_graph! {
    /// The gear reduced by hand: one inertia j1 + n² j2, the damper reflected as n² c.
    pub model GearReduced {
        param j1 = 0.2; param j2 = 0.05; param n = 3.0; param c = 0.1;
        param torque = 1.0; param amplitude = 0.0; param omega = 5.0;
        Se motor = torque + amplitude * (omega * t).sin();
        I shaft = j1 + n * n * j2;
        R damper = n * n * c;
        1 w;
        motor -> w -> { shaft, damper };
    }
}

bond_graph! {
    /// The series dampers reduced by hand: one damper r1 r2/(r1 + r2).
    pub model SeriesDampersReduced {
        param r1 = 2.0; param r2 = 3.0; param m = 1.0; param k = 10.0;
        I mass = m; C spring = k; R damper = r1 * r2 / (r1 + r2);
        1 v;
        v -> { mass, spring, damper };
        init spring.q = 0.1;
    }
}

/// Lambert's W (principal branch) for x > 0: Halley's iteration from
/// ln x − ln ln x (large x) or x (small x), four steps (cubic convergence: well
/// below rounding for the diode's arguments, 1e-2 to 1e13).
fn lambert_w(x: f64) -> f64 {
    let mut w = if x > core::f64::consts::E {
        let l = x.ln();
        l - l.ln()
    } else {
        x / (1.0 + x)
    };
    for _ in 0..4 {
        let e = w.exp();
        let f = w * e - x;
        w -= f / (e * (w + 1.0) - (w + 2.0) * f / (2.0 * w + 2.0));
    }
    w
}

/// The diode circuit reduced by hand: C dv/dt = i(v), the loop current by Lambert's W
/// (see `tests/references/diode_rc.py`). In `f64` only (the bench's scalar); the state
/// is the charge, as the generated model's.
pub struct DiodeRcReduced(DiodeRcParams);

impl Model for DiodeRcReduced {
    type Params = DiodeRcParams;
    const NAME: &'static str = "DiodeRcReduced";
    const STATE_NAMES: &'static [&'static str] = &["cap.q"];
    const OUTPUT_NAMES: &'static [&'static str] = &[];

    fn params(&self) -> &DiodeRcParams {
        &self.0
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0[0] = 0.0;
    }

    fn derivatives<T: Scalar>(&self, _t: f64, x: &[T], dx: &mut [T]) {
        let p = &self.0;
        let v = x[0].to_f64() / p.c;
        let arg = (p.r * p.i_s / p.vt) * ((p.e0 - v + p.r * p.i_s) / p.vt).exp();
        dx[0] = T::from_f64(p.vt / p.r * lambert_w(arg) - p.i_s);
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}

/// `POINTS` deterministic (time, state) points: each state of `x0` moved by up to
/// ±`spread` of `scale[j]` (a golden-ratio sequence, so no two points are alike).
fn points(x0: &[f64], scale: &[f64], spread: f64, t_span: f64) -> Vec<(f64, Vec<f64>)> {
    (0..POINTS)
        .map(|i| {
            let s = (i as f64 * 0.618_033_988_749_895).fract() - 0.5;
            let x = x0
                .iter()
                .zip(scale)
                .enumerate()
                .map(|(j, (v, sc))| v + spread * sc * ((s * (j as f64 + 1.0) * 7.0).sin()))
                .collect();
            (t_span * (s + 0.5), x)
        })
        .collect()
}

/// The sum of every derivative at every point: what the benchmark loop computes.
fn sweep<M: Model>(model: &M, points: &[(f64, Vec<f64>)], dx: &mut [f64]) -> f64 {
    let mut sum = 0.0;
    for (t, x) in points {
        model.derivatives::<f64>(*t, x, dx);
        sum += dx.iter().sum::<f64>();
    }
    sum
}

/// One group: the generated model and its anchor on their own points.
fn group<M: Model, A: Model>(
    c: &mut Criterion,
    name: &str,
    (model, model_points): (&M, Vec<(f64, Vec<f64>)>),
    (anchor, anchor_points): (&A, Vec<(f64, Vec<f64>)>),
) {
    let mut group = c.benchmark_group(name);
    group.throughput(Throughput::Elements(POINTS as u64));
    group.bench_function("generated", |b| {
        let mut dx = vec![0.0; M::N_STATES];
        b.iter(|| sweep(black_box(model), black_box(&model_points), &mut dx))
    });
    group.bench_function("explicit_anchor", |b| {
        let mut dx = vec![0.0; A::N_STATES];
        b.iter(|| sweep(black_box(anchor), black_box(&anchor_points), &mut dx))
    });
    group.finish();
}

fn start<M: Model>(model: &M) -> Vec<f64> {
    let mut x0 = vec![0.0; M::N_STATES];
    model.initial_state(&mut x0);
    x0
}

fn derivatives(c: &mut Criterion) {
    let gear = Gear::default();
    let gear_reduced = GearReduced::default();
    group(
        c,
        "gear",
        (&gear, points(&start(&gear), &[1.0], 0.5, 1.0)),
        (
            &gear_reduced,
            points(&start(&gear_reduced), &[1.0], 0.5, 1.0),
        ),
    );

    let dampers = SeriesDampers::default();
    let dampers_reduced = SeriesDampersReduced::default();
    group(
        c,
        "series_dampers",
        (&dampers, points(&start(&dampers), &[1.0, 0.1], 0.5, 1.0)),
        (
            &dampers_reduced,
            points(&start(&dampers_reduced), &[1.0, 0.1], 0.5, 1.0),
        ),
    );

    // Charges from 0 to about 0.7 V on 10 µF: the loop as a run meets it, each point
    // solved by Newton from the previous point's solution.
    let diode = DiodeRc::default();
    let diode_reduced = DiodeRcReduced(DiodeRcParams::default());
    let charge = |i: usize| 7e-6 * (i as f64 * 0.618_033_988_749_895).fract();
    let diode_points: Vec<(f64, Vec<f64>)> = (0..POINTS).map(|i| (0.0, vec![charge(i)])).collect();
    // The anchor is the same physics: both give the same current to 1e-9.
    let (mut a, mut b) = ([0.0], [0.0]);
    for (t, x) in &diode_points {
        diode.derivatives(*t, x, &mut a);
        diode_reduced.derivatives(*t, x, &mut b);
        assert!(
            (a[0] - b[0]).abs() <= 1e-9 * b[0].abs(),
            "diode at {x:?}: {a:?} vs {b:?}"
        );
    }
    group(
        c,
        "diode_rc",
        (&diode, diode_points.clone()),
        (&diode_reduced, diode_points),
    );

    let crank = SliderCrank::default();
    let crank_reference = SliderCrankLagrange(crank.params.clone());
    let crank_scale = vec![1.0; SliderCrank::N_STATES];
    group(
        c,
        "slider_crank",
        (&crank, points(&start(&crank), &crank_scale, 0.05, 1.0)),
        (
            &crank_reference,
            points(&start(&crank_reference), &[1.0, 1.0], 0.05, 1.0),
        ),
    );

    // The four-bar's angles kept assembled: the points move the crank angle and
    // speed, and set θ3, θ4 by the closed form.
    let four_bar = FourBar::default();
    let four_bar_reference = FourBarLagrange(four_bar.params.clone());
    let reference_points = points(&start(&four_bar_reference), &[1.0, 1.0], 2.0, 1.0);
    let index = |name: &str| {
        FourBar::STATE_NAMES
            .iter()
            .position(|s| *s == name)
            .unwrap()
    };
    let generated_points = reference_points
        .iter()
        .map(|(t, x)| {
            let (t3, t4) = four_bar_angles(&four_bar.params, x[0]);
            let mut y = vec![0.0; FourBar::N_STATES];
            y[index("theta")] = x[0];
            y[index("crank.p")] = four_bar.params.j2 * x[1];
            y[index("theta3")] = t3;
            y[index("theta4")] = t4;
            (*t, y)
        })
        .collect();
    group(
        c,
        "four_bar",
        (&four_bar, generated_points),
        (&four_bar_reference, reference_points),
    );
}

criterion_group!(benches, derivatives);
criterion_main!(benches);
