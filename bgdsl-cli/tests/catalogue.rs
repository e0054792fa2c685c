//! `bgdsl-cli` over a catalogue of its own, as a user's program has: the `catalogue!`
//! defaults, the entry builder, a generic run checked against the closed form, and the
//! extras hooks (a recorder, a results file, a summary line, an `index.html` section).

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::LazyLock;

use bgdsl_cli::catalog::{
    ExtraRun, Extras, Finished, RunContext, RunError, RunPlan, Silent, Written,
};
use bgdsl_cli::scenario::{resolve, Job, Overrides, Scenario};
use bgdsl_cli::{Catalogue, Entry};
use bgdsl_runtime::{bond_graph, Recorder, Solver};
use common::Scratch;

bond_graph! {
    /// A mass on a spring, undamped: `x(t) = x0 cos(ω t)` with `ω = sqrt(k / m)`.
    pub model MassSpring {
        /// mass
        param m = 1.0 in "kg";
        /// stiffness
        param k = 4.0 in "N/m";
        I mass = m, p in "kg·m/s";
        C spring = k, q in "m";
        1 v;
        v -> { mass, spring };
        init spring.q = 0.1;
        /// Position of the mass, m.
        output x = spring.q in "m";
        /// Velocity of the mass, m/s.
        output speed = v.f in "m/s";
    }
}

/// Counts the samples of a run, writes the count to `count.txt`, adds a summary line
/// and a page section.
struct Counter;

/// One run's count.
struct Counting {
    samples: usize,
}

impl Recorder for Counting {
    fn record(&mut self, _t: f64, _x: &[f64], _y: &[f64]) {
        self.samples += 1;
    }
}

impl ExtraRun for Counting {
    fn write(&mut self, dir: &Path) -> Result<Written, RunError> {
        let path = dir.join("count.txt");
        fs::write(&path, self.samples.to_string()).map_err(|source| RunError::Io {
            path,
            action: "writing",
            source,
        })?;
        Ok(Written {
            results: vec!["count.txt".to_owned()],
            others: Vec::new(),
        })
    }

    fn summary_tail(&self, run: &Finished<'_>) -> String {
        format!(
            "counted        {} samples of {}\n",
            self.samples, run.entry.name
        )
    }

    fn sections(&self) -> Vec<String> {
        vec![format!(
            "<section id=\"count\">{} samples</section>\n",
            self.samples
        )]
    }
}

/// How many runs [`Counter`] started.
static STARTED: AtomicUsize = AtomicUsize::new(0);

impl Extras for Counter {
    fn start<'a>(
        &'a self,
        _run: &RunContext<'a>,
    ) -> Result<Option<Box<dyn ExtraRun + 'a>>, RunError> {
        STARTED.fetch_add(1, Ordering::SeqCst);
        Ok(Some(Box::new(Counting { samples: 0 })))
    }
}

static CATALOGUE: LazyLock<Catalogue> = LazyLock::new(|| {
    bgdsl_cli::catalogue![MassSpring].entry(
        Entry::of::<MassSpring>()
            .name("counted")
            .description("the mass on a spring, counted")
            .t_end(2.0)
            .interval(0.5)
            .solver(Solver::dopri5())
            .checks(|p: &MassSpringParams, checks| checks.positive("m", p.m))
            .extras(Counter),
    )
});

/// The run plan of model `name` with `--set` settings, into `out`, without figures.
fn plan(name: &str, set: &[&str], out: &Path) -> Result<RunPlan, String> {
    let scenario = Scenario {
        model: name.to_owned(),
        ..Scenario::default()
    };
    let overrides = Overrides {
        set: set.iter().map(|s| (*s).to_owned()).collect(),
        out: Some(out.to_path_buf()),
        no_plots: true,
        ..Overrides::default()
    };
    match resolve(&CATALOGUE, None, &scenario, &overrides, name) {
        Ok(plan) => match plan.job {
            Job::Run(run) => Ok(run),
            Job::Sweep(_) | Job::Study(_) => Err("not a run".to_owned()),
        },
        Err(d) => Err(d.to_string()),
    }
}

