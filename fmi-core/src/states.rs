//! FMU states, handled alike for both standards: save (get), save into an existing state
//! (update), restore (set), serialize, deserialize, and free when dropped. Each importer gives
//! the six C functions of its instance ([`StateCalls`]); the rest is here, once.

use crate::{check, CallError};
use std::ffi::c_void;
use std::sync::Arc;

/// The names of an importer's state functions, for its errors.
pub struct StateNames {
    pub get: &'static str,
    pub set: &'static str,
    pub size: &'static str,
    pub serialize: &'static str,
    pub deserialize: &'static str,
}

/// The FMU-state functions of one live instance (FMI 2.0 and 3.0 give them the same shapes).
///
/// # Safety
/// Each method calls the FMU's function of that name for the implementor's own instance, with
/// the arguments as given; the instance lives as long as the implementor.
pub unsafe trait StateCalls {
    const NAMES: StateNames;
    /// # Safety
    /// `state` points to a null pointer or to a state of this instance.
    unsafe fn get(&self, state: *mut *mut c_void) -> i32;
    /// # Safety
    /// `state` is a state of this instance.
    unsafe fn set(&self, state: *mut c_void) -> i32;
    /// # Safety
    /// `state` points to a state of this instance, freed once.
    unsafe fn free(&self, state: *mut *mut c_void) -> i32;
    /// # Safety
    /// `state` is a state of this instance; `size` is writable.
    unsafe fn size(&self, state: *mut c_void, size: *mut usize) -> i32;
    /// # Safety
    /// `state` is a state of this instance; `bytes` holds `size` writable bytes.
    unsafe fn serialize(&self, state: *mut c_void, bytes: *mut u8, size: usize) -> i32;
    /// # Safety
    /// `bytes` holds `size` readable bytes; `state` is writable.
    unsafe fn deserialize(&self, bytes: *const u8, size: usize, state: *mut *mut c_void) -> i32;
}

/// An FMU state of an instance; freed on drop. Keeps its instance alive.
pub struct FmuState<I: StateCalls> {
    inner: Arc<I>,
    ptr: *mut c_void,
}

// An instance's state moves with its instance between threads, one call at a time (as the
// standards allow the instance itself).
unsafe impl<I: StateCalls> Send for FmuState<I> {}

impl<I: StateCalls> Drop for FmuState<I> {
    fn drop(&mut self) {
        // SAFETY: ptr is a state of this instance, freed once.
        unsafe { self.inner.free(&mut self.ptr) };
    }
}

impl<I: StateCalls> FmuState<I> {
    /// Saves the instance's current state.
    pub fn get(inner: &Arc<I>) -> Result<Self, CallError> {
        let mut ptr: *mut c_void = std::ptr::null_mut();
        // SAFETY: out pointer to a null state.
        check(I::NAMES.get, unsafe { inner.get(&mut ptr) })?;
        Ok(FmuState {
            inner: inner.clone(),
            ptr,
        })
    }

    /// Saves the instance's current state into this one (the FMU may reuse its memory).
    pub fn update(&mut self, inner: &Arc<I>) -> Result<(), CallError> {
        assert!(
            Arc::ptr_eq(&self.inner, inner),
            "a state of another instance"
        );
        // SAFETY: a state of this instance, overwritten in place.
        check(I::NAMES.get, unsafe { inner.get(&mut self.ptr) })
    }

    /// Restores the instance to this state.
    pub fn set(&self, inner: &Arc<I>) -> Result<(), CallError> {
        // SAFETY: a state of this instance.
        check(I::NAMES.set, unsafe { inner.set(self.ptr) })
    }

    pub fn serialize(&self) -> Result<Vec<u8>, CallError> {
        let mut n = 0usize;
        // SAFETY: a state of this instance; out pointer.
        check(I::NAMES.size, unsafe { self.inner.size(self.ptr, &mut n) })?;
        let mut bytes = vec![0u8; n];
        // SAFETY: buffer of n bytes.
        check(I::NAMES.serialize, unsafe {
            self.inner.serialize(self.ptr, bytes.as_mut_ptr(), n)
        })?;
        Ok(bytes)
    }

    /// A state of the instance from serialized bytes.
    pub fn deserialize(inner: &Arc<I>, bytes: &[u8]) -> Result<Self, CallError> {
        let mut ptr: *mut c_void = std::ptr::null_mut();
        // SAFETY: buffer of bytes.len() bytes; out pointer.
        check(I::NAMES.deserialize, unsafe {
            inner.deserialize(bytes.as_ptr(), bytes.len(), &mut ptr)
        })?;
        Ok(FmuState {
            inner: inner.clone(),
            ptr,
        })
    }
}
