//! Hand-written `#[repr(C)]` mirror of `fmi2TypesPlatform.h` and `fmi2FunctionTypes.h` (FMI 2.0.4).
//!
//! No bindgen: it would need libclang and slow every clean build, and the headers are small and frozen.

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type Fmi2Component = *mut c_void;
pub type Fmi2ComponentEnvironment = *mut c_void;
pub type Fmi2FmuState = *mut c_void;
pub type Fmi2ValueReference = c_uint;
pub type Fmi2Real = f64;
pub type Fmi2Integer = c_int;
pub type Fmi2Boolean = c_int;
pub type Fmi2Char = c_char;
pub type Fmi2String = *const c_char;
pub type Fmi2Byte = c_char;

pub const FMI2_TRUE: Fmi2Boolean = 1;
pub const FMI2_FALSE: Fmi2Boolean = 0;

/// `fmi2Status`. Kept as a plain `c_int` on the wire: a foreign FMU may return any integer,
/// and a Rust enum holding an out-of-range value would be undefined behaviour.
pub type Fmi2StatusRaw = c_int;

/// `fmi2Status` as Rust returns it: the version-neutral status of the FMI core (its
/// discriminants are the C values).
pub use fmi_core::Status;

/// `fmi2Type`
pub type Fmi2Type = c_int;
pub const FMI2_MODEL_EXCHANGE: Fmi2Type = 0;
pub const FMI2_CO_SIMULATION: Fmi2Type = 1;

/// `fmi2StatusKind`
pub type Fmi2StatusKind = c_int;
pub const FMI2_DO_STEP_STATUS: Fmi2StatusKind = 0;
pub const FMI2_PENDING_STATUS: Fmi2StatusKind = 1;
pub const FMI2_LAST_SUCCESSFUL_TIME: Fmi2StatusKind = 2;
pub const FMI2_TERMINATED: Fmi2StatusKind = 3;

/// `fmi2CallbackLogger`: C-variadic. Rust may call a variadic function pointer (we always pass
/// the format `"%s"` and one string) but cannot define one on stable; the importer's C shim does.
pub type Fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        Fmi2ComponentEnvironment,
        Fmi2String,
        Fmi2StatusRaw,
        Fmi2String,
        Fmi2String,
        ...
    ),
>;
pub type Fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>;
pub type Fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(*mut c_void)>;
pub type Fmi2StepFinished = Option<unsafe extern "C" fn(Fmi2ComponentEnvironment, Fmi2StatusRaw)>;

#[repr(C)]
#[derive(Clone, Copy)]
pub struct Fmi2CallbackFunctions {
    pub logger: Fmi2CallbackLogger,
    pub allocate_memory: Fmi2CallbackAllocateMemory,
    pub free_memory: Fmi2CallbackFreeMemory,
    pub step_finished: Fmi2StepFinished,
    pub component_environment: Fmi2ComponentEnvironment,
}

/// `fmi2TypesPlatform` string returned by `fmi2GetTypesPlatform`.
pub const TYPES_PLATFORM: &[u8] = b"default\0";
/// `fmi2Version` string returned by `fmi2GetVersion`.
pub const VERSION: &[u8] = b"2.0\0";
