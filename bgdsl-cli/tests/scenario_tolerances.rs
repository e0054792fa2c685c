//! Per-state tolerances in a scenario (`solver.atol` as a mapping) and
//! `solver.non_negative`: the program's run is bit for bit the run of
//! `Simulation::set_atol` / `set_non_negative` with the same settings, and a wrong
//! state name is an error at its line.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::LazyLock;

use bgdsl_cli::catalog::{RunPlan, Silent};
use bgdsl_cli::scenario::{parse, resolve, Diagnostics, Job, Overrides};
use bgdsl_cli::Catalogue;
use bgdsl_runtime::{bond_graph, FromParams, Model, Simulation};
use common::Scratch;

bond_graph! {
    /// A damped mass on a spring, started displaced: its position decays through zero
    /// and overshoots (negative), which `non_negative` then forbids.
    pub model Damped {
        param m = 1.0 in "kg";
        param k = 100.0 in "N/m";
        param c = 2.0 in "N·s/m";
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        R damper = c;
        1 v;
        v -> { mass, spring, damper };
        init spring.q = 0.1;
        /// Position of the mass, m.
        output x = spring.q in "m";
    }
}

static CATALOGUE: LazyLock<Catalogue> = LazyLock::new(|| bgdsl_cli::catalogue![Damped]);

/// The plan of the scenario `text` (with `flags`), into `out`, or its diagnostics as
/// text.
fn plan(text: &str, flags: Overrides, out: &Path) -> Result<RunPlan, String> {
    let loaded = parse(PathBuf::from("tol.yaml"), text.to_owned()).map_err(|d| d.to_string())?;
    let overrides = Overrides {
        out: Some(out.to_path_buf()),
        no_plots: true,
        ..flags
    };
    let shown = |d: Diagnostics| d.to_string();
    let mut read_errors = loaded.scenario.read_errors.clone();
    let plan = resolve(
        &CATALOGUE,
        Some(&loaded.source),
        &loaded.scenario,
        &overrides,
        "damped",
    );
    match plan {
        Ok(plan) if read_errors.is_empty() => match plan.job {
            Job::Run(run) => Ok(run),
            _ => Err("not a run".to_owned()),
        },
        Ok(_) => {
            read_errors.sort();
            Err(shown(read_errors))
        }
        Err(d) => Err(shown(d)),
    }
}

/// The states from the run's `damped.csv`: `(t, x)` per row in the state vector's
/// order, parsed back (the file's numbers are shortest round-trip: exact).
fn csv_states(dir: &Path) -> Vec<(f64, [f64; 2])> {
    let text = fs::read_to_string(dir.join("damped.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (t, x0, x1) = (
        at("t"),
        at(Damped::STATE_NAMES[0]),
        at(Damped::STATE_NAMES[1]),
    );
    lines
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
            (v[t], [v[x0], v[x1]])
        })
        .collect()
}

/// The same run straight through `Simulation`, with per-state `atol` and
/// `non_negative` applied as the plan says.
fn direct(plan: &RunPlan, atol: Option<&[f64]>, non_negative: &[usize]) -> Vec<(f64, [f64; 2])> {
    direct_with(&Damped::default(), plan, atol, non_negative)
}

/// [`direct`] on `model`.
fn direct_with(
    model: &Damped,
    plan: &RunPlan,
    atol: Option<&[f64]>,
    non_negative: &[usize],
) -> Vec<(f64, [f64; 2])> {
    let mut sim = Simulation::new(model, plan.solver).unwrap();
    if let Some(atol) = atol {
        sim.set_atol(atol).unwrap();
    }
    if !non_negative.is_empty() {
        sim.set_non_negative(non_negative).unwrap();
    }
    let mut x0 = [0.0; 2];
    model.initial_state(&mut x0);
    let mut rows = Vec::new();
    sim.run(
        plan.times[0],
        &x0,
        &plan.times,
        &mut |t: f64, x: &[f64], _: &[f64]| rows.push((t, [x[0], x[1]])),
    )
    .unwrap();
    rows
}

/// Runs `plan` with the program and returns its states.
fn program_run(plan: &RunPlan) -> Vec<(f64, [f64; 2])> {
    let entry = CATALOGUE.find("damped").unwrap();
    let outcome = entry.model.run(entry, plan, &Silent).unwrap();
    assert!(outcome.failure.is_none(), "{outcome:?}");
    csv_states(&plan.out_dir)
}

const PER_STATE: &str = "model: damped
time: {end: 2.0}
output: {interval: 0.01}
solver:
  method: radau5
  rtol: 1.0e-3
  atol:
    default: 1.0e-2
    spring.q: 1.0e-9
";

/// The index of state `name`.
fn state(name: &str) -> usize {
    Damped::STATE_NAMES.iter().position(|s| *s == name).unwrap()
}

/// `spring.q`'s atol `q`, `mass.p`'s `p`, in the state vector's order.
fn atols(q: f64, p: f64) -> Vec<f64> {
    let mut atol = vec![0.0; 2];
    atol[state("spring.q")] = q;
    atol[state("mass.p")] = p;
    atol
}