#[test]
fn the_macro_names_the_package_and_snake_cases_the_model() {
    assert_eq!(CATALOGUE.program, "bgdsl-cli");
    // The FMUs' library: the package's `cdylib`, `libbgdsl_cli.so` on Linux.
    assert_eq!(CATALOGUE.fmi_package, "bgdsl-cli");
    assert_eq!(
        bgdsl_fmi_core::library_name(&CATALOGUE.fmi_package),
        "bgdsl_cli"
    );
    assert_eq!(CATALOGUE.names(), ["mass_spring", "counted"]);
    let entry = CATALOGUE.find("mass_spring").unwrap();
    assert_eq!(entry.description, "MassSpring");
    assert_eq!((entry.t_end, entry.interval), (10.0, 0.01));
    assert_eq!(entry.solver, Solver::stiff());
    assert_eq!(
        CATALOGUE.find("pump").unwrap_err().to_string(),
        "unknown model `pump`; the models are: mass_spring, counted"
    );
}

#[test]
fn a_generic_run_follows_the_closed_form() {
    let dir = Scratch::new("closed-form");
    let out = dir.join("run");
    let entry = CATALOGUE.find("mass_spring").unwrap();
    let plan = plan("mass_spring", &["m=0.25"], &out).unwrap();
    let outcome = entry.model.run(entry, &plan, &Silent).unwrap();
    assert!(outcome.failure.is_none(), "{:?}", outcome.failure);
    let csv = fs::read_to_string(out.join("mass_spring.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("t,mass.p,spring.q,x,speed"));
    // m = 0.25 kg, k = 4 N/m: ω = 4 rad/s, x = 0.1 cos(4 t). Radau5 at its default
    // rtol 1e-6 stays within 1e-6 m of it over the 6.4 periods of 10 s (2.3e-7 m
    // measured).
    let mut rows = 0;
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
        let exact = 0.1 * (4.0 * v[0]).cos();
        assert!(
            (v[3] - exact).abs() < 1e-6,
            "t = {}: x = {} vs {exact}",
            v[0],
            v[3]
        );
        rows += 1;
    }
    assert_eq!(rows, 1001, "0 to 10 s every 0.01 s");
    let units = fs::read_to_string(out.join("mass_spring.units.csv")).unwrap();
    assert!(
        units.contains("\nx,m,\"Position of the mass, m.\"\n"),
        "{units}"
    );
    assert!(out.join("run.yaml").is_file() && out.join("index.html").is_file());
    let record = fs::read_to_string(out.join("run.yaml")).unwrap();
    assert!(record.contains("name: bgdsl-cli"), "{record}");
}

#[test]
fn the_entry_checks_reject_unphysical_parameters() {
    let dir = Scratch::new("checks");
    let err = plan("counted", &["m=0"], &dir.join("run")).unwrap_err();
    assert!(
        err.contains("--set m=0: parameter `m` (mass, kg) must be > 0, found 0"),
        "{err}"
    );
    // The entry without checks takes it (only "finite" applies).
    assert!(plan("mass_spring", &["m=0"], &dir.join("run")).is_ok());
}

#[test]
fn extras_record_write_and_add_to_the_summary_and_the_page() {
    let dir = Scratch::new("extras");
    let out = dir.join("run");
    let entry = CATALOGUE.find("counted").unwrap();
    let plan = plan("counted", &[], &out).unwrap();
    let before = STARTED.load(Ordering::SeqCst);
    let outcome = entry.model.run(entry, &plan, &Silent).unwrap();
    assert_eq!(STARTED.load(Ordering::SeqCst), before + 1);
    // 0, 0.5, ..., 2 s.
    assert_eq!(fs::read_to_string(out.join("count.txt")).unwrap(), "5");
    assert_eq!(
        outcome.files[0],
        out.join("count.txt"),
        "the extras' files first"
    );
    assert_eq!(outcome.files[1], out.join("counted.csv"));
    assert!(
        outcome
            .summary
            .contains("counted        5 samples of counted\n"),
        "{}",
        outcome.summary
    );
    let page = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains("<section id=\"count\">5 samples</section>"));
    let section = page.find("<section id=\"count\">").unwrap();
    assert!(page.find("Summary of the run").unwrap() < section);
    assert!(section < page.find("<h2>Figures</h2>").unwrap());
}

