//! fmi3Get/Set for the types the fmi2 table has (Float64, Int32, Boolean; String has no variables)
//! and fmi3GetOutputDerivatives. Value references are FMI 3.0 ones (see `value_refs`).
//!
//! All our variables are scalars, so `nValues` must equal `nValueReferences`.

use super::{null_argument, slice, slice_mut, with};
use crate::instance::{err, Instance, Res};
use crate::state;
use crate::types::*;
use fmi_core::model::Model;
use fmi_core::Status;

fn check_counts(n_value_references: usize, n_values: usize) -> Result<(), (Status, String)> {
    if n_value_references != n_values {
        return err(format!(
            "nValues ({n_values}) must equal nValueReferences ({n_value_references}): this FMU has no array variables"
        ));
    }
    Ok(())
}

macro_rules! direct {
    // Same element type on both sides (Float64, Int32): the caller's arrays are used in place, no
    // allocation per call (a master calls these every macro step).
    (get $name:ident, $fmi:literal, $ty:ty, $method:ident) => {
        /// # Safety
        /// FMI 3.0 getter: `vr` points to `n_vr` and `value` to `n_values` elements.
        pub unsafe fn $name<M: Model>(
            c: fmi3Instance,
            vr: *const fmi3ValueReference,
            n_vr: usize,
            value: *mut $ty,
            n_values: usize,
        ) -> fmi3Status {
            with::<M>(c, $fmi, |inst| {
                // SAFETY: FMI contract: arrays of the given lengths.
                let (Some(vrs), Some(out)) = (unsafe { slice(vr, n_vr) }, unsafe {
                    slice_mut(value, n_values)
                }) else {
                    return null_argument(inst, $fmi, "valueReferences or values");
                };
                inst.run($fmi, state::MASK_GET, |i| {
                    check_counts(n_vr, n_values)?;
                    i.$method(vrs, out)
                })
            })
        }
    };
    (set $name:ident, $fmi:literal, $ty:ty, $method:ident) => {
        /// # Safety
        /// FMI 3.0 setter: `vr` points to `n_vr` and `value` to `n_values` elements.
        pub unsafe fn $name<M: Model>(
            c: fmi3Instance,
            vr: *const fmi3ValueReference,
            n_vr: usize,
            value: *const $ty,
            n_values: usize,
        ) -> fmi3Status {
            with::<M>(c, $fmi, |inst| {
                // SAFETY: FMI contract: arrays of the given lengths.
                let (Some(vrs), Some(vals)) = (unsafe { slice(vr, n_vr) }, unsafe {
                    slice(value, n_values)
                }) else {
                    return null_argument(inst, $fmi, "valueReferences or values");
                };
                inst.run($fmi, state::MASK_SET, |i| {
                    check_counts(n_vr, n_values)?;
                    i.$method(vrs, vals)
                })
            })
        }
    };
}

direct!(get get_float64, "fmi3GetFloat64", fmi3Float64, get_float64);
direct!(set set_float64_outside_step, "fmi3SetFloat64", fmi3Float64, set_float64);

/// # Safety
/// FMI 3.0 `fmi3SetFloat64`: `vr` points to `n_vr` and `value` to `n_values` elements.
///
/// Inside an intermediateUpdate callback (the model is in fmi3DoStep) the values go to the shell's
/// buffer, which the stepping model reads (`crate::intermediate`); otherwise to the instance.
pub unsafe fn set_float64<M: Model>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    n_vr: usize,
    value: *const fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    const F: &str = "fmi3SetFloat64";
    // SAFETY: FMI contract: the instance from fmi3InstantiateCoSimulation, or null.
    let stepping = unsafe { super::shell::<M>(c) }.is_some_and(|s| s.stepping.get());
    if !stepping {
        // SAFETY: the caller's contract.
        return unsafe { set_float64_outside_step::<M>(c, vr, n_vr, value, n_values) };
    }
    super::with_shell::<M>(c, F, |shell| {
        // SAFETY: FMI contract: arrays of the given lengths.
        let (Some(vrs), Some(vals)) = (unsafe { slice(vr, n_vr) }, unsafe {
            slice(value, n_values)
        }) else {
            return super::refuse_while_stepping(
                shell,
                F,
                "valueReferences or values is a null pointer",
            );
        };
        if n_vr != n_values {
            return super::refuse_while_stepping(
                shell,
                F,
                format!("nValues ({n_values}) must equal nValueReferences ({n_vr})"),
            );
        }
        // Float64 value references are the per-type Real ones (`value_refs`); `set` checks each is an input.
        let result = match shell.buffer.try_borrow_mut() {
            Ok(mut b) => b.set(vrs, vals),
            Err(_) => Err("re-entered while the buffer is in use".into()),
        };
        match result {
            Ok(()) => Status::Ok,
            Err(reason) => super::refuse_while_stepping(shell, F, reason),
        }
    })
}
direct!(get get_int32, "fmi3GetInt32", fmi3Int32, get_int32);
direct!(set set_int32, "fmi3SetInt32", fmi3Int32, set_int32);

