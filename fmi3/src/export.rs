//! `export_fmu!(Model)`: emits every function of `fmi3Functions.h` (FMI 3.0.2, 75 symbols) for a
//! Co-Simulation FMU. The Co-Simulation and common functions are here; the ones this FMU does not
//! provide (Model Exchange, Scheduled Execution, Event and Configuration Mode, clocks, other
//! types) are in `export_unsupported.rs` and return fmi3Error with a logged reason.
//!
//! Use it once per cdylib, behind a cargo feature, so the crate can also be linked as an rlib
//! without clashing symbols. The fmi2 and fmi3 symbols do not clash: one cdylib may export both.

#[macro_export]
macro_rules! export_fmu {
    ($model:ty) => {
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        pub mod fmi3_exports {
            use super::*;
            use $crate::ffi::{fmu_state, lifecycle, step, values};
            use $crate::types::*;
            type M = $model;

            #[no_mangle]
            pub extern "C" fn fmi3GetVersion() -> *const ::std::ffi::c_char {
                lifecycle::version()
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetDebugLogging(
                instance: fmi3Instance,
                logging_on: fmi3Boolean,
                n_categories: usize,
                categories: *const fmi3String,
            ) -> fmi3Status {
                // SAFETY: FMI contract: `categories` holds `n_categories` strings.
                unsafe {
                    lifecycle::set_debug_logging::<M>(
                        instance,
                        logging_on,
                        n_categories,
                        categories,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
                instance_name: fmi3String,
                instantiation_token: fmi3String,
                resource_path: fmi3String,
                _visible: fmi3Boolean,
                logging_on: fmi3Boolean,
                event_mode_used: fmi3Boolean,
                early_return_allowed: fmi3Boolean,
                required_intermediate_variables: *const fmi3ValueReference,
                n_required_intermediate_variables: usize,
                instance_environment: fmi3InstanceEnvironment,
                log_message: fmi3LogMessageCallback,
                intermediate_update: fmi3IntermediateUpdateCallback,
            ) -> fmi3Instance {
                // SAFETY: FMI contract: NUL-terminated strings or null; a valid callback or null.
                unsafe {
                    lifecycle::instantiate_co_simulation::<M>(
                        instance_name,
                        instantiation_token,
                        resource_path,
                        logging_on,
                        event_mode_used,
                        early_return_allowed,
                        required_intermediate_variables,
                        n_required_intermediate_variables,
                        instance_environment,
                        log_message,
                        intermediate_update,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
                // SAFETY: FMI contract: an instance from fmi3InstantiateCoSimulation, or null.
                unsafe { lifecycle::free_instance::<M>(instance) }
            }
            #[no_mangle]
            pub extern "C" fn fmi3EnterInitializationMode(
                instance: fmi3Instance,
                tolerance_defined: fmi3Boolean,
                tolerance: fmi3Float64,
                start_time: fmi3Float64,
                stop_time_defined: fmi3Boolean,
                stop_time: fmi3Float64,
            ) -> fmi3Status {
                lifecycle::enter_initialization_mode::<M>(
                    instance,
                    tolerance_defined,
                    tolerance,
                    start_time,
                    stop_time_defined,
                    stop_time,
                )
            }
            #[no_mangle]
            pub extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
                lifecycle::exit_initialization_mode::<M>(instance)
            }
            #[no_mangle]
            pub extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
                lifecycle::terminate::<M>(instance)
            }
            #[no_mangle]
            pub extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
                lifecycle::reset::<M>(instance)
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetFloat64(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                values: *mut fmi3Float64,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: arrays of the given lengths.
                unsafe { values::get_float64::<M>(instance, vr, n_vr, values, n_values) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetFloat64(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                values: *const fmi3Float64,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: arrays of the given lengths.
                unsafe { values::set_float64::<M>(instance, vr, n_vr, values, n_values) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetInt32(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                values: *mut fmi3Int32,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: arrays of the given lengths.
                unsafe { values::get_int32::<M>(instance, vr, n_vr, values, n_values) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetInt32(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                values: *const fmi3Int32,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: arrays of the given lengths.
                unsafe { values::set_int32::<M>(instance, vr, n_vr, values, n_values) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetBoolean(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                values: *mut fmi3Boolean,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: arrays of the given lengths.
                unsafe { values::get_boolean::<M>(instance, vr, n_vr, values, n_values) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetBoolean(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                values: *const fmi3Boolean,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: arrays of the given lengths.
                unsafe { values::set_boolean::<M>(instance, vr, n_vr, values, n_values) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetString(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                _values: *mut fmi3String,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: `vr` holds `n_vr` value references.
                unsafe {
                    values::no_strings::<M>(
                        instance,
                        "fmi3GetString",
                        $crate::state::MASK_GET,
                        vr,
                        n_vr,
                        n_values,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetString(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                _values: *const fmi3String,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: `vr` holds `n_vr` value references.
                unsafe {
                    values::no_strings::<M>(
                        instance,
                        "fmi3SetString",
                        $crate::state::MASK_SET,
                        vr,
                        n_vr,
                        n_values,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetFMUState(
                instance: fmi3Instance,
                state: *mut fmi3FMUState,
            ) -> fmi3Status {
                // SAFETY: FMI contract: `state` points to a state handle.
                unsafe { fmu_state::get_fmu_state::<M>(instance, state) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetFMUState(
                instance: fmi3Instance,
                state: fmi3FMUState,
            ) -> fmi3Status {
                // SAFETY: FMI contract: a state of this FMU.
                unsafe { fmu_state::set_fmu_state::<M>(instance, state) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3FreeFMUState(
                instance: fmi3Instance,
                state: *mut fmi3FMUState,
            ) -> fmi3Status {
                // SAFETY: FMI contract: `state` points to a state handle.
                unsafe { fmu_state::free_fmu_state::<M>(instance, state) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
                instance: fmi3Instance,
                state: fmi3FMUState,
                size: *mut usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: a state of this FMU and a writable size.
                unsafe { fmu_state::serialized_fmu_state_size::<M>(instance, state, size) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SerializeFMUState(
                instance: fmi3Instance,
                state: fmi3FMUState,
                serialized_state: *mut fmi3Byte,
                size: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: `serialized_state` has room for `size` bytes.
                unsafe {
                    fmu_state::serialize_fmu_state::<M>(instance, state, serialized_state, size)
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3DeserializeFMUState(
                instance: fmi3Instance,
                serialized_state: *const fmi3Byte,
                size: usize,
                state: *mut fmi3FMUState,
            ) -> fmi3Status {
                // SAFETY: FMI contract: `size` readable bytes and a state handle.
                unsafe {
                    fmu_state::deserialize_fmu_state::<M>(instance, serialized_state, size, state)
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetOutputDerivatives(
                instance: fmi3Instance,
                vr: *const fmi3ValueReference,
                n_vr: usize,
                orders: *const fmi3Int32,
                values: *mut fmi3Float64,
                n_values: usize,
            ) -> fmi3Status {
                // SAFETY: FMI contract: arrays of the given lengths.
                unsafe {
                    values::get_output_derivatives::<M>(
                        instance, vr, n_vr, orders, values, n_values,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3DoStep(
                instance: fmi3Instance,
                current_communication_point: fmi3Float64,
                communication_step_size: fmi3Float64,
                no_set_fmu_state_prior_to_current_point: fmi3Boolean,
                event_handling_needed: *mut fmi3Boolean,
                terminate_simulation: *mut fmi3Boolean,
                early_return: *mut fmi3Boolean,
                last_successful_time: *mut fmi3Float64,
            ) -> fmi3Status {
                // SAFETY: FMI contract: the four outputs point to writable values.
                unsafe {
                    step::do_step::<M>(
                        instance,
                        current_communication_point,
                        communication_step_size,
                        no_set_fmu_state_prior_to_current_point,
                        event_handling_needed,
                        terminate_simulation,
                        early_return,
                        last_successful_time,
                    )
                }
            }

            $crate::__export_fmi3_unsupported!($model);
        }
    };
}
