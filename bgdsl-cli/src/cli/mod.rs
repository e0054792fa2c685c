//! The program: its command line (clap) and the commands behind it, over a
//! [`Catalogue`]. Shown here for the `models` program of this repository (another
//! program has its own name and models; without a command it runs its first model).
//!
//! ```text
//! models                                  the flagship: `models run quick_return`
//! models list                             the models, one line each
//! models params <model> [--states] [--outputs]
//!                                         parameters with defaults, units and docs
//! models run <model | scenario.yaml> [--out DIR] [--set NAME=VALUE ...]
//!            [--solver NAME] [--rtol X] [--atol X] [--step X] [--max-steps N]
//!            [--t-start X] [--t-end X] [--interval X] [--no-plots] [--phase X,Y ...]
//!            [--yes] [--shard K/N]
//! models merge DIR... [--out DIR]         join shard folders into the one-process result
//! models graph <model> [--svg]            the causal bond graph as DOT (or SVG via `dot`)
//! models steady <model | scenario.yaml> [--guess STATE=VALUE ...] [--hold STATE ...]
//!                                         the equilibrium: steady.yaml
//! models linearize <model | scenario.yaml> [--at initial|steady|TIME]
//!            [--inputs U,V] [--outputs Y,Z]
//!                                         A, B, C, D and the modes: linear.json, A.csv…
//! models bode <model | scenario.yaml> --input U --output Y [--from F] [--to F]
//!            [--points N] [--at initial|steady|TIME]
//!                                         frequency responses: bode.csv, figures
//! models periodic …, models fit …         periodic orbits, parameter fitting
//! ```
//!
//! The analysis commands ([`analysis`]) take the model, `--set`, the solver flags and
//! `--out` as `run` does (one set of flags, [`ModelArgs`]), and write their results set (with `run.yaml` and
//! `index.html`) into `out/<model>-<command>/` by default; a failed analysis (a
//! singular Jacobian, no convergence) exits with status 1 and writes nothing.
//!
//! # Exit status
//!
//! | status | meaning |
//! |---|---|
//! | 0 | success |
//! | 1 | the run failed or was interrupted (a first SIGINT, SIGTERM or SIGHUP): its partial set is in `<out>.partial/` and `<out>` is untouched; or the set could not be written (nothing changed), or `dot` failed |
//! | 2 | a usage or validation error: bad flags, an unknown model, a scenario error, an output folder with foreign content, a run larger than the size guard allows without `--yes`, a `--shard` of a single run, a `merge` of folders that are not all the shards of one complete study; nothing was written |
//! | 69 | a missing external prerequisite, nothing written: Graphviz's `dot` for `graph --svg`, the FMI library for `fmu` (`lib<package>.so` of the catalogue's [`fmi_package`](crate::Catalogue::fmi_package), `libbgdsl_fmi.so` for `models`; missing or built from other model code) (69 is `EX_UNAVAILABLE` of `sysexits.h`) |
//! | 130 | a second signal (SIGINT, SIGTERM or SIGHUP) during a run: the staging folder is removed, `<out>` and `<out>.partial/` are untouched |
//!
//! The flags of `run` override the scenario's keys of the same meaning (`--step` and
//! `--max-steps` its `solver.step` and `solver.max_steps`, `--t-start` and `--t-end` its
//! `time`, `--interval` its `output.interval` or `output.count`) and are checked by the
//! same code, with the same messages (placed at the flag).
//!
//! Errors go to stderr, one line each (a scenario with several errors gives several
//! lines, each `file:line:column: message`); summaries go to stdout.

pub mod analysis;
mod fmu;
mod graph;
mod info;
mod progress;
mod run;

use core::fmt;
use std::path::PathBuf;

use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};

use crate::catalog::{Catalogue, RunError};
use crate::scenario::{Diagnostics, Overrides};

pub use progress::Progress;

/// The exit statuses, for `--help`.
const EXIT_HELP: &str = "Exit status: 0 success; 1 the run failed part-way or was \
    interrupted (partial results in <out>.partial/, <out> untouched) or output could \
    not be written; 2 usage or validation error (nothing written); 69 a missing \
    external prerequisite (Graphviz's `dot` for `graph --svg`, the FMI library for \
    `fmu`; nothing written); 130 a second SIGINT/SIGTERM (nothing temporary left).";