/// # Safety
/// FMI 3.0 `fmi3GetBoolean`.
pub unsafe fn get_boolean<M: Model>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    n_vr: usize,
    value: *mut fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    const F: &str = "fmi3GetBoolean";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract. The output is viewed as bytes: the importer's array may hold
        // anything before we write it, which a `&mut [bool]` must not.
        let (Some(vrs), Some(out)) = (unsafe { slice(vr, n_vr) }, unsafe {
            slice_mut(value as *mut u8, n_values)
        }) else {
            return null_argument(inst, F, "valueReferences or values");
        };
        inst.run(F, state::MASK_GET, |i| {
            check_counts(n_vr, n_values)?;
            let mut values = vec![false; n_vr];
            let status = i.get_boolean(vrs, &mut values)?;
            for (o, v) in out.iter_mut().zip(values) {
                *o = v as u8;
            }
            Ok(status)
        })
    })
}

/// # Safety
/// FMI 3.0 `fmi3SetBoolean`.
pub unsafe fn set_boolean<M: Model>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    n_vr: usize,
    value: *const fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    const F: &str = "fmi3SetBoolean";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract. Read as bytes: a C bool other than 0 or 1 must not become a Rust
        // bool; any non-zero byte means true.
        let (Some(vrs), Some(bytes)) = (unsafe { slice(vr, n_vr) }, unsafe {
            slice(value as *const u8, n_values)
        }) else {
            return null_argument(inst, F, "valueReferences or values");
        };
        inst.run(F, state::MASK_SET, |i| {
            check_counts(n_vr, n_values)?;
            let values: Vec<bool> = bytes.iter().map(|b| *b != 0).collect();
            i.set_boolean(vrs, &values)
        })
    })
}

/// fmi3GetString / fmi3SetString: the fmi2 table has no String variables, so an empty request
/// succeeds and any value reference is unknown.
///
/// # Safety
/// `vr` points to `n_vr` value references (the values are never touched).
pub unsafe fn no_strings<M: Model>(
    c: fmi3Instance,
    function: &str,
    mask: state::Mask,
    vr: *const fmi3ValueReference,
    n_vr: usize,
    n_values: usize,
) -> fmi3Status {
    with::<M>(c, function, |inst| {
        // SAFETY: FMI contract.
        let Some(vrs) = (unsafe { slice(vr, n_vr) }) else {
            return null_argument(inst, function, "valueReferences");
        };
        inst.run(function, mask, |i| {
            check_counts(n_vr, n_values)?;
            i.inner.no_strings(vrs)
        })
    })
}

/// # Safety
/// FMI 3.0 `fmi3GetOutputDerivatives`.
pub unsafe fn get_output_derivatives<M: Model>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    n_vr: usize,
    orders: *const fmi3Int32,
    value: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    const F: &str = "fmi3GetOutputDerivatives";
    with::<M>(c, F, |inst: &mut Instance<M>| {
        // SAFETY: FMI contract: vr and orders hold n_vr elements, values n_values.
        let (Some(vrs), Some(ord), Some(out)) = (
            unsafe { slice(vr, n_vr) },
            unsafe { slice(orders, n_vr) },
            unsafe { slice_mut(value, n_values) },
        ) else {
            return null_argument(inst, F, "valueReferences, orders or values");
        };
        inst.run(F, state::MASK_GET_OUTPUT_DERIVATIVES, |i| -> Res {
            check_counts(n_vr, n_values)?;
            i.get_output_derivatives(vrs, ord, out)
        })
    })
}
