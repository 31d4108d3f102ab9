//! A minimal importer for the tests: calls the exported `fmi3*` functions of the test binary and
//! records the log messages of each instance.

use super::fmi3_exports::*;
use super::lag::Lag;
use crate::types::*;
use fmi_core::model::Model;
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

/// (status, category, message)
pub type Messages = Mutex<Vec<(fmi3Status, String, String)>>;

unsafe extern "C" fn record(
    env: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: env is the `Messages` of a live `Fmu`; the strings are valid during the call.
    let (log, category, message) = unsafe {
        (
            &*(env as *const Messages),
            CStr::from_ptr(category).to_string_lossy().into_owned(),
            CStr::from_ptr(message).to_string_lossy().into_owned(),
        )
    };
    log.lock().unwrap().push((status, category, message));
}

pub struct Fmu {
    pub instance: fmi3Instance,
    pub log: Box<Messages>,
}

pub fn token() -> CString {
    CString::new(Lag::info().guid()).unwrap()
}

impl Fmu {
    /// Instantiates with the right token; `None` if refused (the log is returned for inspection).
    pub fn try_new(
        name: &str,
        token: &CString,
        logging_on: bool,
        event_mode_used: bool,
    ) -> Result<Fmu, Box<Messages>> {
        let log: Box<Messages> = Box::default();
        let name = CString::new(name).unwrap();
        // SAFETY: valid strings; the environment outlives the instance (both live in `Fmu`).
        let instance = unsafe {
            fmi3InstantiateCoSimulation(
                name.as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                false,
                logging_on,
                event_mode_used,
                false,
                std::ptr::null(),
                0,
                &*log as *const Messages as *mut c_void,
                Some(record),
                None,
            )
        };
        if instance.is_null() {
            Err(log)
        } else {
            Ok(Fmu { instance, log })
        }
    }

    pub fn new(name: &str) -> Fmu {
        Fmu::try_new(name, &token(), true, false).expect("instantiation refused")
    }

    /// Instantiated, parameters set, initialized: in Step Mode at t = 0.
    pub fn started(name: &str, reals: &[(u32, f64)]) -> Fmu {
        let f = Fmu::new(name);
        for (vr, x) in reals {
            assert_eq!(f.set_f64(&[*vr], &[*x]), FMI3_OK);
        }
        assert_eq!(
            fmi3EnterInitializationMode(f.instance, false, 0.0, 0.0, true, 10.0),
            FMI3_OK
        );
        assert_eq!(fmi3ExitInitializationMode(f.instance), FMI3_OK);
        f
    }

    pub fn messages(&self) -> Vec<(fmi3Status, String, String)> {
        self.log.lock().unwrap().clone()
    }

    pub fn last_message(&self) -> String {
        self.messages()
            .last()
            .map(|m| m.2.clone())
            .unwrap_or_default()
    }

    pub fn get_f64(&self, vrs: &[u32]) -> (fmi3Status, Vec<f64>) {
        let mut out = vec![f64::NAN; vrs.len()];
        // SAFETY: arrays of the given lengths.
        let s = unsafe {
            fmi3GetFloat64(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                out.as_mut_ptr(),
                out.len(),
            )
        };
        (s, out)
    }

    pub fn set_f64(&self, vrs: &[u32], values: &[f64]) -> fmi3Status {
        // SAFETY: arrays of the given lengths.
        unsafe {
            fmi3SetFloat64(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    pub fn get_i32(&self, vrs: &[u32]) -> (fmi3Status, Vec<i32>) {
        let mut out = vec![-1; vrs.len()];
        // SAFETY: arrays of the given lengths.
        let s = unsafe {
            fmi3GetInt32(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                out.as_mut_ptr(),
                out.len(),
            )
        };
        (s, out)
    }

    pub fn set_i32(&self, vrs: &[u32], values: &[i32]) -> fmi3Status {
        // SAFETY: arrays of the given lengths.
        unsafe {
            fmi3SetInt32(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    /// One step; returns the status and lastSuccessfulTime.
    pub fn step(&self, t: f64, h: f64) -> (fmi3Status, f64, bool) {
        let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
        // SAFETY: four writable outputs.
        let s = unsafe {
            fmi3DoStep(
                self.instance,
                t,
                h,
                false,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        assert!(!event && !early, "no events, no early return");
        (s, last, terminate)
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: from fmi3InstantiateCoSimulation, freed once.
        unsafe { fmi3FreeInstance(self.instance) };
    }
}
