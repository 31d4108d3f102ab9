//! Hand-written `#[repr(C)]` mirror of `fmi3PlatformTypes.h` and `fmi3FunctionTypes.h` (FMI 3.0.2).
//!
//! No bindgen, for the same reason as `fmi2::types`: the headers are small and frozen.
//! Names follow the C headers (`fmi3Float64`, ...) so a reader can put the two side by side.

#![allow(non_camel_case_types)]

use std::ffi::{c_char, c_int, c_void};

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = u32;

pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// C `bool`. Rust's `bool` has the same size and ABI; only 0 and 1 are valid, so arrays coming
/// from the importer are read as bytes (see `ffi::values`).
pub type fmi3Boolean = bool;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
pub type fmi3Clock = bool;

pub const FMI3_TRUE: fmi3Boolean = true;
pub const FMI3_FALSE: fmi3Boolean = false;

/// `fmi3Status`, a C enum: `c_int` on the wire (a Rust enum holding an out-of-range value from C
/// would be undefined behaviour). Values 0..=4 equal `fmi2::Status` 0..=4.
pub type fmi3Status = c_int;
pub const FMI3_OK: fmi3Status = 0;
pub const FMI3_WARNING: fmi3Status = 1;
pub const FMI3_DISCARD: fmi3Status = 2;
pub const FMI3_ERROR: fmi3Status = 3;
pub const FMI3_FATAL: fmi3Status = 4;

/// `fmi3DependencyKind`
pub type fmi3DependencyKind = c_int;
pub const FMI3_INDEPENDENT: fmi3DependencyKind = 0;
pub const FMI3_CONSTANT: fmi3DependencyKind = 1;
pub const FMI3_FIXED: fmi3DependencyKind = 2;
pub const FMI3_TUNABLE: fmi3DependencyKind = 3;
pub const FMI3_DISCRETE: fmi3DependencyKind = 4;
pub const FMI3_DEPENDENT: fmi3DependencyKind = 5;

/// `fmi3IntervalQualifier`
pub type fmi3IntervalQualifier = c_int;
pub const FMI3_INTERVAL_NOT_YET_KNOWN: fmi3IntervalQualifier = 0;
pub const FMI3_INTERVAL_UNCHANGED: fmi3IntervalQualifier = 1;
pub const FMI3_INTERVAL_CHANGED: fmi3IntervalQualifier = 2;

/// `fmi3LogMessageCallback`: not variadic in FMI 3.0 (the FMU formats the message).
pub type fmi3LogMessageCallback = Option<
    unsafe extern "C" fn(
        instance_environment: fmi3InstanceEnvironment,
        status: fmi3Status,
        category: fmi3String,
        message: fmi3String,
    ),
>;

/// `fmi3ClockUpdateCallback`
pub type fmi3ClockUpdateCallback =
    Option<unsafe extern "C" fn(instance_environment: fmi3InstanceEnvironment)>;

/// `fmi3IntermediateUpdateCallback`
pub type fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        instance_environment: fmi3InstanceEnvironment,
        intermediate_update_time: fmi3Float64,
        intermediate_variable_set_requested: fmi3Boolean,
        intermediate_variable_get_allowed: fmi3Boolean,
        intermediate_step_finished: fmi3Boolean,
        can_return_early: fmi3Boolean,
        early_return_requested: *mut fmi3Boolean,
        early_return_time: *mut fmi3Float64,
    ),
>;

/// `fmi3LockPreemptionCallback`
pub type fmi3LockPreemptionCallback = Option<unsafe extern "C" fn()>;
/// `fmi3UnlockPreemptionCallback`
pub type fmi3UnlockPreemptionCallback = Option<unsafe extern "C" fn()>;

/// `fmi3Version` returned by `fmi3GetVersion`.
pub const VERSION: &[u8] = b"3.0\0";
