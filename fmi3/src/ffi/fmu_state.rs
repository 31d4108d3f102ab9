//! FMU states: a boxed copy of the core instance's `Core` (phase, store, model, times), serialized
//! with `fmi_core::snapshot`, so a blob has the same format in the FMI 2.0 and FMI 3.0 exports.

use super::{null_argument, slice, slice_mut, with};
use crate::instance::Res;
use crate::state;
use crate::types::*;
use fmi_core::instance::Core;
use fmi_core::model::Model;
use fmi_core::Status;

/// An FMU state handed to the importer: a boxed core plus a magic to recognise it.
pub struct StateBox<M: Model> {
    magic: u64,
    core: Core<M>,
}

const STATE_MAGIC: u64 = 0x5354_4154_4533_4149; // "STATE3AI"

/// # Safety
/// `s` null or from `get_fmu_state::<M>`/`deserialize_fmu_state::<M>` and not yet freed.
unsafe fn state_ref<'a, M: Model>(s: fmi3FMUState) -> Option<&'a mut StateBox<M>> {
    if s.is_null() {
        return None;
    }
    // SAFETY: contract above; the magic check refuses a state of another model or a freed one
    // whose memory has not been reused (best effort).
    let b = unsafe { &mut *(s as *mut StateBox<M>) };
    (b.magic == STATE_MAGIC).then_some(b)
}

fn new_state<M: Model>(core: Core<M>) -> fmi3FMUState {
    Box::into_raw(Box::new(StateBox {
        magic: STATE_MAGIC,
        core,
    })) as fmi3FMUState
}

/// # Safety
/// FMI 3.0 `fmi3GetFMUState`: `state` points to a handle, null (a new state) or one of ours (reused).
pub unsafe fn get_fmu_state<M: Model>(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3GetFMUState";
    with::<M>(c, F, |inst| {
        if state.is_null() {
            return null_argument(inst, F, "FMUState");
        }
        inst.run(F, state::MASK_GET_FMU_STATE, |i| -> Res {
            // SAFETY: checked non-null; FMI contract: *state is null or a state of this FMU.
            match unsafe { state_ref::<M>(*state) } {
                // Reuses the buffers of a state the master keeps overwriting (roll-back).
                Some(existing) => existing.core.clone_from(&i.inner.core),
                // SAFETY: as above.
                None => unsafe { *state = new_state(i.inner.core.clone()) },
            }
            Ok(Status::Ok)
        })
    })
}

/// # Safety
/// FMI 3.0 `fmi3SetFMUState`.
pub unsafe fn set_fmu_state<M: Model>(c: fmi3Instance, state: fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3SetFMUState";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract: a state from fmi3GetFMUState/fmi3DeserializeFMUState.
        let Some(b) = (unsafe { state_ref::<M>(state) }) else {
            inst.reject(
                Status::Error,
                F,
                "FMUState is null or not a state of this FMU",
            );
            return Status::Error;
        };
        // Straight into the core, not through fmi2's `restore`: FMI 3.0 allows restoring a state
        // after an error (fmi2 does not), and the mask is the one check.
        inst.run(F, state::MASK_SET_FMU_STATE, |i| {
            i.inner.core.clone_from(&b.core);
            Ok(Status::Ok)
        })
    })
}

/// # Safety
/// FMI 3.0 `fmi3FreeFMUState`: `*state` is null (no-op) or one of ours; it is set to null.
pub unsafe fn free_fmu_state<M: Model>(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3FreeFMUState";
    with::<M>(c, F, |inst| {
        if state.is_null() {
            return null_argument(inst, F, "FMUState");
        }
        inst.run(F, state::MASK_FREE_FMU_STATE, |_| {
            // SAFETY: checked non-null; FMI contract as above.
            unsafe {
                if (*state).is_null() {
                    return Ok(Status::Ok);
                }
                if state_ref::<M>(*state).is_none() {
                    return Err((Status::Error, "not a state of this FMU".into()));
                }
                let mut b = Box::from_raw(*state as *mut StateBox<M>);
                b.magic = 0;
                drop(b);
                *state = std::ptr::null_mut();
            }
            Ok(Status::Ok)
        })
    })
}

/// # Safety
/// FMI 3.0 `fmi3SerializedFMUStateSize`.
pub unsafe fn serialized_fmu_state_size<M: Model>(
    c: fmi3Instance,
    state: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    const F: &str = "fmi3SerializedFMUStateSize";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract.
        let (Some(b), false) = (unsafe { state_ref::<M>(state) }, size.is_null()) else {
            return null_argument(inst, F, "FMUState or size");
        };
        inst.run(F, state::MASK_SERIALIZE_FMU_STATE, |i| {
            let n = fmi_core::snapshot::serialize(&b.core, &i.inner.guid).len();
            // SAFETY: checked non-null.
            unsafe { *size = n };
            Ok(Status::Ok)
        })
    })
}

/// # Safety
/// FMI 3.0 `fmi3SerializeFMUState`: `bytes` has room for `size` bytes.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: fmi3Instance,
    state: fmi3FMUState,
    bytes: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    const F: &str = "fmi3SerializeFMUState";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract.
        let (Some(b), Some(out)) = (unsafe { state_ref::<M>(state) }, unsafe {
            slice_mut(bytes, size)
        }) else {
            return null_argument(inst, F, "FMUState or serializedState");
        };
        inst.run(F, state::MASK_SERIALIZE_FMU_STATE, |i| {
            let blob = fmi_core::snapshot::serialize(&b.core, &i.inner.guid);
            if blob.len() != size {
                return Err((
                    Status::Error,
                    format!(
                        "size {size} differs from fmi3SerializedFMUStateSize {}",
                        blob.len()
                    ),
                ));
            }
            out.copy_from_slice(&blob);
            Ok(Status::Ok)
        })
    })
}

/// # Safety
/// FMI 3.0 `fmi3DeserializeFMUState`: `*state` is null (a new state) or one of ours (overwritten).
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: fmi3Instance,
    bytes: *const fmi3Byte,
    size: usize,
    state: *mut fmi3FMUState,
) -> fmi3Status {
    const F: &str = "fmi3DeserializeFMUState";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract.
        let (Some(data), false) = (unsafe { slice(bytes, size) }, state.is_null()) else {
            return null_argument(inst, F, "serializedState or FMUState");
        };
        inst.run(F, state::MASK_DESERIALIZE_FMU_STATE, |i| {
            let shape = fmi_core::model::Store::from_info(&i.inner.info);
            let core = fmi_core::snapshot::deserialize::<M>(data, &i.inner.guid, &shape)
                .map_err(|e| (Status::Error, e))?;
            // SAFETY: checked non-null; FMI contract: *state is null or a state of this FMU.
            unsafe {
                match state_ref::<M>(*state) {
                    Some(existing) => existing.core = core,
                    None => *state = new_state(core),
                }
            }
            Ok(Status::Ok)
        })
    })
}
