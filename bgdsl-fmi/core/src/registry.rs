//! The models a shared library serves, and how `fmi2Instantiate` finds one by GUID.

use crate::description::ModelDescription;
use crate::model::{Adapter, Exportable, FmuModel};

/// One model a library serves: its `modelIdentifier`, its description (with the GUID
/// `fmi2Instantiate` matches) and how to make a fresh one.
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
    create: fn() -> Box<dyn FmuModel>,
}

impl ModelEntry {
    /// The entry for model `M`, whose FMUs are called `identifier` (a C identifier:
    /// the FMU's binary is `<identifier>.so`).
    pub const fn new<M: Exportable>(identifier: &'static str) -> Self {
        ModelEntry {
            identifier,
            describe: ModelDescription::of::<M>,
            create: Adapter::<M>::boxed,
        }
    }

    /// The `modelIdentifier`.
    pub fn identifier(&self) -> &'static str {
        self.identifier
    }

    /// The model's description (computed on each call).
    pub fn describe(&self) -> ModelDescription {
        (self.describe)()
    }

    /// A fresh model with its default parameters and inputs.
    pub fn create(&self) -> Box<dyn FmuModel> {
        (self.create)()
    }
}

/// The entry called `identifier`, if `registry` has one.
pub fn find<'a>(registry: &'a [ModelEntry], identifier: &str) -> Option<&'a ModelEntry> {
    registry.iter().find(|e| e.identifier == identifier)
}
