//! `export_fmu!(Model)`: emits the 34 `fmi2*` C symbols of an FMI 2.0 co-simulation FMU (25 common +
//! 9 co-simulation functions) and nothing else. Use it once per cdylib, behind the crate's `fmu`
//! feature, so that the same crate can also be linked as an rlib without clashing symbols.

#[macro_export]
macro_rules! export_fmu {
    ($model:ty) => {
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        mod fmi2_exports {
            use super::*;
            use $crate::ffi;
            use $crate::types::*;
            type M = $model;

            #[no_mangle]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const ::std::ffi::c_char {
                ffi::types_platform()
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetVersion() -> *const ::std::ffi::c_char {
                ffi::version()
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetDebugLogging(c: Fmi2Component, on: Fmi2Boolean, n: usize, cats: *const Fmi2String) -> Fmi2StatusRaw {
                unsafe { ffi::set_debug_logging::<M>(c, on, n, cats) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: Fmi2String,
                ty: Fmi2Type,
                guid: Fmi2String,
                res: Fmi2String,
                functions: *const Fmi2CallbackFunctions,
                visible: Fmi2Boolean,
                logging_on: Fmi2Boolean,
            ) -> Fmi2Component {
                unsafe { ffi::instantiate::<M>(name, ty, guid, res, functions, visible, logging_on) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
                unsafe { ffi::free_instance::<M>(c) }
            }
            #[no_mangle]
            pub extern "C" fn fmi2SetupExperiment(c: Fmi2Component, tol_def: Fmi2Boolean, tol: f64, start: f64, stop_def: Fmi2Boolean, stop: f64) -> Fmi2StatusRaw {
                ffi::setup_experiment::<M>(c, tol_def, tol, start, stop_def, stop)
            }
            #[no_mangle]
            pub extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2StatusRaw {
                ffi::enter_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2StatusRaw {
                ffi::exit_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2StatusRaw {
                ffi::terminate::<M>(c)
            }
            #[no_mangle]
            pub extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2StatusRaw {
                ffi::reset::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetReal(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *mut f64) -> Fmi2StatusRaw {
                unsafe { ffi::get_real::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetInteger(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *mut Fmi2Integer) -> Fmi2StatusRaw {
                unsafe { ffi::get_integer::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBoolean(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *mut Fmi2Boolean) -> Fmi2StatusRaw {
                unsafe { ffi::get_boolean::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetString(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *mut Fmi2String) -> Fmi2StatusRaw {
                unsafe { ffi::get_string::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetReal(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *const f64) -> Fmi2StatusRaw {
                unsafe { ffi::set_real::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetInteger(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *const Fmi2Integer) -> Fmi2StatusRaw {
                unsafe { ffi::set_integer::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetBoolean(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *const Fmi2Boolean) -> Fmi2StatusRaw {
                unsafe { ffi::set_boolean::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetString(c: Fmi2Component, vr: *const Fmi2ValueReference, n: usize, v: *const Fmi2String) -> Fmi2StatusRaw {
                unsafe { ffi::set_string::<M>(c, vr, n, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, s: *mut Fmi2FmuState) -> Fmi2StatusRaw {
                unsafe { ffi::get_fmu_state::<M>(c, s) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, s: Fmi2FmuState) -> Fmi2StatusRaw {
                unsafe { ffi::set_fmu_state::<M>(c, s) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: Fmi2Component, s: *mut Fmi2FmuState) -> Fmi2StatusRaw {
                unsafe { ffi::free_fmu_state::<M>(c, s) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(c: Fmi2Component, s: Fmi2FmuState, size: *mut usize) -> Fmi2StatusRaw {
                unsafe { ffi::serialized_fmu_state_size::<M>(c, s, size) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(c: Fmi2Component, s: Fmi2FmuState, bytes: *mut Fmi2Byte, size: usize) -> Fmi2StatusRaw {
                unsafe { ffi::serialize_fmu_state::<M>(c, s, bytes, size) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(c: Fmi2Component, bytes: *const Fmi2Byte, size: usize, s: *mut Fmi2FmuState) -> Fmi2StatusRaw {
                unsafe { ffi::de_serialize_fmu_state::<M>(c, bytes, size, s) }
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetDirectionalDerivative(
                c: Fmi2Component,
                _vu: *const Fmi2ValueReference,
                _nu: usize,
                _vk: *const Fmi2ValueReference,
                _nk: usize,
                _dvk: *const f64,
                _dvu: *mut f64,
            ) -> Fmi2StatusRaw {
                ffi::unsupported::<M>(c, "fmi2GetDirectionalDerivative", "directional derivatives are not provided (providesDirectionalDerivative=false)")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                order: *const Fmi2Integer,
                v: *const f64,
            ) -> Fmi2StatusRaw {
                unsafe { ffi::set_real_input_derivatives::<M>(c, vr, n, order, v) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                order: *const Fmi2Integer,
                v: *mut f64,
            ) -> Fmi2StatusRaw {
                unsafe { ffi::get_real_output_derivatives::<M>(c, vr, n, order, v) }
            }
            #[no_mangle]
            pub extern "C" fn fmi2DoStep(c: Fmi2Component, t: f64, h: f64, no_prior: Fmi2Boolean) -> Fmi2StatusRaw {
                ffi::do_step::<M>(c, t, h, no_prior)
            }
            #[no_mangle]
            pub extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2StatusRaw {
                ffi::cancel_step::<M>(c)
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetStatus(c: Fmi2Component, k: Fmi2StatusKind, v: *mut Fmi2StatusRaw) -> Fmi2StatusRaw {
                ffi::get_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetRealStatus(c: Fmi2Component, k: Fmi2StatusKind, v: *mut f64) -> Fmi2StatusRaw {
                ffi::get_real_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetIntegerStatus(c: Fmi2Component, k: Fmi2StatusKind, v: *mut Fmi2Integer) -> Fmi2StatusRaw {
                ffi::get_integer_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetBooleanStatus(c: Fmi2Component, k: Fmi2StatusKind, v: *mut Fmi2Boolean) -> Fmi2StatusRaw {
                ffi::get_boolean_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetStringStatus(c: Fmi2Component, k: Fmi2StatusKind, v: *mut Fmi2String) -> Fmi2StatusRaw {
                ffi::get_string_status::<M>(c, k, v)
            }
        }
    };
}
