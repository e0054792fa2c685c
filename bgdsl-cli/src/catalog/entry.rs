//! The catalogue a program is built from: [`Catalogue`], its [`Entry`]s and the typed
//! builder [`EntryOf`] that makes an entry from a model type with defaults.

use core::any::Any;
use core::fmt;
use core::marker::PhantomData;

use bgdsl_runtime::{FromParams, Solver, WithInputs};
use serde::de::DeserializeOwned;
use serde::Serialize;

use super::adapter::Adapter;
use super::extras::{Extras, NoExtras};
use super::{CatalogModel, Checks};
use crate::animation::{GroundFn, Look, PosesFn, ShapesFn};

/// The physical checks of a model's parameters: records in `checks` every value that
/// makes no physical sense (a mass of zero, a negative stiffness).
pub type CheckFn<P> = fn(&P, &mut Checks);

/// A model the program knows.
pub struct Entry {
    /// The name on the command line and in scenario files, e.g. `quick_return`.
    pub name: String,
    /// One line saying what it is.
    pub description: String,
    /// The model itself, behind an object-safe interface.
    pub model: Box<dyn CatalogModel>,
    /// The default end of the time span, s (runs start at 0).
    pub t_end: f64,
    /// The default sampling interval, s.
    pub interval: f64,
    /// The solver a run uses unless told otherwise.
    pub solver: Solver,
    /// The states and outputs `<name>.csv` records when a run names none (`None`: every
    /// state and output; empty: no such file).
    pub record: Option<&'static [&'static str]>,
    /// What a run writes and draws beyond the generic files ([`Extras`]).
    pub extras: Box<dyn Extras>,
    /// How the animation draws the model's bodies: a [`Look`]`<M::Params>` set by
    /// [`EntryOf::shapes`], [`EntryOf::ground`] and [`EntryOf::poses`], `None` for
    /// markers, no ground and only the model's `BODIES`.
    pub look: Option<Box<dyn Any + Send + Sync>>,
}

impl fmt::Debug for Entry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Entry")
            .field("name", &self.name)
            .field("model", &self.model.type_name())
            .finish_non_exhaustive()
    }
}

impl Entry {
    /// The builder of an entry for model `M`, with the defaults of [`EntryOf`].
    pub fn of<M>() -> EntryOf<M>
    where
        M: FromParams + WithInputs + Default + Clone + 'static,
        M::Params: Serialize + DeserializeOwned,
    {
        EntryOf::new()
    }
}

/// The builder of an [`Entry`] for model `M` ([`Entry::of`]). Defaults: the name is
/// `M::NAME` in snake case (`MyPump` → `my_pump`), the description `M::NAME`, the span
/// 0–10 s sampled every thousandth of it, [`Solver::stiff`], no physical checks beyond
/// "every number is finite", every state and output recorded, no extras.
pub struct EntryOf<M: FromParams> {
    name: String,
    description: String,
    t_end: f64,
    interval: Option<f64>,
    solver: Solver,
    checks: Option<CheckFn<M::Params>>,
    record: Option<&'static [&'static str]>,
    extras: Box<dyn Extras>,
    look: Look<M::Params>,
    model: PhantomData<fn() -> M>,
}

