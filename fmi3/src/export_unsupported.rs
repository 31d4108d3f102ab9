//! The `fmi3Functions.h` functions this FMU does not provide, emitted by `export_fmu!` next to the
//! real ones: each returns fmi3Error (or a null instance) with a logged reason, in every state.
//! None of them reads its pointer arguments.

/// Getter and setter of a type without variables.
#[doc(hidden)]
#[macro_export]
macro_rules! __export_fmi3_no_type {
    ($model:ty, $get:ident, $set:ident, $ty:ty, $name:literal) => {
        #[no_mangle]
        pub extern "C" fn $get(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _values: *mut $ty,
            _n_values: usize,
        ) -> fmi3Status {
            $crate::ffi::unsupported::no_variables::<$model>(instance, stringify!($get), $name)
        }
        #[no_mangle]
        pub extern "C" fn $set(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _values: *const $ty,
            _n_values: usize,
        ) -> fmi3Status {
            $crate::ffi::unsupported::no_variables::<$model>(instance, stringify!($set), $name)
        }
    };
}

/// Expanded inside `export_fmu!`'s module (it relies on its `use` of the FMI 3.0 types).
#[doc(hidden)]
#[macro_export]
macro_rules! __export_fmi3_unsupported {
    ($model:ty) => {
        use $crate::ffi::not_provided;
        use $crate::ffi::unsupported as why;

        #[no_mangle]
        pub unsafe extern "C" fn fmi3InstantiateModelExchange(
            _instance_name: fmi3String,
            _instantiation_token: fmi3String,
            _resource_path: fmi3String,
            _visible: fmi3Boolean,
            logging_on: fmi3Boolean,
            instance_environment: fmi3InstanceEnvironment,
            log_message: fmi3LogMessageCallback,
        ) -> fmi3Instance {
            // SAFETY: FMI contract: a valid callback (or null) and its environment.
            unsafe {
                $crate::ffi::lifecycle::refuse_instantiation(
                    "fmi3InstantiateModelExchange",
                    logging_on,
                    instance_environment,
                    log_message,
                )
            }
        }
        #[no_mangle]
        pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
            _instance_name: fmi3String,
            _instantiation_token: fmi3String,
            _resource_path: fmi3String,
            _visible: fmi3Boolean,
            logging_on: fmi3Boolean,
            instance_environment: fmi3InstanceEnvironment,
            log_message: fmi3LogMessageCallback,
            _clock_update: fmi3ClockUpdateCallback,
            _lock_preemption: fmi3LockPreemptionCallback,
            _unlock_preemption: fmi3UnlockPreemptionCallback,
        ) -> fmi3Instance {
            // SAFETY: FMI contract: a valid callback (or null) and its environment.
            unsafe {
                $crate::ffi::lifecycle::refuse_instantiation(
                    "fmi3InstantiateScheduledExecution",
                    logging_on,
                    instance_environment,
                    log_message,
                )
            }
        }
        #[no_mangle]
        pub extern "C" fn fmi3EnterEventMode(instance: fmi3Instance) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3EnterEventMode", why::EVENT_MODE)
        }

        $crate::__export_fmi3_no_type!(
            $model,
            fmi3GetFloat32,
            fmi3SetFloat32,
            fmi3Float32,
            "Float32"
        );
        $crate::__export_fmi3_no_type!($model, fmi3GetInt8, fmi3SetInt8, fmi3Int8, "Int8");
        $crate::__export_fmi3_no_type!($model, fmi3GetUInt8, fmi3SetUInt8, fmi3UInt8, "UInt8");
        $crate::__export_fmi3_no_type!($model, fmi3GetInt16, fmi3SetInt16, fmi3Int16, "Int16");
        $crate::__export_fmi3_no_type!($model, fmi3GetUInt16, fmi3SetUInt16, fmi3UInt16, "UInt16");
        $crate::__export_fmi3_no_type!($model, fmi3GetUInt32, fmi3SetUInt32, fmi3UInt32, "UInt32");
        $crate::__export_fmi3_no_type!($model, fmi3GetInt64, fmi3SetInt64, fmi3Int64, "Int64");
        $crate::__export_fmi3_no_type!($model, fmi3GetUInt64, fmi3SetUInt64, fmi3UInt64, "UInt64");

        #[no_mangle]
        pub extern "C" fn fmi3GetBinary(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _value_sizes: *mut usize,
            _values: *mut fmi3Binary,
            _n_values: usize,
        ) -> fmi3Status {
            $crate::ffi::unsupported::no_variables::<$model>(instance, "fmi3GetBinary", "Binary")
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetBinary(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _value_sizes: *const usize,
            _values: *const fmi3Binary,
            _n_values: usize,
        ) -> fmi3Status {
            $crate::ffi::unsupported::no_variables::<$model>(instance, "fmi3SetBinary", "Binary")
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetClock(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _values: *mut fmi3Clock,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3GetClock", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetClock(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _values: *const fmi3Clock,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3SetClock", why::CLOCKS)
        }

        #[no_mangle]
        pub extern "C" fn fmi3GetNumberOfVariableDependencies(
            instance: fmi3Instance,
            _vr: fmi3ValueReference,
            _n_dependencies: *mut usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetNumberOfVariableDependencies",
                why::VARIABLE_DEPENDENCIES,
            )
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetVariableDependencies(
            instance: fmi3Instance,
            _dependent: fmi3ValueReference,
            _element_indices_of_dependent: *mut usize,
            _independents: *mut fmi3ValueReference,
            _element_indices_of_independents: *mut usize,
            _dependency_kinds: *mut fmi3DependencyKind,
            _n_dependencies: usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetVariableDependencies",
                why::VARIABLE_DEPENDENCIES,
            )
        }

        #[no_mangle]
        pub extern "C" fn fmi3GetDirectionalDerivative(
            instance: fmi3Instance,
            _unknowns: *const fmi3ValueReference,
            _n_unknowns: usize,
            _knowns: *const fmi3ValueReference,
            _n_knowns: usize,
            _seed: *const fmi3Float64,
            _n_seed: usize,
            _sensitivity: *mut fmi3Float64,
            _n_sensitivity: usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetDirectionalDerivative",
                why::DIRECTIONAL_DERIVATIVES,
            )
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetAdjointDerivative(
            instance: fmi3Instance,
            _unknowns: *const fmi3ValueReference,
            _n_unknowns: usize,
            _knowns: *const fmi3ValueReference,
            _n_knowns: usize,
            _seed: *const fmi3Float64,
            _n_seed: usize,
            _sensitivity: *mut fmi3Float64,
            _n_sensitivity: usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetAdjointDerivative",
                why::ADJOINT_DERIVATIVES,
            )
        }

        #[no_mangle]
        pub extern "C" fn fmi3EnterConfigurationMode(instance: fmi3Instance) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3EnterConfigurationMode",
                why::CONFIGURATION_MODE,
            )
        }
        #[no_mangle]
        pub extern "C" fn fmi3ExitConfigurationMode(instance: fmi3Instance) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3ExitConfigurationMode",
                why::CONFIGURATION_MODE,
            )
        }

        #[no_mangle]
        pub extern "C" fn fmi3GetIntervalDecimal(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _intervals: *mut fmi3Float64,
            _qualifiers: *mut fmi3IntervalQualifier,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3GetIntervalDecimal", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetIntervalFraction(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _counters: *mut fmi3UInt64,
            _resolutions: *mut fmi3UInt64,
            _qualifiers: *mut fmi3IntervalQualifier,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3GetIntervalFraction", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetShiftDecimal(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _shifts: *mut fmi3Float64,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3GetShiftDecimal", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetShiftFraction(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _counters: *mut fmi3UInt64,
            _resolutions: *mut fmi3UInt64,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3GetShiftFraction", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetIntervalDecimal(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _intervals: *const fmi3Float64,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3SetIntervalDecimal", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetIntervalFraction(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _counters: *const fmi3UInt64,
            _resolutions: *const fmi3UInt64,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3SetIntervalFraction", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetShiftDecimal(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _shifts: *const fmi3Float64,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3SetShiftDecimal", why::CLOCKS)
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetShiftFraction(
            instance: fmi3Instance,
            _vr: *const fmi3ValueReference,
            _n_vr: usize,
            _counters: *const fmi3UInt64,
            _resolutions: *const fmi3UInt64,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3SetShiftFraction", why::CLOCKS)
        }

        #[no_mangle]
        pub extern "C" fn fmi3EvaluateDiscreteStates(instance: fmi3Instance) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3EvaluateDiscreteStates", why::EVENT_MODE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3UpdateDiscreteStates(
            instance: fmi3Instance,
            _discrete_states_need_update: *mut fmi3Boolean,
            _terminate_simulation: *mut fmi3Boolean,
            _nominals_of_continuous_states_changed: *mut fmi3Boolean,
            _values_of_continuous_states_changed: *mut fmi3Boolean,
            _next_event_time_defined: *mut fmi3Boolean,
            _next_event_time: *mut fmi3Float64,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3UpdateDiscreteStates", why::EVENT_MODE)
        }

        #[no_mangle]
        pub extern "C" fn fmi3EnterContinuousTimeMode(instance: fmi3Instance) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3EnterContinuousTimeMode", why::MODEL_EXCHANGE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3CompletedIntegratorStep(
            instance: fmi3Instance,
            _no_set_fmu_state_prior_to_current_point: fmi3Boolean,
            _enter_event_mode: *mut fmi3Boolean,
            _terminate_simulation: *mut fmi3Boolean,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3CompletedIntegratorStep", why::MODEL_EXCHANGE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetTime(instance: fmi3Instance, _time: fmi3Float64) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3SetTime", why::MODEL_EXCHANGE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3SetContinuousStates(
            instance: fmi3Instance,
            _continuous_states: *const fmi3Float64,
            _n_continuous_states: usize,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3SetContinuousStates", why::MODEL_EXCHANGE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetContinuousStateDerivatives(
            instance: fmi3Instance,
            _derivatives: *mut fmi3Float64,
            _n_continuous_states: usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetContinuousStateDerivatives",
                why::MODEL_EXCHANGE,
            )
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetEventIndicators(
            instance: fmi3Instance,
            _event_indicators: *mut fmi3Float64,
            _n_event_indicators: usize,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3GetEventIndicators", why::MODEL_EXCHANGE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetContinuousStates(
            instance: fmi3Instance,
            _continuous_states: *mut fmi3Float64,
            _n_continuous_states: usize,
        ) -> fmi3Status {
            not_provided::<$model>(instance, "fmi3GetContinuousStates", why::MODEL_EXCHANGE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetNominalsOfContinuousStates(
            instance: fmi3Instance,
            _nominals: *mut fmi3Float64,
            _n_continuous_states: usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetNominalsOfContinuousStates",
                why::MODEL_EXCHANGE,
            )
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetNumberOfEventIndicators(
            instance: fmi3Instance,
            _n_event_indicators: *mut usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetNumberOfEventIndicators",
                why::MODEL_EXCHANGE,
            )
        }
        #[no_mangle]
        pub extern "C" fn fmi3GetNumberOfContinuousStates(
            instance: fmi3Instance,
            _n_continuous_states: *mut usize,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3GetNumberOfContinuousStates",
                why::MODEL_EXCHANGE,
            )
        }

        #[no_mangle]
        pub extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
            // Step Mode follows fmi3ExitInitializationMode directly (eventModeUsed is refused).
            not_provided::<$model>(instance, "fmi3EnterStepMode", why::EVENT_MODE)
        }
        #[no_mangle]
        pub extern "C" fn fmi3ActivateModelPartition(
            instance: fmi3Instance,
            _clock_reference: fmi3ValueReference,
            _activation_time: fmi3Float64,
        ) -> fmi3Status {
            not_provided::<$model>(
                instance,
                "fmi3ActivateModelPartition",
                why::SCHEDULED_EXECUTION,
            )
        }
    };
}