#[test]
fn help_names_the_program_and_its_first_model() {
    let mut command = bgdsl_cli::cli::command(&CATALOGUE);
    let help = command.render_long_help().to_string();
    assert!(
        help.starts_with("Run the bond-graph models of bgdsl-cli."),
        "{help}"
    );
    assert!(
        help.contains("Without a command, runs mass_spring and writes out/mass_spring/."),
        "{help}"
    );
    let params = command
        .find_subcommand_mut("params")
        .unwrap()
        .render_long_help()
        .to_string();
    assert!(
        params.contains("The model (see `bgdsl-cli list`)"),
        "{params}"
    );
    assert!(!params.contains("`models "), "{params}");
}

/// `run` and every analysis command take the same model flags ([`ModelArgs`], one help
/// text each): their long helps list each of them with the same text, and only `run`
/// has the flags of a run alone.
///
/// [`ModelArgs`]: bgdsl_cli::cli::ModelArgs
#[test]
fn run_and_the_analyses_share_the_model_flags_and_their_help() {
    let shared = [
        "--out",
        "--set",
        "--solver",
        "--rtol",
        "--atol",
        "--t-start",
        "--t-end",
        "--max-steps",
        "--no-plots",
    ];
    let mut command = bgdsl_cli::cli::command(&CATALOGUE);
    let mut helps = Vec::new();
    for name in ["run", "steady", "linearize", "bode", "periodic", "fit"] {
        let sub = command.find_subcommand_mut(name).unwrap();
        let mut texts = Vec::new();
        for flag in shared {
            let arg = sub
                .get_arguments()
                .find(|a| a.get_long() == Some(&flag[2..]))
                .unwrap_or_else(|| panic!("`{name}` has no {flag}"));
            texts.push(arg.get_long_help().or(arg.get_help()).unwrap().to_string());
        }
        let help = sub.render_long_help().to_string();
        for flag in shared {
            assert!(
                help.contains(&format!("{flag} ")) || help.contains(&format!("{flag}\n")),
                "{help}"
            );
        }
        assert_eq!(
            help.contains("--step <X>") && help.contains("--interval <X>"),
            name == "run",
            "{help}"
        );
        // The renamed program's text, not `models`'.
        assert!(help.contains("(see `bgdsl-cli list`)"), "{help}");
        helps.push((name, texts));
    }
    for (name, texts) in &helps[1..] {
        assert_eq!(
            texts, &helps[0].1,
            "`{name}`'s flags are described as `run`'s"
        );
    }
}

/// The shared scratch folder is removed when its test passes and kept, for inspection,
/// when its test fails (dropped while the thread panics).
#[test]
fn a_scratch_folder_is_kept_only_when_its_test_fails() {
    let passed = Scratch::new("passes");
    fs::write(passed.join("file"), "x").unwrap();
    let path = passed.to_path_buf();
    drop(passed);
    assert!(!path.exists());
    let failed = std::thread::spawn(|| {
        let dir = Scratch::new("fails");
        fs::write(dir.join("file"), "x").unwrap();
        let path = dir.to_path_buf();
        std::panic::panic_any(path);
    })
    .join()
    .unwrap_err();
    let kept = failed.downcast::<PathBuf>().unwrap();
    assert!(kept.join("file").is_file());
    fs::remove_dir_all(*kept).unwrap();
}
