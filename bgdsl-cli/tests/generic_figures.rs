//! The generic figures over a catalogue of this test's own: state charts only on
//! request beyond `STATE_CHART_LIMIT` states, and an entry whose extras draw their own
//! figures getting neither state charts nor the energy balance (its page still shows
//! the causal graph).

mod common;

use std::fs;
use std::path::Path;
use std::sync::LazyLock;

use bgdsl_cli::catalog::{Extras, Plots, RunPlan, Silent, STATE_CHART_LIMIT};
use bgdsl_cli::scenario::{resolve, Job, Overrides, Scenario};
use bgdsl_cli::{Catalogue, Entry};
use bgdsl_runtime::bond_graph;
use common::Scratch;

bond_graph! {
    /// Seven undamped mass-spring pairs side by side: fourteen states.
    pub model Seven {
        param m = 1.0 in "kg";
        param k = 4.0 in "N/m";
        I m1 = m, p in "kg·m/s"; C s1 = k, q in "m"; 1 v1; v1 -> { m1, s1 };
        I m2 = m, p in "kg·m/s"; C s2 = k, q in "m"; 1 v2; v2 -> { m2, s2 };
        I m3 = m, p in "kg·m/s"; C s3 = k, q in "m"; 1 v3; v3 -> { m3, s3 };
        I m4 = m, p in "kg·m/s"; C s4 = k, q in "m"; 1 v4; v4 -> { m4, s4 };
        I m5 = m, p in "kg·m/s"; C s5 = k, q in "m"; 1 v5; v5 -> { m5, s5 };
        I m6 = m, p in "kg·m/s"; C s6 = k, q in "m"; 1 v6; v6 -> { m6, s6 };
        I m7 = m, p in "kg·m/s"; C s7 = k, q in "m"; 1 v7; v7 -> { m7, s7 };
        init s1.q = 0.1;
        /// Position of the first mass, m.
        output x1 = s1.q in "m";
    }
}

/// Extras that draw figures of their own (none here), so the entry opts out of the
/// generic ones.
struct OwnFigures;

impl Extras for OwnFigures {
    fn figure_ids(&self) -> Option<&'static [&'static str]> {
        Some(&["mine"])
    }
}

static CATALOGUE: LazyLock<Catalogue> = LazyLock::new(|| {
    bgdsl_cli::catalogue![Seven].entry(
        Entry::of::<Seven>()
            .name("own")
            .t_end(1.0)
            .interval(0.01)
            .extras(OwnFigures),
    )
});

/// The plan of `name` over 1 s with `plots`, into `out`.
fn plan(name: &str, plots: Option<&str>, out: &Path) -> RunPlan {
    let scenario = Scenario {
        model: name.to_owned(),
        plots: plots.map(|p| serde_yaml::from_str(p).unwrap()),
        ..Scenario::default()
    };
    let overrides = Overrides {
        out: Some(out.to_path_buf()),
        t_end: Some(1.0),
        interval: Some(0.01),
        ..Overrides::default()
    };
    match resolve(&CATALOGUE, None, &scenario, &overrides, name)
        .unwrap()
        .job
    {
        Job::Run(run) => run,
        Job::Sweep(_) | Job::Study(_) => panic!("a sweep or a study"),
    }
}

/// The images of a run of `name`, its summary and its page.
fn run(name: &str, plots: Option<&str>, dir: &Path) -> (Vec<String>, String, String) {
    let out = dir.join(name);
    let entry = CATALOGUE.find(name).unwrap();
    let outcome = entry
        .model
        .run(entry, &plan(name, plots, &out), &Silent)
        .unwrap();
    assert!(
        outcome.failure.is_none() && outcome.figures_error.is_none(),
        "{outcome:?}"
    );
    let mut images: Vec<String> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png"))
        .collect();
    images.sort();
    let page = fs::read_to_string(out.join("index.html")).unwrap();
    (images, outcome.summary, page)
}

#[test]
fn many_states_are_drawn_only_when_named() {
    const { assert!(Seven::N_STATES > STATE_CHART_LIMIT) };
    let dir = Scratch::new("many");
    let (images, summary, page) = run("seven", None, &dir);
    assert_eq!(images, ["energy_balance.png", "x1.png"]);
    assert!(
        summary.contains("\nenergy balance largest residual "),
        "{summary}"
    );
    assert!(page.contains("<section id=\"causal-graph\">"));
    let (images, _, _) = run("seven", Some("[m3.p, x1]"), &dir);
    assert_eq!(images, ["state_m3_p.png", "x1.png"]);
    assert_eq!(
        plan("seven", Some("[m3.p]"), &dir.join("p")).plots,
        Plots::Only(vec!["m3.p".into()])
    );
}

#[test]
fn extras_with_figures_of_their_own_opt_out() {
    let dir = Scratch::new("own");
    let (images, summary, page) = run("own", None, &dir);
    // The outputs the entry records by default are still charted (the extras' hook
    // rule); no states, no energy balance.
    assert_eq!(images, ["x1.png"]);
    assert!(!summary.contains("energy balance"), "{summary}");
    assert!(page.contains("<section id=\"causal-graph\">"));
}