#[test]
fn per_state_atol_is_the_run_of_set_atol() {
    let dir = Scratch::new("atol");
    let plan = plan(PER_STATE, Overrides::default(), &dir.join("run")).unwrap();
    assert_eq!(plan.atol, Some(atols(1e-9, 1e-2)));
    let ran = program_run(&plan);
    let expected = direct(&plan, Some(&atols(1e-9, 1e-2)), &[]);
    assert_eq!(ran.len(), 201);
    // Bit for bit, sample by sample.
    assert_eq!(ran, expected);
    // And it matters: with the default atol for both states the run differs.
    let loose = direct(&plan, None, &[]);
    assert!(ran.iter().zip(&loose).any(|(a, b)| a != b));
    // The run record says what was set.
    let record = fs::read_to_string(plan.out_dir.join("run.yaml")).unwrap();
    assert!(
        record
            .contains("  atol: 0.01\n  max_steps: 100000\n  atol_by_state:\n    spring.q: 1e-9\n"),
        "{record}"
    );
}

#[test]
fn the_flag_replaces_only_the_default() {
    let dir = Scratch::new("flag");
    let flags = Overrides {
        atol: Some(1e-4),
        ..Overrides::default()
    };
    let plan = plan(PER_STATE, flags, &dir).unwrap();
    assert_eq!(plan.atol, Some(atols(1e-9, 1e-4)));
}

#[test]
fn a_scalar_atol_sets_no_per_state_list() {
    let dir = Scratch::new("scalar");
    let text = "model: damped\nsolver: {method: radau5, atol: 1.0e-7}\n";
    let plan = plan(text, Overrides::default(), &dir).unwrap();
    assert_eq!(plan.atol, None);
    assert!(matches!(plan.solver, bgdsl_runtime::Solver::Radau5(o) if o.atol == 1e-7));
}

/// `non_negative` on the overdamped oscillator (`c = 50`: rates 2.0 and 48 s⁻¹), whose
/// position decays to zero from above without crossing it, but which a loose run (rtol
/// = atol = 1e-2, to t = 20) takes slightly below zero: the program's run is the
/// direct one with `set_non_negative`, bit for bit, and stays >= 0.
#[test]
fn non_negative_is_the_run_of_set_non_negative() {
    let dir = Scratch::new("nonneg");
    let text = "model: damped
parameters: {c: 50.0}
time: {end: 20.0}
output: {interval: 0.01}
solver:
  method: radau5
  rtol: 1.0e-2
  atol: 1.0e-2
  non_negative: [spring.q]
";
    let plan = plan(text, Overrides::default(), &dir.join("run")).unwrap();
    let q = state("spring.q");
    assert_eq!(plan.non_negative, [q]);
    let ran = program_run(&plan);
    let model = Damped::from_params(DampedParams {
        c: 50.0,
        ..DampedParams::default()
    });
    assert_eq!(ran, direct_with(&model, &plan, None, &[q]));
    assert!(ran.iter().all(|(_, x)| x[q] >= 0.0));
    let free = direct_with(&model, &plan, None, &[]);
    let lowest = free.iter().map(|(_, x)| x[q]).fold(f64::INFINITY, f64::min);
    // Unconstrained, the loose run ends slightly below zero (measured -1.6e-6).
    assert!(lowest < 0.0, "{lowest}");
    let record = fs::read_to_string(plan.out_dir.join("run.yaml")).unwrap();
    assert!(
        record.contains("  non_negative:\n  - spring.q\n"),
        "{record}"
    );
}

#[test]
fn bad_names_and_values_are_errors_at_their_line() {
    let dir = Scratch::new("bad");
    let text = "model: damped
solver:
  atol:
    spring.x: 1.0e-9
    mass.p: -1.0
  non_negative: [spring.q, nothing]
";
    let err = plan(text, Overrides::default(), &dir).unwrap_err();
    assert_eq!(
        err,
        "tol.yaml:4:5: unknown state `spring.x`; the states of damped are: mass.p, spring.q\n\
         tol.yaml:5:5: the atol of `mass.p` must be a finite number > 0, found -1\n\
         tol.yaml:6:3: unknown state `nothing`; the states of damped are: mass.p, spring.q"
    );
}

#[test]
fn fixed_step_solvers_refuse_per_state_settings() {
    let dir = Scratch::new("fixed");
    let text = "model: damped
solver:
  method: rk4
  atol: {spring.q: 1.0e-9}
  non_negative: [spring.q]
";
    let err = plan(text, Overrides::default(), &dir).unwrap_err();
    assert_eq!(
        err,
        "tol.yaml:4:3: atol does not apply to the fixed-step solver rk4; set `step`\n\
         tol.yaml:5:3: non_negative applies only to the adaptive solvers, not the fixed-step \
         rk4"
    );
}

#[test]
fn a_wrong_type_is_a_shape_error() {
    let dir = Scratch::new("type");
    let text = "model: damped\nsolver:\n  atol: [1, 2]\n";
    let err = plan(text, Overrides::default(), &dir).unwrap_err();
    assert_eq!(
        err,
        "tol.yaml:3:3: solver.atol: invalid type: sequence, expected f64"
    );
}
