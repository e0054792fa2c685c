//! The models a shared library serves, and how `fmi2Instantiate` finds one by GUID.

use crate::description::ModelDescription;
use crate::model::{finite_only, Adapter, Exportable, FmuModel, ParameterCheck};

/// One model a library serves: its `modelIdentifier`, its description (with the GUID
/// `fmi2Instantiate` matches), how to make a fresh one, and the rule its parameters
/// follow (by default [`finite_only`]; [`ModelEntry::with_check`] sets another, so an
/// `fmi2SetReal` that breaks it is refused at the call).
///
/// ```
/// use bgdsl_fmi_core::ModelEntry;
/// # bgdsl_runtime::bond_graph! {
/// #     /// A mass on a spring.
/// #     pub model Spring { param k = 1.0; I mass = 1.0; C spring = k; 1 v;
/// #         v -> { mass, spring }; init spring.q = 1.0; output x = spring.q; }
/// # }
/// static MODELS: &[ModelEntry] = &[ModelEntry::new::<Spring>("spring")];
/// assert_eq!(MODELS[0].identifier(), "spring");
/// assert!(MODELS[0].describe().guid.starts_with('{'));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ModelEntry {
    identifier: &'static str,
    describe: fn() -> ModelDescription,
    create: fn(ParameterCheck) -> Box<dyn FmuModel>,
    check: ParameterCheck,
}

impl ModelEntry {
    /// The entry for model `M`, whose FMUs are called `identifier` (a C identifier:
    /// the FMU's binary is `<identifier>.so`).
    pub const fn new<M: Exportable>(identifier: &'static str) -> Self {
        ModelEntry {
            identifier,
            describe: ModelDescription::of::<M>,
            create: Adapter::<M>::boxed,
            check: finite_only,
        }
    }

    /// The same entry with `check` as the rule for the parameter values an importer
    /// sets (see [`ParameterCheck`]).
    pub const fn with_check(self, check: ParameterCheck) -> Self {
        ModelEntry { check, ..self }
    }

    /// The `modelIdentifier`.
    pub fn identifier(&self) -> &'static str {
        self.identifier
    }

    /// The model's description (computed on each call).
    pub fn describe(&self) -> ModelDescription {
        (self.describe)()
    }

    /// A fresh model with its default parameters and inputs, checking the values set
    /// later with the entry's rule.
    pub fn create(&self) -> Box<dyn FmuModel> {
        (self.create)(self.check)
    }
}

/// The entry called `identifier`, if `registry` has one.
pub fn find<'a>(registry: &'a [ModelEntry], identifier: &str) -> Option<&'a ModelEntry> {
    registry.iter().find(|e| e.identifier == identifier)
}