/// The command line. Its name, version and `--help` text come from the catalogue
/// ([`parse`]).
#[derive(Debug, Parser)]
pub struct Cli {
    /// What to do (default: run the catalogue's first model).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List the models, one line each.
    List,
    /// Show a model's parameters: defaults, units and docs.
    Params {
        /// The model (see `models list`).
        model: String,
        /// Also list the states with their initial values.
        #[arg(long)]
        states: bool,
        /// Also list the outputs.
        #[arg(long)]
        outputs: bool,
    },
    /// Run a model with its defaults, or a scenario file.
    Run(Box<RunArgs>),
    /// Export the model as an FMI 2.0 FMU (Model Exchange and Co-Simulation).
    ///
    /// The FMU carries the FMI shared library of the program's models
    /// (`lib<package>.so`, the `cdylib` of the crate that invokes `export_fmi2!`, built
    /// with `cargo build -p <package> --release`), found beside this program or at
    /// $BGDSL_FMI_LIBRARY.
    Fmu {
        /// The model (see `models list`).
        model: String,
        /// The FMU file (a name ending in .fmu), or a folder to write `<model>.fmu`
        /// into (default: out/fmu/). Missing folders are created, as `run --out` does.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Join the shard folders of a sweep or study (`run ... --shard K/N`) into the
    /// one-process result.
    ///
    /// Refuses folders of different studies, a shard given twice, missing or partial
    /// shards. Writes the data files the run without shards writes, bit for bit, and
    /// draws the figures and index.html again.
    Merge {
        /// The shard folders, all N of them, in any order.
        #[arg(required = true, value_name = "DIR")]
        dirs: Vec<PathBuf>,
        /// The output folder [default: the first folder's name without
        /// `-shard-K-of-N`].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Print the model's causal bond graph as Graphviz DOT (or SVG).
    Graph {
        /// The model (see `models list`).
        model: String,
        /// Draw it as SVG with Graphviz's `dot` program.
        #[arg(long)]
        svg: bool,
    },
    /// Find the model's equilibrium (dx/dt = 0, inputs held) by Newton's method on the
    /// exact Jacobian, from the initial state or a guess; writes steady.yaml.
    ///
    /// A singular Jacobian (a free rigid-body motion, an integrator in a loop) is an
    /// error naming the states it leaves undetermined: hold them (`--hold`) or add
    /// what fixes them. Results in out/MODEL-steady/ (see --out); a failure writes
    /// nothing. Example: `models steady dc_motor --set voltage=24`.
    Steady(Box<analysis::steady::SteadyArgs>),
    /// The linear model dx = A dx + B du, dy = C dx + D du at an operating point,
    /// exact by dual numbers, with its modes; writes linear.json, A.csv–D.csv,
    /// linear.m, modes.csv and the eigenvalue plane.
    ///
    /// Inputs are declared inputs or scalar parameters. Example:
    /// `models linearize rlc --inputs voltage --outputs current --at steady`.
    Linearize(Box<analysis::linearize::LinearizeArgs>),
    /// Frequency responses H(jω) = C (jωI − A)⁻¹ B + D from inputs to outputs at an
    /// operating point; writes bode.csv and the magnitude and phase figures.
    ///
    /// Frequencies in hertz. Example:
    /// `models bode butterworth --input voltage --output load_voltage --from 0.01 --to 10`.
    Bode(Box<analysis::bode::BodeArgs>),
    /// The periodic steady state of a periodically driven model.
    Periodic(Box<analysis::periodic::PeriodicArgs>),
    /// Fit parameters to measured signals.
    Fit(Box<analysis::fit::FitArgs>),
}

/// The model and its settings: the arguments `models run` and every analysis command
/// (`steady`, `linearize`, `bode`, `periodic`, `fit`) share, each flag's help written
/// once, and checked by the same code ([`ModelArgs::overrides`], the scenario's
/// resolution).
#[derive(Clone, Debug, Default, Args)]
pub struct ModelArgs {
    /// A model name (see `models list`) or a scenario file (.yaml): its parameters,
    /// initial state, time span and solver are used; a sweep or Monte Carlo study runs
    /// only under `run` (the analysis commands refuse it).
    #[arg(value_name = "MODEL | SCENARIO.yaml")]
    pub target: String,
    /// The output directory [default: out/NAME for `run`, out/NAME-COMMAND for an
    /// analysis (e.g. out/rlc-linearize); with settings, followed by -SETTINGS].
    ///
    /// NAME is the model's name or the scenario file's without its extension.
    /// SETTINGS lists the command line's overrides as key=value joined by commas: the
    /// --set parameters sorted by name, then solver, rtol, atol, step, t_start, t_end,
    /// interval and max_steps when given, then an analysis's own options (e.g.
    /// at=steady) (e.g. `models run quick_return --set d=0.3 --set w_drive=4` writes
    /// out/quick_return-d=0.3,w_drive=4); a list longer than 64 characters, or with
    /// characters other than letters, digits and `._+-=,`, is cut to 40 and followed by
    /// a hash of the whole. --no-plots does not count. The folder is replaced whole
    /// when the command succeeds and left as it was when it fails (a run that fails
    /// part-way writes its partial results beside it, in <out>.partial/). Every results
    /// folder holds run.yaml, the record of what produced it.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Set a parameter, e.g. `--set g=0` or `--set l1=[0.2,0.01,0.01]` (repeatable;
    /// overrides the scenario).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// The solver of every run the command makes (an analysis's: an operating point
    /// at a time, an orbit, a fit): rk4, dopri5, dopri5-fixed, radau5, rodas4 or
    /// rodas5p.
    #[arg(long, value_name = "NAME")]
    pub solver: Option<String>,
    /// Relative tolerance of an adaptive solver, in [1e-14, 0.1].
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub rtol: Option<f64>,
    /// Absolute tolerance of an adaptive solver, > 0.
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub atol: Option<f64>,
    /// The start of the time span, s: where the initial state is, and the time at which
    /// an equilibrium's rates are evaluated [default: 0, or the scenario's
    /// `time.start`].
    #[arg(long = "t-start", value_name = "X", allow_negative_numbers = true)]
    pub t_start: Option<f64>,
    /// The end of the time span, s (a run's; the analyses run only as far as they
    /// need).
    #[arg(long = "t-end", value_name = "X", allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// The solver's step budget, > 0.
    #[arg(long = "max-steps", value_name = "N")]
    pub max_steps: Option<usize>,
    /// Draw no figures.
    #[arg(long)]
    pub no_plots: bool,
}

impl ModelArgs {
    /// The command line's overrides of the scenario that these flags give (the
    /// run-only ones, `--step`, `--interval`, `--phase`, unset), with the program's
    /// arguments for the record.
    pub fn overrides(&self) -> Overrides {
        Overrides {
            set: self.set.clone(),
            solver: self.solver.clone(),
            rtol: self.rtol,
            atol: self.atol,
            t_start: self.t_start,
            t_end: self.t_end,
            max_steps: self.max_steps,
            no_plots: self.no_plots,
            out: self.out.clone(),
            command_line: std::env::args_os()
                .map(|a| a.to_string_lossy().into_owned())
                .collect(),
            ..Overrides::default()
        }
    }
}

/// The arguments of `models run`: the model and its settings, and the flags only a
/// run has.
#[derive(Clone, Debug, Default, Args)]
pub struct RunArgs {
    /// The model and its settings.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The step of a fixed-step solver (rk4, dopri5-fixed), s, > 0.
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub step: Option<f64>,
    /// Seconds between samples, > 0 (replaces the scenario's `interval` or `count`).
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub interval: Option<f64>,
    /// A phase portrait: two state or output names, e.g. `--phase x,speed`
    /// (repeatable; beside the scenario's `plots: {phase: [[x, speed]]}`).
    #[arg(long, value_name = "X,Y")]
    pub phase: Vec<String>,
    /// Run only the K-th of N disjoint parts of a sweep or Monte Carlo study (K in
    /// 1..=N), into a shard folder [default: out/NAME-shard-K-of-N] that `merge`
    /// joins with the others (for Slurm: `--shard ${SLURM_ARRAY_TASK_ID}/N` with
    /// `--array=1-N`; for a Kubernetes Indexed Job:
    /// `--shard $((JOB_COMPLETION_INDEX + 1))/N`).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<crate::study::shard::Shard>,
    /// Run even if the results would take more than 1 GB (rows × columns × 24 bytes),
    /// or a sweep has more than 1000 runs, 1e8 samples in all or an estimated hour;
    /// without it the program asks at a terminal and refuses otherwise.
    #[arg(long)]
    pub yes: bool,
}

/// Why a command did not succeed; [`Failure::exit_code`] maps it to the exit status.
#[derive(Debug)]
pub enum Failure {
    /// A usage error: an unknown model, a missing program.
    Usage(String),
    /// The scenario or the flags are invalid; nothing was written.
    Invalid(Diagnostics),
    /// The run could not write its results.
    Run(RunError),
    /// The run stopped part-way; its partial results were written.
    Partial {
        /// Why it stopped.
        reason: String,
        /// The partial results file.
        file: Option<PathBuf>,
    },
    /// A program or file the command needs from outside is missing or unusable
    /// (Graphviz's `dot`, the FMI library); nothing was written.
    Prerequisite(String),
    /// Something else failed (writing to stdout, running `dot`).
    Other(String),
}

impl Failure {
    /// The exit status: 2 for usage and validation errors, 69 for a missing
    /// prerequisite (`EX_UNAVAILABLE`), 1 for the rest.
    pub fn exit_code(&self) -> u8 {
        match self {
            Failure::Usage(_) | Failure::Invalid(_) | Failure::Run(RunError::NotOurs { .. }) => 2,
            Failure::Prerequisite(_) => 69,
            Failure::Run(_) | Failure::Partial { .. } | Failure::Other(_) => 1,
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Usage(message) | Failure::Prerequisite(message) | Failure::Other(message) => {
                f.write_str(message)
            }
            Failure::Invalid(d) => write!(f, "{d}"),
            Failure::Run(e) => write!(f, "{e}"),
            Failure::Partial { reason, file } => {
                write!(f, "{reason}")?;
                if let Some(file) = file {
                    write!(
                        f,
                        "; partial results in {} (the output folder was left as it was)",
                        file.display()
                    )?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for Failure {}

/// The clap command of `catalogue`'s program: its name, version, and `--help` saying
/// what it runs without a command.
pub fn command(catalogue: &'static Catalogue) -> clap::Command {
    let program = catalogue.program.as_str();
    let default = match (&catalogue.default_help, catalogue.entries().first()) {
        (Some(text), _) => text.clone(),
        (None, Some(first)) => format!(
            "Without a command, runs {} and writes out/{}/.",
            first.name, first.name
        ),
        (None, None) => "The catalogue has no model.".to_owned(),
    };
    let long_about = format!("{}\n\n{default}\n\n{EXIT_HELP}", catalogue.about);
    let mut command = Cli::command()
        .name(program)
        .version(catalogue.version.as_str())
        .about(catalogue.about.as_str())
        .long_about(long_about);
    if program != "models" {
        command = rename(command, program);
    }
    command
}

/// The help texts' "`models list`" and the like, in another program's name.
fn rename(command: clap::Command, program: &str) -> clap::Command {
    let fix = |text: Option<&clap::builder::StyledStr>| {
        text.map(|t| t.to_string().replace("`models ", &format!("`{program} ")))
    };
    let names: Vec<String> = command
        .get_subcommands()
        .map(|c| c.get_name().to_owned())
        .collect();
    let mut command = command;
    for name in names {
        command = command.mut_subcommand(name, |sub| {
            let ids: Vec<String> = sub
                .get_arguments()
                .map(|a| a.get_id().to_string())
                .collect();
            let about = fix(sub.get_about());
            let long_about = fix(sub.get_long_about());
            let mut sub = sub;
            if let Some(about) = about {
                sub = sub.about(about);
            }
            if let Some(long_about) = long_about {
                sub = sub.long_about(long_about);
            }
            for id in ids {
                sub = sub.mut_arg(id, |arg| {
                    let help = fix(arg.get_help());
                    let long_help = fix(arg.get_long_help());
                    let mut arg = arg;
                    if let Some(help) = help {
                        arg = arg.help(help);
                    }
                    if let Some(long_help) = long_help {
                        arg = arg.long_help(long_help);
                    }
                    arg
                });
            }
            sub
        });
    }
    command
}

/// Parses `std::env::args` for `catalogue`'s program; on a usage error, `--help` or
/// `--version`, prints and exits as clap does (status 2 for an error).
pub fn parse(catalogue: &'static Catalogue) -> Cli {
    let matches = command(catalogue).get_matches();
    Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
}

/// Runs the command line over `catalogue`.
///
/// # Errors
///
/// [`Failure`], whose `Display` is the message for stderr.
pub fn execute(cli: Cli, catalogue: &'static Catalogue) -> Result<(), Failure> {
    match cli.command {
        None => {
            let Some(first) = catalogue.entries().first() else {
                return Err(Failure::Usage("the catalogue has no model".to_owned()));
            };
            run::run(
                &RunArgs {
                    model: ModelArgs {
                        target: first.name.clone(),
                        ..ModelArgs::default()
                    },
                    ..RunArgs::default()
                },
                catalogue,
            )
        }
        Some(Command::List) => info::list(catalogue),
        Some(Command::Params {
            model,
            states,
            outputs,
        }) => info::params(catalogue, &model, states, outputs),
        Some(Command::Run(args)) => run::run(&args, catalogue),
        Some(Command::Merge { dirs, out }) => run::merge(&dirs, out),
        Some(Command::Graph { model, svg }) => graph::graph(catalogue, &model, svg),
        Some(Command::Fmu { model, out }) => fmu::fmu(catalogue, &model, out),
        Some(Command::Steady(args)) => analysis::steady::steady(&args, catalogue),
        Some(Command::Linearize(args)) => analysis::linearize::linearize(&args, catalogue),
        Some(Command::Bode(args)) => analysis::bode::bode(&args, catalogue),
        Some(Command::Periodic(args)) => analysis::periodic::periodic(&args, catalogue),
        Some(Command::Fit(args)) => analysis::fit::fit(&args, catalogue),
    }
}
