//! The FMI 3.0 Co-Simulation functions an importer calls, resolved once with libloading.

use crate::types::*;
use fmi_core::archive::ImportError;
use std::path::Path;

type Vrs = *const fmi3ValueReference;
type Inst = fmi3Instance;

#[allow(clippy::type_complexity)]
pub struct Api {
    // Keeps the library loaded for as long as any function pointer may be called.
    _lib: libloading::Library,
    pub get_version: unsafe extern "C" fn() -> *const std::ffi::c_char,
    pub set_debug_logging: unsafe extern "C" fn(Inst, bool, usize, *const fmi3String) -> fmi3Status,
    pub instantiate_co_simulation: unsafe extern "C" fn(
        fmi3String,
        fmi3String,
        fmi3String,
        bool,
        bool,
        bool,
        bool,
        Vrs,
        usize,
        fmi3InstanceEnvironment,
        fmi3LogMessageCallback,
        fmi3IntermediateUpdateCallback,
    ) -> Inst,
    pub free_instance: unsafe extern "C" fn(Inst),
    pub enter_initialization_mode:
        unsafe extern "C" fn(Inst, bool, f64, f64, bool, f64) -> fmi3Status,
    pub exit_initialization_mode: unsafe extern "C" fn(Inst) -> fmi3Status,
    pub terminate: unsafe extern "C" fn(Inst) -> fmi3Status,
    pub reset: unsafe extern "C" fn(Inst) -> fmi3Status,
    pub get_float64: unsafe extern "C" fn(Inst, Vrs, usize, *mut f64, usize) -> fmi3Status,
    pub set_float64: unsafe extern "C" fn(Inst, Vrs, usize, *const f64, usize) -> fmi3Status,
    pub get_int32: unsafe extern "C" fn(Inst, Vrs, usize, *mut i32, usize) -> fmi3Status,
    pub set_int32: unsafe extern "C" fn(Inst, Vrs, usize, *const i32, usize) -> fmi3Status,
    pub get_boolean: unsafe extern "C" fn(Inst, Vrs, usize, *mut bool, usize) -> fmi3Status,
    pub set_boolean: unsafe extern "C" fn(Inst, Vrs, usize, *const bool, usize) -> fmi3Status,
    pub get_output_derivatives:
        unsafe extern "C" fn(Inst, Vrs, usize, *const i32, *mut f64, usize) -> fmi3Status,
    pub do_step: unsafe extern "C" fn(
        Inst,
        f64,
        f64,
        bool,
        *mut bool,
        *mut bool,
        *mut bool,
        *mut f64,
    ) -> fmi3Status,
    pub get_fmu_state: unsafe extern "C" fn(Inst, *mut fmi3FMUState) -> fmi3Status,
    pub set_fmu_state: unsafe extern "C" fn(Inst, fmi3FMUState) -> fmi3Status,
    pub free_fmu_state: unsafe extern "C" fn(Inst, *mut fmi3FMUState) -> fmi3Status,
    pub serialized_fmu_state_size:
        unsafe extern "C" fn(Inst, fmi3FMUState, *mut usize) -> fmi3Status,
    pub serialize_fmu_state:
        unsafe extern "C" fn(Inst, fmi3FMUState, *mut fmi3Byte, usize) -> fmi3Status,
    pub deserialize_fmu_state:
        unsafe extern "C" fn(Inst, *const fmi3Byte, usize, *mut fmi3FMUState) -> fmi3Status,
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
                // SAFETY: the symbol has the FMI 3.0 signature the field declares.
                let s = unsafe { lib.get(concat!($name, "\0").as_bytes()) }.map_err(|e| {
                    ImportError(format!("{}: missing {}: {e}", path.display(), $name))
                })?;
                *s
            }};
        }
        Ok(Api {
            get_version: sym!("fmi3GetVersion"),
            set_debug_logging: sym!("fmi3SetDebugLogging"),
            instantiate_co_simulation: sym!("fmi3InstantiateCoSimulation"),
            free_instance: sym!("fmi3FreeInstance"),
            enter_initialization_mode: sym!("fmi3EnterInitializationMode"),
            exit_initialization_mode: sym!("fmi3ExitInitializationMode"),
            terminate: sym!("fmi3Terminate"),
            reset: sym!("fmi3Reset"),
            get_float64: sym!("fmi3GetFloat64"),
            set_float64: sym!("fmi3SetFloat64"),
            get_int32: sym!("fmi3GetInt32"),
            set_int32: sym!("fmi3SetInt32"),
            get_boolean: sym!("fmi3GetBoolean"),
            set_boolean: sym!("fmi3SetBoolean"),
            get_output_derivatives: sym!("fmi3GetOutputDerivatives"),
            do_step: sym!("fmi3DoStep"),
            get_fmu_state: sym!("fmi3GetFMUState"),
            set_fmu_state: sym!("fmi3SetFMUState"),
            free_fmu_state: sym!("fmi3FreeFMUState"),
            serialized_fmu_state_size: sym!("fmi3SerializedFMUStateSize"),
            serialize_fmu_state: sym!("fmi3SerializeFMUState"),
            deserialize_fmu_state: sym!("fmi3DeserializeFMUState"),
            _lib: lib,
        })
    }
}