impl<M> EntryOf<M>
where
    M: FromParams + WithInputs + Default + Clone + 'static,
    M::Params: Serialize + DeserializeOwned,
{
    fn new() -> Self {
        EntryOf {
            name: snake_case(M::NAME),
            description: M::NAME.to_owned(),
            t_end: 10.0,
            interval: None,
            solver: Solver::stiff(),
            checks: None,
            record: None,
            extras: Box::new(NoExtras),
            look: Look::default(),
            model: PhantomData,
        }
    }

    /// The name on the command line and in scenario files.
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// The one line `list` prints.
    pub fn description(mut self, description: impl Into<String>) -> Self {
        self.description = description.into();
        self
    }

    /// The default end of the time span, s (runs start at 0).
    pub fn t_end(mut self, t_end: f64) -> Self {
        self.t_end = t_end;
        self
    }

    /// The default sampling interval, s (default: a thousandth of the span).
    pub fn interval(mut self, interval: f64) -> Self {
        self.interval = Some(interval);
        self
    }

    /// The solver a run uses unless told otherwise.
    pub fn solver(mut self, solver: Solver) -> Self {
        self.solver = solver;
        self
    }

    /// The physical checks of the parameters, run after "every number is finite".
    pub fn checks(mut self, checks: CheckFn<M::Params>) -> Self {
        self.checks = Some(checks);
        self
    }

    /// The states and outputs `<name>.csv` records when a run names none (names as
    /// `output.record` takes them); empty: no such file unless a run asks.
    pub fn record(mut self, columns: &'static [&'static str]) -> Self {
        self.record = Some(columns);
        self
    }

    /// What a run writes and draws beyond the generic files.
    pub fn extras(mut self, extras: impl Extras + 'static) -> Self {
        self.extras = Box::new(extras);
        self
    }

    /// How the animation of a model with bodies ([`Model::BODIES`](bgdsl_runtime::Model::BODIES))
    /// draws them: `shapes(params)` gives (body name, [`Shape`](crate::animation::Shape))
    /// pairs, in each body's frame about its centre of mass; a body it leaves out is a
    /// marker.
    pub fn shapes(mut self, shapes: ShapesFn<M::Params>) -> Self {
        self.look.shapes = Some(shapes);
        self
    }

    /// Points fixed in frame 0 that the animation draws as ground (pivots), from the
    /// parameters.
    pub fn ground(mut self, ground: GroundFn<M::Params>) -> Self {
        self.look.ground = Some(ground);
        self
    }

    /// Bodies the animation draws although the model does not list them in
    /// [`Model::BODIES`](bgdsl_runtime::Model::BODIES) (it has no `RigidBody`):
    /// `names`, and their poses at each sample from `poses(params, t, x, y)`, one per
    /// name. Ignored for a model with `BODIES`.
    pub fn poses(mut self, names: &'static [&'static str], poses: PosesFn<M::Params>) -> Self {
        self.look.poses = Some((names, poses));
        self
    }
}

impl<M> From<EntryOf<M>> for Entry
where
    M: FromParams + WithInputs + Default + Clone + 'static,
    M::Params: Serialize + DeserializeOwned,
{
    fn from(e: EntryOf<M>) -> Self {
        Entry {
            name: e.name,
            description: e.description,
            model: Box::new(Adapter::<M>::new(e.checks)),
            t_end: e.t_end,
            interval: e.interval.unwrap_or(e.t_end / 1000.0),
            solver: e.solver,
            record: e.record,
            extras: e.extras,
            look: (!e.look.is_empty()).then(|| Box::new(e.look) as Box<dyn Any + Send + Sync>),
        }
    }
}

