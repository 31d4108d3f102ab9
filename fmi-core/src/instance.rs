//! One FMU instance: the co-simulation call-state machine around a `Model`, for both standards.
//!
//! Every method here is safe Rust on slices; each standard's glue (`fmi2::ffi`, `fmi3::ffi`) turns
//! C pointers into them (FMI 3.0 adds its own call-state masks around these calls). A call in the
//! wrong state, or with bad arguments, is rejected with Error and a logged reason and leaves the
//! instance as it was (as the Reference FMUs do); a model failure in a step moves it to
//! `Phase::Error`. The phases are those of FMI 2.0's co-simulation (FMI 2.0.4, section 4.2.4),
//! which FMI 3.0's co-simulation states refine.

use crate::logging::Logger;
use crate::model::{
    AskedInputs, Inputs, IntermediateInputs, Log, Model, StepInputs, StepOutcome, Store,
    MAX_INPUT_DERIVATIVE_ORDER,
};
use crate::variables::{Causality, ModelInfo, VarIndex, VarType, Variable};
use crate::Status;
use std::path::PathBuf;

/// Marks a live instance; checked on every call so a null or foreign pointer is refused.
pub const INSTANCE_MAGIC: u64 = 0x4149_5252_494e_4731; // "AIRRING1"

/// States of the FMI 2.0 co-simulation state machine (FMI 2.0.4, section 4.2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::Instantiated => "instantiated",
            Phase::InitializationMode => "initialization mode",
            Phase::StepComplete => "step complete",
            Phase::StepFailed => "step failed",
            Phase::Terminated => "terminated",
            Phase::Error => "error",
        }
    }
    pub(crate) fn to_u8(self) -> u8 {
        self as u8
    }
    pub(crate) fn from_u8(b: u8) -> Option<Phase> {
        [
            Phase::Instantiated,
            Phase::InitializationMode,
            Phase::StepComplete,
            Phase::StepFailed,
            Phase::Terminated,
            Phase::Error,
        ]
        .get(b as usize)
        .copied()
    }
}

/// Phases in which an FMU state may be got or set.
const STATE_PHASES: [Phase; 5] = [
    Phase::Instantiated,
    Phase::InitializationMode,
    Phase::StepComplete,
    Phase::StepFailed,
    Phase::Terminated,
];

/// The part of an instance that an FMU state (fmi2GetFMUstate, fmi3GetFMUState) captures.
pub struct Core<M: Model> {
    pub phase: Phase,
    pub store: Store,
    pub model: Option<M>,
    /// Parameters or inputs changed since `model` was built (initialization mode only).
    pub model_stale: bool,
    pub time: f64,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    pub tolerance: Option<f64>,
    pub last_successful_time: f64,
    /// Input derivatives set for the next step, indexed by Real value reference.
    pub input_derivatives: Vec<[f64; MAX_INPUT_DERIVATIVE_ORDER]>,
}

/// `clone_from` copies field by field into the existing buffers: a master that saves states at
/// every macro step (roll-back) reuses one state handle, and the model's own `clone_from` can skip
/// what has not changed (the air film's factorized Jacobians).
impl<M: Model> Clone for Core<M> {
    fn clone(&self) -> Self {
        Core {
            phase: self.phase,
            store: self.store.clone(),
            model: self.model.clone(),
            model_stale: self.model_stale,
            time: self.time,
            start_time: self.start_time,
            stop_time: self.stop_time,
            tolerance: self.tolerance,
            last_successful_time: self.last_successful_time,
            input_derivatives: self.input_derivatives.clone(),
        }
    }

    fn clone_from(&mut self, src: &Self) {
        // Destructured so that a new field fails to compile until it is copied here too.
        let Core {
            phase,
            store,
            model,
            model_stale,
            time,
            start_time,
            stop_time,
            tolerance,
            last_successful_time,
            input_derivatives,
        } = src;
        self.phase = *phase;
        self.store.clone_from(store);
        self.model.clone_from(model);
        self.model_stale = *model_stale;
        self.time = *time;
        self.start_time = *start_time;
        self.stop_time = *stop_time;
        self.tolerance = *tolerance;
        self.last_successful_time = *last_successful_time;
        self.input_derivatives.clone_from(input_derivatives);
    }
}

