//! A program's FMUs: the rules of its catalogue for the parameter values an FMU's
//! importer sets. (The `fmu` command itself, which packs them, is in [`crate::cli`].)

use bgdsl_runtime::Model;

use crate::catalog::Checks;

/// An entry's physical rules (what [`EntryOf::checks`](crate::EntryOf::checks) takes)
/// applied to a model's flat parameter values, in
/// [`Model::parameter_values`] order, as an importer's `fmi2SetReal` would leave them:
/// for [`ModelEntry::with_check`](bgdsl_fmi_core::ModelEntry::with_check), so that an
/// FMU refuses the values `run` refuses, with the same messages. (Finiteness the FMU
/// checks on every value itself.)
///
/// ```
/// # bgdsl_runtime::bond_graph! {
/// #     /// A mass on a spring.
/// #     pub model Spring { param m = 1.0 in "kg"; param k = 1.0 in "N/m"; I mass = m;
/// #         C spring = k; 1 v; v -> { mass, spring }; output x = spring.q; }
/// # }
/// use bgdsl_cli::catalog::Checks;
///
/// fn rules(p: &SpringParams, checks: &mut Checks) {
///     checks.positive("m", p.m);
/// }
/// fn fmu_rules(values: &[f64]) -> Result<(), String> {
///     bgdsl_cli::fmi::check_values::<Spring>(values, rules)
/// }
/// static MODELS: &[bgdsl_fmi_core::ModelEntry] =
///     &[bgdsl_fmi_core::ModelEntry::new::<Spring>("spring").with_check(fmu_rules)];
///
/// assert_eq!(fmu_rules(&[2.0, 1.0]), Ok(()));
/// let refused = fmu_rules(&[0.0, 1.0]).unwrap_err();
/// assert_eq!(refused, "parameter `m` (kg) must be > 0, found 0");
/// ```
///
/// # Errors
///
/// Every problem the rules find, in their order, joined by `; `.
pub fn check_values<M: Model + Default>(
    values: &[f64],
    rules: fn(&M::Params, &mut Checks),
) -> Result<(), String> {
    let mut model = M::default();
    model.set_parameter_values(values);
    let mut checks = Checks::new(M::PARAMETERS);
    rules(model.params(), &mut checks);
    let problems: Vec<String> = checks.problems().iter().map(ToString::to_string).collect();
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("; "))
    }
}