/// `MyPump` → `my_pump`, `DCMotor` → `dc_motor`, `Rlc2` → `rlc2`.
fn snake_case(name: &str) -> String {
    let chars: Vec<char> = name.chars().collect();
    let mut out = String::new();
    for (i, &c) in chars.iter().enumerate() {
        if c.is_uppercase() {
            let after_lower =
                i > 0 && (chars[i - 1].is_lowercase() || chars[i - 1].is_ascii_digit());
            let before_lower = i > 0
                && chars[i - 1].is_uppercase()
                && chars.get(i + 1).is_some_and(|n| n.is_lowercase());
            if after_lower || before_lower {
                out.push('_');
            }
            out.extend(c.to_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

/// The models a program knows, in the order `list` prints them; the first is what the
/// program runs without a command.
pub struct Catalogue {
    /// The program's name (`--help`, `run.yaml`), by default the package's.
    pub program: String,
    /// The program's version.
    pub version: String,
    /// The git commit the program was built from, and whether tracked files differed
    /// from it (`None`: unknown).
    pub commit: (String, Option<bool>),
    /// The first paragraph of `--help`.
    pub about: String,
    /// What running without a command does, for `--help`.
    pub default_help: Option<String>,
    /// The package whose shared library (its `cdylib`, `lib<package>.so` with `-` as
    /// `_`) the FMUs carry and `fmu` looks for beside the program: by default the
    /// program's own package.
    pub fmi_package: String,
    entries: Vec<Entry>,
}

impl fmt::Debug for Catalogue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Catalogue")
            .field("program", &self.program)
            .field("models", &self.names())
            .finish_non_exhaustive()
    }
}

impl Catalogue {
    /// An empty catalogue of the program of package `package` (its Cargo name), which
    /// also builds the FMUs' shared library (see [`Catalogue::fmi_library`]).
    pub fn new(package: &str) -> Self {
        Catalogue {
            program: package.to_owned(),
            version: env!("CARGO_PKG_VERSION").to_owned(),
            commit: ("unknown".to_owned(), None),
            about: format!("Run the bond-graph models of {package}."),
            default_help: None,
            fmi_package: package.to_owned(),
            entries: Vec::new(),
        }
    }

    /// Adds model `M` with the defaults of [`Entry::of`].
    pub fn model<M>(self) -> Self
    where
        M: FromParams + WithInputs + Default + Clone + 'static,
        M::Params: Serialize + DeserializeOwned,
    {
        self.entry(Entry::of::<M>())
    }

    /// Adds an entry.
    pub fn entry(mut self, entry: impl Into<Entry>) -> Self {
        self.entries.push(entry.into());
        self
    }

    /// The program's version (default: bgdsl-cli's).
    pub fn version(mut self, version: &str) -> Self {
        self.version = version.to_owned();
        self
    }

    /// The git commit the program was built from (`unknown` when not known) and whether
    /// tracked files differed from it (`"true"`, `"false"`, anything else unknown).
    pub fn commit(mut self, commit: &str, dirty: &str) -> Self {
        let dirty = match dirty {
            "true" => Some(true),
            "false" => Some(false),
            _ => None,
        };
        self.commit = (commit.to_owned(), dirty);
        self
    }

    /// The first paragraph of `--help`.
    pub fn about(mut self, about: &str) -> Self {
        self.about = about.to_owned();
        self
    }

    /// What running without a command does, for `--help` (default: names the first
    /// model and its folder).
    pub fn default_help(mut self, text: &str) -> Self {
        self.default_help = Some(text.to_owned());
        self
    }

    /// The package that builds the shared library the FMUs carry (default: the
    /// program's package, as [`Catalogue::new`] was given it). `fmu` finds its library,
    /// `lib<package>.so` with `-` as `_`, beside the program (or at
    /// `$BGDSL_FMI_LIBRARY`), and says `cargo build -p <package> --release` when it is
    /// missing or was built from other model code. The `models` catalogue names
    /// `bgdsl-fmi` here.
    pub fn fmi_library(mut self, package: &str) -> Self {
        self.fmi_package = package.to_owned();
        self
    }

    /// Every entry, in order.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// The model names, in order.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name.as_str()).collect()
    }

    /// The model called `name`.
    ///
    /// # Errors
    ///
    /// [`UnknownModel`], whose message lists the models.
    pub fn find(&self, name: &str) -> Result<&Entry, UnknownModel> {
        self.entries
            .iter()
            .find(|e| e.name == name)
            .ok_or_else(|| UnknownModel {
                name: name.to_owned(),
                known: self.names().join(", "),
            })
    }
}

/// A model name the catalogue does not have.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownModel {
    /// The name asked for.
    pub name: String,
    /// The model names, comma-separated.
    pub known: String,
}

impl fmt::Display for UnknownModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown model `{}`; the models are: {}",
            self.name, self.known
        )
    }
}

impl std::error::Error for UnknownModel {}

#[cfg(test)]
mod tests {
    use super::snake_case;

    #[test]
    fn type_names_become_snake_case() {
        assert_eq!(snake_case("MyPump"), "my_pump");
        assert_eq!(snake_case("DCMotor"), "dc_motor");
        assert_eq!(snake_case("SeriesRlc"), "series_rlc");
        assert_eq!(snake_case("Rlc2"), "rlc2");
        assert_eq!(snake_case("Stage2Pump"), "stage2_pump");
        assert_eq!(snake_case("x"), "x");
    }
}
