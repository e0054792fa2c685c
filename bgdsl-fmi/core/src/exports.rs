//! [`export_fmi2!`](crate::export_fmi2): the C symbols of an FMI 2.0 shared library.

/// Defines, in the invoking crate, every function of the FMI 2.0 C interface (Model
/// Exchange and Co-Simulation, `fmi2Functions.h`) as an unmangled `extern "C"` symbol,
/// serving the models of a registry (a `&'static [ModelEntry]` expression).
///
/// Invoke it once, at module level (the root of a crate built as a `cdylib`), not
/// inside a function:
///
/// ```
/// # bgdsl_runtime::bond_graph! {
/// #     /// A mass on a spring.
/// #     pub model Spring { param k = 1.0; I mass = 1.0; C spring = k; 1 v;
/// #         v -> { mass, spring }; init spring.q = 1.0; output x = spring.q; }
/// # }
/// static MODELS: &[bgdsl_fmi_core::ModelEntry] = &[
///     bgdsl_fmi_core::ModelEntry::new::<Spring>("spring"),
/// ];
/// bgdsl_fmi_core::export_fmi2!(MODELS);
///
/// fn main() {
///     // The symbols are ordinary Rust items too.
///     let version = unsafe { core::ffi::CStr::from_ptr(fmi2::fmi2GetVersion()) };
///     assert_eq!(version, c"2.0");
/// }
/// ```
///
/// Each symbol forwards to the function of the same meaning in
/// [`bgdsl_fmi_core::ffi`](crate::ffi), whose documentation states the checks made.
/// The symbols are `pub`, so Rust code (tests) can call them as the importer would.
#[macro_export]
macro_rules! export_fmi2 {
    ($registry:expr) => {
        /// The models the FMI symbols of this library serve (`export_fmi2!`'s argument).
        #[doc(hidden)]
        pub fn __bgdsl_fmi_registry() -> &'static [$crate::ModelEntry] {
            $registry
        }

        /// The FMI 2.0 C interface of this library (see `bgdsl_fmi_core::export_fmi2!`).
        /// Every function follows `fmi2Functions.h`; the safety contract of each is the
        /// standard's: pointers as the standard describes them, one thread per
        /// instance at a time.
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        pub mod fmi2 {
            use ::core::ffi::{c_char, c_int};
            use $crate::ffi::{self, ByteArray, ByteArrayOut, FmuStateOut, IntegerOut, StringOut};
            use $crate::fmi2::{
                Boolean, CallbackFunctions, Component, EventInfo, FmiString, FmuState, Real,
                Status, ValueReference, TYPES_PLATFORM, VERSION,
            };
            use $crate::instance::Instance;
            use $crate::machine::Call;

            /// `fmi2GetTypesPlatform`: `"default"`.
            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
                ffi::static_string(TYPES_PLATFORM)
            }

            /// `fmi2GetVersion`: `"2.0"`.
            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetVersion() -> *const c_char {
                ffi::static_string(VERSION)
            }

            /// `fmi2SetDebugLogging`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Component,
                logging_on: Boolean,
                n_categories: usize,
                categories: *const FmiString,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::set_debug_logging(c, logging_on, n_categories, categories) }
            }

            /// `fmi2Instantiate`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Instantiate(
                instance_name: FmiString,
                fmu_type: c_int,
                fmu_guid: FmiString,
                fmu_resource_location: FmiString,
                functions: *const CallbackFunctions,
                visible: Boolean,
                logging_on: Boolean,
            ) -> Component {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::instantiate(
                        super::__bgdsl_fmi_registry(),
                        instance_name,
                        fmu_type,
                        fmu_guid,
                        fmu_resource_location,
                        functions,
                        visible,
                        logging_on,
                    )
                }
            }

            /// `fmi2FreeInstance`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::free_instance(c) }
            }

            /// `fmi2SetupExperiment`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: Component,
                tolerance_defined: Boolean,
                tolerance: Real,
                start_time: Real,
                stop_time_defined: Boolean,
                stop_time: Real,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::setup_experiment(
                        c,
                        tolerance_defined,
                        tolerance,
                        start_time,
                        stop_time_defined,
                        stop_time,
                    )
                }
            }

            /// `fmi2EnterInitializationMode`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::enter_initialization_mode(c) }
            }

            /// `fmi2ExitInitializationMode`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::exit_initialization_mode(c) }
            }

            /// `fmi2Terminate`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Terminate(c: Component) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::terminate(c) }
            }

            /// `fmi2Reset`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Reset(c: Component) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::reset(c) }
            }

            /// `fmi2GetReal`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                value: *mut Real,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::get_real(c, vr, nvr, value) }
            }

            /// `fmi2GetInteger`: there are no Integer variables.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                _value: IntegerOut,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::no_variables_of_type(c, Call::GetInteger, "Integer", vr, nvr) }
            }

            /// `fmi2GetBoolean`: there are no Boolean variables.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                _value: *mut Boolean,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::no_variables_of_type(c, Call::GetBoolean, "Boolean", vr, nvr) }
            }

            /// `fmi2GetString`: there are no String variables.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetString(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                _value: StringOut,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::no_variables_of_type(c, Call::GetString, "String", vr, nvr) }
            }

            /// `fmi2SetReal`.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                value: *const Real,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::set_real(c, vr, nvr, value) }
            }

            /// `fmi2SetInteger`: there are no Integer variables.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                _value: *const c_int,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::no_variables_of_type(c, Call::SetInteger, "Integer", vr, nvr) }
            }

            /// `fmi2SetBoolean`: there are no Boolean variables.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                _value: *const Boolean,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::no_variables_of_type(c, Call::SetBoolean, "Boolean", vr, nvr) }
            }

            /// `fmi2SetString`: there are no String variables.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetString(
                c: Component,
                vr: *const ValueReference,
                nvr: usize,
                _value: *const FmiString,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::no_variables_of_type(c, Call::SetString, "String", vr, nvr) }
            }

            /// `fmi2GetFMUstate`: not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, _state: FmuStateOut) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::GetFmuState) }
            }

            /// `fmi2SetFMUstate`: not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, _state: FmuState) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::SetFmuState) }
            }

            /// `fmi2FreeFMUstate`: not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, _state: FmuStateOut) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::FreeFmuState) }
            }

            /// `fmi2SerializedFMUstateSize`: not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Component,
                _state: FmuState,
                _size: *mut usize,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::SerializedFmuStateSize) }
            }

            /// `fmi2SerializeFMUstate`: not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Component,
                _state: FmuState,
                _bytes: ByteArrayOut,
                _size: usize,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::SerializeFmuState) }
            }

            /// `fmi2DeSerializeFMUstate`: not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Component,
                _bytes: ByteArray,
                _size: usize,
                _state: FmuStateOut,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::DeSerializeFmuState) }
            }

            /// `fmi2GetDirectionalDerivative`: not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: Component,
                _v_unknown_ref: *const ValueReference,
                _n_unknown: usize,
                _v_known_ref: *const ValueReference,
                _n_known: usize,
                _dv_known: *const Real,
                _dv_unknown: *mut Real,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::GetDirectionalDerivative) }
            }

            /// `fmi2EnterEventMode` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterEventMode(c: Component) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::enter_event_mode(c) }
            }

            /// `fmi2NewDiscreteStates` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2NewDiscreteStates(
                c: Component,
                event_info: *mut EventInfo,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::new_discrete_states(c, event_info) }
            }

            /// `fmi2EnterContinuousTimeMode` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: Component) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::enter_continuous_time_mode(c) }
            }

            /// `fmi2CompletedIntegratorStep` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
                c: Component,
                no_set_fmu_state_prior_to_current_point: Boolean,
                enter_event_mode: *mut Boolean,
                terminate_simulation: *mut Boolean,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::completed_integrator_step(
                        c,
                        no_set_fmu_state_prior_to_current_point,
                        enter_event_mode,
                        terminate_simulation,
                    )
                }
            }

            /// `fmi2SetTime` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetTime(c: Component, time: Real) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::set_time(c, time) }
            }

            /// `fmi2SetContinuousStates` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetContinuousStates(
                c: Component,
                x: *const Real,
                nx: usize,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::set_continuous_states(c, x, nx) }
            }

            /// `fmi2GetDerivatives` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDerivatives(
                c: Component,
                derivatives: *mut Real,
                nx: usize,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::get_array(
                        c,
                        Call::GetDerivatives,
                        derivatives,
                        nx,
                        Instance::get_derivatives,
                    )
                }
            }

            /// `fmi2GetEventIndicators` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetEventIndicators(
                c: Component,
                event_indicators: *mut Real,
                ni: usize,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::get_array(
                        c,
                        Call::GetEventIndicators,
                        event_indicators,
                        ni,
                        Instance::get_event_indicators,
                    )
                }
            }

            /// `fmi2GetContinuousStates` (Model Exchange).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetContinuousStates(
                c: Component,
                x: *mut Real,
                nx: usize,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::get_array(
                        c,
                        Call::GetContinuousStates,
                        x,
                        nx,
                        Instance::get_continuous_states,
                    )
                }
            }

            /// `fmi2GetNominalsOfContinuousStates` (Model Exchange): all 1.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
                c: Component,
                x_nominal: *mut Real,
                nx: usize,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::get_array(
                        c,
                        Call::GetNominalsOfContinuousStates,
                        x_nominal,
                        nx,
                        Instance::get_nominals_of_continuous_states,
                    )
                }
            }

            /// `fmi2SetRealInputDerivatives` (Co-Simulation): not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _nvr: usize,
                _order: *const c_int,
                _value: *const Real,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::SetRealInputDerivatives) }
            }

            /// `fmi2GetRealOutputDerivatives` (Co-Simulation): not supported.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _nvr: usize,
                _order: *const c_int,
                _value: *mut Real,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::unsupported(c, Call::GetRealOutputDerivatives) }
            }

            /// `fmi2DoStep` (Co-Simulation).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DoStep(
                c: Component,
                current_communication_point: Real,
                communication_step_size: Real,
                no_set_fmu_state_prior_to_current_point: Boolean,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::do_step(
                        c,
                        current_communication_point,
                        communication_step_size,
                        no_set_fmu_state_prior_to_current_point,
                    )
                }
            }

            /// `fmi2CancelStep` (Co-Simulation): steps are never asynchronous.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::cancel_step(c) }
            }

            /// `fmi2GetStatus` (Co-Simulation).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStatus(
                c: Component,
                s: c_int,
                value: *mut Status,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::get_status(c, Call::GetStatus, s, value, Instance::get_status) }
            }

            /// `fmi2GetRealStatus` (Co-Simulation).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: Component,
                s: c_int,
                value: *mut Real,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe {
                    ffi::get_status(c, Call::GetRealStatus, s, value, Instance::get_real_status)
                }
            }

            /// `fmi2GetIntegerStatus` (Co-Simulation): no status kind answers with one.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: Component,
                s: c_int,
                value: IntegerOut,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::get_status(c, Call::GetIntegerStatus, s, value, ffi::no_status) }
            }

            /// `fmi2GetBooleanStatus` (Co-Simulation).
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Component,
                s: c_int,
                value: *mut Boolean,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::get_status(c, Call::GetBooleanStatus, s, value, ffi::boolean_status) }
            }

            /// `fmi2GetStringStatus` (Co-Simulation): no status kind answers with one.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: Component,
                s: c_int,
                value: StringOut,
            ) -> Status {
                // SAFETY: forwarded under the standard's contract, which `ffi` states.
                unsafe { ffi::get_status(c, Call::GetStringStatus, s, value, ffi::no_status) }
            }
        }
    };
}