pub struct Instance<M: Model> {
    pub magic: u64,
    pub info: ModelInfo,
    index: VarIndex,
    pub guid: String,
    pub logger: Logger,
    pub resource_dir: Option<PathBuf>,
    pub core: Core<M>,
    /// Reused between steps so doStep does not allocate.
    inputs: Inputs,
    /// The `rtol` / `atol` parameters the master set (fmi2SetReal, fmi3SetFloat64): they win over
    /// the tolerance of fmi2SetupExperiment / fmi3EnterInitializationMode (see
    /// [`Instance::effective_store`]).
    tolerances_set: [bool; 2],
}

/// Value references of a model's Real parameters named `rtol` and `atol`, with their start values.
fn tolerance_parameters(info: &ModelInfo) -> [Option<(u32, f64)>; 2] {
    ["rtol", "atol"].map(|name| {
        info.variables
            .iter()
            .find(|v| {
                v.name == name
                    && v.var_type == VarType::Real
                    && v.causality == crate::variables::Causality::Parameter
            })
            .map(|v| (v.vr, v.start.unwrap_or(0.0)))
    })
}

/// Adapter that lets the model log through the instance's logger.
struct ModelLog<'a>(&'a Logger);

impl Log for ModelLog<'_> {
    fn debug(&mut self, category: &str, message: &str) {
        self.0.log(Status::Ok, category, message);
    }
    fn warning(&mut self, message: &str) {
        self.0.log(Status::Warning, "logStatusWarning", message);
    }
    fn enabled(&self, category: &str) -> bool {
        self.0.enabled(category)
    }
}

type Res = Result<Status, (Status, String)>;

fn err<T>(msg: impl Into<String>) -> Result<T, (Status, String)> {
    Err((Status::Error, msg.into()))
}

impl<M: Model> Instance<M> {
    /// fmi2Instantiate / fmi3InstantiateCoSimulation after the C strings have been read, with
    /// the logger the glue made (of the model's categories, [`ModelInfo::all_log_categories`])
    /// and the resource folder it read (or why it could not). Returns the reason on refusal.
    pub fn new(
        instance_name: &str,
        guid: &str,
        resources: Result<Option<PathBuf>, String>,
        logger: Logger,
    ) -> Result<Self, (Logger, String)> {
        let info = M::info();
        if instance_name.is_empty() {
            return Err((logger, "instanceName must not be empty".into()));
        }
        let own_guid = info.guid();
        if guid != own_guid {
            return Err((
                logger,
                format!("GUID '{guid}' does not match this FMU's '{own_guid}' (modelDescription.xml from another build?)"),
            ));
        }
        if let Err(e) = info.check() {
            return Err((
                logger,
                format!("the model's variable table is inconsistent: {e}"),
            ));
        }
        let resource_dir = resources.unwrap_or_else(|e| {
            logger.log(
                Status::Warning,
                "logStatusWarning",
                &format!(
                    "{}: {e}; resources unavailable",
                    logger.standard().instantiate()
                ),
            );
            None
        });
        let store = Store::from_info(&info);
        let n_real = store.reals.len();
        let de = info.default_experiment;
        Ok(Instance {
            magic: INSTANCE_MAGIC,
            guid: own_guid,
            logger,
            resource_dir,
            core: Core {
                phase: Phase::Instantiated,
                store: store.clone(),
                model: None,
                model_stale: true,
                time: de.start_time,
                start_time: de.start_time,
                stop_time: None,
                tolerance: None,
                last_successful_time: de.start_time,
                input_derivatives: vec![[0.0; MAX_INPUT_DERIVATIVE_ORDER]; n_real],
            },
            inputs: Inputs {
                t0: 0.0,
                values: vec![0.0; n_real],
                derivatives: vec![[0.0; MAX_INPUT_DERIVATIVE_ORDER]; n_real],
            },
            index: VarIndex::new(&info),
            info,
            tolerances_set: [false; 2],
        })
    }

