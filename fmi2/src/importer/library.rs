//! The 34 function pointers of an FMI 2.0 co-simulation binary, resolved once with libloading.

use super::ImportError;
use crate::types::*;
use std::path::Path;

type VrArr = *const Fmi2ValueReference;

#[allow(clippy::type_complexity)]
pub struct Api {
    // Keeps the library loaded for as long as any function pointer may be called.
    _lib: libloading::Library,
    pub get_types_platform: unsafe extern "C" fn() -> *const std::ffi::c_char,
    pub get_version: unsafe extern "C" fn() -> *const std::ffi::c_char,
    pub set_debug_logging:
        unsafe extern "C" fn(Fmi2Component, Fmi2Boolean, usize, *const Fmi2String) -> Fmi2StatusRaw,
    pub instantiate: unsafe extern "C" fn(
        Fmi2String,
        Fmi2Type,
        Fmi2String,
        Fmi2String,
        *const Fmi2CallbackFunctions,
        Fmi2Boolean,
        Fmi2Boolean,
    ) -> Fmi2Component,
    pub free_instance: unsafe extern "C" fn(Fmi2Component),
    pub setup_experiment: unsafe extern "C" fn(
        Fmi2Component,
        Fmi2Boolean,
        f64,
        f64,
        Fmi2Boolean,
        f64,
    ) -> Fmi2StatusRaw,
    pub enter_initialization_mode: unsafe extern "C" fn(Fmi2Component) -> Fmi2StatusRaw,
    pub exit_initialization_mode: unsafe extern "C" fn(Fmi2Component) -> Fmi2StatusRaw,
    pub terminate: unsafe extern "C" fn(Fmi2Component) -> Fmi2StatusRaw,
    pub reset: unsafe extern "C" fn(Fmi2Component) -> Fmi2StatusRaw,
    pub get_real: unsafe extern "C" fn(Fmi2Component, VrArr, usize, *mut f64) -> Fmi2StatusRaw,
    pub get_integer:
        unsafe extern "C" fn(Fmi2Component, VrArr, usize, *mut Fmi2Integer) -> Fmi2StatusRaw,
    pub get_boolean:
        unsafe extern "C" fn(Fmi2Component, VrArr, usize, *mut Fmi2Boolean) -> Fmi2StatusRaw,
    pub get_string:
        unsafe extern "C" fn(Fmi2Component, VrArr, usize, *mut Fmi2String) -> Fmi2StatusRaw,
    pub set_real: unsafe extern "C" fn(Fmi2Component, VrArr, usize, *const f64) -> Fmi2StatusRaw,
    pub set_integer:
        unsafe extern "C" fn(Fmi2Component, VrArr, usize, *const Fmi2Integer) -> Fmi2StatusRaw,
    pub set_boolean:
        unsafe extern "C" fn(Fmi2Component, VrArr, usize, *const Fmi2Boolean) -> Fmi2StatusRaw,
    pub set_string:
        unsafe extern "C" fn(Fmi2Component, VrArr, usize, *const Fmi2String) -> Fmi2StatusRaw,
    pub get_fmu_state: unsafe extern "C" fn(Fmi2Component, *mut Fmi2FmuState) -> Fmi2StatusRaw,
    pub set_fmu_state: unsafe extern "C" fn(Fmi2Component, Fmi2FmuState) -> Fmi2StatusRaw,
    pub free_fmu_state: unsafe extern "C" fn(Fmi2Component, *mut Fmi2FmuState) -> Fmi2StatusRaw,
    pub serialized_fmu_state_size:
        unsafe extern "C" fn(Fmi2Component, Fmi2FmuState, *mut usize) -> Fmi2StatusRaw,
    pub serialize_fmu_state:
        unsafe extern "C" fn(Fmi2Component, Fmi2FmuState, *mut Fmi2Byte, usize) -> Fmi2StatusRaw,
    pub de_serialize_fmu_state: unsafe extern "C" fn(
        Fmi2Component,
        *const Fmi2Byte,
        usize,
        *mut Fmi2FmuState,
    ) -> Fmi2StatusRaw,
    pub get_directional_derivative: unsafe extern "C" fn(
        Fmi2Component,
        VrArr,
        usize,
        VrArr,
        usize,
        *const f64,
        *mut f64,
    ) -> Fmi2StatusRaw,
    pub set_real_input_derivatives: unsafe extern "C" fn(
        Fmi2Component,
        VrArr,
        usize,
        *const Fmi2Integer,
        *const f64,
    ) -> Fmi2StatusRaw,
    pub get_real_output_derivatives: unsafe extern "C" fn(
        Fmi2Component,
        VrArr,
        usize,
        *const Fmi2Integer,
        *mut f64,
    ) -> Fmi2StatusRaw,
    pub do_step: unsafe extern "C" fn(Fmi2Component, f64, f64, Fmi2Boolean) -> Fmi2StatusRaw,
    pub cancel_step: unsafe extern "C" fn(Fmi2Component) -> Fmi2StatusRaw,
    pub get_status:
        unsafe extern "C" fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2StatusRaw) -> Fmi2StatusRaw,
    pub get_real_status:
        unsafe extern "C" fn(Fmi2Component, Fmi2StatusKind, *mut f64) -> Fmi2StatusRaw,
    pub get_integer_status:
        unsafe extern "C" fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2Integer) -> Fmi2StatusRaw,
    pub get_boolean_status:
        unsafe extern "C" fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2Boolean) -> Fmi2StatusRaw,
    pub get_string_status:
        unsafe extern "C" fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2String) -> Fmi2StatusRaw,
}

