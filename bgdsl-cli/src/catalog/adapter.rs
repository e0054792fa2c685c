//! The one implementation of [`CatalogModel`], for every model [`Entry::of`] accepts.

use core::marker::PhantomData;

use bgdsl_runtime::{CausalGraph, FromParams, ParameterInfo, WithInputs};
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_yaml::{Mapping, Value};

use super::entry::CheckFn;
use super::run::{initial_state, params_from, run_model, sweep_point, trajectory};
use super::{CatalogModel, Checks, Entry, Metric, Observer, Outcome};
use super::{Problem, RunError, RunPlan};

/// Model `M` behind [`CatalogModel`], with its entry's physical checks.
pub(super) struct Adapter<M: FromParams> {
    checks: Option<CheckFn<M::Params>>,
    model: PhantomData<fn() -> M>,
}

impl<M: FromParams> Adapter<M> {
    /// The adapter of `M` with these checks.
    pub(super) fn new(checks: Option<CheckFn<M::Params>>) -> Self {
        Adapter {
            checks,
            model: PhantomData,
        }
    }
}

impl<M> CatalogModel for Adapter<M>
where
    M: FromParams + WithInputs + Default + Clone + 'static,
    M::Params: Serialize + DeserializeOwned,
{
    fn inputs(&self) -> &'static [bgdsl_runtime::InputInfo] {
        <M as bgdsl_runtime::WithInputs>::INPUTS
    }

    fn fmu_description(&self) -> bgdsl_fmi_core::ModelDescription {
        bgdsl_fmi_core::ModelDescription::of::<M>()
    }

    fn type_name(&self) -> &'static str {
        M::NAME
    }

    fn parameters(&self) -> &'static [ParameterInfo] {
        M::PARAMETERS
    }

    fn default_parameters(&self) -> Mapping {
        match serde_yaml::to_value(M::Params::default()) {
            Ok(Value::Mapping(m)) => m,
            // A generated parameter struct always serialises to a mapping.
            _ => Mapping::new(),
        }
    }

    fn state_names(&self) -> &'static [&'static str] {
        M::STATE_NAMES
    }

    fn output_names(&self) -> &'static [&'static str] {
        M::OUTPUT_NAMES
    }

    fn states(&self) -> &'static [bgdsl_runtime::SignalInfo] {
        M::STATES
    }

    fn outputs(&self) -> &'static [bgdsl_runtime::SignalInfo] {
        M::OUTPUTS
    }

    fn check(&self, params: &Mapping) -> Vec<Problem> {
        let mut checks = Checks::new(M::PARAMETERS);
        checks.finite(params);
        // The model's own checks still run, with each non-finite parameter at its
        // default; what they find about those parameters is left out (already said).
        let non_finite: Vec<String> = checks
            .problems()
            .iter()
            .flat_map(|p| p.keys.clone())
            .collect();
        let mut usable = params.clone();
        let defaults = self.default_parameters();
        for name in &non_finite {
            if let Some(default) = defaults.get(name.as_str()) {
                usable.insert(Value::String(name.clone()), default.clone());
            }
        }
        let found = checks.count();
        match params_from::<M::Params>(&usable) {
            Ok(p) => {
                if let Some(check) = self.checks {
                    check(&p, &mut checks);
                }
            }
            Err(e) => checks.problem(&[], e.to_string()),
        }
        let mut problems = checks.into_problems();
        let mut index = 0;
        problems.retain(|p| {
            index += 1;
            index <= found || !p.keys.iter().any(|k| non_finite.contains(k))
        });
        problems
    }

    fn initial_state(&self, params: &Mapping) -> Result<Vec<f64>, RunError> {
        let model = M::from_params(params_from(params)?);
        Ok(initial_state(&model, &[]))
    }

    fn causal_graph(&self) -> Option<&'static CausalGraph> {
        M::from_params(M::Params::default()).causal_graph()
    }

    fn run(
        &self,
        entry: &Entry,
        plan: &RunPlan,
        observer: &dyn Observer,
    ) -> Result<Outcome, RunError> {
        run_model::<M>(entry, plan, observer)
    }

    fn sweep_point(
        &self,
        plan: &RunPlan,
        metrics: &[Metric],
        window: [f64; 2],
        observer: &dyn Observer,
    ) -> Result<Vec<f64>, RunError> {
        sweep_point::<M>(plan, metrics, window, observer)
    }

    fn trajectory(
        &self,
        plan: &RunPlan,
        columns: &[super::Column],
        observer: &dyn Observer,
    ) -> Result<Vec<f64>, RunError> {
        trajectory::<M>(plan, columns, observer)
    }

    fn steady(
        &self,
        plan: &RunPlan,
        request: &super::analysis::steady::SteadyRequest,
    ) -> Result<super::analysis::steady::SteadyResult, super::analysis::AnalysisFailure> {
        super::analysis::steady::steady::<M>(plan, request)
    }

    fn linearize(
        &self,
        plan: &RunPlan,
        request: &super::analysis::linear::LinearRequest,
    ) -> Result<bgdsl_analysis::LinearModel, super::analysis::AnalysisFailure> {
        super::analysis::linear::linearize::<M>(plan, request)
    }

    fn periodic(
        &self,
        plan: &RunPlan,
        columns: &[super::Column],
        request: &super::analysis::periodic::PeriodicRequest,
    ) -> Result<super::analysis::periodic::PeriodicFound, super::analysis::AnalysisFailure> {
        super::analysis::periodic::periodic_of::<M>(plan, columns, request)
    }

    fn fit(
        &self,
        plan: &RunPlan,
        data: &bgdsl_analysis::fit::Measurements,
        parameters: &[super::analysis::fit::FitBound],
        options: &bgdsl_analysis::fit::FitOptions,
    ) -> Result<super::analysis::fit::FitFound, super::analysis::AnalysisFailure> {
        super::analysis::fit::fit_of::<M>(plan, data, parameters, options)
    }
}