    /// The store the model is built from: with a tolerance from fmi2SetupExperiment, a model's
    /// Real parameters `rtol` and `atol` that the master did not set take it: rtol = tolerance,
    /// atol = its start value scaled by tolerance / rtol's start value (both tighten together).
    /// A value the master set through fmi2SetReal wins.
    fn effective_store(&self) -> std::borrow::Cow<'_, Store> {
        let Some(tol) = self.core.tolerance else {
            return std::borrow::Cow::Borrowed(&self.core.store);
        };
        let [rtol, atol] = tolerance_parameters(&self.info);
        let mut store = self.core.store.clone();
        if let (Some((vr, _)), false) = (rtol, self.tolerances_set[0]) {
            store.reals[vr as usize] = tol;
        }
        if let (Some((vr, atol0)), Some((_, rtol0)), false) = (atol, rtol, self.tolerances_set[1]) {
            if rtol0 > 0.0 {
                store.reals[vr as usize] = atol0 * tol / rtol0;
            }
        }
        std::borrow::Cow::Owned(store)
    }

    /// The variable of a type and value reference (O(1)).
    fn variable(&self, t: VarType, vr: u32) -> Option<&Variable> {
        self.index.variable(&self.info, t, vr)
    }

    /// Runs a call body and logs its rejection, if any. `function` names the FMI function.
    pub fn run(&mut self, function: &str, body: impl FnOnce(&mut Self) -> Res) -> Status {
        match body(self) {
            Ok(s) => s,
            Err((status, reason)) => {
                self.logger.reject(status, function, &reason);
                status
            }
        }
    }

    fn require(&self, allowed: &[Phase]) -> Result<(), (Status, String)> {
        if allowed.contains(&self.core.phase) {
            Ok(())
        } else {
            Err((
                Status::Error,
                format!("not allowed in state '{}'", self.core.phase.name()),
            ))
        }
    }

    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Res {
        let unknown = self.logger.set_debug_logging(on, categories);
        if unknown.is_empty() {
            Ok(Status::Ok)
        } else {
            Err((
                Status::Warning,
                format!("unknown log categories {unknown:?} ignored"),
            ))
        }
    }

    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Res {
        self.require(&[Phase::Instantiated])?;
        if !start.is_finite() {
            return err(format!("startTime {start} is not finite"));
        }
        M::check_start_time(start).or_else(err)?;
        if let Some(stop) = stop {
            if !(stop.is_finite() && stop >= start) {
                return err(format!(
                    "stopTime {stop} must be finite and >= startTime {start}"
                ));
            }
        }
        if let Some(tol) = tolerance {
            // A relative tolerance: 1 and above would accept any error (the models' rtol has
            // the same range; refused here, not later as a parameter the master never set).
            if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
                return err(format!(
                    "tolerance {tol} must lie in (0, 1): it is the relative tolerance of the \
                     model's error control"
                ));
            }
            M::check_tolerance(tol).or_else(err)?;
        }
        let c = &mut self.core;
        c.start_time = start;
        c.time = start;
        c.last_successful_time = start;
        c.stop_time = stop;
        c.tolerance = tolerance;
        Ok(Status::Ok)
    }

    pub fn enter_initialization_mode(&mut self) -> Res {
        self.require(&[Phase::Instantiated])?;
        self.core.phase = Phase::InitializationMode;
        Ok(Status::Ok)
    }

    /// Builds the model from the current parameters if it is missing or stale, and updates outputs.
    fn ensure_model(&mut self) -> Result<(), (Status, String)> {
        if self.core.model.is_some() && !self.core.model_stale {
            return Ok(());
        }
        let mut log = ModelLog(&self.logger);
        let model = M::new(
            &self.effective_store(),
            self.core.start_time,
            self.resource_dir.as_deref(),
            &mut log,
        )
        .map_err(|e| (Status::Error, e))?;
        model.write_outputs(&mut self.core.store);
        self.core.model = Some(model);
        self.core.model_stale = false;
        Ok(())
    }

    pub fn exit_initialization_mode(&mut self) -> Res {
        self.require(&[Phase::InitializationMode])?;
        if let Err((s, e)) = self.ensure_model() {
            self.core.phase = Phase::Error;
            return Err((s, format!("the model could not be initialized: {e}")));
        }
        self.core.phase = Phase::StepComplete;
        Ok(Status::Ok)
    }

    pub fn terminate(&mut self) -> Res {
        self.require(&[Phase::StepComplete, Phase::StepFailed])?;
        self.core.phase = Phase::Terminated;
        Ok(Status::Ok)
    }

    /// fmi2Reset / fmi3Reset: back to the state right after instantiation (start values, no
    /// model).
    pub fn reset(&mut self) -> Res {
        let store = Store::from_info(&self.info);
        let de = self.info.default_experiment;
        let c = &mut self.core;
        c.phase = Phase::Instantiated;
        c.store = store;
        c.model = None;
        c.model_stale = true;
        c.time = de.start_time;
        c.start_time = de.start_time;
        c.stop_time = None;
        c.tolerance = None;
        self.tolerances_set = [false; 2];
        c.last_successful_time = de.start_time;
        c.input_derivatives
            .iter_mut()
            .for_each(|d| *d = [0.0; MAX_INPUT_DERIVATIVE_ORDER]);
        Ok(Status::Ok)
    }

    const READABLE: &'static [Phase] = &[
        Phase::InitializationMode,
        Phase::StepComplete,
        Phase::StepFailed,
        Phase::Terminated,
        Phase::Error,
    ];

    fn check_vrs(&self, t: VarType, vrs: &[u32]) -> Result<(), (Status, String)> {
        let n = self.index.count(t) as u32;
        match vrs.iter().find(|&&vr| vr >= n) {
            Some(vr) => err(format!("unknown {} value reference {vr}", t.as_str())),
            None => Ok(()),
        }
    }

    /// Makes outputs current before a read in initialization mode.
    fn prepare_read(&mut self) -> Result<(), (Status, String)> {
        self.require(Self::READABLE)?;
        // After a failed initialization there is no model: the store holds start values and
        // zeros (h_min = 0 m, p_max = 0 Pa), which a master that ignores statuses would plot.
        if self.core.phase == Phase::Error && self.core.model.is_none() {
            return err(format!(
                "no values to read: the model could not be initialized (see the error logged \
                 then); {} starts again",
                self.logger.standard().reset()
            ));
        }
        if self.core.phase == Phase::InitializationMode {
            self.ensure_model()?;
        }
        Ok(())
    }

    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Res {
        self.check_vrs(VarType::Real, vrs)?;
        self.prepare_read()?;
        for (o, vr) in out.iter_mut().zip(vrs) {
            *o = self.core.store.real(*vr);
        }
        Ok(Status::Ok)
    }

    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> Res {
        self.check_vrs(VarType::Integer, vrs)?;
        self.prepare_read()?;
        for (o, vr) in out.iter_mut().zip(vrs) {
            *o = self.core.store.integer(*vr);
        }
        Ok(Status::Ok)
    }

    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> Res {
        self.check_vrs(VarType::Boolean, vrs)?;
        self.prepare_read()?;
        for (o, vr) in out.iter_mut().zip(vrs) {
            *o = self.core.store.boolean(*vr);
        }
        Ok(Status::Ok)
    }

    /// Our models have no String variables: any value reference is unknown.
    pub fn no_strings(&mut self, vrs: &[u32]) -> Res {
        self.require(&[
            Phase::Instantiated,
            Phase::InitializationMode,
            Phase::StepComplete,
            Phase::StepFailed,
            Phase::Terminated,
            Phase::Error,
        ])?;
        match vrs.first() {
            Some(vr) => err(format!(
                "unknown String value reference {vr} (this FMU has no String variables)"
            )),
            None => Ok(Status::Ok),
        }
    }

    /// Checks that every variable may be set now; returns a reason otherwise.
    fn check_settable(&self, t: VarType, vrs: &[u32]) -> Result<(), (Status, String)> {
        self.check_vrs(t, vrs)?;
        let phase = self.core.phase;
        for vr in vrs {
            let v = self.variable(t, *vr).expect("checked above");
            let ok = match phase {
                Phase::Instantiated | Phase::InitializationMode => v.settable_before_init(),
                Phase::StepComplete => v.settable_during_run(),
                _ => return err(format!("not allowed in state '{}'", phase.name())),
            };
            if !ok {
                return err(format!(
                    "variable '{}' ({}, {}) cannot be set in state '{}'",
                    v.name,
                    v.causality.as_str(),
                    v.variability.as_str(),
                    phase.name()
                ));
            }
        }
        Ok(())
    }

    fn check_range(&self, t: VarType, vr: u32, x: f64) -> Result<(), (Status, String)> {
        let v = self.variable(t, vr).expect("checked");
        // " Pa" after a value with a unit, nothing after one without.
        let unit = v.unit.map_or(String::new(), |u| format!(" {u}"));
        if !x.is_finite() {
            return err(format!("value {x} for '{}' is not finite", v.name));
        }
        if let Some(min) = v.min {
            if x < min {
                return err(format!(
                    "value {x}{unit} for '{}' is below its minimum {min}{unit}",
                    v.name
                ));
            }
        }
        if let Some(max) = v.max {
            if x > max {
                return err(format!(
                    "value {x}{unit} for '{}' is above its maximum {max}{unit}",
                    v.name
                ));
            }
        }
        Ok(())
    }

    /// Parameters or inputs set before the step phase invalidate a model built for an output read in
    /// initialization mode; inputs set between steps are read by the next fmi2DoStep from the store.
    fn after_set(&mut self) {
        if self.core.phase != Phase::StepComplete {
            self.core.model_stale = true;
        }
    }

    /// All values are checked before any is applied, so a rejected call changes nothing.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Res {
        self.check_settable(VarType::Real, vrs)?;
        for (vr, x) in vrs.iter().zip(values) {
            self.check_range(VarType::Real, *vr, *x)?;
        }
        for (vr, x) in vrs.iter().zip(values) {
            self.core.store.reals[*vr as usize] = *x;
        }
        let [rtol, atol] = tolerance_parameters(&self.info);
        for (k, p) in [rtol, atol].iter().enumerate() {
            if p.is_some_and(|(vr, _)| vrs.contains(&vr)) {
                self.tolerances_set[k] = true;
            }
        }
        self.after_set();
        Ok(Status::Ok)
    }

    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Res {
        self.check_settable(VarType::Integer, vrs)?;
        for (vr, x) in vrs.iter().zip(values) {
            self.check_range(VarType::Integer, *vr, *x as f64)?;
        }
        for (vr, x) in vrs.iter().zip(values) {
            self.core.store.integers[*vr as usize] = *x;
        }
        self.after_set();
        Ok(Status::Ok)
    }

    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Res {
        self.check_settable(VarType::Boolean, vrs)?;
        for (vr, x) in vrs.iter().zip(values) {
            self.core.store.booleans[*vr as usize] = *x;
        }
        self.after_set();
        Ok(Status::Ok)
    }

    /// fmi2SetRealInputDerivatives: the k-th derivative of each input at the current communication
    /// point. They shape the inputs of the next fmi2DoStep only and are cleared after it.
    pub fn set_input_derivatives(&mut self, vrs: &[u32], orders: &[i32], values: &[f64]) -> Res {
        self.require(&[
            Phase::Instantiated,
            Phase::InitializationMode,
            Phase::StepComplete,
        ])?;
        self.check_vrs(VarType::Real, vrs)?;
        for ((vr, order), x) in vrs.iter().zip(orders).zip(values) {
            let v = self.variable(VarType::Real, *vr).expect("checked");
            if v.causality != Causality::Input {
                return err(format!("'{}' is not an input", v.name));
            }
            if *order < 1 || *order as usize > MAX_INPUT_DERIVATIVE_ORDER {
                return err(format!(
                    "derivative order {order} for '{}' is outside 1..={MAX_INPUT_DERIVATIVE_ORDER}",
                    v.name
                ));
            }
            if !x.is_finite() {
                return err(format!("derivative {x} for '{}' is not finite", v.name));
            }
        }
        for ((vr, order), x) in vrs.iter().zip(orders).zip(values) {
            self.core.input_derivatives[*vr as usize][*order as usize - 1] = *x;
        }
        Ok(Status::Ok)
    }

    pub fn get_output_derivatives(&mut self, vrs: &[u32], orders: &[i32], out: &mut [f64]) -> Res {
        self.require(&[
            Phase::StepComplete,
            Phase::StepFailed,
            Phase::Terminated,
            Phase::Error,
        ])?;
        self.check_vrs(VarType::Real, vrs)?;
        let model = self
            .core
            .model
            .as_ref()
            .ok_or((Status::Error, "the model is not initialized".to_string()))?;
        for ((vr, order), o) in vrs.iter().zip(orders).zip(out.iter_mut()) {
            let v = self.variable(VarType::Real, *vr).expect("checked");
            if v.causality != Causality::Output {
                return err(format!("'{}' is not an output", v.name));
            }
            *o = model.output_derivative(*vr, *order).ok_or((
                Status::Error,
                format!(
                    "derivative of order {order} of '{}' is not provided",
                    v.name
                ),
            ))?;
        }
        Ok(Status::Ok)
    }

    pub fn do_step(&mut self, t: f64, h: f64) -> Res {
        self.do_step_with(t, h, None)
    }

    /// A step whose inputs come from `intermediate` at the model's internal times (FMI 3.0
    /// intermediate update) instead of the polynomial set before the step.
    pub fn do_step_with(
        &mut self,
        t: f64,
        h: f64,
        intermediate: Option<&dyn IntermediateInputs>,
    ) -> Res {
        self.require(&[Phase::StepComplete])?;
        if !(h.is_finite() && h > 0.0) {
            return err(format!("communicationStepSize {h} must be finite and > 0"));
        }
        let now = self.core.time;
        // The master's clock and ours may differ by the round-off of a sum of steps.
        let slack = 1e-12 * now.abs().max(h).max(1.0);
        if !t.is_finite() || (t - now).abs() > slack {
            return err(format!(
                "currentCommunicationPoint {t} s does not match the FMU time {now} s (restore a saved FMU state to go back)"
            ));
        }
        if let Some(stop) = self.core.stop_time {
            if t + h > stop + slack {
                return err(format!(
                    "step to {} s passes the stopTime {stop} s given in {}",
                    t + h,
                    self.logger.standard().setup_experiment()
                ));
            }
        }
        self.inputs.t0 = t;
        self.inputs.values.copy_from_slice(&self.core.store.reals);
        self.inputs
            .derivatives
            .copy_from_slice(&self.core.input_derivatives);
        let model = self
            .core
            .model
            .as_mut()
            .expect("a model exists after initialization");
        let mut log = ModelLog(&self.logger);
        let asked;
        let inputs: &dyn StepInputs = match intermediate {
            None => &self.inputs,
            Some(master) => {
                asked = AskedInputs {
                    held: &self.inputs,
                    master,
                };
                &asked
            }
        };
        let outcome = model.do_step(t, h, inputs, &mut log);
        self.core
            .input_derivatives
            .iter_mut()
            .for_each(|d| *d = [0.0; MAX_INPUT_DERIVATIVE_ORDER]);
        match outcome {
            StepOutcome::Ok => {
                model.write_outputs(&mut self.core.store);
                self.core.time = t + h;
                self.core.last_successful_time = t + h;
                Ok(Status::Ok)
            }
            StepOutcome::Discard {
                reason,
                reached_time,
            } => {
                model.write_outputs(&mut self.core.store);
                self.core.time = reached_time;
                self.core.last_successful_time = reached_time;
                self.core.phase = Phase::StepFailed;
                Err((
                    Status::Discard,
                    format!("step from {t} s by {h} s stopped at {reached_time} s: {reason}"),
                ))
            }
            StepOutcome::Error(reason) => {
                self.core.phase = Phase::Error;
                Err((
                    Status::Error,
                    format!("step from {t} s by {h} s failed: {reason}"),
                ))
            }
        }
    }

    pub fn snapshot(&self) -> Result<Core<M>, (Status, String)> {
        self.require(&STATE_PHASES)?;
        Ok(self.core.clone())
    }

    /// Like `snapshot`, into an existing state (its buffers are reused).
    pub fn snapshot_into(&self, dst: &mut Core<M>) -> Res {
        self.require(&STATE_PHASES)?;
        dst.clone_from(&self.core);
        Ok(Status::Ok)
    }

    pub fn restore(&mut self, core: &Core<M>) -> Res {
        self.require(&STATE_PHASES)?;
        self.core.clone_from(core);
        Ok(Status::Ok)
    }

    pub fn status_allowed(&self) -> Result<(), (Status, String)> {
        self.require(&[Phase::StepComplete, Phase::StepFailed, Phase::Terminated])
    }
}