// The function pointers are plain code addresses; the library stays loaded while the Api lives.
unsafe impl Send for Api {}
unsafe impl Sync for Api {}

impl Api {
    pub fn load(path: &Path) -> Result<Api, ImportError> {
        // SAFETY: loading a shared library runs its initializers; an FMU binary is trusted code.
        let lib = unsafe { libloading::Library::new(path) }
            .map_err(|e| ImportError(format!("cannot load {}: {e}", path.display())))?;
        macro_rules! sym {
            ($name:literal) => {{
                // SAFETY: the symbol has the FMI 2.0 signature the field declares.
                let s = unsafe { lib.get(concat!($name, "\0").as_bytes()) }.map_err(|e| {
                    ImportError(format!("{}: missing {}: {e}", path.display(), $name))
                })?;
                *s
            }};
        }
        Ok(Api {
            get_types_platform: sym!("fmi2GetTypesPlatform"),
            get_version: sym!("fmi2GetVersion"),
            set_debug_logging: sym!("fmi2SetDebugLogging"),
            instantiate: sym!("fmi2Instantiate"),
            free_instance: sym!("fmi2FreeInstance"),
            setup_experiment: sym!("fmi2SetupExperiment"),
            enter_initialization_mode: sym!("fmi2EnterInitializationMode"),
            exit_initialization_mode: sym!("fmi2ExitInitializationMode"),
            terminate: sym!("fmi2Terminate"),
            reset: sym!("fmi2Reset"),
            get_real: sym!("fmi2GetReal"),
            get_integer: sym!("fmi2GetInteger"),
            get_boolean: sym!("fmi2GetBoolean"),
            get_string: sym!("fmi2GetString"),
            set_real: sym!("fmi2SetReal"),
            set_integer: sym!("fmi2SetInteger"),
            set_boolean: sym!("fmi2SetBoolean"),
            set_string: sym!("fmi2SetString"),
            get_fmu_state: sym!("fmi2GetFMUstate"),
            set_fmu_state: sym!("fmi2SetFMUstate"),
            free_fmu_state: sym!("fmi2FreeFMUstate"),
            serialized_fmu_state_size: sym!("fmi2SerializedFMUstateSize"),
            serialize_fmu_state: sym!("fmi2SerializeFMUstate"),
            de_serialize_fmu_state: sym!("fmi2DeSerializeFMUstate"),
            get_directional_derivative: sym!("fmi2GetDirectionalDerivative"),
            set_real_input_derivatives: sym!("fmi2SetRealInputDerivatives"),
            get_real_output_derivatives: sym!("fmi2GetRealOutputDerivatives"),
            do_step: sym!("fmi2DoStep"),
            cancel_step: sym!("fmi2CancelStep"),
            get_status: sym!("fmi2GetStatus"),
            get_real_status: sym!("fmi2GetRealStatus"),
            get_integer_status: sym!("fmi2GetIntegerStatus"),
            get_boolean_status: sym!("fmi2GetBooleanStatus"),
            get_string_status: sym!("fmi2GetStringStatus"),
            _lib: lib,
        })
    }
}
